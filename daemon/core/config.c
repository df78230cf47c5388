/* SPDX-License-Identifier: MIT */
#include "daemon/core/config.h"

#include <ctype.h>
#include <errno.h>
#include <stdarg.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "can/assembler.h"
#include "can/candump_log.h"
#include "daemon/core/config_syntax.h"
#include "base/addr.h"
#include "verdict/regulation.h"

/*
 * How a value is read and checked: every kind checks the whole syntax and range of its value
 * (files are checked later, in hl_config_check_files, once every override is in).
 */
enum kind {
	STRING, /* free text: GPIO line names or offsets */
	PATH,
	BOOL,
	INT, /* min..max */
	DOUBLE, /* min..max */
	SIZE, /* WxH into width, height */
	FAILSAFE,
	ENUM, /* one of choices ("a|b|c") */
	ADDRESS, /* HOST:PORT as hl_addr_parse takes it, or empty (off) */
	IFACE, /* a network interface name */
	LAMPS, /* lamp names, comma separated, 1..HL_ASM_MAX_LAMPS */
	SETS, /* comma-separated set ids into verdict_sets, n_verdict_sets */
	TRAFFIC, /* right | left into traffic_left */
	PAIR, /* two positive numbers "a,b" into a double[2] (min, max bound each) */
	MODES, /* MODE:ID+ID,MODE:ID,... (checked against the DBC and the sets at start) */
	SETID, /* one set id (a file name in the regulations directory) */
	UDP, /* udp:HOST:PORT as ADDRESS, or empty (off) */
	TRIPLE, /* three numbers "a,b,c" into a double[3] (min, max bound each) */
	WORLD, /* osi:file:PATH or osi:udp:HOST:PORT (docs/osi.md), or empty (off) */
};

/*
 * The keys. Adding one: a field in struct hl_config (config.h), its default in
 * hl_config_defaults, a line here with a kind that checks it (a new kind: its case in
 * set_value and print_value), and its line in docs/daemon.md, hdlampd.conf(5) and
 * systemd/hdlampd.conf (test_config_example checks the last).
 */
struct key {
	const char *section, *name;
	enum kind kind;
	size_t offset;
	double min, max; /* INT, DOUBLE, PAIR; PATH: max > 0 is its longest length */
	const char *help;
	const char *choices; /* ENUM: "a|b|c" */
};

#define F(field) offsetof(struct hl_config, field)

