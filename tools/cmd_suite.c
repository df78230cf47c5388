/* SPDX-License-Identifier: MIT */
/*
 * hdlamp suite: the ADB lab's test suites (docs/lab.md) — list the shipped ones, show one, run
 * one against a held preset or an ECU in the loop (tools/suite_run.h).
 */
#include <dirent.h>
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "commands.h"
#include "base/share_dir.h"
#include "daemon/core/config.h"
#include "ecu/node.h"
#include "tools/sil_args.h"
#include "tools/suite_run.h"
#include "verdict/suite.h"
#include "verdict/suite_scenario.h"

static void usage(FILE *f)
{
	fputs("usage: hdlamp suite list\n"
	      "       hdlamp suite show NAME|FILE.json\n"
	      "       hdlamp suite run NAME|FILE.json [--ecu reference|FILE.fmu | --preset NAME |\n"
	      "                        --can IFACE]\n"
	      "                        [--fault F]... [--only ID] [--samples N] [--out DIR]\n"
	      "                        [--config FILE] [--set SECTION.KEY=VALUE]...\n"
	      "Runs every scenario variant of a suite (the FMVSS 108 ADB track test, the IIHS\n"
	      "headlight track, the R149 ADB glare table; docs/lab.md) in virtual time with the ECU\n"
	      "in the loop (default: the reference ECU), or with a held preset of the lamps (low,\n"
	      "high, glarefree, bend_left, bend_right or a preset file; no ECU, no bus). --only: one\n"
	      "scenario or variant id; --samples N: N points of each speed and radius range (default\n"
	      "2: both ends). Writes DIR (default suite-NAME) /report.json, junit.xml, index.html,\n"
	      "plots/, scenarios/, traces/. --can IFACE: in real time against the ECU on IFACE\n"
	      "(hdlampd --suite NAME --can IFACE --restbus IFACE runs it, with --config and --set).\n"
	      "Exit: 0 every test held, 3 one failed, 2 bad input, 1 an output could not be written.\n",
	      f);
}

int hl_cli_suite_load(const char *prog, const char *arg, struct hl_suite **ret)
{
	char path[4096], buf[1024];
	struct hl_json_error err;
	size_t n = strlen(arg);
	int rc;

	if (strchr(arg, '/') || (n > 5 && !strcmp(arg + n - 5, ".json"))) {
		snprintf(path, sizeof(path), "%s", arg);
	} else {
		if (hl_suite_default_dir(path, sizeof(path) - 64) < 0) {
			fprintf(stderr,
				"%s: cannot find the shipped suites beside the binary; give a file\n",
				prog);
			return 2;
		}
		snprintf(path + strlen(path), 64 + 1, "/%.48s.json", arg);
	}
	rc = hl_suite_read(path, ret, &err);
	if (rc == -ENOENT && !strchr(arg, '/') && !(n > 5 && !strcmp(arg + n - 5, ".json"))) {
		fprintf(stderr, "%s: no suite named '%s' (hdlamp suite list shows them)\n", prog,
			arg);
		return 2;
	}
	if (rc < 0) {
		fprintf(stderr, "%s: %s\n", prog, hl_json_error_format(&err, buf, sizeof(buf)));
		return 2;
	}
	return 0;
}

static int cmd_list(void)
{
	char dir[4096];
	struct dirent **ents;
	int n;

	if (hl_suite_default_dir(dir, sizeof(dir)) < 0) {
		fprintf(stderr, "hdlamp suite: cannot find the shipped suites beside the binary\n");
		return 1;
	}
	n = scandir(dir, &ents, NULL, alphasort);
	if (n < 0) {
		fprintf(stderr, "hdlamp suite: '%s': %s\n", dir, strerror(errno));
		return 1;
	}
	for (int i = 0; i < n; i++) {
		const char *name = ents[i]->d_name;
		const size_t len = strlen(name);
		struct hl_suite *s;
		struct hl_json_error err;
		char path[4096 + 256], buf[1024];

		if (len > 5 && !strcmp(name + len - 5, ".json")) {
			snprintf(path, sizeof(path), "%s/%s", dir, name);
			if (hl_suite_read(path, &s, &err) == 0) {
				printf("%s\t%s\n", s->name, s->title);
				hl_suite_free(s);
			} else {
				fprintf(stderr, "hdlamp suite: %s\n",
					hl_json_error_format(&err, buf, sizeof(buf)));
			}
		}
		free(ents[i]);
	}
	free(ents);
	return 0;
}

