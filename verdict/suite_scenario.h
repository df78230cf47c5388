/* SPDX-License-Identifier: MIT */
/*
 * A suite's scenarios made concrete (docs/lab.md "The scenarios"): each row of a procedure's
 * table (a speed range, a radius range, a measured range) becomes variants — every combination
 * of the ends of its speed and radius ranges (samples 2), or of `samples` evenly spaced points
 * of each — and each variant a scenario file (docs/scenarios.md) hdlamp can run.
 *
 * The track: two lanes of 3.5 m; a curve is a 10 m straight, then an arc of the radius (of the
 * road's centre line) turning left or right. The test vehicle drives lane 1 at the variant's
 * constant speed; the stimulus vehicle stands still (documented default: docs/lab.md) — in
 * lane 2 facing it when oncoming, ahead in lane 1 facing away when preceding. The run starts
 * where every photometer of the stimulus vehicle is at least 5 m beyond the measured range and
 * ends at the first 10 ms step where every one is 1 m inside its near end. An empty road
 * (IIHS) has the vehicle standing at the start of the curve for 1 s.
 *
 * Thread-safety: plain functions; each call allocates what it returns.
 */
#ifndef HL_VERDICT_SUITE_SCENARIO_H
#define HL_VERDICT_SUITE_SCENARIO_H

#include <stddef.h>

#include "verdict/suite.h"

#define HL_SUITE_MPH_MPS 0.44704 /* 1 mph = 1609.344 m / 3600 s (exact by definition) */

/* How many variants a scenario has with samples points per range (2: both ends). */
int hl_suite_variant_count(const struct hl_suite_scenario *d, int samples);
/* Variant k's speed (mph) and radius (m; 0 on a straight), and its id "ID-NNmph[-rRRRm]". */
void hl_suite_variant_params(const struct hl_suite_scenario *d, int samples, int k,
			     double *ret_speed_mph, double *ret_radius_m, char *ret_id,
			     size_t id_size);

/* The variant's title: the scenario's with its speed (and radius). */
void hl_suite_variant_title(const struct hl_suite_scenario *d, double speed_mph, double radius_m,
			    char *buf, size_t size);

/*
 * The variant's scenario as JSON text (*ret malloc'd). 0, -ENOMEM, -EINVAL (the geometry
 * cannot give the measured range: msg says why; a generated file refused by the reader is
 * -EBADMSG with the reader's message).
 */
int hl_suite_variant_scenario(const struct hl_suite *s, const struct hl_suite_scenario *d,
			      double speed_mph, double radius_m, char **ret, char *msg,
			      size_t msg_size);

#endif
