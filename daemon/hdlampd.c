/* SPDX-License-Identifier: MIT */
/*
 * hdlampd: the headlamp HIL daemon. This file reads the options and the configuration;
 * daemon/live.c wires and runs the daemon: rendering and serving frames, or with --no-render
 * decoding only and printing JSON lines.
 */
#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "can/assembler.h"
#include "daemon/core/config.h"
#include "daemon/live.h"
#include "daemon/live_suite.h"

#define MAX_OVERRIDES 128

struct options {
	struct hl_config cfg;
	const char *config_path;
	char *overrides[MAX_OVERRIDES]; /* SECTION.KEY=VALUE, in order; re-applied on reload */
	char *origins[MAX_OVERRIDES]; /* each one's option as given, for messages */
	int n_overrides;
	char *lamp_names[HL_ASM_MAX_LAMPS];
	int n_lamps;
	char lamps_buf[HL_CONFIG_NAME];
	unsigned ring_slots;
	bool no_render, print_cycles, print_config;
	struct hl_live_suite_options suite; /* --suite: suite.suite set */
};

static void usage(FILE *f)
{
	fprintf(f,
		"usage: hdlampd [--config FILE] [--set SECTION.KEY=VALUE ...] [options]\n"
		"\n"
		"  --config FILE      INI configuration (hdlampd.conf(5) lists every key; --print-config shows\n"
		"                     them with their values)\n"
		"  --set S.K=V        override one key (e.g. --set render.view=lux)\n"
		"  --can IFACE        = can.interface: a SocketCAN interface (CAN or CAN FD); waited\n"
		"                     for, and reopened when it goes down or disappears\n"
		"  --replay LOG       = can.replay: a candump -L log ('-' for stdin) with its timing\n"
		"  --fast, --loop     = can.replay_fast, can.replay_loop\n"
		"  --loop-passes N    = --loop and can.replay_passes: stop after N passes\n"
		"  --dbc FILE         = can.dbc (default dbc/hd84.dbc)\n"
		"                     loaded leniently, its irregularities printed as warnings;\n"
		"                     --set dbc.strict=true refuses them (docs/dbc-compat.md)\n"
		"  --lamps A,B        = can.lamps (default left,right)\n"
		"  --timeout-ms N     = can.timeout_ms (default 100)\n"
		"  --scenario FILE    = scene.scenario: a scenario (docs/scenarios.md); its clock runs\n"
		"                     on the replayed log's time (or the monotonic clock live), and\n"
		"                     every frame reports the glare at its road users' eyes\n"
		"  --world SPEC       = scene.world: the world from ASAM OSI (docs/osi.md): a trace\n"
		"                     osi:file:TRACE.osi or a simulator's osi:udp:HOST:PORT; with\n"
		"                     --scenario, it lends the ego's lamps and camera (and a road)\n"
		"  --pose udp:H:P     = pose.listen: poses from a driving simulator, one JSON object\n"
		"                     per datagram (needs --scenario)\n"
		"  --restbus IFACE    = restbus.interface: send the ECU's inputs (vehicle state,\n"
		"                     camera objects) from the scenario on IFACE (needs --scenario)\n"
		"  --ecu MODEL        = ecu.model: 'reference' or an FMI 2.0 FMU: the ECU in process on\n"
		"                     the virtual bus vbus0, which is then can.interface and\n"
		"                     restbus.interface (needs --scenario; no CAN interface at all)\n"
		"  --ecu-fault F      = ecu.faults (comma separated): ignore-objects, no-failsafe,\n"
		"                     late=MS, stuck-counter, bad-crc\n"
		"  --exit-at-end      = loop.exit_at_end: stop at the scenario's end (needs --scenario)\n"
		"  --report FILE      = loop.report: the run's JSON report at exit; the exit code is\n"
		"                     then 0 only when every verdict held, 3 when one failed\n"
		"  --junit FILE       = loop.junit: the run's verdicts as JUnit XML at exit\n"
		"  --loop-events FILE = loop.events: JSON lines per loop event ('-': stdout)\n"
		"  --suite NAME|FILE  run a test suite's variants one after the other in real time\n"
		"                     (docs/lab.md): each its own scenario with --exit-at-end,\n"
		"                     against --ecu MODEL or the ECU on --can IFACE --restbus IFACE;\n"
		"                     exit 0 every test held, 3 one failed\n"
		"  --suite-out DIR    where the suite's results go (default suite-NAME)\n"
		"  --suite-only ID    one scenario or variant of the suite\n"
		"  --ring-slots N     snapshots between CAN and render thread, a power of two (256)\n"
		"  --no-render        decode only: print to stdout instead of rendering\n"
		"  --print-cycles     with --no-render: one JSON line per complete lamp cycle\n"
		"  --print-config     print the resulting configuration and exit\n"
		"\n"
		"Live mode renders every new complete cycle and serves the frames (stream, HTTP);\n"
		"SIGHUP re-reads the configuration, SIGUSR1 writes a capture, SIGINT/SIGTERM stop\n"
		"(exit 0). --no-render prints JSON lines: cycles, status changes and a summary.\n");
}

