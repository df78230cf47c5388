/* SPDX-License-Identifier: MIT */
#include "daemon/config.h"

#include <ctype.h>
#include <errno.h>
#include <ini.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "lamp/regulation.h"

enum kind {
	STRING,
	PATH,
	BOOL,
	INT,
	DOUBLE,
	SIZE, /* WxH into width, height */
	FAILSAFE,
	BACKEND,
	EDGE,
	SETS, /* comma-separated set ids into verdict_sets, n_verdict_sets */
	TRAFFIC, /* right | left into traffic_left */
	PAIR, /* two positive numbers "a,b" into a double[2] (min, max bound each) */
	MODES, /* MODE:ID+ID,MODE:ID,... (checked against the DBC and the sets at start) */
};

struct key {
	const char *section, *name;
	enum kind kind;
	size_t offset;
	double min, max; /* INT, DOUBLE */
	const char *help;
};

#define F(field) offsetof(struct hl_config, field)

static const struct key keys[] = {
	{ "can", "interface", STRING, F(interface), 0, 0, "SocketCAN interface (or replay)" },
	{ "can", "replay", PATH, F(replay), 0, 0, "candump -L log to replay (or interface)" },
	{ "can", "replay_fast", BOOL, F(replay_fast), 0, 0,
	  "replay as fast as the output keeps up" },
	{ "can", "replay_loop", BOOL, F(replay_loop), 0, 0, "replay the log over and over" },
	{ "can", "dbc", PATH, F(dbc), 0, 0, "the CAN database" },
	{ "can", "lamps", STRING, F(lamps), 0, 0,
	  "lamp names as the DBC's HdlLamp, comma separated" },
	{ "can", "timeout_ms", INT, F(timeout_ms), 1, 60000,
	  "a lamp with no complete cycle this long is stale" },
	{ "dbc", "strict", BOOL, F(dbc_strict), 0, 0,
	  "refuse a DBC with irregularities instead of loading it with warnings" },
	{ "lamps", "left", PATH, F(lid_left), 0, 0, "the left lamp's LID file" },
	{ "lamps", "right", PATH, F(lid_right), 0, 0, "the right lamp's LID file" },
	{ "lamps", "presets", PATH, F(presets), 0, 0, "directory of NAME.json presets" },
	{ "lamps", "failsafe", FAILSAFE, F(failsafe), 0, 0,
	  "hold | dark | preset:NAME, while a lamp is stale" },
	{ "render", "scene", STRING, F(scene), 0, 0, "sphere | wall | road | bird" },
	{ "render", "view", STRING, F(view), 0, 0, "display | lux | hdr" },
	{ "render", "size", SIZE, F(width), 0, 0, "WxH pixels" },
	{ "render", "exposure_ev", DOUBLE, F(exposure_ev), -20, 20, "display view exposure" },
	{ "render", "combine", BACKEND, F(combine), 0, 0, "auto | cpu | gles" },
	{ "render", "headlight", BACKEND, F(headlight), 0, 0, "auto | cpu | gles" },
	{ "render", "threads", INT, F(render_threads), 0, 16,
	  "threads lighting a frame (render thread + helpers); 0 = one per CPU" },
	{ "render", "rate_hz", DOUBLE, F(rate_hz), 0, 1000,
	  "fixed output rate; 0 = on every new cycle" },
	{ "render", "coalesce_ms", DOUBLE, F(coalesce_ms), 0, 20,
	  "rate 0: wait this long at most for the other lamp's cycle, one frame for both" },
	{ "stream", "tcp", STRING, F(stream_tcp), 0, 0,
	  "host:port of the frame stream, empty = off" },
	{ "stream", "unix", PATH, F(stream_unix), 0, 0,
	  "Unix socket of the frame stream, empty = off" },
	{ "stream", "raw", BOOL, F(stream_raw), 0, 0,
	  "pixels only, no header (for ffmpeg -f rawvideo)" },
	{ "stream", "max_clients", INT, F(stream_max_clients), 1, 64, "clients at once" },
	{ "http", "listen", STRING, F(http_listen), 0, 0,
	  "host:port of the HTTP live view, empty = off" },
	{ "http", "capture", BOOL, F(http_capture), 0, 0, "allow POST /capture" },
	{ "capture", "dir", PATH, F(capture_dir), 0, 0, "where captures are written" },
	{ "gpio", "chip", PATH, F(gpio_chip), 0, 0, "GPIO chip name or path, empty = no GPIO" },
	{ "gpio", "strobe", STRING, F(gpio_strobe), 0, 0,
	  "output line toggled per published frame" },
	{ "gpio", "trigger", STRING, F(gpio_trigger), 0, 0,
	  "input line whose edge writes a capture" },
	{ "gpio", "trigger_edge", EDGE, F(gpio_trigger_edge), 0, 0, "rising | falling | both" },
	{ "gpio", "ecu_enable", STRING, F(gpio_ecu_enable), 0, 0,
	  "output line held active while running" },
	{ "verdict", "sets", SETS, F(verdict_sets), 0, 0,
	  "regulation set ids checked on every frame, comma separated; empty = none" },
	{ "verdict", "regulations", PATH, F(regulations), 0, 0,
	  "directory of the regulation sets (ID.json)" },
	{ "verdict", "traffic", TRAFFIC, F(traffic_left), 0, 0,
	  "right | left: left-hand traffic mirrors the sets' H" },
	{ "verdict", "modes", MODES, F(verdict_modes), 0, 0,
	  "MODE:ID+ID,...: the sets evaluated in each beam mode (the DBC's HdlBeamMode signal's "
	  "VAL_ names); empty = every set on every frame" },
	{ "road", "levels", PAIR, F(road_levels_lx), 0.01, 1000,
	  "illuminance levels (lx) of the road ranges, two, comma separated" },
	{ "road", "width_at", PAIR, F(road_width_at_m), 1, 300,
	  "distances (m) at which the width of the first level's area is taken, two" },
	{ "sched", "realtime_priority", INT, F(rt_priority), 0, 99,
	  "SCHED_FIFO priority of the CAN and render threads (and the render helpers); "
	  "0 = normal scheduling" },
};

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
	c->coalesce_ms = 2.0;
	strcpy(c->stream_tcp, "127.0.0.1:5600");
	c->stream_max_clients = 8;
	strcpy(c->http_listen, "127.0.0.1:8080");
	strcpy(c->capture_dir, "captures");
	strcpy(c->gpio_trigger_edge, "rising");
	/* the sets beside the binary (lamp/regulation.h): /usr/bin/hdlampd ->
	 * /usr/share/hdlamp/regulations, and the build tree's own link */
	if (hl_regulation_default_dir(c->regulations, sizeof(c->regulations)) < 0)
		c->regulations[0] = '\0'; /* a configured set then names the missing directory */
	c->road_levels_lx[0] = 1.0;
	c->road_levels_lx[1] = 3.0;
	c->road_width_at_m[0] = 25.0;
	c->road_width_at_m[1] = 50.0;
}

