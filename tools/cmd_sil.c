/* SPDX-License-Identifier: MIT */
/*
 * hdlamp sil: software in the loop in virtual time (docs/sil.md, sil/sil.h): a scenario, the
 * restbus, the virtual bus, the ECU (the reference or an FMU) and hdlamp's verdicts in one
 * process, as fast as the CPU allows, the same bits every run.
 */
#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "commands.h"
#include "base/make_dirs.h"
#include "daemon/core/config.h"
#include "ecu/node.h"
#include "sil/sil.h"
#include "tools/sil_args.h"

static void usage(FILE *f)
{
	fputs("usage: hdlamp sil SCENARIO [--ecu reference|FILE.fmu] [--fault F]... [--report FILE]\n"
	      "                  [--junit FILE] [--trace FILE.log|FILE.blf] [--config FILE]\n"
	      "                  [--set SECTION.KEY=VALUE]... [--bitrate BIT/S] [--data-bitrate BIT/S]\n"
	      "                  [--timeout-ms MS] [--frames DIR]\n"
	      "Runs SCENARIO in virtual time: the restbus, a virtual CAN bus, the ECU and the verdicts\n"
	      "in one process. --ecu: the reference ECU (default) or an FMI 2.0 co-simulation FMU;\n"
	      "--fault (reference ECU; late/stuck-counter/bad-crc for either): ignore-objects,\n"
	      "no-failsafe, late=MS, stuck-counter, bad-crc. --config and --set: hdlampd's keys (lamps,\n"
	      "can.dbc, restbus.*, verdict.*, scene.glare_set, loop.reaction_ms, render.* for\n"
	      "--frames). --frames: every judged frame also rendered as hdlampd's live view shows it,\n"
	      "to DIR/frame-NNNNNN.png (NNNNNN its seq; DIR is created if missing).\n"
	      "Exit: 0 the verdict held, 3 it failed, 2 bad input, 1 the run could not go on.\n",
	      f);
}

static int bad(const char *opt, const char *arg, const char *expected)
{
	fprintf(stderr, "hdlamp sil: %s '%s': expected %s\n", opt, arg, expected);
	return 2;
}

static int parse_uint(const char *s, unsigned long lo, unsigned long hi, unsigned long *ret)
{
	char *end;

	errno = 0;
	*ret = strtoul(s, &end, 10);
	return errno || end == s || *end || *ret < lo || *ret > hi ? -EINVAL : 0;
}

int hl_cmd_sil(int argc, char **argv)
{
	static const struct option long_opts[] = {
		{ "ecu", required_argument, NULL, 'e' },
		{ "fault", required_argument, NULL, 'f' },
		{ "report", required_argument, NULL, 'r' },
		{ "junit", required_argument, NULL, 'j' },
		{ "trace", required_argument, NULL, 't' },
		{ "config", required_argument, NULL, 'c' },
		{ "set", required_argument, NULL, 's' },
		{ "bitrate", required_argument, NULL, 'b' },
		{ "data-bitrate", required_argument, NULL, 'd' },
		{ "timeout-ms", required_argument, NULL, 'T' },
		{ "frames", required_argument, NULL, 'F' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	struct hl_config *cfg = calloc(1, sizeof(*cfg));
	struct hl_sil_options o = { .ecu = "reference", .log = stderr };
	struct hl_config_error cerr;
	unsigned long v;
	int c, rc;

	if (!cfg)
		return 1;
	if (hl_tool_sil_config("sil", argc, argv, cfg, &o)) {
		free(cfg);
		return 2;
	}
	rc = 0;
	while (rc == 0 && (c = getopt_long(argc, argv, "h", long_opts, NULL)) != -1) {
		switch (c) {
		case 'e':
			o.ecu = optarg;
			break;
		case 'f':
			if (hl_tool_sil_fault(optarg, &o) < 0)
				rc = bad("--fault", optarg, HL_ECU_NODE_FAULTS);
			break;
		case 'r':
			o.report = optarg;
			break;
		case 'j':
			o.junit = optarg;
			break;
		case 't':
			o.trace = optarg;
			break;
		case 'F':
			o.frames = optarg;
			break;
		case 'c':
			break;
		case 's':
			if (hl_config_set_arg(cfg, optarg, "--set", &cerr) < 0) {
				fprintf(stderr, "hdlamp sil: %s\n", cerr.msg);
				rc = 2;
			}
			break;
		case 'b':
		case 'd':
			if (parse_uint(optarg, 10000, 16000000, &v) < 0)
				rc = bad(c == 'b' ? "--bitrate" : "--data-bitrate", optarg,
					 "bit/s from 10000 to 16000000");
			else if (c == 'b')
				o.bitrate = (uint32_t)v;
			else
				o.data_bitrate = (uint32_t)v;
			break;
		case 'T':
			if (parse_uint(optarg, 1, 60000, &v) < 0) {
				rc = bad("--timeout-ms", optarg, "1..60000");
			} else {
				o.ref.vehicle_timeout_ns = o.ref.objects_timeout_ns =
					(int64_t)v * 1000000;
				o.ref_timeouts_set = true;
			}
			break;
		case 'h':
			usage(stdout);
			free(cfg);
			return 0;
		default:
			usage(stderr);
			rc = 2;
		}
	}
	if (rc == 0 && optind != argc - 1) {
		usage(stderr);
		rc = 2;
	}
	if (rc == 0) {
		/* no can.interface, no can.replay: the bus is the virtual one (the files the
		 * keys name are checked as they are loaded) */
		snprintf(cfg->scenario, sizeof(cfg->scenario), "%s", argv[optind]);
	}
	if (rc == 0 && o.frames) {
		const int mk = hl_make_dirs(o.frames);

		if (mk < 0) {
			fprintf(stderr,
				"hdlamp sil: --frames '%s': cannot make the directory: %s\n",
				o.frames, strerror(-mk));
			rc = 2;
		}
	}
	if (rc == 0) {
		o.cfg = cfg;
		rc = hl_sil_run(&o);
	}
	free(cfg);
	return rc;
}
