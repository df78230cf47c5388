/* SPDX-License-Identifier: MIT */
/* Road, path and body geometry of a scenario: closed forms, no allocation. */
#include "world/road.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <string.h>

#define DEG (M_PI / 180.0)

/* Where segment seg is u metres after its start (0 <= u; past its end it curves on). */
static void in_segment(const struct hl_road_segment *seg, double u, struct hl_pose2 *ret)
{
	if (seg->kind == HL_SEG_STRAIGHT) {
		ret->x_m = seg->x0_m + u * cos(seg->heading0_rad);
		ret->y_m = seg->y0_m + u * sin(seg->heading0_rad);
		ret->heading_rad = seg->heading0_rad;
		return;
	}
	/* An arc of curvature k: the chord 2 sin(k u / 2) / k at half the turned angle. */
	const double k = seg->turn / seg->radius_m, half = k * u / 2;
	const double chord = 2.0 * sin(half) / k, dir = seg->heading0_rad + half;

	ret->x_m = seg->x0_m + chord * cos(dir);
	ret->y_m = seg->y0_m + chord * sin(dir);
	ret->heading_rad = seg->heading0_rad + 2.0 * half;
}

void hl_road_layout(struct hl_road *road)
{
	double s = 0.0;
	struct hl_pose2 p = { road->x0_m, road->y0_m, road->heading0_rad };

	for (int i = 0; i < road->n_segments; i++) {
		struct hl_road_segment *seg = &road->seg[i];

		p.heading_rad += seg->kink_rad;
		seg->s0_m = s;
		seg->x0_m = p.x_m;
		seg->y0_m = p.y_m;
		seg->heading0_rad = p.heading_rad;
		in_segment(seg, seg->length_m, &p);
		s += seg->length_m;
	}
	road->length_m = s;
}

/* Distance from p to the segment a-b (to a when they coincide). */
static double seg_dist(const double p[2], const double a[2], const double b[2])
{
	const double ex = b[0] - a[0], ey = b[1] - a[1], len2 = ex * ex + ey * ey;
	double u = len2 > 0.0 ? ((p[0] - a[0]) * ex + (p[1] - a[1]) * ey) / len2 : 0.0;

	u = u < 0.0 ? 0.0 : u > 1.0 ? 1.0 : u;
	return hypot(p[0] - a[0] - u * ex, p[1] - a[1] - u * ey);
}

int hl_road_set_polyline(struct hl_road *road, const double (*xy)[2], int n, double tol_m)
{
	int keep[HL_SCN_MAX_SEGMENTS + 1], nk = 2;
	bool distinct = false, split = true;
	double h_prev = 0.0;

	if (n < 2 || !(tol_m >= 0.0) || !isfinite(tol_m))
		return -EINVAL;
	for (int i = 0; i < n; i++) {
		if (!isfinite(xy[i][0]) || !isfinite(xy[i][1]))
			return -EINVAL;
		distinct |= xy[i][0] != xy[0][0] || xy[i][1] != xy[0][1];
	}
	if (!distinct)
		return -EINVAL;
	/*
	 * Douglas-Peucker without recursion: each pass splits every leg at its farthest point
	 * beyond tol (the order of the splits does not change the result). A point kept lies more
	 * than tol >= 0 from its leg, so it equals neither end: no leg of zero length arises but
	 * the first, when the line closes on itself within tol.
	 */
	keep[0] = 0;
	keep[1] = n - 1;
	while (split) {
		split = false;
		for (int j = nk - 2; j >= 0; j--) {
			const int a = keep[j], b = keep[j + 1];
			double far = tol_m;
			int at = -1;

			for (int i = a + 1; i < b; i++) {
				const double dist = seg_dist(xy[i], xy[a], xy[b]);

				if (dist > far) {
					far = dist;
					at = i;
				}
			}
			if (at < 0)
				continue;
			if (nk == HL_SCN_MAX_SEGMENTS + 1)
				return -E2BIG;
			memmove(&keep[j + 2], &keep[j + 1], sizeof(keep[0]) * (size_t)(nk - j - 1));
			keep[j + 1] = at;
			nk++;
			split = true;
		}
	}
	if (xy[keep[0]][0] == xy[keep[1]][0] && xy[keep[0]][1] == xy[keep[1]][1])
		return -EINVAL; /* nk == 2: every point within tol of a closed line's ends */
	road->x0_m = xy[keep[0]][0];
	road->y0_m = xy[keep[0]][1];
	road->n_segments = nk - 1;
	for (int j = 0; j + 1 < nk; j++) {
		const double dx = xy[keep[j + 1]][0] - xy[keep[j]][0];
		const double dy = xy[keep[j + 1]][1] - xy[keep[j]][1], h = atan2(dy, dx);

		road->seg[j] = (struct hl_road_segment){
			.kind = HL_SEG_STRAIGHT,
			.length_m = hypot(dx, dy),
			.turn = 1,
			.kink_rad = j ? remainder(h - h_prev, 2 * M_PI) : 0.0,
		};
		if (!j)
			road->heading0_rad = h;
		h_prev = h;
	}
	hl_road_layout(road);
	return 0;
}

