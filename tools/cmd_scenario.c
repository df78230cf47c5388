/* SPDX-License-Identifier: MIT */
/*
 * hdlamp scenario: a drive as a candump -L log with correct E2E, for replay tests and demos
 * (the verbs validate and builtin, for scenario files, are in cmd_scenario_file.c).
 * HD84 lamps: low beam, high beam, a glare-free window sweeping across, bend left and right;
 * pixel lamps (hdlamp model --sources N, tools/pixel_drive.h): a moving glare-free window, a
 * sweeping bar and a ramp, a new pattern every cycle. Then the same injected faults (one CRC
 * error, one missing page, one counter jump, 300 ms of silence) and N cycles more. --expect
 * writes what a correct receiver must report: every complete cycle of each lamp (counter and
 * raw dimming values) and the fault counters.
 */
#include <errno.h>
#include <getopt.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "can/assembler.h"
#include "can/candump.h"
#include "tools/commands.h"
#include "lamp/model.h"
#include "tools/pixel_drive.h"

#define CYCLE_US 20000 /* ECU period, 50 Hz */
#define FRAME_GAP_US 400 /* between frames of one cycle on the bus */
#define SILENCE_US 300000

enum fault {
	FAULT_NONE,
	FAULT_CRC, /* one frame's payload corrupted after protection */
	FAULT_MISSING, /* one frame never sent */
	FAULT_JUMP, /* the counter skips two values */
};

enum drive {
	DRIVE_AUTO, /* hd84 for 95 sources per lamp, else pixel */
	DRIVE_HD84,
	DRIVE_PIXEL,
};

struct gen {
	struct hl_assembler *a;
	FILE *log, *expect;
	const char *iface;
	int64_t t_us;
	unsigned counter[2];
	uint64_t cycles[2];
	float *i; /* one lamp's intensities */
	int64_t mode[2]; /* each lamp's HdlBeamMode value to send, -1: none (left 0) */
	bool mode_given; /* --mode: no phase changes it */
	struct hl_encoded_frame frames[2][HL_ASM_MAX_PARTS];
};

/*
 * Each lamp's HdlBeamMode value named name (the phase's beam: low, high, glarefree, unset), -1
 * when its DBC has no mode signal or no value of that name (the bits are left 0). --mode wins.
 */
static void phase_mode(struct gen *g, const char *name)
{
	for (int l = 0; l < 2 && !g->mode_given; l++)
		if (hl_assembler_mode_value(g->a, l, name, &g->mode[l]) < 0)
			g->mode[l] = -1;
}

/* Sets the values of cycle c of a section of n cycles (the fault section's patterns). */
typedef int (*fill_fn)(const void *ud, int c, int n, struct hl_preset *p);

static void usage(FILE *f)
{
	fprintf(f,
		"usage: hdlamp scenario --dbc FILE --out LOG [--expect FILE] [--iface NAME]\n"
		"                       [--phase-cycles N] [--start SECONDS] [--drive hd84|pixel]\n"
		"                       [--hold PRESET [--mode NAME]]\n"
		"       hdlamp scenario validate FILE...\n"
		"       hdlamp scenario builtin --list | NAME --out FILE\n"
		"       hdlamp scenario osi SCENARIO.json --out FILE.osi [--rate HZ]\n"
		"\n"
		"validate checks scenario files (road, ego vehicle, road users over time:\n"
		"docs/scenarios.md); builtin lists or writes the shipped ones. Without a verb:\n"
		"\n"
		"Writes a drive scenario for the lamps 'left' and 'right' of the DBC as a candump -L\n"
		"log. --drive hd84 (the default for 95 sources per lamp, the HD84 lamps): N cycles\n"
		"(default 25) each of low beam, high beam, 2N of a glare-free window sweeping\n"
		"H -20..+20, N bend left, N bend right. --drive pixel (the default for any other\n"
		"number of sources K, the lamps of 'hdlamp model --sources K'): 2N cycles of high\n"
		"beam with a glare-free window moving H -20..+20, 2N of low beam with a bright bar\n"
		"sweeping left to right, a new pattern every cycle. Then the faults - a CRC error\n"
		"(left), a missing page (right), a counter jump by 3 (left), 300 ms of silence - and\n"
		"N cycles more: HD84 low beam, or pixel values ramping through 0..63 (one step per\n"
		"cycle). --expect writes JSON lines: every complete cycle per lamp, then the expected\n"
		"counters.\n"
		"\n"
		"--hold PRESET writes N cycles of one preset instead, without faults: the name of an\n"
		"HD84 preset (low, high, glarefree, bend_left, bend_right) or a preset file\n"
		"NAME.json of the DBC's number of sources. --mode NAME sets the lamps' HdlBeamMode\n"
		"signal (if the DBC has one) to the value its VAL_ descriptions call NAME.\n"
		"\n"
		"When the DBC has an HdlBeamMode signal, every cycle says its beam by the value its\n"
		"VAL_ descriptions name (any case; 0 bits when there is none of that name): low,\n"
		"high, glarefree, bend_left and bend_right \"low\", the pixel drive's glare-free window\n"
		"\"glarefree\" and its bar \"low\", the pixel ramp \"unset\"; --hold a preset name\n"
		"without --mode says the preset's, a preset file nothing.\n");
}

