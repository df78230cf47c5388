/* SPDX-License-Identifier: MIT */
/*
 * hdlamp ecu: the reference virtual headlamp ECU (docs/ecu.md) - a reference for software in
 * the loop and CI, not a product. Its options, the databases, lamps and beams it loads, and the
 * lighting functions (ecu/lighting.h) it builds from them; tools/ecu_bus.c runs them on the bus.
 */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <net/if.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "can/assembler.h"
#include "can/inputs.h"
#include "ecu/beams.h"
#include "ecu/lighting.h"
#include "lamp/model.h"
#include "base/share_dir.h"
#include "tools/commands.h"
#include "tools/ecu_bus.h"
#include "tools/ecu_fmu_export.h"
#include "tools/json_out.h"
#include "tools/preset_arg.h"

#define DEFAULT_TIMEOUT_CYCLES 3 /* input cycles without a message before the fail-safe */
#define DEG (M_PI / 180.0)

struct opts {
	struct hl_ecu_bus_opts bus; /* the interface, the I/O faults, --cycles */
	const char *inputs_dbc, *dbc; /* NULL: the shipped ones */
	const char *lamps_dir, *lid[2];
	int n_lid;
	const char *low, *high; /* preset files or built-in names */
	const char *windows_out;
	const char *fmu_out; /* --fmu: write the FMU instead of running on a bus */
	struct hl_ecu_fmu_faults fmu_faults; /* --fault step-error=N, step-crash=N (--fmu only) */
	char inputs_dbc_path[4096]; /* the input database loaded */
	struct hl_ecu_config cfg;
	struct hl_ecu_mount mount[2];
	int timeout_ms; /* -1: DEFAULT_TIMEOUT_CYCLES of each input's cycle time */
};

/* What the command builds and the bus runs. */
struct ecu_parts {
	struct hl_assembler *a; /* the dimming database's encoder */
	struct hl_inputs_map *map;
	struct hl_inputs_decoder *dec;
	struct hl_ecu *e;
};

static void usage(FILE *f)
{
	fprintf(f,
		"usage: hdlamp ecu (--can IFACE | --fmu OUT.fmu) [--inputs-dbc FILE] [--dbc FILE]\n"
		"                  [--lamps DIR | --lid LEFT --lid RIGHT] [--low PRESET] [--high PRESET]\n"
		"                  [--camera X,Y,Z[,YAW,PITCH]] [--lamp-left X,Y,Z[,YAW,PITCH]]\n"
		"                  [--lamp-right X,Y,Z[,YAW,PITCH]] [--timeout-ms MS] [--margin-deg D]\n"
		"                  [--margin-m M]\n"
		"                  [--window-fraction F] [--auto-kmh V] [--min-confidence C] [--no-bend]\n"
		"                  [--fault NAME]... [--cycles N] [--windows FILE]\n"
		"\n"
		"The reference virtual headlamp ECU (docs/ecu.md; a reference, not a product): reads\n"
		"the vehicle state and the camera's objects from IFACE (the messages of --inputs-dbc,\n"
		"default the shipped hd84_inputs.dbc), runs low/high beam, auto and glare-free high\n"
		"beam, bend light and the fail-safe, and sends the lamps 'left' and 'right' of --dbc\n"
		"(default the shipped hd84.dbc) every 20 ms with E2E. Lamps: the built-in HD84 pair,\n"
		"DIR/hd84_left.lid.exr and _right, or two LID files; beams: the HD84 presets or\n"
		"--low/--high (preset files or built-in names).\n"
		"\n"
		"Positions in the vehicle frame (m; x forward, y left, z up; yaw left, pitch up, deg):\n"
		"camera default -1.8,0,1.3; lamps 0,0.7,0.65 and 0,-0.7,0.65 pitched -0.573.\n"
		"--timeout-ms: each input's timeout (default 3 of its GenMsgCycleTime); --margin-deg\n"
		"(0.5) around each object, and --margin-m (0.2) at its distance in H (mirrors);\n"
		"--window-fraction (0.05) of the high beam that makes a\n"
		"source's window; --auto-kmh (40) auto high beam speed; --min-confidence (0.5).\n"
		"\n"
		"--fault NAME: ignore-objects (sees no objects), no-failsafe (keeps the last inputs),\n"
		"late=MS (sends every cycle MS late), stuck-counter (the alive counter stops),\n"
		"bad-crc (every frame's CRC is wrong).\n"
		"--cycles N stops after N cycles; --windows FILE writes every source's window (JSON).\n"
		"Prints JSON lines: start, mode (each change), summary. SIGINT/SIGTERM end it.\n"
		"\n"
		"--fmu OUT.fmu writes the ECU so configured as an FMI 2.0 co-simulation FMU instead\n"
		"(docs/ecu.md, \"The ECU as an FMU\"); the bus faults do not apply to it; its own,\n"
		"for tests of an importer: step-error=N (the Nth fmi2DoStep returns fmi2Error),\n"
		"step-crash=N (the Nth fmi2DoStep crashes with a segmentation fault).\n");
}

