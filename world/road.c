/* SPDX-License-Identifier: MIT */
/* Road, path and body geometry of a scenario: closed forms, no allocation. */
#include "world/road.h"

#include <math.h>
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

		seg->s0_m = s;
		seg->x0_m = p.x_m;
		seg->y0_m = p.y_m;
		seg->heading0_rad = p.heading_rad;
		in_segment(seg, seg->length_m, &p);
		s += seg->length_m;
	}
	road->length_m = s;
}

void hl_road_centre(const struct hl_road *road, double s_m, struct hl_pose2 *ret)
{
	const struct hl_road_segment *last;
	int i;

	if (road->n_segments < 1 || s_m < 0.0) {
		ret->x_m = road->x0_m + s_m * cos(road->heading0_rad);
		ret->y_m = road->y0_m + s_m * sin(road->heading0_rad);
		ret->heading_rad = road->heading0_rad;
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

void hl_road_proj_init(const struct hl_road *road, struct hl_road_proj *ret)
{
	struct hl_pose2 end;
	int n = 0;

	/* The run-on before s = 0 and after the end, then the segments. */
	ret->part[n++] = (struct hl_road_proj_part){
		.arc = false,
		.s0_m = 0.0,
		.lo_m = -INFINITY,
		.hi_m = 0.0,
		.x0_m = road->x0_m,
		.y0_m = road->y0_m,
		.c = cos(road->heading0_rad),
		.s = sin(road->heading0_rad),
		.half_m = INFINITY,
	};
	hl_road_centre(road, road->length_m, &end);
	ret->part[n++] = (struct hl_road_proj_part){
		.arc = false,
		.s0_m = road->length_m,
		.lo_m = 0.0,
		.hi_m = INFINITY,
		.x0_m = end.x_m,
		.y0_m = end.y_m,
		.c = cos(end.heading_rad),
		.s = sin(end.heading_rad),
		.half_m = INFINITY,
	};
	for (int i = 0; i < road->n_segments; i++) {
		const struct hl_road_segment *seg = &road->seg[i];
		struct hl_road_proj_part *pp = &ret->part[n++];
		struct hl_pose2 mid, e;

		in_segment(seg, seg->length_m / 2, &mid);
		in_segment(seg, seg->length_m, &e);
		*pp = (struct hl_road_proj_part){
			.arc = seg->kind == HL_SEG_ARC,
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
		if (pp->arc) {
			/* Centre to the left (turn +1) or right; the middle's radial direction. */
			pp->turn = seg->turn;
			pp->r0_m = seg->radius_m;
			pp->cx_m = seg->x0_m - seg->turn * seg->radius_m * pp->s;
			pp->cy_m = seg->y0_m + seg->turn * seg->radius_m * pp->c;
			pp->mx = (mid.x_m - pp->cx_m) / seg->radius_m;
			pp->my = (mid.y_m - pp->cy_m) / seg->radius_m;
			pp->cos_half = cos(seg->length_m / (2.0 * seg->radius_m));
		}
	}
	ret->n = n;
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
	for (int i = 0; i < p->n; i++) {
		const struct hl_road_proj_part *pp = &p->part[i];
		double dist2;

		if (i == hint)
			continue;
		/* Every point of a part lies within half its length of its middle. */
		if (isfinite(pp->half_m)) {
			const double mx = x_m - pp->mid_x_m, my = y_m - pp->mid_y_m;
			const double lb = sqrt(mx * mx + my * my) - pp->half_m;

			if (lb > 0.0 && lb * lb >= best)
				continue;
		}
		dist2 = hl_road_part_dist2(pp, x_m, y_m, &d);
		if (dist2 < best || (dist2 == best && i < k)) {
			best = dist2;
			k = i;
			*ret_d_m = d;
		}
	}
	return k;
}

/* Slack on the bounds for rounding (m): a candidate too many costs time, one too few a pixel. */
#define CANDIDATE_SLACK_M 1e-6

int hl_road_proj_candidates(const struct hl_road_proj *p, double ax, double ay, double bx,
			    double by, int *ret)
{
	const double len = hypot(bx - ax, by - ay);
	double lo[HL_SCN_MAX_SEGMENTS + 2], least_hi = INFINITY, d;
	int n = 0;

	for (int i = 0; i < p->n; i++) {
		const double da = sqrt(hl_road_part_dist2(&p->part[i], ax, ay, &d));
		const double db = sqrt(hl_road_part_dist2(&p->part[i], bx, by, &d));
		const double hi = (da + db + len) / 2;

		lo[i] = (da + db - len) / 2;
		least_hi = hi < least_hi ? hi : least_hi;
	}
	for (int i = 0; i < p->n; i++)
		if (lo[i] <= least_hi + CANDIDATE_SLACK_M * (1.0 + least_hi))
			ret[n++] = i;
	return n;
}

double hl_road_proj_s(const struct hl_road_proj *p, int part, double x_m, double y_m)
{
	const struct hl_road_proj_part *pp = &p->part[part];
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

void hl_road_project(const struct hl_road *road, double x_m, double y_m, double *ret_s_m,
		     double *ret_d_m)
{
	struct hl_road_proj p;
	int k;

	hl_road_proj_init(road, &p);
	k = hl_road_proj_lateral(&p, x_m, y_m, -1, ret_d_m);
	*ret_s_m = hl_road_proj_s(&p, k, x_m, y_m);
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

	hl_road_point(road, (k + 1) * road->post_spacing_m, d, ret);
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