/* A set id is a file name in the regulations directory: letters, digits, '.', '_', '+', '-'. */
static bool valid_set_id(const char *s, size_t n)
{
	if (n == 0 || n >= HL_CONFIG_SET_ID || s[0] == '.')
		return false;
	for (size_t i = 0; i < n; i++)
		if (!isalnum((unsigned char)s[i]) && !strchr("._+-", s[i]))
			return false;
	return true;
}

/* MODE:ID+ID,... : names and ids of the set id's characters, each entry with one ':'. */
static bool valid_modes(const char *v)
{
	const char *entry = v;

	while (*entry) {
		const char *end = strchr(entry, ','), *colon = strchr(entry, ':');

		if (!end)
			end = entry + strlen(entry);
		if (!colon || colon >= end || colon == entry)
			return false;
		for (const char *c = entry; c < end; c++)
			if (c != colon && !isalnum((unsigned char)*c) && !strchr("._+-", *c))
				return false;
		if (!*end)
			break;
		entry = end + 1;
		if (!*entry)
			return false;
	}
	return true;
}

/* "a, b, c" into cfg's verdict sets; what says why not. 0 or -EINVAL (cfg untouched). */
static int parse_sets(struct hl_config *cfg, const char *value, char *what, size_t what_size)
{
	char ids[HL_CONFIG_MAX_SETS][HL_CONFIG_SET_ID];
	const char *p = value;
	int n = 0;

	while (*p == ' ' || *p == '\t')
		p++;
	while (*p) {
		const char *end = strchr(p, ','), *last;
		size_t len;

		if (!end)
			end = p + strlen(p);
		last = end;
		while (last > p && (last[-1] == ' ' || last[-1] == '\t'))
			last--;
		len = (size_t)(last - p);
		if (!valid_set_id(p, len)) {
			snprintf(what, what_size,
				 "'%.*s': expected set ids (letters, digits, . _ + -, at most %d "
				 "characters) separated by commas",
				 (int)(end - p), p, HL_CONFIG_SET_ID - 1);
			return -EINVAL;
		}
		if (n == HL_CONFIG_MAX_SETS) {
			snprintf(what, what_size,
				 "at most %d sets (one bit each in the frame header)",
				 HL_CONFIG_MAX_SETS);
			return -EINVAL;
		}
		memcpy(ids[n], p, len);
		ids[n][len] = '\0';
		for (int i = 0; i < n; i++)
			if (strcmp(ids[i], ids[n]) == 0) {
				snprintf(what, what_size, "'%.*s' is named twice", HL_CONFIG_SET_ID,
					 ids[n]);
				return -EINVAL;
			}
		n++;
		p = *end ? end + 1 : end;
		while (*p == ' ' || *p == '\t')
			p++;
		if (*end && !*p) {
			snprintf(what, what_size, "a set id after the last comma");
			return -EINVAL;
		}
	}
	memcpy(cfg->verdict_sets, ids, sizeof(ids[0]) * n);
	cfg->n_verdict_sets = n;
	return 0;
}