static int bad(const char *opt, const char *arg, const char *expected)
{
	fprintf(stderr, "hdlamp ecu: %s '%s': expected %s\n", opt, arg, expected);
	return HL_EXIT_USAGE;
}

static int parse_num(const char *s, double lo, double hi, double *ret)
{
	char *end;
	double v;

	errno = 0;
	v = strtod(s, &end);
	if (errno || end == s || *end || !isfinite(v) || v < lo || v > hi)
		return -EINVAL;
	*ret = v;
	return 0;
}

/* X,Y,Z or X,Y,Z,YAW,PITCH */
static int parse_mount(const char *s, struct hl_ecu_mount *m)
{
	double v[5] = { 0 };
	int n = 0;
	const char *p = s;

	for (;;) {
		char *end;

		if (n == 5)
			return -EINVAL;
		errno = 0;
		v[n] = strtod(p, &end);
		if (errno || end == p || !isfinite(v[n]))
			return -EINVAL;
		n++;
		if (*end == '\0')
			break;
		if (*end != ',')
			return -EINVAL;
		p = end + 1;
	}
	if ((n != 3 && n != 5) || fabs(v[0]) > 30 || fabs(v[1]) > 5 || v[2] < 0 || v[2] > 5 ||
	    fabs(v[3]) > 90 || fabs(v[4]) > 30)
		return -EINVAL;
	*m = (struct hl_ecu_mount){ .pos_m = { v[0], v[1], v[2] },
				    .yaw_deg = v[3],
				    .pitch_deg = v[4] };
	return 0;
}

static int parse_fault(const char *s, struct opts *o)
{
	char *end;
	long ms;

	if (strcmp(s, "ignore-objects") == 0)
		o->cfg.faults |= HL_ECU_FAULT_IGNORE_OBJECTS;
	else if (strcmp(s, "no-failsafe") == 0)
		o->cfg.faults |= HL_ECU_FAULT_NO_FAILSAFE;
	else if (strcmp(s, "stuck-counter") == 0)
		o->bus.stuck_counter = true;
	else if (strcmp(s, "bad-crc") == 0)
		o->bus.bad_crc = true;
	else if (strncmp(s, "late=", 5) == 0) {
		errno = 0;
		ms = strtol(s + 5, &end, 10);
		if (errno || end == s + 5 || *end || ms < 1 || ms > HL_ECU_BUS_MAX_LATE_MS)
			return -EINVAL;
		o->bus.late_ms = (int)ms;
	} else if (strncmp(s, "step-error=", 11) == 0 || strncmp(s, "step-crash=", 11) == 0) {
		errno = 0;
		ms = strtol(s + 11, &end, 10);
		if (errno || end == s + 11 || *end || ms < 1 || ms > 1000000000)
			return -EINVAL;
		if (s[5] == 'e')
			o->fmu_faults.step_error = (int)ms;
		else
			o->fmu_faults.step_crash = (int)ms;
	} else
		return -EINVAL;
	return 0;
}