static void write_frame(struct gen *g, const struct hl_encoded_frame *e)
{
	struct hl_candump_frame f = { .t_us = g->t_us, .fd = e->fd, .frame = e->frame };
	char line[HL_CANDUMP_MAX_LINE];

	snprintf(f.iface, sizeof(f.iface), "%s", g->iface);
	if (f.fd)
		f.frame.flags = CANFD_BRS;
	if (hl_candump_format(&f, line, sizeof(line)) > 0)
		fprintf(g->log, "%s\n", line);
}

/* One ECU period: both lamps' frames interleaved, with an optional fault on one lamp. */
static int cycle(struct gen *g, const struct hl_preset *p, int fault_lamp, enum fault fault)
{
	const int64_t t0 = g->t_us;
	int n[2];

	for (int l = 0; l < 2; l++) {
		const unsigned max = hl_assembler_counter_max(g->a, l);

		if (l == fault_lamp && fault == FAULT_JUMP)
			g->counter[l] = (g->counter[l] + 2) % (max + 1);
		hl_preset_intensities(p, l, g->i);
		n[l] = hl_assembler_encode_mode(g->a, l, g->i, g->counter[l], g->mode[l],
						g->frames[l], HL_ASM_MAX_PARTS);
		if (n[l] < 0)
			return n[l];
		if (l == fault_lamp && fault == FAULT_CRC)
			g->frames[l][n[l] > 3 ? 3 : 0].frame.data[5] ^= 0x04;
		if (l != fault_lamp || (fault != FAULT_CRC && fault != FAULT_MISSING)) {
			g->cycles[l]++;
			if (g->expect) {
				fprintf(g->expect, "{\"lamp\":\"%s\",\"counter\":%u,\"dims\":[",
					hl_assembler_lamp_name(g->a, l), g->counter[l]);
				for (int k = 0; k < p->n_sources; k++)
					fprintf(g->expect, "%s%u", k ? "," : "", p->dim[l][k]);
				fprintf(g->expect, "]}\n");
			}
		}
		g->counter[l] = (g->counter[l] + 1) % (max + 1);
	}
	for (int j = 0; j < n[0] || j < n[1]; j++) {
		for (int l = 0; l < 2; l++) {
			if (j >= n[l])
				continue;
			if (l == fault_lamp && fault == FAULT_MISSING && j == (n[l] > 7 ? 7 : 0))
				continue;
			write_frame(g, &g->frames[l][j]);
			g->t_us += FRAME_GAP_US;
		}
	}
	g->t_us = t0 + CYCLE_US;
	return 0;
}

/*
 * The end of every drive: a CRC error (left), a missing page (right), a counter jump by 3
 * (left), each followed by a good cycle, 300 ms of silence, then phase cycles; fill (NULL: p
 * stays) sets each cycle's values. Then the expected counters.
 */
static int faults(struct gen *g, struct hl_preset *p, int phase, fill_fn fill, const void *ud)
{
	static const struct {
		int lamp;
		enum fault fault;
	} seq[] = {
		{ 0, FAULT_CRC },   { -1, FAULT_NONE }, { 1, FAULT_MISSING },
		{ -1, FAULT_NONE }, { 0, FAULT_JUMP },	{ -1, FAULT_NONE },
	};
	const int n_faults = (int)(sizeof(seq) / sizeof(seq[0])), n = n_faults + phase;
	int rc = 0;

	for (int c = 0; c < n && rc == 0; c++) {
		if (fill)
			rc = fill(ud, c, n, p);
		if (c == n_faults)
			g->t_us += SILENCE_US;
		if (rc == 0)
			rc = c < n_faults ? cycle(g, p, seq[c].lamp, seq[c].fault) :
					    cycle(g, p, -1, FAULT_NONE);
	}
	if (rc == 0 && g->expect)
		fprintf(g->expect,
			"{\"expect\":\"counters\",\"silence_ms\":%d,"
			"\"left\":{\"cycles\":%" PRIu64 ",\"crc_errors\":1,\"incomplete\":1,"
			"\"lost_cycles\":2,\"stale_events\":1,\"recoveries\":1},"
			"\"right\":{\"cycles\":%" PRIu64 ",\"crc_errors\":0,\"incomplete\":1,"
			"\"lost_cycles\":0,\"stale_events\":1,\"recoveries\":1}}\n",
			SILENCE_US / 1000, g->cycles[0], g->cycles[1]);
	return rc;
}