static const struct key keys[] = {
	{ "can", "interface", IFACE, F(interface), 0, 0, "SocketCAN interface (or replay)", NULL },
	{ "can", "replay", PATH, F(replay), 0, 0, "candump -L log to replay (or interface)", NULL },
	{ "can", "replay_fast", BOOL, F(replay_fast), 0, 0, "replay as fast as the output keeps up",
	  NULL },
	{ "can", "replay_loop", BOOL, F(replay_loop), 0, 0, "replay the log over and over", NULL },
	{ "can", "replay_passes", INT, F(replay_passes), 0, 1000000,
	  "with replay_loop: stop after this many passes; 0 = never", NULL },
	{ "can", "dbc", PATH, F(dbc), 0, 0, "the CAN database", NULL },
	{ "can", "lamps", LAMPS, F(lamps), 0, 0, "lamp names as the DBC's HdlLamp, comma separated",
	  NULL },
	{ "can", "timeout_ms", INT, F(timeout_ms), 1, 60000,
	  "a lamp with no complete cycle this long is stale", NULL },
	{ "dbc", "strict", BOOL, F(dbc_strict), 0, 0,
	  "refuse a DBC with irregularities instead of loading it with warnings", NULL },
	{ "lamps", "left", PATH, F(lid_left), 0, 0, "the left lamp's LID file", NULL },
	{ "lamps", "right", PATH, F(lid_right), 0, 0, "the right lamp's LID file", NULL },
	{ "lamps", "presets", PATH, F(presets), 0, 0, "directory of NAME.json presets", NULL },
	{ "lamps", "failsafe", FAILSAFE, F(failsafe), 0, 0,
	  "hold | dark | preset:NAME, while a lamp is stale", NULL },
	{ "render", "scene", ENUM, F(scene), 0, 0, "sphere | wall | road | bird | bounce",
	  "sphere|wall|road|bird|bounce" },
	{ "render", "view", ENUM, F(view), 0, 0, "display | lux | hdr", "display|lux|hdr" },
	{ "render", "size", SIZE, F(width), 0, 0, "WxH pixels", NULL },
	{ "render", "exposure_ev", DOUBLE, F(exposure_ev), -20, 20, "display view exposure", NULL },
	{ "render", "combine", ENUM, F(combine), 0, 0, "auto | cpu | gles", "auto|cpu|gles" },
	{ "render", "headlight", ENUM, F(headlight), 0, 0, "auto | cpu | gles", "auto|cpu|gles" },
	{ "render", "threads", INT, F(render_threads), 0, 16,
	  "threads lighting a frame (render thread + helpers); 0 = one per CPU", NULL },
	{ "render", "rate_hz", DOUBLE, F(rate_hz), 0, 1000,
	  "fixed output rate; 0 = on every new cycle", NULL },
	{ "render", "coalesce_ms", DOUBLE, F(coalesce_ms), 0, 20,
	  "rate 0: wait this long at most for the other lamp's cycle, one frame for both", NULL },
	{ "stream", "tcp", ADDRESS, F(stream_tcp), 0, 0,
	  "HOST:PORT of the frame stream (port 0: any free one), empty = off", NULL },
	{ "stream", "unix", PATH, F(stream_unix), 0, 107 /* bytes: sun_path holds 108 with NUL */,
	  "Unix socket of the frame stream, empty = off", NULL },
	{ "stream", "raw", BOOL, F(stream_raw), 0, 0,
	  "pixels only, no header (for ffmpeg -f rawvideo)", NULL },
	{ "stream", "max_clients", INT, F(stream_max_clients), 1, 64,
	  "clients at once; a new one replaces a client behind, else it is refused", NULL },
	{ "stream", "stall_timeout_ms", INT, F(stream_stall_timeout_ms), 100, 600000,
	  "a client that takes no byte of its frame this long is dropped", NULL },
	{ "http", "listen", ADDRESS, F(http_listen), 0, 0,
	  "HOST:PORT of the HTTP live view (port 0: any free one), empty = off", NULL },
	{ "http", "capture", BOOL, F(http_capture), 0, 0, "allow POST /capture", NULL },
	{ "capture", "dir", PATH, F(capture_dir), 0, 0, "where captures are written", NULL },
	{ "capture", "queue", INT, F(capture_queue), 1, 16,
	  "captures waiting or being written at once; more are refused", NULL },
	{ "gpio", "chip", PATH, F(gpio_chip), 0, 0, "GPIO chip name or path, empty = no GPIO",
	  NULL },
	{ "gpio", "strobe", STRING, F(gpio_strobe), 0, 0, "output line toggled per published frame",
	  NULL },
	{ "gpio", "trigger", STRING, F(gpio_trigger), 0, 0,
	  "input line whose edge writes a capture", NULL },
	{ "gpio", "trigger_edge", ENUM, F(gpio_trigger_edge), 0, 0, "rising | falling | both",
	  "rising|falling|both" },
	{ "gpio", "ecu_enable", STRING, F(gpio_ecu_enable), 0, 0,
	  "output line held active while running", NULL },
	{ "verdict", "sets", SETS, F(verdict_sets), 0, 0,
	  "regulation set ids checked on every frame, comma separated; empty = none", NULL },
	{ "verdict", "regulations", PATH, F(regulations), 0, 0,
	  "directory of the regulation sets (ID.json)", NULL },
	{ "verdict", "traffic", TRAFFIC, F(traffic_left), 0, 0,
	  "right | left: left-hand traffic mirrors the sets' H", NULL },
	{ "verdict", "modes", MODES, F(verdict_modes), 0, 0,
	  "MODE:ID+ID,...: the sets evaluated in each beam mode (the DBC's HdlBeamMode signal's "
	  "VAL_ names); empty = by the sets' beams (low/passing, high/driving, glarefree/adb), "
	  "every set without a mode signal",
	  NULL },
	{ "road", "levels", PAIR, F(road_levels_lx), 0.01, 1000,
	  "illuminance levels (lx) of the road ranges, two, comma separated", NULL },
	{ "road", "width_at", PAIR, F(road_width_at_m), 1, 300,
	  "distances (m) at which the width of the first level's area is taken, two", NULL },
	{ "scene", "scenario", PATH, F(scenario), 0, 0,
	  "scenario file (docs/scenarios.md): the moving scene's clock, poses and live glare; "
	  "empty = none",
	  NULL },
	{ "scene", "glare_set", SETID, F(glare_set), 0, 0,
	  "regulation set of the glare limits at the road users' eyes (in verdict.regulations)",
	  NULL },
	{ "scene", "glare_history", INT, F(glare_history), 1, 100000,
	  "frames of per-road-user glare GET /glare.json keeps (3000 = 60 s at 50 Hz)", NULL },
	{ "scene", "world", WORLD, F(world), 0, 0,
	  "the world from ASAM OSI (docs/osi.md): osi:file:TRACE.osi or osi:udp:HOST:PORT; "
	  "scene.scenario then lends the ego's lamps and camera (and a road); empty = the "
	  "scenario's own",
	  NULL },
	{ "scene", "world_message", ENUM, F(world_message), 0, 0,
	  "the OSI message: auto (a trace: its file name; udp: ground-truth, as esmini) | ground-truth | "
	  "sensor-view",
	  "auto|ground-truth|sensor-view" },
	{ "scene", "world_timeout_s", DOUBLE, F(world_timeout_s), 0.01, 3600,
	  "osi:udp: no good message this long and the world is none (no road users)", NULL },
	{ "scene", "world_wait_s", DOUBLE, F(world_wait_s), 0.1, 86400,
	  "osi:udp: how long hdlampd waits at start for the simulator's first message", NULL },
	{ "pose", "listen", UDP, F(pose_listen), 0, 0,
	  "udp:HOST:PORT for poses from a driving simulator (needs scene.scenario); empty = off",
	  NULL },
	{ "restbus", "interface", IFACE, F(restbus_interface), 0, 0,
	  "SocketCAN interface the restbus sends the ECU's inputs on (needs scene.scenario); "
	  "empty = off",
	  NULL },
	{ "ecu", "model", PATH, F(ecu_model), 0, 0,
	  "reference | FILE.fmu: the ECU in process on the virtual bus " HL_CONFIG_VBUS
	  " (can.interface and restbus.interface); empty = an ECU outside",
	  NULL },
	{ "ecu", "faults", STRING, F(ecu_faults), 0, 0,
	  "the in-process ECU's faults, comma separated: ignore-objects, no-failsafe, late=MS, "
	  "stuck-counter, bad-crc",
	  NULL },
	{ "restbus", "dbc", PATH, F(restbus_dbc), 0, 0,
	  "the ECU's input database (HdlInput attributes); empty = the shipped hd84_inputs.dbc",
	  NULL },
	{ "restbus", "camera_pos_m", TRIPLE, F(restbus_camera_pos_m), -30, 30,
	  "the front camera in the ego's body frame: x (forward), y (left), z (up), m", NULL },
	{ "restbus", "fov_deg", PAIR, F(restbus_fov_deg), 1, 170,
	  "the camera's horizontal and vertical field of view (full angles, degrees)", NULL },
	{ "restbus", "range_m", DOUBLE, F(restbus_range_m), 1, 10000,
	  "the camera's range: farther road users are not sent", NULL },
	{ "restbus", "light_switch", ENUM, F(restbus_light_switch), 0, 0,
	  "off | auto | low | high: the driver's light switch the restbus sends",
	  "off|auto|low|high" },
	{ "restbus", "adb_enable", BOOL, F(restbus_adb_enable), 0, 0,
	  "the driver allows the glare-free high beam (ADB)", NULL },
	{ "loop", "reaction_ms", DOUBLE, F(loop_reaction_ms), 1, 60000,
	  "glare over a road user's limit is allowed this long after it enters the camera's view "
	  "(default 60: three ECU cycles, docs/loop.md)",
	  NULL },
	{ "loop", "events", PATH, F(loop_events), 0, 0,
	  "JSON lines per loop event (enter, leave): a file, - for stdout, empty = none", NULL },
	{ "loop", "exit_at_end", BOOL, F(loop_exit_at_end), 0, 0,
	  "stop at the scenario's end (live: its duration on the daemon's clock; replay: the log's "
	  "end)",
	  NULL },
	{ "loop", "report", PATH, F(loop_report), 0, 0,
	  "write the run's JSON report (frames, cycles, verdicts, glare, loop latencies) here at "
	  "exit; empty = none",
	  NULL },
	{ "loop", "junit", PATH, F(loop_junit), 0, 0,
	  "write the run's verdicts as JUnit XML here at exit (as hdlamp sil --junit); empty = none",
	  NULL },
	{ "sched", "realtime_priority", INT, F(rt_priority), 0, 99,
	  "SCHED_FIFO priority of the CAN and render threads (and the render helpers), the frame "
	  "stream thread one below; 0 = normal scheduling",
	  NULL },
};

