/* SPDX-License-Identifier: MIT */
#include "render/road_kpi.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_SAMPLES 1000000 /* per line: 300 m at 0.3 mm; more is a mistake */

/* The lines a plan samples: the two range lines, then the width lines. */
enum { LINE_CENTRE, LINE_EDGE, LINE_WIDTH0, N_LINES = LINE_WIDTH0 + HL_ROAD_KPI_WIDTHS };

struct line {
	double first_m; /* coordinate along the line of sample 0 (x for ranges, y for widths) */
	size_t first, count; /* its samples in taps[] (n_lamps taps each) */
};

struct hl_road_kpi_plan {
	struct hl_road_kpi_options opts;
	int n_lamps;
	int width[HL_HEADLIGHT_MAX_LAMPS]; /* grid columns of each lamp */
	struct line lines[N_LINES];
	struct hl_headlight_tap *taps; /* n_lamps per sample, lamps interleaved; g = 0: dark */
};

void hl_road_kpi_defaults(struct hl_road_kpi_options *ret)
{
	*ret = (struct hl_road_kpi_options){
		.levels_lx = { 1.0, 3.0 },
		.lane_centre_y_m = -1.75,
		.edge_y_m = -3.5,
		.width_at_m = { 25.0, 50.0 },
		.max_range_m = 300.0,
		.step_m = 0.05,
	};
}

static bool positive(double v)
{
	return isfinite(v) && v > 0.0;
}

static int check(const struct hl_road_kpi_options *o)
{
	if (!positive(o->step_m) || !positive(o->max_range_m) || o->max_range_m < o->step_m ||
	    o->max_range_m / o->step_m > MAX_SAMPLES ||
	    2 * HL_ROAD_KPI_WIDTH_HALF_M / o->step_m > MAX_SAMPLES ||
	    !isfinite(o->lane_centre_y_m) || !isfinite(o->edge_y_m))
		return -EINVAL;
	for (int i = 0; i < HL_ROAD_KPI_LEVELS; i++)
		if (!positive(o->levels_lx[i]))
			return -EINVAL;
	for (int i = 0; i < HL_ROAD_KPI_WIDTHS; i++)
		if (!positive(o->width_at_m[i]))
			return -EINVAL;
	return 0;
}

int hl_road_kpi_new(int n_lamps, const struct hl_headlight_lamp *lamps,
		    const struct hl_road_kpi_options *opts, struct hl_road_kpi_plan **ret)
{
	static const double up[3] = { 0.0, 0.0, 1.0 };
	const double half = HL_ROAD_KPI_WIDTH_HALF_M;
	struct hl_road_kpi_plan *p;
	size_t n_range, n_width, total;

	if (n_lamps < 1 || n_lamps > HL_HEADLIGHT_MAX_LAMPS || check(opts) < 0)
		return -EINVAL;
	for (int k = 0; k < n_lamps; k++)
		if (hl_lid_grid_check(&lamps[k].grid) < 0)
			return -EINVAL;
	p = calloc(1, sizeof(*p));
	if (!p)
		return -ENOMEM;
	p->opts = *opts;
	p->n_lamps = n_lamps;
	for (int k = 0; k < n_lamps; k++)
		p->width[k] = lamps[k].grid.width;
	/* Samples at 0, step, ..., the last whole step within max_range (and within 1e-9 of it). */
	n_range = (size_t)floor(opts->max_range_m / opts->step_m + 1e-9) + 1;
	n_width = (size_t)floor(2 * half / opts->step_m + 1e-9) + 1;
	total = 2 * n_range + HL_ROAD_KPI_WIDTHS * n_width;
	p->lines[LINE_CENTRE] = (struct line){ 0.0, 0, n_range };
	p->lines[LINE_EDGE] = (struct line){ 0.0, n_range, n_range };
	for (int i = 0; i < HL_ROAD_KPI_WIDTHS; i++)
		p->lines[LINE_WIDTH0 + i] =
			(struct line){ -half, 2 * n_range + i * n_width, n_width };
	p->taps = malloc(sizeof(*p->taps) * n_lamps * total);
	if (!p->taps) {
		hl_road_kpi_free(p);
		return -ENOMEM;
	}
	for (int l = 0; l < N_LINES; l++) {
		const struct line *ln = &p->lines[l];

		for (size_t i = 0; i < ln->count; i++) {
			const double s = ln->first_m + (double)i * opts->step_m;
			double pt[3] = { s, 0.0, 0.0 };

			if (l == LINE_CENTRE)
				pt[1] = opts->lane_centre_y_m;
			else if (l == LINE_EDGE)
				pt[1] = opts->edge_y_m;
			else
				pt[0] = opts->width_at_m[l - LINE_WIDTH0], pt[1] = s;
			for (int k = 0; k < n_lamps; k++)
				hl_headlight_tap(&lamps[k], pt, up,
						 &p->taps[(ln->first + i) * n_lamps + k]);
		}
	}
	*ret = p;
	return 0;
}