static int bad(struct hl_config_error *err, const char *origin, int line, const char *section,
	       const char *key, const char *what)
{
	if (err) {
		if (line > 0)
			snprintf(err->msg, sizeof(err->msg), "'%s':%d: key '%s.%s': %s", origin,
				 line, section, key, what);
		else
			snprintf(err->msg, sizeof(err->msg), "%s: key '%s.%s': %s", origin, section,
				 key, what);
	}
	return -EINVAL;
}

static int copy_string(char *dst, size_t size, const char *v)
{
	if (strlen(v) >= size)
		return -EINVAL;
	strcpy(dst, v);
	return 0;
}

int hl_config_set(struct hl_config *cfg, const char *section, const char *name, const char *value,
		  const char *origin, int line, struct hl_config_error *err)
{
	const struct key *k = NULL;
	char *at, *end, what[256];

	for (size_t i = 0; i < sizeof(keys) / sizeof(keys[0]); i++)
		if (strcmp(keys[i].section, section) == 0 && strcmp(keys[i].name, name) == 0)
			k = &keys[i];
	if (!k)
		return bad(err, origin, line, section, name,
			   "unknown key (see hdlampd --help-config)");
	at = (char *)cfg + k->offset;
	switch (k->kind) {
	case STRING:
	case EDGE:
		if (k->kind == EDGE && strcmp(value, "rising") != 0 &&
		    strcmp(value, "falling") != 0 && strcmp(value, "both") != 0)
			return bad(err, origin, line, section, name,
				   "expected rising, falling or both");
		if (copy_string(at, HL_CONFIG_NAME, value) < 0)
			return bad(err, origin, line, section, name, "too long");
		return 0;
	case PATH:
		if (copy_string(at, HL_CONFIG_PATH, value) < 0)
			return bad(err, origin, line, section, name, "path too long");
		return 0;
	case BACKEND:
		if (strcmp(value, "auto") != 0 && strcmp(value, "cpu") != 0 &&
		    strcmp(value, "gles") != 0)
			return bad(err, origin, line, section, name, "expected auto, cpu or gles");
		strcpy(at, value);
		return 0;
	case BOOL:
		if (strcmp(value, "true") == 0 || strcmp(value, "yes") == 0 ||
		    strcmp(value, "1") == 0)
			*(bool *)at = true;
		else if (strcmp(value, "false") == 0 || strcmp(value, "no") == 0 ||
			 strcmp(value, "0") == 0)
			*(bool *)at = false;
		else
			return bad(err, origin, line, section, name, "expected true or false");
		return 0;
	case INT: {
		long v = strtol(value, &end, 10);

		if (!*value || *end || v < k->min || v > k->max) {
			snprintf(what, sizeof(what), "'%s': expected an integer %.0f..%.0f", value,
				 k->min, k->max);
			return bad(err, origin, line, section, name, what);
		}
		*(int *)at = (int)v;
		return 0;
	}
	case DOUBLE: {
		double v = strtod(value, &end);

		if (!*value || *end || !isfinite(v) || v < k->min || v > k->max) {
			snprintf(what, sizeof(what), "'%s': expected a number %g..%g", value,
				 k->min, k->max);
			return bad(err, origin, line, section, name, what);
		}
		*(double *)at = v;
		return 0;
	}
	case SIZE: {
		long w = strtol(value, &end, 10), h;

		if (*end != 'x' || w < 16 || w > 8192)
			return bad(err, origin, line, section, name, "expected WxH, each 16..8192");
		h = strtol(end + 1, &end, 10);
		if (*end || h < 16 || h > 8192)
			return bad(err, origin, line, section, name, "expected WxH, each 16..8192");
		cfg->width = (int)w;
		cfg->height = (int)h;
		return 0;
	}
	case FAILSAFE:
		if (strcmp(value, "hold") == 0) {
			cfg->failsafe = HL_FAILSAFE_HOLD;
		} else if (strcmp(value, "dark") == 0) {
			cfg->failsafe = HL_FAILSAFE_DARK;
		} else if (strncmp(value, "preset:", 7) == 0 && value[7] &&
			   copy_string(cfg->failsafe_preset, HL_CONFIG_NAME, value + 7) == 0) {
			cfg->failsafe = HL_FAILSAFE_PRESET;
		} else {
			return bad(err, origin, line, section, name,
				   "expected hold, dark or preset:NAME");
		}
		return 0;
	case SETS:
		if (parse_sets(cfg, value, what, sizeof(what)) < 0)
			return bad(err, origin, line, section, name, what);
		return 0;
	case MODES:
		if (!valid_modes(value))
			return bad(err, origin, line, section, name,
				   "expected MODE:ID+ID,MODE:ID,... (a mode's sets joined by +, "
				   "no spaces)");
		if (copy_string(at, HL_CONFIG_PATH, value) < 0)
			return bad(err, origin, line, section, name, "too long");
		return 0;
	case TRAFFIC:
		if (strcmp(value, "right") != 0 && strcmp(value, "left") != 0)
			return bad(err, origin, line, section, name, "expected right or left");
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
		    !(v[1] >= k->min && v[1] <= k->max)) {
			snprintf(what, sizeof(what), "'%s': expected two numbers %g..%g, as A,B",
				 value, k->min, k->max);
			return bad(err, origin, line, section, name, what);
		}
		memcpy(at, v, sizeof(v));
		return 0;
	}
	}
	return -EINVAL;
}

