/* SPDX-License-Identifier: MIT */
/*
 * A suite run live (hdlampd --suite, docs/lab.md "In real time"): the suite's variants one
 * after the other, each a run of the daemon on its generated scenario, measured on every
 * published frame by the render thread (verdict/suite_measure.h) — the photometers'
 * illuminance against the limit of their range's bin, the bins so far — and shown on /status
 * ("suite") and /metrics (hdlamp_suite_*), with the variants finished before it.
 *
 * Thread-safety: new, free, begin and end on the main thread while no run is going;
 * hl_suite_live_frame() from the render thread only; the status and metrics from any thread.
 * The measurement is under a priority-inheritance mutex that the render thread holds for one
 * frame's measurement (< 1 µs for the FMVSS photometers; docs/lab.md "Speed").
 */
#ifndef HL_DAEMON_CORE_SUITE_LIVE_H
#define HL_DAEMON_CORE_SUITE_LIVE_H

#include <stdio.h>

#include "daemon/core/prom.h"
#include "lamp/lid.h"
#include "verdict/regulation.h"
#include "verdict/suite.h"
#include "verdict/suite_result.h"
#include "world/world.h"

struct hl_suite_live;

/* For r (its suite and variants, the caller's; reg: the r149 glare set or NULL). 0, -ENOMEM. */
int hl_suite_live_new(struct hl_suite_result *r, const struct hl_regulation *reg,
		      struct hl_suite_live **ret);
void hl_suite_live_free(struct hl_suite_live *sl);

/* Variant r->v[i] of scenario d starts: its measurement made. 0, -EINVAL, -ENOMEM. */
int hl_suite_live_begin(struct hl_suite_live *sl, const struct hl_suite_scenario *d, int i);
/* The variant ends: its cases judged. 0, or -ENOMEM (a frame could not be kept). */
int hl_suite_live_end(struct hl_suite_live *sl);

/* Render thread: one published frame (the pipeline's frame hook, daemon/pipeline.h). */
void hl_suite_live_frame(void *sl, const struct hl_scenario *sc, const struct hl_world_state *w,
			 const struct hl_lid_grid *const grids[2], const float *const dist[2]);

/* The /status part ',"suite":{...}' (nothing for a NULL sl). */
void hl_suite_live_status_json(struct hl_suite_live *sl, FILE *out);
/* The /metrics families hdlamp_suite_* (nothing for a NULL sl). */
void hl_suite_live_metrics(struct hl_suite_live *sl, struct hl_prom *p);

#endif