/* The heading the road starts with, and runs on with before s = 0. */
static double start_heading(const struct hl_road *road)
{
	return road->n_segments > 0 ? road->seg[0].heading0_rad : road->heading0_rad;
}

void hl_road_centre(const struct hl_road *road, double s_m, struct hl_pose2 *ret)
{
	const struct hl_road_segment *last;
	int i;

	if (road->n_segments < 1 || s_m < 0.0) {
		const double h = start_heading(road);

		ret->x_m = road->x0_m + s_m * cos(h);
		ret->y_m = road->y0_m + s_m * sin(h);
		ret->heading_rad = h;
		return;
	}
	for (i = road->n_segments - 1; i > 0 && road->seg[i].s0_m > s_m; i--)
		;
	last = &road->seg[road->n_segments - 1];
	if (i == road->n_segments - 1 && s_m > last->s0_m + last->length_m) {
		struct hl_pose2 end;

		in_segment(last, last->length_m, &end);
		ret->x_m = end.x_m + (s_m - road->length_m) * cos(end.heading_rad);
		ret->y_m = end.y_m + (s_m - road->length_m) * sin(end.heading_rad);
		ret->heading_rad = end.heading_rad;
		return;
	}
	in_segment(&road->seg[i], s_m - road->seg[i].s0_m, ret);
}

void hl_road_point(const struct hl_road *road, double s_m, double d_m, double ret[3])
{
	struct hl_pose2 c;

	hl_road_centre(road, s_m, &c);
	ret[0] = c.x_m - d_m * sin(c.heading_rad);
	ret[1] = c.y_m + d_m * cos(c.heading_rad);
	ret[2] = 0.0;
}

/* Beyond a vertex with this kink: the sign of d (the outside of the turn), 0 without one. */
static int outside(double kink_rad)
{
	return kink_rad > 0.0 ? -1 : kink_rad < 0.0 ? 1 : 0;
}