static int parse_args(int argc, char **argv, struct opts *o)
{
	static const struct option long_opts[] = {
		{ "can", required_argument, NULL, 'c' },
		{ "inputs-dbc", required_argument, NULL, 'I' },
		{ "dbc", required_argument, NULL, 'd' },
		{ "lamps", required_argument, NULL, 'L' },
		{ "lid", required_argument, NULL, 'l' },
		{ "low", required_argument, NULL, 'w' },
		{ "high", required_argument, NULL, 'H' },
		{ "camera", required_argument, NULL, 'C' },
		{ "lamp-left", required_argument, NULL, '0' },
		{ "lamp-right", required_argument, NULL, '1' },
		{ "timeout-ms", required_argument, NULL, 't' },
		{ "margin-deg", required_argument, NULL, 'm' },
		{ "margin-m", required_argument, NULL, 'M' },
		{ "window-fraction", required_argument, NULL, 'f' },
		{ "auto-kmh", required_argument, NULL, 'a' },
		{ "min-confidence", required_argument, NULL, 'k' },
		{ "no-bend", no_argument, NULL, 'B' },
		{ "fault", required_argument, NULL, 'F' },
		{ "cycles", required_argument, NULL, 'n' },
		{ "windows", required_argument, NULL, 'W' },
		{ "fmu", required_argument, NULL, 'U' },
		{ "help", no_argument, NULL, 'h' },
		{ 0 },
	};
	int c;
	double v;

	hl_ecu_config_default(&o->cfg);
	for (int s = 0; s < 2; s++)
		o->mount[s] = (struct hl_ecu_mount){ .pos_m = { 0.0, s == 0 ? 0.7 : -0.7, 0.65 },
						     .pitch_deg = atan(-0.01) / DEG };
	o->timeout_ms = -1;
	while ((c = getopt_long(argc, argv, "h", long_opts, NULL)) != -1) {
		switch (c) {
		case 'c':
			if (!*optarg || strlen(optarg) >= IFNAMSIZ)
				return bad("--can", optarg, "an interface name");
			o->bus.iface = optarg;
			break;
		case 'I':
			o->inputs_dbc = optarg;
			break;
		case 'd':
			o->dbc = optarg;
			break;
		case 'L':
			o->lamps_dir = optarg;
			break;
		case 'l':
			if (o->n_lid == 2)
				return bad("--lid", optarg, "two files: --lid LEFT --lid RIGHT");
			o->lid[o->n_lid++] = optarg;
			break;
		case 'w':
			o->low = optarg;
			break;
		case 'H':
			o->high = optarg;
			break;
		case 'C':
			if (parse_mount(optarg, &o->cfg.camera) < 0)
				return bad("--camera", optarg,
					   "X,Y,Z[,YAW,PITCH]: |X| <= 30, |Y| <= 5, Z in [0, 5] m, "
					   "|YAW| <= 90, |PITCH| <= 30 degrees");
			break;
		case '0':
		case '1':
			if (parse_mount(optarg, &o->mount[c - '0']) < 0)
				return bad(c == '0' ? "--lamp-left" : "--lamp-right", optarg,
					   "X,Y,Z[,YAW,PITCH]: |X| <= 30, |Y| <= 5, Z in [0, 5] m, "
					   "|YAW| <= 90, |PITCH| <= 30 degrees");
			break;
		case 't':
			if (parse_num(optarg, 1, 60000, &v) < 0 || v != floor(v))
				return bad("--timeout-ms", optarg, "an integer in [1, 60000]");
			o->timeout_ms = (int)v;
			break;
		case 'm':
			if (parse_num(optarg, 0, 45, &o->cfg.margin_deg) < 0)
				return bad("--margin-deg", optarg, "degrees in [0, 45]");
			break;
		case 'M':
			if (parse_num(optarg, 0, 5, &o->cfg.margin_m) < 0)
				return bad("--margin-m", optarg, "metres in [0, 5]");
			break;
		case 'f':
			if (parse_num(optarg, 0, 1, &v) < 0 || v == 0 || v == 1)
				return bad("--window-fraction", optarg, "a number in (0, 1)");
			o->cfg.window_fraction = v;
			break;
		case 'a':
			if (parse_num(optarg, 0, 360, &v) < 0)
				return bad("--auto-kmh", optarg, "km/h in [0, 360]");
			o->cfg.auto_high_mps = v / 3.6;
			break;
		case 'k':
			if (parse_num(optarg, 0, 1, &o->cfg.min_confidence) < 0)
				return bad("--min-confidence", optarg, "a number in [0, 1]");
			break;
		case 'B':
			o->cfg.bend = false;
			break;
		case 'F':
			if (parse_fault(optarg, o) < 0)
				return bad("--fault", optarg,
					   "ignore-objects, no-failsafe, late=MS (1..10000), "
					   "stuck-counter, bad-crc, or with --fmu step-error=N or "
					   "step-crash=N");
			break;
		case 'n':
			if (parse_num(optarg, 1, 1e12, &v) < 0 || v != floor(v))
				return bad("--cycles", optarg, "a positive integer");
			o->bus.cycles = (long long)v;
			break;
		case 'W':
			o->windows_out = optarg;
			break;
		case 'U':
			o->fmu_out = optarg;
			break;
		case 'h':
			usage(stdout);
			return -1;
		default:
			usage(stderr);
			return HL_EXIT_USAGE;
		}
	}
	if (optind < argc)
		return bad("argument", argv[optind], "options only");
	if (!o->bus.iface && !o->fmu_out) {
		fprintf(stderr, "hdlamp ecu: --can IFACE or --fmu OUT.fmu is required\n");
		return HL_EXIT_USAGE;
	}
	if (!o->fmu_out && (o->fmu_faults.step_error || o->fmu_faults.step_crash)) {
		fprintf(stderr, "hdlamp ecu: --fault step-error and step-crash are the FMU's: "
				"they need --fmu\n");
		return HL_EXIT_USAGE;
	}
	if (o->bus.iface && o->fmu_out) {
		fprintf(stderr, "hdlamp ecu: --can and --fmu exclude each other\n");
		return HL_EXIT_USAGE;
	}
	if (o->lamps_dir && o->n_lid) {
		fprintf(stderr, "hdlamp ecu: --lamps and --lid exclude each other\n");
		return HL_EXIT_USAGE;
	}
	if (o->n_lid == 1) {
		fprintf(stderr, "hdlamp ecu: --lid needs two files: --lid LEFT --lid RIGHT\n");
		return HL_EXIT_USAGE;
	}
	return 0;
}