void hl_road_kpi_free(struct hl_road_kpi_plan *p)
{
	if (!p)
		return;
	free(p->taps);
	free(p);
}

/* E at sample i of line ln, both lamps added. */
static double illuminance(const struct hl_road_kpi_plan *p, const float *const *dense,
			  const struct line *ln, size_t i)
{
	const struct hl_headlight_tap *t = &p->taps[(ln->first + i) * p->n_lamps];
	double e = 0.0;

	for (int k = 0; k < p->n_lamps; k++)
		if (dense[k] && t[k].g > 0.0)
			e += hl_headlight_tap_lookup(&t[k], dense[k], p->width[k]);
	return e;
}

/* Where E crosses level between samples a (at s, value ea) and s + step (value eb). */
static double crossing(double s, double step, double ea, double eb, double level)
{
	return s + step * (ea - level) / (ea - eb);
}

/*
 * The farthest distance along ln where E >= level, for each level: the last crossing from at
 * or above to below, or the line's end when its last sample is still at or above.
 */
static void ranges(const struct hl_road_kpi_plan *p, const float *const *dense,
		   const struct line *ln, double *ret_m)
{
	const double step = p->opts.step_m;
	double prev = 0.0;

	for (int j = 0; j < HL_ROAD_KPI_LEVELS; j++)
		ret_m[j] = 0.0;
	for (size_t i = 0; i < ln->count; i++) {
		const double e = illuminance(p, dense, ln, i);
		const double s = ln->first_m + (double)i * step;

		for (int j = 0; j < HL_ROAD_KPI_LEVELS; j++) {
			const double level = p->opts.levels_lx[j];

			if (i > 0 && prev >= level && e < level)
				ret_m[j] = crossing(s - step, step, prev, e, level);
			else if (i + 1 == ln->count && e >= level)
				ret_m[j] = s;
		}
		prev = e;
	}
}

/*
 * The extent across ln of E >= level: from the first crossing to at or above (or the line's
 * start) to the last crossing back below (or the line's end); 0 when no sample reaches it.
 */
static double extent(const struct hl_road_kpi_plan *p, const float *const *dense,
		     const struct line *ln, double level)
{
	const double step = p->opts.step_m;
	double prev = 0.0, lo = NAN, hi = NAN;

	for (size_t i = 0; i < ln->count; i++) {
		const double e = illuminance(p, dense, ln, i);
		const double s = ln->first_m + (double)i * step;

		if (e >= level && isnan(lo))
			lo = i == 0 ? s : crossing(s - step, step, prev, e, level);
		if (i > 0 && prev >= level && e < level)
			hi = crossing(s - step, step, prev, e, level);
		else if (i + 1 == ln->count && e >= level)
			hi = s;
		prev = e;
	}
	return isnan(lo) ? 0.0 : hi - lo;
}

void hl_road_kpi_run(const struct hl_road_kpi_plan *p, const float *const *dense,
		     struct hl_road_kpi *ret)
{
	ranges(p, dense, &p->lines[LINE_CENTRE], ret->centre_range_m);
	ranges(p, dense, &p->lines[LINE_EDGE], ret->edge_range_m);
	for (int i = 0; i < HL_ROAD_KPI_WIDTHS; i++)
		ret->width_m[i] =
			extent(p, dense, &p->lines[LINE_WIDTH0 + i], p->opts.levels_lx[0]);
}