#define N_KEYS (sizeof(keys) / sizeof(keys[0]))

_Static_assert(N_KEYS <= HL_CONFIG_MAX_KEYS, "raise HL_CONFIG_MAX_KEYS");

void hl_config_defaults(struct hl_config *c)
{
	memset(c, 0, sizeof(*c));
	strcpy(c->dbc, "dbc/hd84.dbc");
	strcpy(c->lamps, "left,right");
	c->timeout_ms = 100;
	c->failsafe = HL_FAILSAFE_HOLD;
	strcpy(c->scene, "road");
	strcpy(c->view, "display");
	c->width = 1280;
	c->height = 720;
	strcpy(c->combine, "auto");
	strcpy(c->headlight, "auto");
	/* the ECU sends one lamp's pages, then the other's: 12 pages of 8 bytes take 2.9 ms on a
	 * 500 kbit/s bus (docs/loop.md), so the window must be longer for one frame per cycle */
	c->coalesce_ms = 5.0;
	strcpy(c->stream_tcp, "127.0.0.1:5600");
	c->stream_max_clients = 8;
	c->stream_stall_timeout_ms = 2000;
	strcpy(c->http_listen, "127.0.0.1:8080");
	strcpy(c->capture_dir, "captures");
	c->capture_queue = 4;
	strcpy(c->gpio_trigger_edge, "rising");
	/* the sets beside the binary (verdict/regulation.h): /usr/bin/hdlampd ->
	 * /usr/share/hdlamp/regulations, and the build tree's own link */
	if (hl_regulation_default_dir(c->regulations, sizeof(c->regulations)) < 0)
		c->regulations[0] = '\0'; /* a configured set then names the missing directory */
	c->road_levels_lx[0] = 1.0;
	c->road_levels_lx[1] = 3.0;
	c->road_width_at_m[0] = 25.0;
	c->road_width_at_m[1] = 50.0;
	strcpy(c->glare_set, "unece-r149-01-adb-glare");
	c->glare_history = 3000;
	snprintf(c->world_message, sizeof(c->world_message), "auto");
	c->world_timeout_s = 1.0;
	c->world_wait_s = 60.0;
	c->restbus_camera_pos_m[0] = -1.8; /* behind the windscreen, at the mirror */
	c->restbus_camera_pos_m[1] = 0.0;
	c->restbus_camera_pos_m[2] = 1.3;
	c->restbus_fov_deg[0] = 50.0;
	c->restbus_fov_deg[1] = 30.0;
	c->restbus_range_m = 250.0;
	strcpy(c->restbus_light_switch, "auto");
	c->restbus_adb_enable = true;
	c->loop_reaction_ms = 60.0; /* 3 ECU cycles of 20 ms: docs/loop.md */
}