/* Part i of the road's projection (0: run-on before s = 0, 1: after the end, 2..: segments). */
static void make_part(const struct hl_road *road, int i, struct hl_road_proj_part *ret)
{
	const struct hl_road_segment *seg;
	struct hl_pose2 mid, e;

	if (i < 2) {
		const double h = start_heading(road);

		if (i == 1)
			hl_road_centre(road, road->length_m, &e);
		*ret = (struct hl_road_proj_part){
			.arc = false,
			.s0_m = i ? road->length_m : 0.0,
			.lo_m = i ? 0.0 : -INFINITY,
			.hi_m = i ? INFINITY : 0.0,
			.x0_m = i ? e.x_m : road->x0_m,
			.y0_m = i ? e.y_m : road->y0_m,
			.c = cos(i ? e.heading_rad : h),
			.s = sin(i ? e.heading_rad : h),
			.half_m = INFINITY,
		};
		return;
	}
	seg = &road->seg[i - 2];
	in_segment(seg, seg->length_m / 2, &mid);
	in_segment(seg, seg->length_m, &e);
	*ret = (struct hl_road_proj_part){
		.arc = seg->kind == HL_SEG_ARC,
		/* the road's first kink has no vertex: the run-on before takes its heading */
		.out0 = i > 2 ? outside(seg->kink_rad) : 0,
		.out1 = i - 1 < road->n_segments ? outside(road->seg[i - 1].kink_rad) : 0,
		.s0_m = seg->s0_m,
		.lo_m = 0.0,
		.hi_m = seg->length_m,
		.x0_m = seg->x0_m,
		.y0_m = seg->y0_m,
		.c = cos(seg->heading0_rad),
		.s = sin(seg->heading0_rad),
		.mid_x_m = mid.x_m,
		.mid_y_m = mid.y_m,
		.half_m = seg->length_m / 2,
		.x1_m = e.x_m,
		.y1_m = e.y_m,
	};
	if (ret->arc) {
		/* Centre to the left (turn +1) or right; the middle's radial direction. */
		ret->turn = seg->turn;
		ret->r0_m = seg->radius_m;
		ret->cx_m = seg->x0_m - seg->turn * seg->radius_m * ret->s;
		ret->cy_m = seg->y0_m + seg->turn * seg->radius_m * ret->c;
		ret->mx = (mid.x_m - ret->cx_m) / seg->radius_m;
		ret->my = (mid.y_m - ret->cy_m) / seg->radius_m;
		ret->cos_half = cos(seg->length_m / (2.0 * seg->radius_m));
	}
}

void hl_road_proj_init(const struct hl_road *road, struct hl_road_proj *ret)
{
	ret->n = road->n_segments + 2;
	for (int i = 0; i < ret->n; i++)
		make_part(road, i, &ret->part[i]);
	/* Blocks of segments: the centroid of their middles, the farthest reach from it. */
	ret->n_blocks = 0;
	for (int first = 2; first < ret->n; first += HL_ROAD_PROJ_BLOCK) {
		struct hl_road_proj_block *b = &ret->block[ret->n_blocks++];

		b->first = first;
		b->n = ret->n - first < HL_ROAD_PROJ_BLOCK ? ret->n - first : HL_ROAD_PROJ_BLOCK;
		b->cx_m = b->cy_m = b->r_m = 0.0;
		for (int i = first; i < first + b->n; i++) {
			b->cx_m += ret->part[i].mid_x_m / b->n;
			b->cy_m += ret->part[i].mid_y_m / b->n;
		}
		for (int i = first; i < first + b->n; i++) {
			const struct hl_road_proj_part *pp = &ret->part[i];
			const double r =
				hypot(pp->mid_x_m - b->cx_m, pp->mid_y_m - b->cy_m) + pp->half_m;

			b->r_m = r > b->r_m ? r : b->r_m;
		}
		b->r_m *= 1.0 + 1e-12; /* rounding: the circle holds its parts */
	}
}

/* Part i against the best so far (index order; ties: the lower index). */
static void lateral_try(const struct hl_road_proj *p, int i, double x_m, double y_m, int hint,
			double *best, int *k, double *ret_d_m)
{
	const struct hl_road_proj_part *pp = &p->part[i];
	double dist2, d;

	if (i == hint)
		return;
	/* Every point of a part lies within half its length of its middle. */
	if (isfinite(pp->half_m)) {
		const double mx = x_m - pp->mid_x_m, my = y_m - pp->mid_y_m;
		const double lb = sqrt(mx * mx + my * my) - pp->half_m;

		if (lb > 0.0 && lb * lb >= *best)
			return;
	}
	dist2 = hl_road_part_dist2(pp, x_m, y_m, &d);
	if (dist2 < *best || (dist2 == *best && i < *k)) {
		*best = dist2;
		*k = i;
		*ret_d_m = d;
	}
}

