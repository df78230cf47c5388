/* SPDX-License-Identifier: MIT */
/* The ground of a moving scene, a run of pixels at a time (render/world_ground.h). */
#include "render/world_ground.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>

#include "render/scene_layout.h"

int hl_ground_init(const struct hl_road *road, struct hl_ground *g)
{
	const double half = hl_road_half_width(road), ew = road->edge_line_width_m;
	const int lanes = road->lanes > 1 ? road->lanes : 1;
	double *b = malloc(sizeof(double) * (8 + 2 * lanes));
	double *dc = malloc(sizeof(double) * lanes);
	int n = 0, nd = 0;

	if (!b || !dc) {
		free(b);
		free(dc);
		return -ENOMEM;
	}
	for (int side = -1; side <= 1; side += 2) {
		b[n++] = side * HL_WORLD_GROUND_HALF_M;
		b[n++] = side * half;
		if (road->edge != HL_MARK_NONE) {
			b[n++] = side * (half - ew - ew / 2);
			b[n++] = side * (half - ew + ew / 2);
		}
	}
	for (int i = 1; road->separator != HL_MARK_NONE && i < road->lanes; i++) {
		const double c = -half + i * road->lane_width_m;

		b[n++] = c - road->separator_line_width_m / 2;
		b[n++] = c + road->separator_line_width_m / 2;
		if (road->separator == HL_MARK_DASHED)
			dc[nd++] = c;
	}
	g->road = road;
	hl_road_proj_init(road, &g->proj);
	g->bounds = b;
	g->n_bounds = n;
	g->dashed = dc;
	g->n_dashed = nd;
	return 0;
}

void hl_ground_free(struct hl_ground *g)
{
	free(g->bounds);
	free(g->dashed);
	g->bounds = g->dashed = NULL;
}

static bool near_line(double d, double centre, double width)
{
	return fabs(d - centre) <= width / 2;
}

/*
 * What the ground is at (x, y) (world) with lateral offset d on part k of the road: s is
 * computed only where a dashed line needs it.
 */
static enum hl_surface classify(const struct hl_road *road, const struct hl_road_proj *proj, int k,
				double x, double y, double d, double *albedo)
{
	const double half = hl_road_half_width(road), ad = fabs(d);

	if (ad > half) {
		if (ad > HL_WORLD_GROUND_HALF_M)
			return HL_SURF_NONE;
		*albedo = HL_ALBEDO_SHOULDER;
		return HL_SURF_SHOULDER;
	}
	*albedo = HL_ALBEDO_MARKING;
	/* Edge lines: their outer border one line width inside the edge, as the road scene's. */
	if (road->edge != HL_MARK_NONE &&
	    near_line(ad, half - road->edge_line_width_m, road->edge_line_width_m))
		return HL_SURF_MARKING;
	if (road->separator != HL_MARK_NONE) {
		for (int i = 1; i < road->lanes; i++) {
			const double c = -half + i * road->lane_width_m;
			const double period = road->dash_m + road->gap_m;
			double s;

			if (!near_line(d, c, road->separator_line_width_m))
				continue;
			if (road->separator == HL_MARK_SOLID)
				return HL_SURF_MARKING;
			s = hl_road_proj_s(proj, k, x, y);
			if (s - period * floor(s / period) < road->dash_m)
				return HL_SURF_MARKING;
		}
	}
	*albedo = HL_ALBEDO_ROAD;
	return HL_SURF_ROAD;
}

/* The road's parts that can hold the ground points of a run of pixels (road coordinates). */
struct parts {
	int n, i[HL_SCN_MAX_SEGMENTS + 2]; /* 1 kB on the stack per run: fine */
};