static int run_hd84(struct gen *g, int phase)
{
	struct hl_lid *lamps[2] = { NULL, NULL };
	struct hl_preset *p = NULL;
	int rc;

	for (int s = 0; s < 2; s++) {
		rc = hl_model_hd84(s, &lamps[s]);
		if (rc < 0)
			goto out;
	}
	rc = hl_preset_new(HL_HD84_SOURCES, &p);
	if (rc < 0)
		goto out;
	hl_model_hd84_preset("low", lamps, p);
	phase_mode(g, "low");
	for (int c = 0; c < phase && rc == 0; c++)
		rc = cycle(g, p, -1, FAULT_NONE);
	hl_model_hd84_preset("high", lamps, p);
	phase_mode(g, "high");
	for (int c = 0; c < phase && rc == 0; c++)
		rc = cycle(g, p, -1, FAULT_NONE);
	phase_mode(g, "glarefree");
	for (int c = 0; c < 2 * phase && rc == 0; c++) {
		const float centre = -20.0f + 40.0f * c / (2 * phase - 1);

		hl_model_hd84_glarefree(lamps, centre - 2.0f, centre + 2.0f, p);
		rc = cycle(g, p, -1, FAULT_NONE);
	}
	hl_model_hd84_preset("bend_left", lamps, p); /* the low beam, swivelled */
	phase_mode(g, "low");
	for (int c = 0; c < phase && rc == 0; c++)
		rc = cycle(g, p, -1, FAULT_NONE);
	hl_model_hd84_preset("bend_right", lamps, p);
	for (int c = 0; c < phase && rc == 0; c++)
		rc = cycle(g, p, -1, FAULT_NONE);
	hl_model_hd84_preset("low", lamps, p);
	if (rc == 0)
		rc = faults(g, p, phase, NULL, NULL);
out:
	hl_preset_free(p);
	hl_lid_free(lamps[0]);
	hl_lid_free(lamps[1]);
	return rc;
}

/* --mode: each lamp's HdlBeamMode value named name; -ENOENT when no lamp has one by that name. */
static int set_mode(struct gen *g, const char *name)
{
	int found = -ENOENT;

	for (int l = 0; l < 2; l++)
		if (hl_assembler_mode_value(g->a, l, name, &g->mode[l]) == 0)
			found = 0;
	g->mode_given = found == 0;
	return found;
}

/* The beam an HD84 preset shows: a bend light is the low beam swivelled. */
static const char *preset_mode(const char *preset)
{
	return strncmp(preset, "bend_", 5) == 0 ? "low" : preset;
}

/* N cycles of one preset (a name of the HD84 model's, or a file), no faults. */
static int run_hold(struct gen *g, int phase, int n_src, const char *hold)
{
	struct hl_lid *lamps[2] = { NULL, NULL };
	struct hl_preset *p = NULL;
	struct hl_preset_error perr;
	int rc = -EINVAL;

	if (!strchr(hold, '/') && !strstr(hold, ".json")) {
		for (int k = 0; hl_model_preset_names[k]; k++)
			if (strcmp(hl_model_preset_names[k], hold) == 0)
				rc = 0;
		if (rc < 0 || n_src != HL_HD84_SOURCES) {
			fprintf(stderr,
				"hdlamp scenario: --hold '%s': expected an HD84 preset name (low, high, "
				"glarefree, bend_left, bend_right; 95 sources per lamp) or a preset file\n",
				hold);
			return -EINVAL;
		}
		for (int s = 0; s < 2 && rc == 0; s++)
			rc = hl_model_hd84(s, &lamps[s]);
		if (rc == 0)
			rc = hl_preset_new(HL_HD84_SOURCES, &p);
		if (rc == 0)
			rc = hl_model_hd84_preset(hold, lamps, p);
		phase_mode(g, preset_mode(hold));
	} else {
		rc = hl_preset_read(hold, &p, &perr);
		if (rc < 0) {
			fprintf(stderr, "hdlamp scenario: --hold '%s':%d:%d: %s\n", hold, perr.line,
				perr.column, perr.msg);
		} else if (p->n_sources != n_src) {
			fprintf(stderr,
				"hdlamp scenario: --hold '%s': %d values per lamp; the DBC's lamps have "
				"%d sources\n",
				hold, p->n_sources, n_src);
			rc = -EINVAL;
		}
	}
	for (int c = 0; c < phase && rc == 0; c++)
		rc = cycle(g, p, -1, FAULT_NONE);
	if (rc == 0 && g->expect)
		fprintf(g->expect,
			"{\"expect\":\"counters\",\"silence_ms\":0,"
			"\"left\":{\"cycles\":%" PRIu64 ",\"crc_errors\":0,\"incomplete\":0,"
			"\"lost_cycles\":0,\"stale_events\":0,\"recoveries\":0},"
			"\"right\":{\"cycles\":%" PRIu64 ",\"crc_errors\":0,\"incomplete\":0,"
			"\"lost_cycles\":0,\"stale_events\":0,\"recoveries\":0}}\n",
			g->cycles[0], g->cycles[1]);
	hl_preset_free(p);
	hl_lid_free(lamps[0]);
	hl_lid_free(lamps[1]);
	return rc;
}