int hl_road_proj_lateral(const struct hl_road_proj *p, double x_m, double y_m, int hint,
			 double *ret_d_m)
{
	double best = INFINITY, d;
	int k = -1;

	/* The hint first (neighbouring pixels share their part): the others are culled sooner. */
	if (hint >= 0 && hint < p->n) {
		best = hl_road_part_dist2(&p->part[hint], x_m, y_m, &d);
		k = hint;
		*ret_d_m = d;
	}
	for (int i = 0; i < p->n && i < 2; i++)
		lateral_try(p, i, x_m, y_m, hint, &best, &k, ret_d_m);
	for (int b = 0; b < p->n_blocks; b++) {
		const struct hl_road_proj_block *bl = &p->block[b];
		const double lb = hypot(x_m - bl->cx_m, y_m - bl->cy_m) - bl->r_m;

		if (lb > 0.0 && lb * lb >= best)
			continue;
		for (int i = bl->first; i < bl->first + bl->n; i++)
			lateral_try(p, i, x_m, y_m, hint, &best, &k, ret_d_m);
	}
	return k;
}

/* Slack on the bounds for rounding (m): a candidate too many costs time, one too few a pixel. */
#define CANDIDATE_SLACK_M 1e-6

static double slack_above(double least_hi)
{
	return least_hi + CANDIDATE_SLACK_M * (1.0 + least_hi);
}

/* Part i's bounds over the segment a-b (length len): lo[i] and the least upper bound. */
static void candidate_bounds(const struct hl_road_proj *p, int i, double ax, double ay, double bx,
			     double by, double len, double *lo, double *least_hi)
{
	double d;
	const double da = sqrt(hl_road_part_dist2(&p->part[i], ax, ay, &d));
	const double db = sqrt(hl_road_part_dist2(&p->part[i], bx, by, &d));
	const double hi = (da + db + len) / 2;

	lo[i] = (da + db - len) / 2;
	*least_hi = hi < *least_hi ? hi : *least_hi;
}

int hl_road_proj_candidates(const struct hl_road_proj *p, double ax, double ay, double bx,
			    double by, int *ret)
{
	const double len = hypot(bx - ax, by - ay);
	double lo[HL_SCN_MAX_SEGMENTS + 2], blo[HL_ROAD_PROJ_MAX_BLOCKS], least_hi = INFINITY;
	int n = 0;

	for (int i = 0; i < p->n; i++)
		lo[i] = INFINITY;
	for (int i = 0; i < p->n && i < 2; i++)
		candidate_bounds(p, i, ax, ay, bx, by, len, lo, &least_hi);
	/* A block's lower bound from its circle; then the blocks nearest first. */
	for (int b = 0; b < p->n_blocks; b++) {
		const struct hl_road_proj_block *bl = &p->block[b];

		blo[b] =
			(hypot(ax - bl->cx_m, ay - bl->cy_m) + hypot(bx - bl->cx_m, by - bl->cy_m) -
			 len) / 2 -
			bl->r_m;
	}
	for (;;) {
		int near = -1;

		for (int b = 0; b < p->n_blocks; b++)
			if (!isnan(blo[b]) && (near < 0 || blo[b] < blo[near]))
				near = b;
		if (near < 0 || blo[near] > slack_above(least_hi))
			break;
		blo[near] = NAN; /* judged */
		for (int i = p->block[near].first; i < p->block[near].first + p->block[near].n; i++)
			candidate_bounds(p, i, ax, ay, bx, by, len, lo, &least_hi);
	}
	for (int i = 0; i < p->n; i++)
		if (lo[i] <= slack_above(least_hi))
			ret[n++] = i;
	return n;
}

static double part_s(const struct hl_road_proj_part *pp, double x_m, double y_m)
{
	double u;

	if (!pp->arc) {
		u = (x_m - pp->x0_m) * pp->c + (y_m - pp->y0_m) * pp->s;
	} else {
		const double vx = x_m - pp->cx_m, vy = y_m - pp->cy_m;
		const double a = atan2(pp->mx * vy - pp->my * vx, pp->mx * vx + pp->my * vy);

		u = pp->hi_m / 2 + pp->turn * pp->r0_m * a;
	}
	u = u < pp->lo_m ? pp->lo_m : u > pp->hi_m ? pp->hi_m : u;
	return pp->s0_m + u;
}

double hl_road_proj_s(const struct hl_road_proj *p, int part, double x_m, double y_m)
{
	return part_s(&p->part[part], x_m, y_m);
}

