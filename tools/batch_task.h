/* SPDX-License-Identifier: MIT */
/*
 * One task of a batch plan (tools/batch.h): its line read from the plan, the command that runs
 * it, and its result.json from how that command ended and what it wrote.
 */
#ifndef HL_TOOLS_BATCH_TASK_H
#define HL_TOOLS_BATCH_TASK_H

#include <stdbool.h>
#include <stddef.h>

#include "tools/batch.h"

enum hl_batch_kind { HL_BATCH_SUITE, HL_BATCH_SIL, HL_BATCH_DRIVE };

enum hl_batch_status { HL_BATCH_PASSED, HL_BATCH_FAILED, HL_BATCH_ERROR };

struct hl_batch_task {
	unsigned index;
	char id[HL_BATCH_ID_MAX];
	enum hl_batch_kind kind;
	/* the task's line (jansson's json_t *), for its fields */
	void *json;
};

struct hl_batch_outcome {
	bool ran; /* the child was started and waited for */
	int exit; /* its exit code (1 when it was not started or died of a signal) */
	int signal; /* the signal it died of, or 0 */
	int stop_signal; /* a signal this process was sent (and forwarded), or 0 */
	double started_unix, duration_s;
	char reason[512]; /* why it is an error (set before the result when it did not run) */
	enum hl_batch_status status; /* set by hl_batch_result_write */
};

/* Task index of the plan at path (streamed: memory does not grow with the plan). 0 or -errno
 * (msg names the file, line and what was expected). */
int hl_batch_task_read(const char *plan, unsigned index, struct hl_batch_task *t, char *msg,
		       size_t msg_size);
void hl_batch_task_free(struct hl_batch_task *t);

/*
 * The command of t writing into dir: self (this hdlamp) for suite and sil tasks, daemon
 * (hdlampd) for drives. *ret is one malloc'd block (NULL-terminated). 0 or -errno.
 */
int hl_batch_task_argv(const struct hl_batch_task *t, const char *self, const char *daemon,
		       const char *dir, char ***ret);

/*
 * dir/result.json of t from oc and the files the task wrote (junit.xml, report.json, log.txt):
 * oc->status and oc->reason set. 0 or -errno (msg says why).
 */
int hl_batch_result_write(const struct hl_batch_task *t, const char *dir,
			  struct hl_batch_outcome *oc, char *msg, size_t msg_size);

const char *hl_batch_status_name(enum hl_batch_status s);

/*
 * path's file name without its folder and without ext (NULL: without its last extension), cut
 * to size: what the ids and the merge's groups call a scenario, drive, suite or FMU.
 */
void hl_batch_stem(const char *path, const char *ext, char *ret, size_t size);

/* out/plan.jsonl made a copy of plan (nothing when it already is plan). 0 or -errno. */
int hl_batch_copy_plan(const char *plan, const char *out);

#endif
