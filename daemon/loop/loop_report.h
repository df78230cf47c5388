/* SPDX-License-Identifier: MIT */
/*
 * The closed-loop run's report (docs/loop.md, "--exit-at-end and --report") as data and as
 * JSON: one object with the frames, the lamps' cycles (rendered, not rendered, dropped), each
 * configured verdict set's frames passed and failed with its record, the glare per road user,
 * the loop latencies per event, and the verdict: true only when every configured verdict held —
 * every verdict set on every frame it was evaluated on, and the scenario's glare rule
 * (daemon/loop/loop_latency.h) — with at least one frame rendered and every frame judged.
 *
 * hdlampd fills it from its threads' counters (daemon/run_report.c), `hdlamp sil` from its
 * discrete-event loop (sil/engine.c): one format for both.
 *
 * Thread-safety: after whatever feeds the counters has stopped.
 */
#ifndef HL_DAEMON_LOOP_LOOP_REPORT_H
#define HL_DAEMON_LOOP_LOOP_REPORT_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "can/assembler.h"
#include "daemon/core/frame.h"
#include "daemon/core/verdict_records.h"
#include "daemon/core/verdicts.h"
#include "daemon/loop/loop_latency.h"
#include "world/scenario.h"

struct hl_loop_report {
	const char *scenario_path;
	const struct hl_scenario *sc;
	const char *glare_set; /* the glare limits' regulation set */
	const char *end; /* how the run ended: "scenario_end", "replay_end", "signal" */
	const char *ecu; /* the ECU in the loop when it is ours to name (sil), else NULL */
	const char *ecu_error; /* what stopped the in-process ECU (the verdict fails), else NULL */
	int n_lamps;
	const char *const *lamp_names;
	/* frames */
	uint64_t frames, not_published;
	double render_ms_max;
	/* the hand-over ring's snapshots */
	uint64_t snapshots_pushed, snapshots_superseded, snapshots_dropped;
	/* per lamp */
	struct hl_lamp_counters lamp[HL_FRAME_MAX_LAMPS];
	uint64_t cycles_not_rendered[HL_FRAME_MAX_LAMPS];
	uint64_t failsafe_frames[HL_FRAME_MAX_LAMPS];
	/* per verdict set */
	const struct hl_verdicts *verdicts; /* may be NULL */
	struct hl_verdict_records *records; /* may be NULL */
	uint64_t verdict_frames[HL_VERDICTS_MAX_SETS];
	uint64_t verdict_failed_frames[HL_VERDICTS_MAX_SETS];
	struct hl_loop_latency *loop; /* finished (hl_loop_latency_finish) */
	bool have_restbus;
	struct {
		uint64_t camera_cycles, vehicle_cycles, overruns, tx_full, tx_errors, link_down;
	} restbus;
};

/* The verdict alone (what the report's "verdict" says). */
bool hl_loop_report_passed(const struct hl_loop_report *r);
/* The report into f. */
void hl_loop_report_json(const struct hl_loop_report *r, FILE *f);
/* The report into path (written beside it and renamed). 0 or -errno. */
int hl_loop_report_write(const struct hl_loop_report *r, const char *path);

#endif