static void run_rays(const struct hl_ground_view *v, const struct hl_ground_pose *xf, double sy,
		     int col0, struct hl_ground_run *r)
{
	const double *o = v->o;

	for (int c = 0; c < HL_GROUND_RUN_PX; c++) {
		const double sx = (col0 + c + 0.5 - v->half_w) * v->tx;
		const double d0 = v->f[0] + sx * v->r[0] + sy * v->u[0];
		const double d1 = v->f[1] + sx * v->r[1] + sy * v->u[1];
		const double d2 = v->f[2] + sx * v->r[2] + sy * v->u[2];
		const double t = -o[2] / d2, px = o[0] + t * d0, py = o[1] + t * d1;

		r->d[0][c] = d0;
		r->d[1][c] = d1;
		r->d[2][c] = d2;
		r->t[c] = t;
		r->wx[c] = xf->x + px * xf->c - py * xf->s;
		r->wy[c] = xf->y + px * xf->s + py * xf->c;
	}
}

/* The lateral offset of (x, y) on part pp: hl_road_part_dist2()'s, the same expressions. */
static inline double part_lat(const struct hl_road_proj_part *pp, double x, double y)
{
	if (!pp->arc) {
		const double dx = x - pp->x0_m, dy = y - pp->y0_m;

		return -dx * pp->s + dy * pp->c;
	}
	const double vx = x - pp->cx_m, vy = y - pp->cy_m;

	return pp->turn * (pp->r0_m - sqrt(vx * vx + vy * vy));
}

/* Lateral offsets of the run's pixels on the one part pp (no other can be nearer). */
static void run_lateral_one(const struct hl_road_proj_part *pp, struct hl_ground_run *r)
{
	if (!pp->arc) {
		for (int c = 0; c < HL_GROUND_RUN_PX; c++)
			r->lat[c] = part_lat(pp, r->wx[c], r->wy[c]);
	} else {
		for (int c = 0; c < HL_GROUND_RUN_PX; c++)
			r->lat[c] = part_lat(pp, r->wx[c], r->wy[c]);
	}
}

/*
 * The least and greatest lateral offset on part pp of the run's first n ground points, from
 * its ends alone: the points lie on the segment between the ends' (up to rounding, far below
 * UNIFORM_SLACK_M). On a straight part the offset is affine along it; on an arc it is the
 * distance from the centre, greatest at an end and least at an end or the foot of the
 * perpendicular from the centre.
 */
static void lat_range(const struct hl_road_proj_part *pp, const struct hl_ground_run *r, int n,
		      double *lo, double *hi)
{
	const double ax = r->wx[0], ay = r->wy[0], bx = r->wx[n - 1], by = r->wy[n - 1];

	if (!pp->arc) {
		const double la = part_lat(pp, ax, ay), lb = part_lat(pp, bx, by);

		*lo = la < lb ? la : lb;
		*hi = la < lb ? lb : la;
		return;
	}
	const double vax = ax - pp->cx_m, vay = ay - pp->cy_m, ex = bx - ax, ey = by - ay;
	const double vbx = bx - pp->cx_m, vby = by - pp->cy_m;
	const double da = sqrt(vax * vax + vay * vay), db = sqrt(vbx * vbx + vby * vby);
	const double len2 = ex * ex + ey * ey;
	double u = len2 > 0.0 ? -(vax * ex + vay * ey) / len2 : 0.0, dmin, dmax;

	u = u < 0.0 ? 0.0 : u > 1.0 ? 1.0 : u;
	const double fx = vax + u * ex, fy = vay + u * ey;

	dmin = sqrt(fx * fx + fy * fy);
	dmin = fmin(dmin, fmin(da, db));
	dmax = fmax(da, db);
	*lo = pp->turn > 0 ? pp->r0_m - dmax : dmin - pp->r0_m;
	*hi = pp->turn > 0 ? pp->r0_m - dmin : dmax - pp->r0_m;
}

/*
 * Whether the run's first n ground points all lie where part pp's lateral offset is its line's
 * (circle's): none beyond an end at a kink's vertex, where it is the distance to the vertex.
 * The offset along a straight part is affine in the run, so its ends decide.
 */
static bool run_off_vertices(const struct hl_road_proj_part *pp, const struct hl_ground_run *r,
			     int n)
{
	if (!pp->out0 && !pp->out1)
		return true;
	if (pp->arc)
		return false;
	for (int e = 0; e < 2; e++) {
		const double x = r->wx[e ? n - 1 : 0], y = r->wy[e ? n - 1 : 0];
		const double u = (x - pp->x0_m) * pp->c + (y - pp->y0_m) * pp->s;

		if ((pp->out0 && u < pp->lo_m) || (pp->out1 && u > pp->hi_m))
			return false;
	}
	return true;
}