static int pixel_ramp(const void *layout, int c, int n, struct hl_preset *p)
{
	return hl_pixel_drive(layout, HL_PIXEL_RAMP, c, n, p);
}

static int run_pixel(struct gen *g, int phase, int n_sources)
{
	static const enum hl_pixel_phase phases[] = { HL_PIXEL_GLAREFREE, HL_PIXEL_SWEEP };
	struct hl_pixel_layout layout;
	struct hl_preset *p = NULL;
	int rc;

	rc = hl_model_pixel_layout(n_sources, &layout);
	if (rc == 0)
		rc = hl_preset_new(n_sources, &p);
	for (size_t ph = 0; ph < sizeof(phases) / sizeof(phases[0]) && rc == 0; ph++) {
		/* a window in the high beam; a bar sweeping over the low beam */
		phase_mode(g, phases[ph] == HL_PIXEL_GLAREFREE ? "glarefree" : "low");
		for (int c = 0; c < 2 * phase && rc == 0; c++) {
			rc = hl_pixel_drive(&layout, phases[ph], c, 2 * phase, p);
			if (rc == 0)
				rc = cycle(g, p, -1, FAULT_NONE);
		}
	}
	phase_mode(g, "unset"); /* the ramp is no beam */
	if (rc == 0)
		rc = faults(g, p, phase, pixel_ramp, &layout);
	hl_preset_free(p);
	return rc;
}