/* One override: the key's assignment and the option it came from (for messages). */
static int add_override(struct options *o, const char *section_key, const char *value,
			const char *option, const char *arg)
{
	char *s = NULL, *origin = NULL;

	if (o->n_overrides == MAX_OVERRIDES ||
	    (section_key ? asprintf(&s, "%s=%s", section_key, value) : asprintf(&s, "%s", value)) <
		    0 ||
	    asprintf(&origin, "%s%s%s", option, arg ? " " : "", arg ? arg : "") < 0) {
		free(s);
		fprintf(stderr, "hdlampd: too many overrides\n");
		return -EINVAL;
	}
	o->overrides[o->n_overrides] = s;
	o->origins[o->n_overrides++] = origin;
	return 0;
}

static int parse_options(int argc, char **argv, struct options *o)
{
	static const struct option opts[] = {
		{ "suite", required_argument, NULL, 1000 },
		{ "suite-out", required_argument, NULL, 1001 },
		{ "suite-only", required_argument, NULL, 1002 },
		{ "config", required_argument, NULL, 'C' },
		{ "set", required_argument, NULL, 'S' },
		{ "can", required_argument, NULL, 'c' },
		{ "replay", required_argument, NULL, 'r' },
		{ "fast", no_argument, NULL, 'f' },
		{ "loop", no_argument, NULL, 'l' },
		{ "loop-passes", required_argument, NULL, 'N' },
		{ "dbc", required_argument, NULL, 'd' },
		{ "lamps", required_argument, NULL, 'L' },
		{ "timeout-ms", required_argument, NULL, 't' },
		{ "ring-slots", required_argument, NULL, 's' },
		{ "scenario", required_argument, NULL, 'A' },
		{ "pose", required_argument, NULL, 'O' },
		{ "world", required_argument, NULL, 'W' },
		{ "restbus", required_argument, NULL, 'B' },
		{ "ecu", required_argument, NULL, 'U' },
		{ "ecu-fault", required_argument, NULL, 'F' },
		{ "exit-at-end", no_argument, NULL, 'E' },
		{ "report", required_argument, NULL, 'R' },
		{ "junit", required_argument, NULL, 'J' },
		{ "loop-events", required_argument, NULL, 'V' },
		{ "no-render", no_argument, NULL, 'n' },
		{ "print-cycles", no_argument, NULL, 'p' },
		{ "print-config", no_argument, NULL, 'P' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	struct hl_config_error err;
	struct hl_config check; /* --suite: what each run will be, for the checks */
	const struct hl_config *checked = &o->cfg;
	char *end;
	long v;
	int c, rc = 0;

	*o = (struct options){ .ring_slots = 256 };
	hl_config_defaults(&o->cfg);
	while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1 && rc == 0) {
		switch (c) {
		case 'C':
			o->config_path = optarg;
			break;
		case 'S':
			rc = add_override(o, NULL, optarg, "--set", optarg);
			break;
		case 'c':
			rc = add_override(o, "can.interface", optarg, "--can", optarg);
			break;
		case 'r':
			rc = add_override(o, "can.replay", optarg, "--replay", optarg);
			break;
		case 'f':
			rc = add_override(o, "can.replay_fast", "true", "--fast", NULL);
			break;
		case 'l':
			rc = add_override(o, "can.replay_loop", "true", "--loop", NULL);
			break;
		case 'N':
			rc = add_override(o, "can.replay_loop", "true", "--loop-passes", optarg);
			if (rc == 0)
				rc = add_override(o, "can.replay_passes", optarg, "--loop-passes",
						  optarg);
			break;
		case 'd':
			rc = add_override(o, "can.dbc", optarg, "--dbc", optarg);
			break;
		case 'L':
			rc = add_override(o, "can.lamps", optarg, "--lamps", optarg);
			break;
		case 't':
			rc = add_override(o, "can.timeout_ms", optarg, "--timeout-ms", optarg);
			break;
		case 'A':
			rc = add_override(o, "scene.scenario", optarg, "--scenario", optarg);
			break;
		case 'O':
			rc = add_override(o, "pose.listen", optarg, "--pose", optarg);
			break;
		case 'W':
			rc = add_override(o, "scene.world", optarg, "--world", optarg);
			break;
		case 'B':
			rc = add_override(o, "restbus.interface", optarg, "--restbus", optarg);
			break;
		case 'U':
			rc = add_override(o, "ecu.model", optarg, "--ecu", optarg);
			break;
		case 'F':
			rc = add_override(o, "ecu.faults", optarg, "--ecu-fault", optarg);
			break;
		case 'E':
			rc = add_override(o, "loop.exit_at_end", "true", "--exit-at-end", NULL);
			break;
		case 'R':
			rc = add_override(o, "loop.report", optarg, "--report", optarg);
			break;
		case 'J':
			rc = add_override(o, "loop.junit", optarg, "--junit", optarg);
			break;
		case 'V':
			rc = add_override(o, "loop.events", optarg, "--loop-events", optarg);
			break;
		case 's':
			v = strtol(optarg, &end, 10);
			if (*end || v < 2 || v > 65536 || (v & (v - 1))) {
				fprintf(stderr,
					"hdlampd: --ring-slots '%s': expected a power of two 2..65536\n",
					optarg);
				return -EINVAL;
			}
			o->ring_slots = (unsigned)v;
			break;
		case 'n':
			o->no_render = true;
			break;
		case 1000:
			o->suite.suite = optarg;
			break;
		case 1001:
			o->suite.out = optarg;
			break;
		case 1002:
			o->suite.only = optarg;
			break;
		case 'p':
			o->print_cycles = true;
			break;
		case 'P':
			o->print_config = true;
			break;
		case 'h':
			usage(stdout);
			exit(0);
		default:
			usage(stderr);
			return -EINVAL;
		}
	}
	if (rc < 0)
		return rc;
	if (optind != argc) {
		fprintf(stderr, "hdlampd: unexpected argument '%s'\n", argv[optind]);
		return -EINVAL;
	}
	/* defaults, then the file, then the command line, whatever their order there */
	if (o->config_path) {
		rc = hl_config_load(&o->cfg, o->config_path, &err);
		for (int i = 0; i < err.n_warnings && i < HL_CONFIG_MAX_WARNINGS; i++)
			fprintf(stderr, "hdlampd: %s\n", err.warnings[i]);
		if (err.n_warnings > HL_CONFIG_MAX_WARNINGS)
			fprintf(stderr, "hdlampd: '%s': %d more keys set twice\n", o->config_path,
				err.n_warnings - HL_CONFIG_MAX_WARNINGS);
		if (rc < 0) {
			fprintf(stderr, "hdlampd: %s\n", err.msg);
			return -EINVAL;
		}
	}
	for (int i = 0; i < o->n_overrides; i++) {
		if (hl_config_set_arg(&o->cfg, o->overrides[i], o->origins[i], &err) < 0) {
			fprintf(stderr, "hdlampd: %s\n", err.msg);
			return -EINVAL;
		}
	}
	if (o->print_config)
		return 0;
	if ((o->suite.out || o->suite.only) && !o->suite.suite) {
		fprintf(stderr, "hdlampd: --suite-out and --suite-only go with --suite\n");
		return -EINVAL;
	}
	if (o->suite.suite) {
		const char *why =
			o->cfg.scenario[0]    ? "--scenario: the suite makes its own" :
			o->cfg.replay[0]      ? "--replay: a suite runs in real time" :
			o->cfg.pose_listen[0] ? "--pose: the suite's scenarios move" :
			o->cfg.world[0]	      ? "--world: the suite's scenarios are the world" :
			o->no_render	      ? "--no-render: the photometers need frames" :
			o->cfg.loop_report[0] ? "--report: each run's goes to DIR/runs" :
			o->cfg.loop_junit[0]  ? "--junit: the suite writes DIR/junit.xml" :
			!o->cfg.ecu_model[0] && !o->cfg.restbus_interface[0] ?
					       "give --ecu MODEL, or --restbus IFACE for the "
					       "ECU on --can IFACE" :
					       NULL;

		if (why) {
			fprintf(stderr, "hdlampd: --suite: not with %s\n", why);
			return -EINVAL;
		}
		/* the suite gives every run its scenario, and each run ends with it */
		check = o->cfg;
		snprintf(check.scenario, sizeof(check.scenario), "(the suite's)");
		check.loop_exit_at_end = true;
		checked = &check;
	}
	if (hl_config_check(checked, &err) < 0) {
		/* the input's check says how to give one */
		fprintf(stderr, "hdlampd: %s%s\n", err.msg,
			strncmp(err.msg, "exactly one", 11) == 0 ?
				" (--can IFACE or --replay LOG)" :
				"");
		return -EINVAL;
	}
	/* can.lamps' syntax is checked as it is set: 1..HL_ASM_MAX_LAMPS names */
	snprintf(o->lamps_buf, sizeof(o->lamps_buf), "%s", o->cfg.lamps);
	for (char *save = NULL, *tok = strtok_r(o->lamps_buf, ",", &save);
	     tok && o->n_lamps < HL_ASM_MAX_LAMPS; tok = strtok_r(NULL, ",", &save))
		o->lamp_names[o->n_lamps++] = tok;
	/* the files the keys name, before anything starts */
	if (hl_config_check_files(&o->cfg, !o->no_render, &err) < 0) {
		fprintf(stderr, "hdlampd: %s\n", err.msg);
		return -EINVAL;
	}
	return 0;
}

static void free_overrides(struct options *o)
{
	for (int i = 0; i < o->n_overrides; i++) {
		free(o->overrides[i]);
		free(o->origins[i]);
	}
	o->n_overrides = 0;
}

int main(int argc, char **argv)
{
	struct options o;
	int rc;

	setvbuf(stdout, NULL, _IOLBF, 0);
	rc = parse_options(argc, argv, &o);
	if (rc < 0) {
		free_overrides(&o);
		return 2; /* a usage or configuration error */
	}
	if (o.print_config) {
		hl_config_print(&o.cfg, stdout);
		rc = 0;
	} else {
		const struct hl_live_args args = {
			.config_path = o.config_path,
			.overrides = o.overrides,
			.n_overrides = o.n_overrides,
			.lamp_names = o.lamp_names,
			.n_lamps = o.n_lamps,
			.ring_slots = o.ring_slots,
			.render = !o.no_render,
			.print_cycles = o.print_cycles,
		};

		if (o.print_cycles && !o.no_render) {
			fprintf(stderr, "hdlampd: --print-cycles goes with --no-render\n");
			rc = 2;
		} else {
			rc = o.suite.suite ? hl_live_suite_run(&o.cfg, &args, &o.suite) :
					     hl_live_run(&o.cfg, &args);
		}
	}
	free_overrides(&o);
	return rc;
}