static int bad(struct hl_config_error *err, const char *origin, int line, const struct key *k,
	       const char *fmt, ...) __attribute__((format(printf, 5, 6)));

/* "'FILE':LINE: key 'S.K': what", "ORIGIN: key 'S.K': what" or, for a default value,
 * "key 'S.K' (default): what"; -EINVAL. */
static int bad(struct hl_config_error *err, const char *origin, int line, const struct key *k,
	       const char *fmt, ...)
{
	char what[400];
	va_list ap;

	if (!err)
		return -EINVAL;
	va_start(ap, fmt);
	vsnprintf(what, sizeof(what), fmt, ap);
	va_end(ap);
	if (line > 0)
		snprintf(err->msg, sizeof(err->msg), "'%s':%d: key '%s.%s': %s", origin, line,
			 k->section, k->name, what);
	else if (origin)
		snprintf(err->msg, sizeof(err->msg), "%s: key '%s.%s': %s", origin, k->section,
			 k->name, what);
	else
		snprintf(err->msg, sizeof(err->msg), "key '%s.%s' (default): %s", k->section,
			 k->name, what);
	return -EINVAL;
}

/* Reads value into cfg at k; 0 or -EINVAL (err says why, cfg untouched). */
static int set_value(struct hl_config *cfg, const struct key *k, const char *value,
		     const char *origin, int line, struct hl_config_error *err)
{
	char *at = (char *)cfg + k->offset, *end, what[400];

	switch (k->kind) {
	case STRING:
		if (hl_cfg_copy_string(at, HL_CONFIG_NAME, value) < 0)
			return bad(err, origin, line, k, "'%s': too long (at most %d bytes)", value,
				   HL_CONFIG_NAME - 1);
		return 0;
	case WORLD:
		if (value[0] && !(strncmp(value, "osi:file:", 9) == 0 && value[9]) &&
		    !(strncmp(value, "osi:udp:", 8) == 0 &&
		      hl_addr_parse(value + 8, &(struct sockaddr_storage){ 0 }, NULL) == 0))
			return bad(err, origin, line, k,
				   "'%s': expected osi:file:TRACE.osi or osi:udp:HOST:PORT", value);
		if (hl_cfg_copy_string(at, HL_CONFIG_PATH, value) < 0)
			return bad(err, origin, line, k, "too long (at most %d bytes)",
				   HL_CONFIG_PATH - 1);
		return 0;
	case PATH:
		if (k->max > 0 && strlen(value) > k->max)
			return bad(
				err, origin, line, k,
				"'%s': path too long (at most %.0f bytes: a Unix socket's address)",
				value, k->max);
		if (hl_cfg_copy_string(at, HL_CONFIG_PATH, value) < 0)
			return bad(err, origin, line, k, "path too long (at most %d bytes)",
				   HL_CONFIG_PATH - 1);
		return 0;
	case ENUM:
		if (!hl_cfg_is_choice(k->choices, value)) {
			hl_cfg_choices_text(k->choices, what, sizeof(what));
			return bad(err, origin, line, k, "'%s': expected %s", value, what);
		}
		strcpy(at, value); /* a choice is short */
		return 0;
	case ADDRESS:
		if (hl_cfg_check_address(value, what, sizeof(what)) < 0 ||
		    hl_cfg_copy_string(at, HL_CONFIG_NAME, value) < 0)
			return bad(err, origin, line, k, "%s", what);
		return 0;
	case IFACE:
		if (!hl_cfg_valid_iface(value) || hl_cfg_copy_string(at, HL_CONFIG_NAME, value) < 0)
			return bad(
				err, origin, line, k,
				"'%s': expected an interface name (1..15 characters, no '/', ':' "
				"or spaces), or empty",
				value);
		return 0;
	case LAMPS:
		if (!hl_cfg_valid_lamps(value) || hl_cfg_copy_string(at, HL_CONFIG_NAME, value) < 0)
			return bad(
				err, origin, line, k,
				"'%s': expected 1..%d lamp names (letters, digits, _ -) separated "
				"by commas, such as left,right",
				value, HL_ASM_MAX_LAMPS);
		return 0;
	case BOOL:
		if (strcmp(value, "true") == 0 || strcmp(value, "yes") == 0 ||
		    strcmp(value, "1") == 0)
			*(bool *)at = true;
		else if (strcmp(value, "false") == 0 || strcmp(value, "no") == 0 ||
			 strcmp(value, "0") == 0)
			*(bool *)at = false;
		else
			return bad(err, origin, line, k, "'%s': expected true or false", value);
		return 0;
	case INT: {
		long v;

		errno = 0;
		v = strtol(value, &end, 10);
		if (!*value || *end || errno || v < k->min || v > k->max)
			return bad(err, origin, line, k, "'%s': expected an integer %.0f..%.0f",
				   value, k->min, k->max);
		*(int *)at = (int)v;
		return 0;
	}
	case DOUBLE: {
		double v = strtod(value, &end);

		if (!*value || *end || !isfinite(v) || v < k->min || v > k->max)
			return bad(err, origin, line, k, "'%s': expected a number %g..%g", value,
				   k->min, k->max);
		*(double *)at = v;
		return 0;
	}
	case SIZE: {
		long w = isdigit((unsigned char)value[0]) ? strtol(value, &end, 10) : 0, h = 0;

		if (w >= 16 && w <= 8192 && *end == 'x' && isdigit((unsigned char)end[1]))
			h = strtol(end + 1, &end, 10);
		if (*end || h < 16 || h > 8192)
			return bad(err, origin, line, k, "'%s': expected WxH, each 16..8192",
				   value);
		cfg->width = (int)w;
		cfg->height = (int)h;
		return 0;
	}
	case FAILSAFE:
		if (strcmp(value, "hold") == 0) {
			cfg->failsafe = HL_FAILSAFE_HOLD;
		} else if (strcmp(value, "dark") == 0) {
			cfg->failsafe = HL_FAILSAFE_DARK;
		} else if (strncmp(value, "preset:", 7) == 0 &&
			   hl_cfg_valid_set_id(value + 7, strlen(value + 7)) &&
			   hl_cfg_copy_string(cfg->failsafe_preset, HL_CONFIG_NAME, value + 7) ==
				   0) {
			cfg->failsafe = HL_FAILSAFE_PRESET;
		} else {
			return bad(err, origin, line, k,
				   "'%s': expected hold, dark or preset:NAME (NAME.json in "
				   "lamps.presets)",
				   value);
		}
		return 0;
	case SETS:
		if (hl_cfg_parse_sets(value, cfg->verdict_sets, &cfg->n_verdict_sets, what,
				      sizeof(what)) < 0)
			return bad(err, origin, line, k, "%s", what);
		return 0;
	case MODES:
		if (!hl_cfg_valid_modes(value))
			return bad(
				err, origin, line, k,
				"'%s': expected MODE:ID+ID,MODE:ID,... (a mode's sets joined by +, "
				"no spaces)",
				value);
		if (hl_cfg_copy_string(at, HL_CONFIG_PATH, value) < 0)
			return bad(err, origin, line, k, "too long (at most %d bytes)",
				   HL_CONFIG_PATH - 1);
		return 0;
	case SETID:
		if (!hl_cfg_valid_set_id(value, strlen(value)))
			return bad(err, origin, line, k,
				   "'%s': expected a set id (letters, digits, . _ + -, at most %d "
				   "characters)",
				   value, HL_CONFIG_SET_ID - 1);
		strcpy(at, value);
		return 0;
	case UDP:
		if (*value && strncmp(value, "udp:", 4) != 0)
			return bad(
				err, origin, line, k,
				"'%s': expected udp:HOST:PORT (e.g. udp:127.0.0.1:5700), or empty "
				"for off",
				value);
		if (hl_cfg_check_address(*value ? value + 4 : value, what, sizeof(what)) < 0 ||
		    (*value && !value[4]) || hl_cfg_copy_string(at, HL_CONFIG_NAME, value) < 0)
			return bad(err, origin, line, k, "%s",
				   *value && !value[4] ? "expected udp:HOST:PORT" : what);
		return 0;
	case TRAFFIC:
		if (strcmp(value, "right") != 0 && strcmp(value, "left") != 0)
			return bad(err, origin, line, k, "'%s': expected right or left", value);
		cfg->traffic_left = strcmp(value, "left") == 0;
		return 0;
	case PAIR: {
		double v[2] = { strtod(value, &end), NAN };

		if (end != value && *end == ',') {
			const char *b = end + 1;

			v[1] = strtod(b, &end);
			if (end == b)
				v[1] = NAN;
		}
		if (*end || !(v[0] >= k->min && v[0] <= k->max) ||
		    !(v[1] >= k->min && v[1] <= k->max))
			return bad(err, origin, line, k,
				   "'%s': expected two numbers %g..%g, as A,B", value, k->min,
				   k->max);
		memcpy(at, v, sizeof(v));
		return 0;
	}
	case TRIPLE: {
		double v[3] = { NAN, NAN, NAN };
		const char *b = value;

		for (int i = 0; i < 3; i++) {
			v[i] = strtod(b, &end);
			if (end == b || (i < 2 && *end != ',')) {
				v[i] = NAN;
				break;
			}
			b = end + 1;
		}
		if (*end || !(v[0] >= k->min && v[0] <= k->max) ||
		    !(v[1] >= k->min && v[1] <= k->max) || !(v[2] >= k->min && v[2] <= k->max))
			return bad(err, origin, line, k,
				   "'%s': expected three numbers %g..%g, as X,Y,Z", value, k->min,
				   k->max);
		memcpy(at, v, sizeof(v));
		return 0;
	}
	}
	return -EINVAL;
}

