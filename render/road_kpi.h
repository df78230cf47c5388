/* SPDX-License-Identifier: MIT */
/*
 * The road's verdict (docs/rendering.md, "Road KPIs"): range and width as lighting engineers
 * quote them, from the lamps at their mounted pose lighting the flat road (z = 0, normal up):
 * the farthest distance along the lane centre and along the right road edge where the
 * illuminance E = sum over lamps of I * cos(eps) / r^2 reaches each level (1 lx and 3 lx by
 * default), and the width of the area at the first level across the road at 25 m and 50 m.
 *
 * Sampling: the range lines are sampled at x = 0, step, 2 step, ... up to max_range; a range is
 * the farthest x where E >= level, the crossing linearly interpolated between the samples on
 * either side of it (max_range when the last sample is still at or above the level). The width
 * lines x = width_at_m[i] are sampled at y = -HL_ROAD_KPI_WIDTH_HALF_M .. +HL_ROAD_KPI_WIDTH_HALF_M
 * in the same steps; a width is the extent from the rightmost to the leftmost point with E >=
 * levels_lx[0] (crossings interpolated the same way; dark gaps in between count). E at a
 * sample is what hl_headlight_point() gives there (the same taps, in double precision).
 *
 * hl_road_kpi_new() precomputes, for every sample point on those lines, each lamp's bilinear
 * taps and cos(eps) / r^2 (hl_headlight_tap()); a frame is then weighted sums.
 *
 * The default step is 0.05 m because the width lines need it: across the road at 25 m, a 0.2°
 * grid step is 8.7 cm, and at 0.25 m the HD84 low beam's 1 lx width came out 1.9 % short of
 * its converged value (0.05 m: within 0.05 %). Along the range lines 0.25 m would do (a V step
 * of 0.2° spans metres there), but one step keeps the definition simple; a plan is then 14,404
 * samples and a run some 29,000 lookups.
 *
 * Thread-safety: built by one thread, read-only afterwards; hl_road_kpi_run() may run on several
 * threads at once.
 */
#ifndef HL_RENDER_ROAD_KPI_H
#define HL_RENDER_ROAD_KPI_H

#include "render/headlight.h"

#define HL_ROAD_KPI_LEVELS 2
#define HL_ROAD_KPI_WIDTHS 2
#define HL_ROAD_KPI_WIDTH_HALF_M 30.0 /* width lines reach this far either side of y = 0 */

struct hl_road_kpi_options {
	double levels_lx[HL_ROAD_KPI_LEVELS]; /* 1, 3 */
	double lane_centre_y_m; /* -1.75: the ego lane's centre (vehicle frame, y left) */
	double edge_y_m; /* -3.5: the right road edge */
	double width_at_m[HL_ROAD_KPI_WIDTHS]; /* 25, 50: where the width is taken */
	double max_range_m; /* how far the lines are scanned (300) */
	double step_m; /* sample spacing along the lines (0.05: see below) */
};

struct hl_road_kpi {
	double centre_range_m[HL_ROAD_KPI_LEVELS]; /* 0 when the level is never reached */
	double edge_range_m[HL_ROAD_KPI_LEVELS];
	double width_m[HL_ROAD_KPI_WIDTHS]; /* of the levels_lx[0] area, 0 when none */
};

void hl_road_kpi_defaults(struct hl_road_kpi_options *ret);

struct hl_road_kpi_plan;

/*
 * 0, -EINVAL (n_lamps outside 1..2, a bad grid, or bad options: levels, step, max_range and
 * width_at not finite and > 0, max_range < step, more than 10^6 samples on a line), -ENOMEM.
 * The lamps are read only here; *ret is the caller's, freed with hl_road_kpi_free().
 */
int hl_road_kpi_new(int n_lamps, const struct hl_headlight_lamp *lamps,
		    const struct hl_road_kpi_options *opts, struct hl_road_kpi_plan **ret);
void hl_road_kpi_free(struct hl_road_kpi_plan *p);

/* From the lamps' current distributions (dense[k] NULL: lamp k dark). Allocates nothing. */
void hl_road_kpi_run(const struct hl_road_kpi_plan *p, const float *const *dense,
		     struct hl_road_kpi *ret);

#endif