static int cmd_show(const char *arg)
{
	struct hl_suite *s;
	int rc = hl_cli_suite_load("hdlamp suite", arg, &s);

	if (rc)
		return rc;
	printf("%s: %s\nprocedure %s\nsource: %s\n", s->name, s->title,
	       hl_suite_procedure_name(s->procedure), s->source);
	if (s->has_rounding)
		printf("rounding: %d decimal(s), %s (%s)\n", s->decimals,
		       s->rounding == HL_SUITE_HALF_EVEN ? "half to even" : "half up",
		       s->rounding_source);
	if (s->n_bins)
		printf("\nlimits (lx):\n");
	for (int i = 0; i < s->n_bins; i++) {
		const struct hl_suite_bin *b = &s->bin[i];

		if (isnan(b->max_lx))
			printf("  %-9s %6.1f-%6.1f m  none\n", hl_actor_role_name(b->role),
			       b->from_m, b->to_m);
		else
			printf("  %-9s %6.1f-%6.1f m  %g  (%s)\n", hl_actor_role_name(b->role),
			       b->from_m, b->to_m, b->max_lx, b->source);
	}
	if (s->n_photometers)
		printf("\nphotometers (stimulus vehicle's frame, m):\n");
	for (int i = 0; i < s->n_photometers; i++) {
		const struct hl_suite_photometer *p = &s->photometer[i];

		printf("  %s on the %s vehicle at (%g, %g, %g), normal (%g, %g, %g)\n", p->id,
		       hl_actor_role_name(p->role), p->pos_m[0], p->pos_m[1], p->pos_m[2],
		       p->normal[0], p->normal[1], p->normal[2]);
	}
	printf("\nscenarios and their variants (samples 2):\n");
	for (int i = 0; i < s->n_scenarios; i++) {
		const struct hl_suite_scenario *d = &s->scenario[i];

		printf("  %s: %s\n", d->id, d->title);
		for (int k = 0; k < hl_suite_variant_count(d, 2); k++) {
			double sp, rad;
			char id[96];

			hl_suite_variant_params(d, 2, k, &sp, &rad, id, sizeof(id));
			printf("    %s\n", id);
		}
	}
	if (s->n_defaults)
		printf("\ndocumented defaults (not found in the official text):\n");
	for (int i = 0; i < s->n_defaults; i++)
		printf("  %s: %s\n    %s\n", s->def[i].what, s->def[i].value, s->def[i].why);
	hl_suite_free(s);
	return 0;
}

/*
 * --can IFACE: hdlampd --suite in real time (daemon/live_suite.h), with this command's --config
 * and --set; hdlampd beside this binary (installed) or in the build tree's daemon/.
 */
int hl_cli_hdlampd_path(char *buf, size_t size)
{
	if (hl_exe_relative("hdlampd", buf, size) == 0 && access(buf, X_OK) == 0)
		return 0;
	if (hl_exe_relative("../daemon/hdlampd", buf, size) == 0 && access(buf, X_OK) == 0)
		return 0;
	return -ENOENT;
}

static int run_can(int argc, char **argv, const char *suite, const char *can, const char *out,
		   const char *only)
{
	char exe[4096];
	char *args[2 * 64 + 16];
	int n = 0;

	if (hl_cli_hdlampd_path(exe, sizeof(exe)) < 0) {
		fprintf(stderr, "hdlamp suite: --can: cannot find hdlampd beside hdlamp\n");
		return 1;
	}
	args[n++] = exe;
	args[n++] = "--suite";
	args[n++] = (char *)suite;
	args[n++] = "--can";
	args[n++] = (char *)can;
	args[n++] = "--restbus";
	args[n++] = (char *)can;
	if (out) {
		args[n++] = "--suite-out";
		args[n++] = (char *)out;
	}
	if (only) {
		args[n++] = "--suite-only";
		args[n++] = (char *)only;
	}
	for (int i = 1; i + 1 < argc && n < (int)(sizeof(args) / sizeof(args[0])) - 3; i++)
		if (!strcmp(argv[i], "--config") || !strcmp(argv[i], "--set")) {
			args[n++] = argv[i];
			args[n++] = argv[++i];
		}
	args[n] = NULL;
	fflush(NULL);
	execv(exe, args);
	fprintf(stderr, "hdlamp suite: --can: '%s': %s\n", exe, strerror(errno));
	return 1;
}

