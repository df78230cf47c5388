/* SPDX-License-Identifier: MIT */
/*
 * hdlamp batch (docs/scale.md, tools/batch.h): the usage and the dispatch to the verbs; each
 * verb is a file of its own (tools/batch_*.c).
 */
#include <stdio.h>
#include <string.h>

#include "tools/batch.h"
#include "tools/commands.h"

struct verb {
	const char *name;
	int (*run)(int argc, char **argv);
};

static const struct verb verbs[] = {
	{ "k8s", hl_batch_k8s_cmd },
};

static void usage(FILE *f)
{
	fputs("usage: hdlamp batch k8s PLAN.jsonl [--out MANIFEST.yaml] [--name NAME] [--image IMAGE]\n"
	      "                        [--parallelism P] [--backoff-limit-per-index B]\n"
	      "                        [--max-failed-indexes M] [--results-claim PVC]\n"
	      "                        [--plan-configmap NAME] [--cpu C] [--memory M]\n"
	      "                        [--active-deadline-s S]\n"
	      "Many runs as a plan of tasks that a scheduler runs by index. 'hdlamp batch VERB --help'\n"
	      "describes a verb.\n"
	      "k8s  a Kubernetes Indexed Job running the plan's tasks, one pod per task\n",
	      f);
}

int hl_cmd_batch(int argc, char **argv)
{
	if (argc < 2) {
		usage(stderr);
		return HL_EXIT_USAGE;
	}
	if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
		usage(stdout);
		return HL_EXIT_OK;
	}
	for (size_t i = 0; i < sizeof(verbs) / sizeof(verbs[0]); i++)
		if (strcmp(argv[1], verbs[i].name) == 0)
			return verbs[i].run(argc - 1, argv + 1);
	fprintf(stderr, "hdlamp batch: unknown verb '%s'\n", argv[1]);
	usage(stderr);
	return HL_EXIT_USAGE;
}