int hl_cmd_scenario(int argc, char **argv)
{
	static const struct option opts[] = {
		{ "dbc", required_argument, NULL, 'd' },
		{ "out", required_argument, NULL, 'o' },
		{ "expect", required_argument, NULL, 'e' },
		{ "iface", required_argument, NULL, 'i' },
		{ "phase-cycles", required_argument, NULL, 'n' },
		{ "start", required_argument, NULL, 's' },
		{ "drive", required_argument, NULL, 'D' },
		{ "hold", required_argument, NULL, 'H' },
		{ "mode", required_argument, NULL, 'M' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	static const char *const names[2] = { "left", "right" };
	const char *dbc_path = NULL, *out = NULL, *expect = NULL, *hold = NULL, *mode = NULL;
	struct gen g = { .iface = "can0", .t_us = 1700000000000000LL, .mode = { -1, -1 } };
	struct hl_dbc *db = NULL;
	struct hl_dbc_error derr;
	struct hl_asm_error aerr;
	enum drive drive = DRIVE_AUTO;
	int phase = 25, c, n_src, rc = HL_EXIT_FAIL;
	char *end;

	if (argc > 1 && !strcmp(argv[1], "validate"))
		return hl_cmd_scenario_validate(argc - 1, argv + 1);
	if (argc > 1 && !strcmp(argv[1], "builtin"))
		return hl_cmd_scenario_builtin(argc - 1, argv + 1);
	if (argc > 1 && !strcmp(argv[1], "osi"))
		return hl_cmd_scenario_osi(argc - 1, argv + 1);
	optind = 1;
	while ((c = getopt_long(argc, argv, "d:o:e:i:n:s:D:H:M:h", opts, NULL)) != -1) {
		switch (c) {
		case 'd':
			dbc_path = optarg;
			break;
		case 'o':
			out = optarg;
			break;
		case 'e':
			expect = optarg;
			break;
		case 'i':
			g.iface = optarg;
			break;
		case 'n':
			phase = (int)strtol(optarg, &end, 10);
			if (*end || phase < 1 || phase > 10000) {
				fprintf(stderr,
					"hdlamp scenario: --phase-cycles '%s': expected 1..10000\n",
					optarg);
				return HL_EXIT_USAGE;
			}
			break;
		case 's':
			g.t_us = (int64_t)(strtod(optarg, &end) * 1e6);
			if (*end || g.t_us <= 0) {
				fprintf(stderr,
					"hdlamp scenario: --start '%s': expected seconds > 0\n",
					optarg);
				return HL_EXIT_USAGE;
			}
			break;
		case 'D':
			if (strcmp(optarg, "hd84") == 0) {
				drive = DRIVE_HD84;
			} else if (strcmp(optarg, "pixel") == 0) {
				drive = DRIVE_PIXEL;
			} else {
				fprintf(stderr,
					"hdlamp scenario: --drive '%s': expected hd84 or pixel\n",
					optarg);
				return HL_EXIT_USAGE;
			}
			break;
		case 'H':
			hold = optarg;
			break;
		case 'M':
			mode = optarg;
			break;
		case 'h':
			usage(stdout);
			return HL_EXIT_OK;
		default:
			usage(stderr);
			return HL_EXIT_USAGE;
		}
	}
	if (!dbc_path || !out || optind != argc || strlen(g.iface) >= IFNAMSIZ || (mode && !hold)) {
		usage(stderr);
		return HL_EXIT_USAGE;
	}
	if (hl_dbc_parse_file(dbc_path, &db, &derr) < 0) {
		fprintf(stderr, "hdlamp scenario: '%s':%d:%d: %s\n", dbc_path, derr.line,
			derr.column, derr.msg);
		return HL_EXIT_FAIL;
	}
	if (hl_assembler_new(db, names, 2, 100, 0, &g.a, &aerr) < 0) {
		fprintf(stderr, "hdlamp scenario: '%s': %s\n", dbc_path, aerr.msg);
		goto out;
	}
	if (mode && set_mode(&g, mode) < 0) {
		fprintf(stderr,
			"hdlamp scenario: --mode '%s': '%s' has no signal with HdlBeamMode whose "
			"VAL_ descriptions name it\n",
			mode, dbc_path);
		goto out;
	}
	n_src = hl_assembler_n_sources(g.a, 0);
	if (hl_assembler_n_sources(g.a, 1) != n_src) {
		fprintf(stderr,
			"hdlamp scenario: '%s': lamp 'left' has %d sources, 'right' %d; expected the same\n",
			dbc_path, n_src, hl_assembler_n_sources(g.a, 1));
		goto out;
	}
	if (drive == DRIVE_AUTO)
		drive = n_src == HL_HD84_SOURCES ? DRIVE_HD84 : DRIVE_PIXEL;
	if (drive == DRIVE_HD84 && n_src != HL_HD84_SOURCES) {
		fprintf(stderr,
			"hdlamp scenario: '%s': the HD84 drive needs 95 sources per lamp, not %d\n",
			dbc_path, n_src);
		goto out;
	}
	if (drive == DRIVE_PIXEL && n_src > HL_LID_MAX_SOURCES) {
		fprintf(stderr,
			"hdlamp scenario: '%s': %d sources per lamp; a pixel lamp has at most %d\n",
			dbc_path, n_src, HL_LID_MAX_SOURCES);
		goto out;
	}
	g.i = calloc(n_src, sizeof(float));
	if (!g.i) {
		fprintf(stderr, "hdlamp scenario: out of memory\n");
		goto out;
	}
	g.log = fopen(out, "we");
	if (!g.log || (expect && !(g.expect = fopen(expect, "we")))) {
		fprintf(stderr, "hdlamp scenario: cannot create '%s': %s\n", g.log ? expect : out,
			strerror(errno));
		goto out;
	}
	if (hold) {
		if (run_hold(&g, phase, n_src, hold) < 0)
			goto out; /* said why */
	} else if ((drive == DRIVE_HD84 ? run_hd84(&g, phase) : run_pixel(&g, phase, n_src)) < 0) {
		fprintf(stderr, "hdlamp scenario: '%s' cannot carry the presets\n", dbc_path);
		goto out;
	}
	rc = HL_EXIT_OK;
out:
	if (g.log && fclose(g.log) != 0)
		rc = HL_EXIT_FAIL;
	if (g.expect && fclose(g.expect) != 0)
		rc = HL_EXIT_FAIL;
	free(g.i);
	hl_assembler_free(g.a);
	hl_dbc_free(db);
	return rc;
}