/* Slack for rounding (m) when a run's offsets are judged to lie between two bounds. */
#define UNIFORM_SLACK_M 1e-6

/*
 * Whether the run's pixels (all on the ground, on part k, lateral offsets within lo .. hi)
 * are one surface: the offsets lie between two neighbouring bounds of classify() and not on a
 * dashed line (where s decides). Then classify()'s answer for the first (offset lat0) is every
 * pixel's.
 */
static bool run_uniform(const struct hl_ground *g, int k, double lo, double hi, double lat0,
			struct hl_ground_run *r)
{
	for (int b = 0; b < g->n_bounds; b++)
		if (g->bounds[b] >= lo - UNIFORM_SLACK_M && g->bounds[b] <= hi + UNIFORM_SLACK_M)
			return false;
	for (int b = 0; b < g->n_dashed; b++)
		if (fabs(lat0 - g->dashed[b]) <=
		    g->road->separator_line_width_m / 2 + UNIFORM_SLACK_M)
			return false;
	r->albedo = 0.0;
	r->id = classify(g->road, &g->proj, k, r->wx[0], r->wy[0], lat0, &r->albedo);
	r->uniform = true;
	return true;
}

void hl_ground_run(const struct hl_ground *g, const struct hl_ground_view *v,
		   const struct hl_ground_pose *pose, double sy, int col0, int n, int *hint,
		   struct hl_ground_run *r)
{
	const double *o = v->o;
	struct parts parts;
	bool ends;

	r->uniform = false;
	run_rays(v, pose, sy, col0, r);
	/* both ends' rays meet the ground: so do those between them, on the segment of theirs */
	ends = o[2] > 0.0 && r->d[2][0] < 0.0 && r->d[2][n - 1] < 0.0;
	if (ends) {
		parts.n = hl_road_proj_candidates(&g->proj, r->wx[0], r->wy[0], r->wx[n - 1],
						  r->wy[n - 1], parts.i);
		if (parts.n == 1 && run_off_vertices(&g->proj.part[parts.i[0]], r, n)) {
			const int k = parts.i[0];
			const struct hl_road_proj_part *pp = &g->proj.part[k];
			double lo, hi;

			*hint = k;
			for (int c = 0; c < n; c++)
				r->part[c] = k;
			lat_range(pp, r, n, &lo, &hi);
			if (!run_uniform(g, k, lo, hi, part_lat(pp, r->wx[0], r->wy[0]), r))
				run_lateral_one(pp, r);
			return;
		}
	} else {
		parts.n = g->proj.n;
		for (int i = 0; i < parts.n; i++)
			parts.i[i] = i;
	}
	for (int c = 0; c < n; c++) {
		r->part[c] = -1;
		if (!(r->d[2][c] < 0.0) || o[2] <= 0.0)
			continue;
		r->part[c] = hl_road_proj_lateral_among(&g->proj, parts.i, parts.n, r->wx[c],
							r->wy[c], *hint, &r->lat[c]);
		*hint = r->part[c];
	}
}

bool hl_ground_hit(const struct hl_ground *g, const struct hl_ground_run *r, int c,
		   enum hl_surface *id, double *albedo)
{
	if (r->part[c] < 0 || !(r->d[2][c] < 0.0))
		return false;
	if (r->uniform) {
		*id = r->id;
		*albedo = r->albedo;
	} else {
		*albedo = 0.0;
		*id = classify(g->road, &g->proj, r->part[c], r->wx[c], r->wy[c], r->lat[c],
			       albedo);
	}
	return *id != HL_SURF_NONE;
}

bool hl_ground_run_sky(const struct hl_ground_view *v, const struct hl_ground_run *r, int n)
{
	bool sky = true;

	for (int c = 0; c < n; c++)
		sky &= !(r->d[2][c] < 0.0) || v->o[2] <= 0.0;
	return sky;
}