struct load_ctx {
	struct hl_config *cfg;
	int rc;
	char section[64], name[64], value[HL_CONFIG_PATH]; /* the first bad key */
};

/* inih (as Debian builds it) gives no line number to the handler; ini_parse_file returns the
 * line of the first key the handler refused, and the message is made again with it. */
static int on_pair(void *user, const char *section, const char *name, const char *value)
{
	struct load_ctx *c = user;

	if (c->rc < 0)
		return 0;
	c->rc = hl_config_set(c->cfg, section, name, value, "", 0, NULL);
	if (c->rc < 0) {
		snprintf(c->section, sizeof(c->section), "%s", section);
		snprintf(c->name, sizeof(c->name), "%s", name);
		snprintf(c->value, sizeof(c->value), "%s", value);
	}
	return c->rc == 0;
}

/* The line of key name under [section] (inih's syntax: whitespace, '=' or ':'), 0 if none. */
static int key_line(FILE *f, const char *section, const char *name)
{
	char buf[1024], cur[64] = "";
	int line = 0;

	rewind(f);
	while (fgets(buf, sizeof(buf), f)) {
		char *p = buf, *end;
		size_t n;

		line++;
		while (*p == ' ' || *p == '\t')
			p++;
		if (*p == '[' && (end = strchr(p, ']'))) {
			n = (size_t)(end - p - 1);
			snprintf(cur, sizeof(cur), "%.*s",
				 (int)(n < sizeof(cur) ? n : sizeof(cur) - 1), p + 1);
			continue;
		}
		n = strlen(name);
		if (strcmp(cur, section) == 0 && strncmp(p, name, n) == 0 &&
		    strspn(p + n, " \t") + n < strlen(p) &&
		    strchr("=:", p[n + strspn(p + n, " \t")]))
			return line;
	}
	return 0;
}