static const struct key *find_key(const char *section, const char *name)
{
	for (size_t i = 0; i < N_KEYS; i++)
		if (strcmp(keys[i].section, section) == 0 && strcmp(keys[i].name, name) == 0)
			return &keys[i];
	return NULL;
}

int hl_config_set(struct hl_config *cfg, const char *section, const char *name, const char *value,
		  const char *origin, int line, struct hl_config_error *err)
{
	const struct key *k = find_key(section, name);
	int rc;

	if (!k) {
		const struct key unknown = { .section = section, .name = name };

		return bad(err, origin, line, &unknown,
			   "unknown key (hdlampd --print-config lists every key)");
	}
	rc = set_value(cfg, k, value, origin, line, err);
	if (rc == 0)
		cfg->set_at[k - keys] = (struct hl_config_origin){ origin, line };
	return rc;
}

int hl_config_set_arg(struct hl_config *cfg, const char *assignment, const char *origin,
		      struct hl_config_error *err)
{
	char section[64], key[64];
	const char *dot = strchr(assignment, '.'), *eq = strchr(assignment, '=');

	if (!dot || !eq || dot > eq || dot - assignment >= (long)sizeof(section) ||
	    eq - dot - 1 >= (long)sizeof(key)) {
		if (err)
			snprintf(err->msg, sizeof(err->msg), "%s: '%s': expected SECTION.KEY=VALUE",
				 origin, assignment);
		return -EINVAL;
	}
	memcpy(section, assignment, dot - assignment);
	section[dot - assignment] = '\0';
	memcpy(key, dot + 1, eq - dot - 1);
	key[eq - dot - 1] = '\0';
	return hl_config_set(cfg, section, key, eq + 1, origin, 0, err);
}