/* The database of arg, else the shipped one; path (4096 bytes) gets the file's path. */
static int load_dbc(const char *arg, const char *shipped, struct hl_dbc **ret, char *path)
{
	struct hl_dbc_error err;
	int rc;

	if (arg) {
		snprintf(path, 4096, "%s", arg);
	} else {
		rc = hl_share_dir("dbc", path, 4096);
		if (rc < 0) {
			fprintf(stderr, "hdlamp ecu: cannot find the shipped databases: %s\n",
				strerror(-rc));
			return rc;
		}
		strncat(path, "/", 4096 - strlen(path) - 1);
		strncat(path, shipped, 4096 - strlen(path) - 1);
	}
	rc = hl_dbc_parse_file(path, ret, &err);
	if (rc < 0) {
		if (err.line > 0)
			fprintf(stderr, "hdlamp ecu: '%s':%d:%d: %s\n", path, err.line, err.column,
				err.msg);
		else
			fprintf(stderr, "hdlamp ecu: '%s': %s\n", path, err.msg);
	}
	return rc;
}

static int load_lamps(const struct opts *o, struct hl_lid *lids[2])
{
	for (int s = 0; s < 2; s++) {
		char path[4096];
		struct hl_lid_error err;
		int rc;

		if (!o->lamps_dir && !o->n_lid) {
			rc = hl_model_hd84(s, &lids[s]);
			if (rc < 0) {
				fprintf(stderr, "hdlamp ecu: the HD84 model: %s\n", strerror(-rc));
				return rc;
			}
			continue;
		}
		if (o->lamps_dir)
			snprintf(path, sizeof(path), "%s/hd84_%s.lid.exr", o->lamps_dir,
				 hl_side_name(s));
		else
			snprintf(path, sizeof(path), "%s", o->lid[s]);
		rc = hl_lid_read(path, &lids[s], &err);
		if (rc < 0) {
			fprintf(stderr, "hdlamp ecu: %s\n", err.msg);
			return rc;
		}
		if (hl_lid_is_combined(lids[s])) {
			fprintf(stderr,
				"hdlamp ecu: '%s': a combined distribution; expected a LID file of "
				"sources\n",
				path);
			return -EINVAL;
		}
	}
	return 0;
}

