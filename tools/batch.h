/* SPDX-License-Identifier: MIT */
/*
 * hdlamp batch (docs/scale.md): the work of many runs as a plan of self-contained tasks that a
 * scheduler distributes (Slurm job arrays, Kubernetes Indexed Jobs) — hdlamp plans, runs one
 * task by its index, and merges the results. No scheduler of our own.
 *
 * The plan (PLAN.jsonl): a header line, then one line per task, in index order:
 *   {"plan": "hdlamp batch plan", "version": 1, "tasks": N, "spec": "/abs/SPEC.json"}
 *   {"index": 0, "id": "suite/fmvss108-adb/preceding-straight-60mph/reference/none",
 *    "kind": "suite", "suite": "fmvss108-adb", "variant": "preceding-straight-60mph",
 *    "ecu": "reference", "fault": "", "preset": "", "samples": 0,
 *    "config": "", "set": ["render.size=64x36", ...]}
 *   {"index": 1, "id": "sil/iihs-approach-straight/reference/late=100", "kind": "sil",
 *    "scenario": "/abs/scenarios/iihs-approach-straight.json", "ecu": "reference",
 *    "fault": "late=100", "config": "", "set": []}
 *   {"index": 2, "id": "drive/night-01", "kind": "drive", "log": "/abs/drives/night-01.log",
 *    "scenario": "/abs/drives/night-01.json", "config": "", "set": []}
 * Paths are absolute (resolved against the spec's folder when planned). The id is made from the
 * task's content, so the same spec gives the same ids; the index is its place in the plan.
 *
 * A task's results (hdlamp batch run --index N --out DIR): DIR/N/ holds what the run wrote
 * (report.json, junit.xml, index.html, plots/, traces/ ...), log.txt (its stdout and stderr),
 * started.json (host, pid, time) at its start and, written last and renamed into place,
 * result.json:
 *   {"result": "hdlamp batch task", "version": 1, "index": N, "id": "...", "kind": "suite",
 *    "suite": "...", "scenario": "...", "ecu": "...", "fault": "...", "preset": "...",
 *    "status": "passed" | "failed" | "error", "exit": 0, "signal": 0, "reason": "...",
 *    "host": "...", "started_unix": T, "duration_s": S,
 *    "tests": N, "failures": N, "errors": N,
 *    "worst": {"case": "...", "margin_lx": M} | null,
 *    "latency_ms": {"n": N, "p50": X, "p99": X, "max": X} | null}
 * A task is finished when result.json says exit 0 (passed), 3 (failed) or 2 (bad input: running
 * it again cannot help); a task without a result, or ended by a signal or a runtime error
 * (exit 1), is run again by a re-submission.
 */
#ifndef HL_TOOLS_BATCH_H
#define HL_TOOLS_BATCH_H

#include <stdbool.h>
#include <stdio.h>

#define HL_BATCH_ID_MAX 512

/* hdlamp batch plan SPEC.json --out PLAN.jsonl (tools/batch_plan.c). */
int hl_batch_plan_cmd(int argc, char **argv);
/* hdlamp batch run PLAN.jsonl (--index N | --jobs J) --out DIR (tools/batch_run.c). */
int hl_batch_run_cmd(int argc, char **argv);
/* hdlamp batch merge DIR [--plan PLAN] --junit F --html F --json F (tools/batch_merge.c). */
int hl_batch_merge_cmd(int argc, char **argv);
/* hdlamp batch slurm PLAN.jsonl --out DIR [...] (tools/batch_slurm.c). */
int hl_batch_slurm_cmd(int argc, char **argv);
/* hdlamp batch k8s PLAN.jsonl [...] (tools/batch_k8s.c). */
int hl_batch_k8s_cmd(int argc, char **argv);

/*
 * The plan's header: the number of tasks. Reads the first line of path; msg names the file,
 * line and what was expected. 0 or -errno.
 */
int hl_batch_plan_count(const char *path, unsigned *ret_n, char *msg, size_t msg_size);

/*
 * Task index's finished state in DIR: true when DIR/index/result.json exists, is for the task
 * with this id (NULL: any) and its exit is 0, 2 or 3.
 */
bool hl_batch_task_finished(const char *dir, unsigned index, const char *id);

/*
 * The indices of plan's tasks not finished in dir, as a Slurm array list ("0-3,7,9-12") into
 * buf. Returns how many, or -errno (msg says why).
 */
int hl_batch_unfinished_list(const char *plan, const char *dir, char *buf, size_t buf_size,
			     char *msg, size_t msg_size);

/* The merged page (tools/batch_merge_html.c): see hl_batch_merge_cmd. */
struct hl_batch_group {
	char key[256]; /* "fmvss108-adb", "reference", "high", a scenario's name */
	unsigned passed, failed, errors;
};

struct hl_batch_worst {
	unsigned index;
	char id[HL_BATCH_ID_MAX];
	char case_name[256];
	double margin_lx; /* negative: over the limit by that much */
};

#define HL_BATCH_WORST_N 20

struct hl_batch_error {
	unsigned index;
	char id[HL_BATCH_ID_MAX];
	char reason[512];
};

struct hl_batch_summary {
	unsigned tasks, passed, failed, errors;
	unsigned long tests, test_failures, test_errors;
	/* by what the tasks ran; groups with an empty key are not listed */
	struct hl_batch_group *by_suite, *by_scenario, *by_ecu, *by_preset;
	unsigned n_suite, n_scenario, n_ecu, n_preset;
	/* the smallest margins, ascending */
	struct hl_batch_worst worst[HL_BATCH_WORST_N];
	unsigned n_worst;
	/* the loop latency: over the tasks with a loop, the distribution of each task's p50, p99 and max */
	unsigned latency_tasks;
	double p50_of_p50, p50_of_p99, p99_of_p99, max_of_max;
	/* the first errors, in index order (all are in the JUnit and the JSON) */
	struct hl_batch_error *errors_list;
	unsigned n_errors_list;
};

/*
 * The dashboard page at path: totals, pass/fail by suite, scenario, ECU and preset, the worst
 * margins, the loop latency, the errors; links to each task's page (task_href_prefix + "N/index.html",
 * relative to the page). One file, no scripts fetched. 0 or -errno.
 */
int hl_batch_html_write(const struct hl_batch_summary *s, const char *task_href_prefix,
			const char *path);

#endif