int hl_config_check(const struct hl_config *cfg, struct hl_config_error *err)
{
	const char *why = NULL;
	const bool scene = cfg->scenario[0] || cfg->world[0];
	const bool vbus_iface = !cfg->interface[0] || strcmp(cfg->interface, HL_CONFIG_VBUS) == 0;
	const bool vbus_restbus = !cfg->restbus_interface[0] ||
				  strcmp(cfg->restbus_interface, HL_CONFIG_VBUS) == 0;

	if (cfg->ecu_model[0] && cfg->replay[0])
		why = "ecu.model runs the loop on the virtual bus " HL_CONFIG_VBUS
		      ": not with can.replay";
	else if (cfg->ecu_model[0] && (!vbus_iface || !vbus_restbus))
		why = "ecu.model runs the loop on the virtual bus " HL_CONFIG_VBUS
		      ": can.interface and restbus.interface must be " HL_CONFIG_VBUS " or empty";
	else if (cfg->ecu_model[0] && !scene)
		why = "ecu.model needs scene.scenario or scene.world: the restbus sends the ECU its state";
	else if (!cfg->ecu_model[0] && cfg->ecu_faults[0])
		why = "ecu.faults needs ecu.model";
	else if (!cfg->ecu_model[0] && !cfg->interface[0] == !cfg->replay[0])
		why = "exactly one of can.interface and can.replay is needed";
	else if ((cfg->replay_fast || cfg->replay_loop) && !cfg->replay[0])
		why = "can.replay_fast and can.replay_loop need can.replay";
	else if (cfg->replay_passes && !cfg->replay_loop)
		why = "can.replay_passes needs can.replay_loop";
	else if (cfg->replay_loop && strcmp(cfg->replay, "-") == 0)
		why = "can.replay_loop needs a file: standard input cannot be replayed again";
	else if (cfg->pose_listen[0] && !cfg->scenario[0])
		why = "pose.listen needs scene.scenario: the poses move its road users";
	else if (cfg->pose_listen[0] && cfg->world[0])
		why = "pose.listen and scene.world both move the scene: give one";
	else if (cfg->restbus_interface[0] && !scene)
		why = "restbus.interface needs scene.scenario or scene.world: the restbus sends its state";
	else if (cfg->loop_exit_at_end && !scene)
		why = "loop.exit_at_end needs scene.scenario or scene.world: the run ends with it";
	else if (cfg->loop_report[0] && !scene)
		why = "loop.report needs scene.scenario or scene.world: the report judges its run";
	else if (cfg->loop_junit[0] && !scene)
		why = "loop.junit needs scene.scenario or scene.world: the JUnit judges its run";
	if (why && err)
		snprintf(err->msg, sizeof(err->msg), "%s", why);
	return why ? -EINVAL : 0;
}

