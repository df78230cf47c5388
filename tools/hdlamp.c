/* SPDX-License-Identifier: MIT */
/* hdlamp: the command-line tool (lamp models, LID files, ...); one subcommand per file. */
#include <stdio.h>
#include <string.h>

#include "tools/commands.h"

struct command {
	const char *name;
	int (*run)(int argc, char **argv);
	const char *summary;
};

static const struct command commands[] = {
	{ "model", hl_cmd_model, "generate the HD84 lamp pair and its presets, or a pixel lamp" },
	{ "lid", hl_cmd_lid, "inspect, combine, plot, import and export LID files" },
	{ "dbc", hl_cmd_dbc, "show CAN databases, decode candump logs, encode frames" },
	{ "scenario", hl_cmd_scenario,
	  "write the drive as a candump log; check and write scenario files" },
	{ "render", hl_cmd_render, "render a still of a scene lit by the lamps (PNG or EXR)" },
	{ "glare", hl_cmd_glare, "the light at road users' eyes in a scenario and its limit" },
	{ "ecu", hl_cmd_ecu, "the reference virtual headlamp ECU on a CAN interface" },
	{ "sil", hl_cmd_sil, "the loop in virtual time: restbus, virtual bus, ECU, verdicts" },
	{ "suite", hl_cmd_suite, "the ADB lab's test suites: FMVSS 108 ADB, IIHS, R149 ADB" },
	{ "batch", hl_cmd_batch,
	  "thousands of runs: plan, run by index, Slurm arrays, Kubernetes Indexed Jobs, merge" },
};

static void usage(FILE *f)
{
	fprintf(f, "usage: hdlamp COMMAND [ARGS...]\n\ncommands:\n");
	for (size_t i = 0; i < sizeof(commands) / sizeof(commands[0]); i++)
		fprintf(f, "  %-8s %s\n", commands[i].name, commands[i].summary);
	fprintf(f, "\n'hdlamp COMMAND --help' describes a command.\n");
}

int main(int argc, char **argv)
{
	if (argc < 2) {
		usage(stderr);
		return HL_EXIT_USAGE;
	}
	if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
		usage(stdout);
		return HL_EXIT_OK;
	}
	for (size_t i = 0; i < sizeof(commands) / sizeof(commands[0]); i++)
		if (strcmp(argv[1], commands[i].name) == 0)
			return commands[i].run(argc - 1, argv + 1);
	fprintf(stderr, "hdlamp: unknown command '%s'\n", argv[1]);
	usage(stderr);
	return HL_EXIT_USAGE;
}