void hl_road_project(const struct hl_road *road, double x_m, double y_m, double *ret_s_m,
		     double *ret_d_m)
{
	struct hl_road_proj_part pp, best_pp;
	double best, d;

	/* Each part made on the fly (no table on the stack); ties: the lower index. */
	make_part(road, 0, &best_pp);
	best = hl_road_part_dist2(&best_pp, x_m, y_m, ret_d_m);
	for (int i = 1; i < road->n_segments + 2; i++) {
		double dist2;

		make_part(road, i, &pp);
		dist2 = hl_road_part_dist2(&pp, x_m, y_m, &d);
		if (dist2 < best) {
			best = dist2;
			best_pp = pp;
			*ret_d_m = d;
		}
	}
	*ret_s_m = part_s(&best_pp, x_m, y_m);
}

double hl_road_half_width(const struct hl_road *road)
{
	return road->lanes * road->lane_width_m / 2;
}

double hl_road_lane_offset(const struct hl_road *road, int lane)
{
	return -hl_road_half_width(road) + (lane - 0.5) * road->lane_width_m;
}

int hl_road_post_count(const struct hl_road *road)
{
	if (!(road->post_spacing_m > 0.0))
		return 0;
	return (int)floor(road->length_m / road->post_spacing_m + 1e-9);
}

void hl_road_post(const struct hl_road *road, int k, int side, double ret[3])
{
	const double d = side * (hl_road_half_width(road) + road->post_offset_m);
	const double s = (k + 1) * road->post_spacing_m;
	int i;

	hl_road_point(road, s, d, ret);
	for (i = road->n_segments - 1; i > 0 && road->seg[i].s0_m > s; i--)
		;
	/* The vertices at the start of that segment and of the next. */
	for (int j = i; j <= i + 1 && j < road->n_segments; j++) {
		const struct hl_road_segment *seg = &road->seg[j];
		const double kink = seg->kink_rad, h = seg->heading0_rad - kink / 2;

		/* the inside (d on the side the road turns to), within the offset lines' crossing */
		if (j == 0 || kink == 0.0 || (kink > 0.0) != (d > 0.0) ||
		    fabs(s - seg->s0_m) >= fabs(d) * tan(fabs(kink) / 2))
			continue;
		ret[0] = seg->x0_m - d / cos(kink / 2) * sin(h);
		ret[1] = seg->y0_m + d / cos(kink / 2) * cos(h);
		return;
	}
}

void hl_speed_layout(struct hl_speed_profile *sp)
{
	sp->dist_m[0] = 0.0;
	for (int i = 1; i < sp->n; i++)
		sp->dist_m[i] = sp->dist_m[i - 1] + (sp->v_mps[i - 1] + sp->v_mps[i]) / 2 *
							    (sp->t_s[i] - sp->t_s[i - 1]);
}

/* Distance from the profile's first point to t: exact for a piecewise-linear speed. */
static double from_first(const struct hl_speed_profile *sp, double t)
{
	const int n = sp->n;
	int i;

	if (t <= sp->t_s[0])
		return sp->v_mps[0] * (t - sp->t_s[0]);
	if (t >= sp->t_s[n - 1])
		return sp->dist_m[n - 1] + sp->v_mps[n - 1] * (t - sp->t_s[n - 1]);
	for (i = n - 2; i > 0 && sp->t_s[i] > t; i--)
		;
	const double tau = t - sp->t_s[i], dt = sp->t_s[i + 1] - sp->t_s[i];
	const double a = (sp->v_mps[i + 1] - sp->v_mps[i]) / dt;

	return sp->dist_m[i] + sp->v_mps[i] * tau + a * tau * tau / 2;
}

double hl_speed_distance(const struct hl_speed_profile *sp, double t_s)
{
	return from_first(sp, t_s) - from_first(sp, 0.0);
}

double hl_speed_at(const struct hl_speed_profile *sp, double t_s)
{
	const int n = sp->n;
	int i;

	if (t_s <= sp->t_s[0])
		return sp->v_mps[0];
	if (t_s >= sp->t_s[n - 1])
		return sp->v_mps[n - 1];
	for (i = n - 2; i > 0 && sp->t_s[i] > t_s; i--)
		;
	return sp->v_mps[i] + (sp->v_mps[i + 1] - sp->v_mps[i]) * (t_s - sp->t_s[i]) /
				      (sp->t_s[i + 1] - sp->t_s[i]);
}