/* The beams: --low/--high (preset files or built-in names), else ecu/beams.h's defaults. */
static int load_beams(const struct opts *o, struct hl_lid *lids[2], float *low[2], float *high[2])
{
	for (int s = 0; s < 2; s++) {
		int rc = hl_ecu_beams_default(lids[s], s, o->cfg.window_fraction, low[s], high[s]);

		if (rc < 0) {
			fprintf(stderr, "hdlamp ecu: the beams of the %s lamp: %s\n",
				hl_side_name(s), strerror(-rc));
			return rc;
		}
	}
	for (int b = 0; b < 2; b++) {
		const char *arg = b == 0 ? o->low : o->high;
		struct hl_preset *p;
		int rc;

		if (!arg)
			continue;
		rc = hl_tool_preset_load("ecu", arg, lids, 2, &p);
		if (rc < 0)
			return rc;
		for (int s = 0; s < 2; s++)
			hl_preset_intensities(p, s, b == 0 ? low[s] : high[s]);
		hl_preset_free(p);
	}
	return 0;
}

static int write_windows(const char *path, const struct hl_ecu *e, struct hl_lid *lids[2])
{
	FILE *f = fopen(path, "we");

	if (!f) {
		fprintf(stderr, "hdlamp ecu: '%s': %s\n", path, strerror(errno));
		return -errno;
	}
	fprintf(f, "{");
	for (int s = 0; s < 2; s++) {
		const struct hl_ecu_window *w = hl_ecu_windows_of(e, s);

		fprintf(f, "%s\"%s\":[", s ? "," : "", hl_side_name(s));
		for (int k = 0; k < hl_lid_n_sources(lids[s]); k++) {
			fprintf(f, "%s", k ? "," : "");
			if (w[k].empty) {
				fprintf(f, "null");
				continue;
			}
			fprintf(f, "[");
			hl_tool_json_num(f, w[k].h0_deg);
			fprintf(f, ",");
			hl_tool_json_num(f, w[k].h1_deg);
			fprintf(f, ",");
			hl_tool_json_num(f, w[k].v0_deg);
			fprintf(f, ",");
			hl_tool_json_num(f, w[k].v1_deg);
			fprintf(f, "]");
		}
		fprintf(f, "]");
	}
	fprintf(f, "}\n");
	if (fclose(f) != 0) {
		fprintf(stderr, "hdlamp ecu: '%s': %s\n", path, strerror(errno));
		return -EIO;
	}
	return 0;
}

/* Each input's timeout: --timeout-ms, else DEFAULT_TIMEOUT_CYCLES of its message's cycle. */
static void set_timeouts(struct opts *o, const struct hl_inputs_map *map)
{
	for (int i = 0; i < hl_inputs_map_n_messages(map); i++) {
		const struct hl_inputs_message *m = hl_inputs_map_message(map, i);
		const int64_t cycle_ns = (int64_t)(m->cycle_ms ? m->cycle_ms : 20) * 1000000;
		const int64_t t = o->timeout_ms > 0 ? (int64_t)o->timeout_ms * 1000000 :
						      DEFAULT_TIMEOUT_CYCLES * cycle_ns;

		if (m->kind == HL_INPUTS_VEHICLE)
			o->cfg.vehicle_timeout_ns = t;
		else
			o->cfg.objects_timeout_ns = t;
	}
}

static int prepare(struct opts *o, struct ecu_parts *r, struct hl_dbc *dim_db, struct hl_dbc *in_db,
		   struct hl_lid *lids[2], float *beams)
{
	static const char *const names[2] = { "left", "right" };
	struct hl_asm_error aerr = { { 0 } };
	char msg[512] = "";
	float *low[2], *high[2];
	struct hl_ecu_lamp lamps[2];
	const char *what = NULL;
	int rc;

