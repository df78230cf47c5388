/* SPDX-License-Identifier: MIT */
/*
 * hdlamp batch: thousands of runs as a plan of self-contained tasks that a scheduler distributes
 * (tools/batch.h, docs/scale.md): plan, run (one task by index, or all here), slurm, k8s, merge.
 */
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "tools/batch.h"

static void usage(FILE *f)
{
	fputs("usage: hdlamp batch plan SPEC.json --out PLAN.jsonl\n"
	      "       hdlamp batch run PLAN.jsonl --out DIR (--index N | --index env | --jobs J)\n"
	      "       hdlamp batch slurm PLAN.jsonl --out DIR [--max-parallel P] [--partition P]\n"
	      "       hdlamp batch k8s PLAN.jsonl [--out MANIFEST.yaml] [...]\n"
	      "       hdlamp batch merge DIR [--plan PLAN.jsonl] [--junit F] [--html F] [--json F]\n"
	      "A plan is a list of self-contained tasks (suite variants, SIL scenarios, recorded\n"
	      "drives, each with its ECU, fault or preset); a scheduler runs task N as\n"
	      "'hdlamp batch run PLAN --index N --out DIR' (Slurm job arrays, Kubernetes Indexed\n"
	      "Jobs); merge makes one JUnit, one dashboard and one JSON of all of them. Each verb's\n"
	      "--help says more (docs/scale.md).\n",
	      f);
}

int hl_cmd_batch(int argc, char **argv)
{
	static const struct {
		const char *verb;
		int (*fn)(int argc, char **argv);
	} verbs[] = {
		{ "plan", hl_batch_plan_cmd },	 { "run", hl_batch_run_cmd },
		{ "merge", hl_batch_merge_cmd }, { "slurm", hl_batch_slurm_cmd },
		{ "k8s", hl_batch_k8s_cmd },

	};

	if (argc < 2 || !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
		usage(argc < 2 ? stderr : stdout);
		return argc < 2 ? 2 : 0;
	}
	for (size_t i = 0; i < sizeof(verbs) / sizeof(verbs[0]); i++)
		if (!strcmp(argv[1], verbs[i].verb))
			return verbs[i].fn(argc - 1, argv + 1);
	fprintf(stderr, "hdlamp batch: unknown verb '%s' (plan, run, slurm, k8s, merge)\n",
		argv[1]);
	return 2;
}