/* A readable regular file (or directory, dir); 0 or -errno / -EISDIR / -ENOTDIR. */
static int need(const char *path, bool dir)
{
	struct stat st;

	if (stat(path, &st) < 0)
		return -errno;
	if (dir != !!S_ISDIR(st.st_mode))
		return dir ? -ENOTDIR : -EISDIR;
	return access(path, dir ? X_OK : R_OK) < 0 ? -errno : 0;
}

static const struct key *key_of(size_t offset)
{
	for (size_t i = 0; i < N_KEYS; i++)
		if (keys[i].offset == offset)
			return &keys[i];
	return NULL;
}

/* A file key's value that is no readable file (or directory): the error naming both. */
static int check_path(const struct hl_config *cfg, size_t offset, const char *path, bool dir,
		      const char *expected, struct hl_config_error *err)
{
	const struct key *k = key_of(offset);
	const struct hl_config_origin *o = &cfg->set_at[k - keys];
	const int rc = need(path, dir);

	if (rc == 0)
		return 0;
	if (rc == -EISDIR || rc == -ENOTDIR)
		return bad(err, o->origin, o->line, k, "'%s': %s; expected %s", path,
			   rc == -EISDIR ? "a directory" : "not a directory", expected);
	return bad(err, o->origin, o->line, k, "'%s': %s; expected %s", path, strerror(-rc),
		   expected);
}