int hl_config_load(struct hl_config *cfg, const char *path, struct hl_config_error *err)
{
	struct load_ctx c = { .cfg = cfg };
	FILE *f = fopen(path, "re");
	int line;

	if (!f) {
		int rc = -errno;

		if (err)
			snprintf(err->msg, sizeof(err->msg), "'%s': %s", path, strerror(errno));
		return rc;
	}
	{
		struct stat st;

		/* fopen() opens a directory and reading it yields nothing: refuse it */
		if (fstat(fileno(f), &st) == 0 && S_ISDIR(st.st_mode)) {
			fclose(f);
			if (err)
				snprintf(err->msg, sizeof(err->msg),
					 "'%s': a directory; expected an INI file", path);
			return -EINVAL;
		}
	}
	line = ini_parse_file(f, on_pair, &c);
	/* the first fault is either the refused key or a syntax error before it */
	if (c.rc < 0 && key_line(f, c.section, c.name) == line) {
		fclose(f);
		return hl_config_set(cfg, c.section, c.name, c.value, path, line, err);
	}
	fclose(f);
	if (line != 0 || c.rc < 0) {
		if (err)
			snprintf(err->msg, sizeof(err->msg),
				 "'%s':%d: expected [section], key = value, or a ; comment", path,
				 line);
		return -EINVAL;
	}
	return 0;
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

	if (!cfg->interface[0] == !cfg->replay[0])
		why = "exactly one of can.interface and can.replay is needed";
	else if ((cfg->replay_fast || cfg->replay_loop) && !cfg->replay[0])
		why = "can.replay_fast and can.replay_loop need can.replay";
	if (why && err)
		snprintf(err->msg, sizeof(err->msg), "%s", why);
	return why ? -EINVAL : 0;
}

void hl_config_print(const struct hl_config *cfg, void *file)
{
	FILE *f = file;
	const char *section = "";

	for (size_t i = 0; i < sizeof(keys) / sizeof(keys[0]); i++) {
		const struct key *k = &keys[i];
		const char *at = (const char *)cfg + k->offset;

		if (strcmp(section, k->section) != 0) {
			fprintf(f, "%s[%s]\n", i ? "\n" : "", k->section);
			section = k->section;
		}
		fprintf(f, "; %s\n%s = ", k->help, k->name);
		switch (k->kind) {
		case STRING:
		case PATH:
		case BACKEND:
		case EDGE:
		case MODES:
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
		case FAILSAFE:
			fprintf(f, "%s%s\n",
				cfg->failsafe == HL_FAILSAFE_HOLD ? "hold" :
				cfg->failsafe == HL_FAILSAFE_DARK ? "dark" :
								    "preset:",
				cfg->failsafe == HL_FAILSAFE_PRESET ? cfg->failsafe_preset : "");
			break;
		}
	}
}
