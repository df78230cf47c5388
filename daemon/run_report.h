/* SPDX-License-Identifier: MIT */
/*
 * The closed-loop run's report (docs/loop.md, "--exit-at-end and --report") of hdlampd: the
 * counters of its threads collected into the report's data (daemon/loop/loop_report.h, the
 * format and the verdict's rule), written at exit.
 *
 * Thread-safety: main thread, after the threads that feed the counters have stopped.
 */
#ifndef HL_DAEMON_RUN_REPORT_H
#define HL_DAEMON_RUN_REPORT_H

#include <stdbool.h>
#include <stdio.h>

#include "daemon/core/can_input.h"
#include "daemon/loop/loop_latency.h"
#include "daemon/loop/loop_report.h"
#include "daemon/pipeline.h"
#include "daemon/loop/restbus.h"
#include "daemon/core/ring.h"
#include "daemon/core/verdicts.h"
#include "world/scenario.h"

struct hl_run_report_sources {
	const char *scenario_path;
	const struct hl_scenario *sc;
	const char *glare_set; /* the glare limits' regulation set */
	int n_lamps;
	const char *const *lamp_names;
	struct hl_can_input *in;
	struct hl_ring *ring;
	struct hl_pipeline *pipe;
	const struct hl_verdicts *verdicts; /* may be NULL */
	struct hl_loop_latency *loop; /* finished (hl_loop_latency_finish) */
	struct hl_restbus *restbus; /* may be NULL */
	const char *end; /* how the run ended: "scenario_end", "replay_end", "signal", "ecu_error" */
	const char *ecu; /* ecu.model's name, NULL: an ECU outside */
	const char *ecu_error; /* what stopped the in-process ECU, NULL: nothing */
};

/* The report's data from the sources. */
void hl_run_report_collect(const struct hl_run_report_sources *s, struct hl_loop_report *ret);
/* The verdict alone (what the report's "verdict" says). */
bool hl_run_report_passed(const struct hl_run_report_sources *s);
/* The report into f. */
void hl_run_report_json(const struct hl_run_report_sources *s, FILE *f);
/* The report into path (written beside it and renamed). 0 or -errno. */
int hl_run_report_write(const struct hl_run_report_sources *s, const char *path);

/*
 * At the run's end (every thread that fed the counters stopped): finishes the loop's judge,
 * writes the report to path and the verdicts as JUnit XML to junit (each if not empty; the
 * JUnit as hdlamp sil --junit writes it, daemon/loop/loop_junit.h) and logs the verdict. Returns the exit code: code
 * when neither a report nor exit_at_end was asked for, else 3 when the verdict failed (and code
 * was 0), 1 when the report or the JUnit could not be written.
 */
int hl_run_report_end(const struct hl_run_report_sources *s, const char *path, const char *junit,
		      bool exit_at_end, int code);

#endif