static int bad(const char *opt, const char *arg, const char *expected)
{
	fprintf(stderr, "hdlamp suite: %s '%s': expected %s\n", opt, arg, expected);
	return 2;
}

static int cmd_run(int argc, char **argv)
{
	static const struct option long_opts[] = {
		{ "ecu", required_argument, NULL, 'e' },
		{ "can", required_argument, NULL, 'C' },
		{ "preset", required_argument, NULL, 'p' },
		{ "fault", required_argument, NULL, 'f' },
		{ "only", required_argument, NULL, 'o' },
		{ "samples", required_argument, NULL, 'n' },
		{ "out", required_argument, NULL, 'O' },
		{ "config", required_argument, NULL, 'c' },
		{ "set", required_argument, NULL, 's' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	struct hl_config *cfg = calloc(1, sizeof(*cfg));
	struct hl_suite_run_options o = { .samples = 2, .log = stderr };
	struct hl_config_error cerr;
	struct hl_suite *s = NULL;
	char faults[256] = "", out[4096];
	const char *can = NULL;
	bool ecu_given = false;
	int c, rc = 0;

	if (!cfg)
		return 1;
	if (hl_tool_sil_config("suite", argc, argv, cfg, &o.sil)) {
		free(cfg);
		return 2;
	}
	optind = 1;
	while (rc == 0 && (c = getopt_long(argc, argv, "h", long_opts, NULL)) != -1) {
		switch (c) {
		case 'e':
			o.sil.ecu = optarg;
			ecu_given = true;
			break;
		case 'p':
			o.preset = optarg;
			break;
		case 'C':
			can = optarg;
			break;
		case 'f':
			if (hl_tool_sil_fault(optarg, &o.sil) < 0) {
				rc = bad("--fault", optarg, HL_ECU_NODE_FAULTS);
				break;
			}
			snprintf(faults + strlen(faults), sizeof(faults) - strlen(faults), "%s%s",
				 faults[0] ? "," : "", optarg);
			break;
		case 'o':
			o.only = optarg;
			break;
		case 'n': {
			char *end;
			const long v = strtol(optarg, &end, 10);

			if (end == optarg || *end || v < 2 || v > 50)
				rc = bad("--samples", optarg, "2..50");
			else
				o.samples = (int)v;
			break;
		}
		case 'O':
			o.out = optarg;
			break;
		case 'c':
			break;
		case 's':
			if (hl_config_set_arg(cfg, optarg, "--set", &cerr) < 0) {
				fprintf(stderr, "hdlamp suite: %s\n", cerr.msg);
				rc = 2;
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
	if (rc == 0 && o.preset && (ecu_given || faults[0])) {
		fprintf(stderr, "hdlamp suite: --preset holds a beam with no ECU: it takes neither "
				"--ecu nor --fault\n");
		rc = 2;
	}
	if (rc == 0 && can && (o.preset || ecu_given || faults[0] || o.samples != 2)) {
		fprintf(stderr,
			"hdlamp suite: --can runs the ECU on the interface in real time: not "
			"with --preset, --ecu, --fault or --samples\n");
		rc = 2;
	}
	if (rc == 0 && can) {
		free(cfg);
		return run_can(argc, argv, argv[optind], can, o.out, o.only);
	}
	if (rc == 0)
		rc = hl_cli_suite_load("hdlamp suite", argv[optind], &s);
	if (rc == 0) {
		if (!o.out) {
			snprintf(out, sizeof(out), "suite-%s", s->name);
			o.out = out;
		}
		o.suite = s;
		o.cfg = cfg;
		o.fault_text = faults;
		rc = hl_suite_run(&o);
	}
	hl_suite_free(s);
	free(cfg);
	return rc;
}

int hl_cmd_suite(int argc, char **argv)
{
	if (argc < 2 || !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
		usage(argc < 2 ? stderr : stdout);
		return argc < 2 ? 2 : 0;
	}
	for (int i = 2; i < argc; i++)
		if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
			usage(stdout);
			return 0;
		}
	if (!strcmp(argv[1], "list") && argc == 2)
		return cmd_list();
	if (!strcmp(argv[1], "show") && argc == 3)
		return cmd_show(argv[2]);
	if (!strcmp(argv[1], "run"))
		return cmd_run(argc - 1, argv + 1);
	usage(stderr);
	return 2;
}