	rc = hl_assembler_new(dim_db, names, 2, 1000, 0, &r->a, &aerr);
	if (rc < 0) {
		fprintf(stderr, "hdlamp ecu: the dimming database: %s\n", aerr.msg);
		return rc;
	}
	rc = hl_inputs_map_new(in_db, &r->map, msg, sizeof(msg));
	if (rc < 0) {
		fprintf(stderr, "hdlamp ecu: the input database: %s\n", msg);
		return rc;
	}
	rc = hl_inputs_decoder_new(r->map, &r->dec);
	if (rc < 0)
		return rc;
	set_timeouts(o, r->map);
	for (int s = 0; s < 2; s++) {
		if (hl_assembler_n_sources(r->a, s) != hl_lid_n_sources(lids[s])) {
			fprintf(stderr,
				"hdlamp ecu: the %s lamp has %d sources, the dimming database "
				"carries %d\n",
				names[s], hl_lid_n_sources(lids[s]),
				hl_assembler_n_sources(r->a, s));
			return -EINVAL;
		}
		low[s] = beams + (size_t)2 * s * HL_LID_MAX_SOURCES;
		high[s] = low[s] + HL_LID_MAX_SOURCES;
	}
	rc = load_beams(o, lids, low, high);
	if (rc < 0)
		return rc;
	for (int s = 0; s < 2; s++)
		lamps[s] = (struct hl_ecu_lamp){
			.lid = lids[s], .mount = o->mount[s], .low = low[s], .high = high[s]
		};
	rc = hl_ecu_new(&o->cfg, lamps, 2, &r->e, &what);
	if (rc < 0)
		fprintf(stderr, "hdlamp ecu: %s\n", what ? what : strerror(-rc));
	return rc;
}

/* --fmu: the ECU prepare() built, packed with what it was built from. */
static int export_fmu(const struct opts *o, const struct ecu_parts *r, struct hl_lid *lids[2],
		      const float *beams)
{
	struct hl_ecu_fmu_lamp lamps[2];
	char paths[2][4096];

	for (int s = 0; s < 2; s++) {
		const float *low = beams + (size_t)2 * s * HL_LID_MAX_SOURCES;

		lamps[s] = (struct hl_ecu_fmu_lamp){ .name = hl_side_name(s),
						     .lid = lids[s],
						     .mount = o->mount[s],
						     .low = low,
						     .high = low + HL_LID_MAX_SOURCES };
		if (o->lamps_dir) {
			snprintf(paths[s], sizeof(paths[s]), "%s/hd84_%s.lid.exr", o->lamps_dir,
				 hl_side_name(s));
			lamps[s].lid_path = paths[s];
		} else if (o->n_lid) {
			lamps[s].lid_path = o->lid[s];
		} else {
			lamps[s].builtin = s == 0 ? "hd84_left" : "hd84_right";
		}
	}
	return hl_ecu_fmu_export(o->fmu_out, &o->cfg, &o->fmu_faults, o->inputs_dbc_path, r->map,
				 lamps, 2);
}

int hl_cmd_ecu(int argc, char **argv)
{
	struct opts o = { 0 };
	struct ecu_parts r = { 0 };
	struct hl_dbc *dim_db = NULL, *in_db = NULL;
	struct hl_lid *lids[2] = { NULL, NULL };
	float *beams = NULL;
	char dim_path[4096];
	int rc = parse_args(argc, argv, &o), ret = HL_EXIT_FAIL;

	if (rc != 0)
		return rc < 0 ? HL_EXIT_OK : rc;
	beams = malloc(sizeof(float) * 4 * HL_LID_MAX_SOURCES);
	if (!beams || load_dbc(o.dbc, "hd84.dbc", &dim_db, dim_path) < 0 ||
	    load_dbc(o.inputs_dbc, "hd84_inputs.dbc", &in_db, o.inputs_dbc_path) < 0 ||
	    load_lamps(&o, lids) < 0 || prepare(&o, &r, dim_db, in_db, lids, beams) < 0)
		goto out;
	if (o.windows_out && write_windows(o.windows_out, r.e, lids) < 0)
		goto out;
	if (o.fmu_out) {
		if (export_fmu(&o, &r, lids, beams) == 0)
			ret = HL_EXIT_OK;
		goto out;
	}
	if (hl_ecu_bus_run(&o.bus, &o.cfg, r.a, r.map, r.dec, r.e) == 0)
		ret = HL_EXIT_OK;
out:
	hl_ecu_free(r.e);
	hl_inputs_decoder_free(r.dec);
	hl_inputs_map_free(r.map);
	hl_assembler_free(r.a);
	hl_lid_free(lids[0]);
	hl_lid_free(lids[1]);
	hl_dbc_free(dim_db);
	hl_dbc_free(in_db);
	free(beams);
	return ret;
}
