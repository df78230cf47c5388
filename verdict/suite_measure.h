/* SPDX-License-Identifier: MIT */
/*
 * Measuring one scenario variant of a suite frame by frame (docs/lab.md): the stimulus
 * vehicle's photometers (FMVSS 108: E on each photometer's plane, binned by range), the glare
 * table's rows (R149: half the pair's intensity toward the stimulus vehicle's driver), or the
 * IIHS figures (the visibility distance along each road edge at the visibility height, the
 * illuminance at the glare height over the oncoming lane's centre) — the same for a held
 * preset stepped through the scenario, the SIL loop's frames, and hdlampd's live frames.
 *
 * IIHS, as docs/lab.md documents: points every 1 m along each edge from the vehicle's front to
 * the far end of the variant's range and over the centre of lane 2 across the range (centre-line
 * distance ahead of the front), each on a plane facing the
 * lamps' midpoint; a visibility distance is the length along its edge to the farthest point
 * still at the visibility illuminance or above; the last frame measured is the one reported.
 *
 * Thread-safety: one measurement is fed by one thread.
 */
#ifndef HL_VERDICT_SUITE_MEASURE_H
#define HL_VERDICT_SUITE_MEASURE_H

#include "lamp/lid.h"
#include "verdict/regulation.h"
#include "verdict/suite.h"
#include "verdict/suite_result.h"
#include "world/world.h"

struct hl_suite_measure;

/*
 * Starts measuring variant v (its range_m, road and scenario_id filled) of suite scenario d.
 * reg: the glare set of an r149-adb suite (NULL otherwise); it must outlive the measurement.
 * 0, -EINVAL (an r149-adb suite without reg), -ENOMEM.
 */
int hl_suite_measure_new(const struct hl_suite *s, const struct hl_suite_scenario *d,
			 const struct hl_regulation *reg, struct hl_suite_variant *v,
			 struct hl_suite_measure **ret);
/* One frame: the world at its time and the lamps' distributions (cd) on their grids. */
void hl_suite_measure_frame(struct hl_suite_measure *m, const struct hl_scenario *sc,
			    const struct hl_world_state *w,
			    const struct hl_lid_grid *const grids[2], const float *const dist[2]);
/*
 * Series i's newest reading (the frame last measured): its range (m; IIHS: the distance of the
 * highest reading) and value (lx). false before one.
 */
bool hl_suite_measure_last(const struct hl_suite_measure *m, int series, double *ret_range_m,
			   double *ret_lx);
/* Ends it: the cases judged (verdict/suite_judge.h). 0, or -ENOMEM if a frame could not be kept. */
int hl_suite_measure_finish(struct hl_suite_measure *m);
void hl_suite_measure_free(struct hl_suite_measure *m);

#define HL_SUITE_IIHS_STEP_M 1.0 /* between the IIHS points */

#endif
