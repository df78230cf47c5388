/* SPDX-License-Identifier: MIT */
/*
 * The live verdict sets' records over the run (verdict/record.h; docs/verdicts.md,
 * "Now and so far"): one record per set of the daemon's verdicts, fed by the render thread with
 * every frame it evaluated, read by /status, the live page and the run's report.
 *
 * A frame's time on the records is the seconds since the run's first evaluated frame on the CAN
 * cycles' receive clock (the frame header's t_cycle_rx_ns: the replayed log's time, or the
 * kernel's receive time live). A frame's cell per set: not applicable when the set was not
 * active in the frame's beam mode, else pass or FAIL, deciding requirement the one of the
 * smallest margin over the set's parts.
 *
 * Thread-safety: hl_verdict_records_add on the render thread only; hl_verdict_records_read on
 * any thread (it holds the records' priority-inheritance mutex while fn runs: fn copies what it
 * needs and returns). new and free on the main thread.
 */
#ifndef HL_DAEMON_CORE_VERDICT_RECORDS_H
#define HL_DAEMON_CORE_VERDICT_RECORDS_H

#include <stdio.h>

#include "daemon/core/frame.h"
#include "daemon/core/verdicts.h"
#include "verdict/record.h"

#define HL_VERDICT_RECORDS_RUNS 16384 /* whole-run strip runs kept per set */

struct hl_verdict_records;

/* One record per set of v (v must outlive it). 0, -ENOMEM, -errno (the mutex). */
int hl_verdict_records_new(const struct hl_verdicts *v, struct hl_verdict_records **ret);
void hl_verdict_records_free(struct hl_verdict_records *r);

/* Render thread: a frame whose verdicts ran (its header's masks, results and beam mode). */
void hl_verdict_records_add(struct hl_verdict_records *r, const struct hl_frame *f);

/* Calls fn with the records (n of them, the sets' order) under the records' lock. */
void hl_verdict_records_read(struct hl_verdict_records *r,
			     void (*fn)(void *ud, const struct hl_record *const *records, int n),
			     void *ud);

/* The whole-run strip of set as JSON members "strip_runs":[...] (under the lock: fn's ud). */
void hl_verdict_records_json_runs(const struct hl_verdicts *v, int set, const struct hl_record *rec,
				  FILE *out);

#endif