int hl_config_check_files(const struct hl_config *cfg, bool render, struct hl_config_error *err)
{
	char path[HL_CONFIG_PATH + HL_CONFIG_NAME + 8];
	const char *lids[2] = { cfg->lid_left, cfg->lid_right };
	int rc, n_lamps = 1;

	if (cfg->replay[0] && strcmp(cfg->replay, "-") != 0) {
		struct hl_candump_log *log = NULL;
		const struct key *k = key_of(F(replay));
		const struct hl_config_origin *o = &cfg->set_at[k - keys];

		rc = check_path(cfg, F(replay), cfg->replay, false, "a candump -L log", err);
		if (rc < 0)
			return rc;
		rc = hl_candump_log_open(cfg->replay, 1, &log);
		hl_candump_log_free(log);
		if (rc == -ENODATA)
			return bad(err, o->origin, o->line, k,
				   "'%s': no CAN frame in it; expected candump -L lines such as "
				   "'(1700000000.000000) can0 123#11223344'",
				   cfg->replay);
		if (rc < 0)
			return bad(err, o->origin, o->line, k, "'%s': %s", cfg->replay,
				   strerror(-rc));
	}
	rc = check_path(cfg, F(dbc), cfg->dbc, false, "a DBC file", err);
	if (rc < 0 || !render)
		return rc;
	if (cfg->scenario[0]) {
		rc = check_path(cfg, F(scenario), cfg->scenario, false,
				"a scenario file (docs/scenarios.md)", err);
		if (rc < 0)
			return rc;
	}
	if (cfg->ecu_model[0] && strcmp(cfg->ecu_model, "reference") != 0) {
		rc = check_path(cfg, F(ecu_model), cfg->ecu_model, false,
				"'reference' or an FMI 2.0 co-simulation FMU (docs/fmu.md)", err);
		if (rc < 0)
			return rc;
	}
	if (cfg->restbus_interface[0] && cfg->restbus_dbc[0]) {
		rc = check_path(cfg, F(restbus_dbc), cfg->restbus_dbc, false,
				"a DBC file with HdlInput attributes (docs/ecu-inputs.md)", err);
		if (rc < 0)
			return rc;
	}
	for (const char *c = cfg->lamps; *c; c++)
		n_lamps += *c == ',';
	if (n_lamps > 2) {
		const struct key *k = key_of(F(lamps));

		return bad(err, cfg->set_at[k - keys].origin, cfg->set_at[k - keys].line, k,
			   "'%s': the renderer takes one or two lamps", cfg->lamps);
	}
	for (int l = 0; l < n_lamps && l < 2; l++) {
		const size_t off = l ? F(lid_right) : F(lid_left);

		if (!lids[l][0]) {
			const struct key *k = key_of(off);

			return bad(err, cfg->set_at[k - keys].origin, cfg->set_at[k - keys].line, k,
				   "no LID file configured for lamp %d of can.lamps (make one with "
				   "'hdlamp model --out DIR')",
				   l + 1);
		}
		rc = check_path(cfg, off, lids[l], false, "a LID file (.lid.exr)", err);
		if (rc < 0)
			return rc;
	}
	if (cfg->failsafe == HL_FAILSAFE_PRESET) {
		snprintf(path, sizeof(path), "%s/%s.json", cfg->presets[0] ? cfg->presets : ".",
			 cfg->failsafe_preset);
		rc = check_path(cfg, F(failsafe), path, false,
				"the preset NAME.json in the directory lamps.presets", err);
		if (rc < 0)
			return rc;
	}
	if (cfg->stream_unix[0]) {
		const char *slash = strrchr(cfg->stream_unix, '/');

		snprintf(path, sizeof(path), "%.*s", slash ? (int)(slash - cfg->stream_unix) : 1,
			 slash ? cfg->stream_unix : ".");
		if (slash == cfg->stream_unix)
			strcpy(path, "/");
		rc = check_path(cfg, F(stream_unix), path, true,
				"the directory of the socket to exist", err);
		if (rc < 0)
			return rc;
	}
	return 0;
}

/* One key's value as hl_config_set reads it. */
static void print_value(const struct hl_config *cfg, const struct key *k, FILE *f)
{
	const char *at = (const char *)cfg + k->offset;

	switch (k->kind) {
	case STRING:
	case PATH:
	case WORLD:
	case ENUM:
	case ADDRESS:
	case IFACE:
	case LAMPS:
	case MODES:
	case SETID:
	case UDP:
		fprintf(f, "%s\n", at);
		break;
	case BOOL:
		fprintf(f, "%s\n", *(const bool *)at ? "true" : "false");
		break;
	case INT:
		fprintf(f, "%d\n", *(const int *)at);
		break;
	case DOUBLE:
		fprintf(f, "%g\n", *(const double *)at);
		break;
	case SIZE:
		fprintf(f, "%dx%d\n", cfg->width, cfg->height);
		break;
	case SETS:
		for (int s = 0; s < cfg->n_verdict_sets; s++)
			fprintf(f, "%s%s", s ? "," : "", cfg->verdict_sets[s]);
		fputc('\n', f);
		break;
	case TRAFFIC:
		fprintf(f, "%s\n", cfg->traffic_left ? "left" : "right");
		break;
	case PAIR:
		fprintf(f, "%g,%g\n", ((const double *)at)[0], ((const double *)at)[1]);
		break;
	case TRIPLE:
		fprintf(f, "%g,%g,%g\n", ((const double *)at)[0], ((const double *)at)[1],
			((const double *)at)[2]);
		break;
	case FAILSAFE:
		fprintf(f, "%s%s\n",
			cfg->failsafe == HL_FAILSAFE_HOLD ? "hold" :
			cfg->failsafe == HL_FAILSAFE_DARK ? "dark" :
							    "preset:",
			cfg->failsafe == HL_FAILSAFE_PRESET ? cfg->failsafe_preset : "");
		break;
	}
}

void hl_config_print(const struct hl_config *cfg, void *file)
{
	FILE *f = file;
	const char *section = "";

	for (size_t i = 0; i < N_KEYS; i++) {
		const struct key *k = &keys[i];

		if (strcmp(section, k->section) != 0) {
			fprintf(f, "%s[%s]\n", i ? "\n" : "", k->section);
			section = k->section;
		}
		fprintf(f, "; %s\n%s = ", k->help, k->name);
		print_value(cfg, k, f);
	}
}