/* Whether leg i (waypoint i-1 to i) moves; its heading into ret. */
static int leg_heading(const struct hl_path *path, int i, double *ret)
{
	const double dx = path->wp[i].x_m - path->wp[i - 1].x_m;
	const double dy = path->wp[i].y_m - path->wp[i - 1].y_m;

	if (hypot(dx, dy) <= 1e-9)
		return 0;
	*ret = atan2(dy, dx);
	return 1;
}

void hl_waypoints_layout(struct hl_path *path, double heading_rad)
{
	double h = 0.0, first;
	int i;

	/* Before the first move: the given heading, else that of the first move, else 0. */
	for (i = 1; i < path->n_waypoints; i++)
		if (leg_heading(path, i, &first)) {
			h = first;
			break;
		}
	if (!isnan(heading_rad))
		h = heading_rad;
	path->wp[0].heading_rad = h;
	/* Each waypoint: the heading of the leg that ends there; a standing leg keeps it. */
	for (i = 1; i < path->n_waypoints; i++) {
		leg_heading(path, i, &h);
		path->wp[i].heading_rad = h;
	}
}

static void waypoint_pose(const struct hl_path *path, double t, struct hl_body_pose *ret)
{
	const struct hl_waypoint *wp = path->wp;
	const int n = path->n_waypoints;
	int i;

	ret->pos_m[2] = 0.0;
	ret->s_m = NAN;
	ret->speed_mps = 0.0;
	if (t <= wp[0].t_s || n == 1) {
		ret->pos_m[0] = wp[0].x_m;
		ret->pos_m[1] = wp[0].y_m;
		ret->heading_rad = wp[0].heading_rad;
		return;
	}
	if (t >= wp[n - 1].t_s) {
		ret->pos_m[0] = wp[n - 1].x_m;
		ret->pos_m[1] = wp[n - 1].y_m;
		ret->heading_rad = wp[n - 1].heading_rad;
		return;
	}
	for (i = n - 2; i > 0 && wp[i].t_s > t; i--)
		;
	const double dt = wp[i + 1].t_s - wp[i].t_s, f = (t - wp[i].t_s) / dt;
	const double dx = wp[i + 1].x_m - wp[i].x_m, dy = wp[i + 1].y_m - wp[i].y_m;

	ret->pos_m[0] = wp[i].x_m + f * dx;
	ret->pos_m[1] = wp[i].y_m + f * dy;
	ret->heading_rad = wp[i + 1].heading_rad;
	ret->speed_mps = hypot(dx, dy) / dt;
}

void hl_path_pose(const struct hl_road *road, const struct hl_path *path, double t_s,
		  struct hl_body_pose *ret)
{
	struct hl_pose2 c;
	double d;

	if (path->kind == HL_PATH_WAYPOINTS) {
		waypoint_pose(path, t_s, ret);
		return;
	}
	ret->s_m = path->start_s_m + path->direction * hl_speed_distance(&path->speed, t_s);
	ret->speed_mps = hl_speed_at(&path->speed, t_s);
	d = hl_road_lane_offset(road, path->lane) + path->offset_m;
	hl_road_centre(road, ret->s_m, &c);
	ret->pos_m[0] = c.x_m - d * sin(c.heading_rad);
	ret->pos_m[1] = c.y_m + d * cos(c.heading_rad);
	ret->pos_m[2] = 0.0;
	ret->heading_rad = path->direction < 0 ? c.heading_rad + M_PI : c.heading_rad;
}

void hl_body_to_world(const struct hl_body_pose *pose, const double p[3], double ret[3])
{
	const double c = cos(pose->heading_rad), s = sin(pose->heading_rad);

	ret[0] = pose->pos_m[0] + p[0] * c - p[1] * s;
	ret[1] = pose->pos_m[1] + p[0] * s + p[1] * c;
	ret[2] = pose->pos_m[2] + p[2];
}
