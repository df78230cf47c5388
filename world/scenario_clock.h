/* SPDX-License-Identifier: MIT */
/*
 * The one scenario clock (docs/scenarios.md, "Scenario time in the daemon"): scenario time is
 * the time since the scenario's origin t0 on a nanosecond timeline, held at 0 before it and at
 * the scenario's duration past its end. Every reader of scenario time - the render thread
 * (CLOCK_MONOTONIC since the renderer was ready on a live bus, or the replayed log's time since
 * the start of its pass), the restbus (its deadlines) and the daemon's end of a scenario run -
 * computes it here, from the one t0 the render thread sets (hl_pipeline_scene_t0_ns).
 *
 * Thread-safety: pure functions; any thread.
 */
#ifndef HL_WORLD_SCENARIO_CLOCK_H
#define HL_WORLD_SCENARIO_CLOCK_H

#include <stdbool.h>
#include <stdint.h>

#include "world/scenario.h"

/* Scenario time (s) at t_ns on a timeline whose scenario time 0 is t0_ns, clamped to the run. */
double hl_scenario_clock_at(const struct hl_scenario *sc, int64_t t0_ns, int64_t t_ns);

/* t_s held at 0 before the start and at the scenario's duration past its end. */
double hl_scenario_clock_clamp(const struct hl_scenario *sc, double t_s);

/* Whether the scenario is over at now_ns: its duration and then margin_ns have passed since t0_ns. */
bool hl_scenario_clock_over(const struct hl_scenario *sc, int64_t t0_ns, int64_t now_ns,
			    int64_t margin_ns);

#endif
