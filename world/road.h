/* SPDX-License-Identifier: MIT */
/*
 * The road of a scenario (world/scenario.h, docs/scenarios.md): its segments, lanes and
 * markings, its centre line as a function of the distance s along it, lanes and posts, the
 * projection of a point onto it, and the paths and speed profiles along it (a body's pose at
 * time t). Where the ego vehicle, its lamps and camera and each road user are in a scenario is
 * world/world.h's. Exact closed forms in double
 * precision: arcs by their chord, a piecewise-linear speed integrated to a piecewise-quadratic
 * distance.
 *
 * Beyond its ends the road runs on straight: before s = 0 back along the first segment's start
 * heading, after its length along the end heading.
 *
 * Kinks: a segment may start with a heading change (kink_rad; a polyline's legs,
 * hl_road_set_polyline()). The centre line stays continuous; its heading jumps there (at the
 * vertex's s, hl_road_centre() gives the outgoing leg's). Ground points in the wedge on the
 * outside of a kink, beyond the end of one leg and before the start of the next, are nearest to
 * the vertex itself: their s is the vertex's, their d the distance to the vertex, negative
 * (right) at a left kink and positive at a right one, so |d| is the distance to the centre line
 * everywhere and lines of constant |d| (edges, markings) go round the vertex on a circle. There
 * hl_road_point() is not the inverse of the projection. On the inside of a kink the offset
 * lines of the two legs cross; a post there stands at the crossing (hl_road_post()).
 *
 * None of the per-frame calls allocates; a road laid out by hl_road_layout() (the parser does
 * it) is needed. Thread-safety: pure functions of read-only data; any thread.
 */
#ifndef HL_WORLD_ROAD_H
#define HL_WORLD_ROAD_H

#include <math.h>
#include <stdbool.h>

#define HL_SCN_MAX_SEGMENTS 256
#define HL_SCN_MAX_POINTS 64 /* speed profile points, waypoints */

enum hl_seg_kind { HL_SEG_STRAIGHT, HL_SEG_ARC };

struct hl_road_segment {
	enum hl_seg_kind kind;
	double length_m;
	double radius_m; /* arc */
	int turn; /* arc: +1 left (counter-clockwise seen from above), -1 right */
	double kink_rad; /* heading change at its start, + left (0: continues the one before) */
	/* derived: where it starts */
	double s0_m, x0_m, y0_m, heading0_rad;
	int line; /* where it is in the file */
};

enum hl_marking { HL_MARK_NONE, HL_MARK_SOLID, HL_MARK_DASHED };

struct hl_road {
	double x0_m, y0_m, heading0_rad; /* where s = 0 is, and the heading there */
	int n_segments;
	struct hl_road_segment seg[HL_SCN_MAX_SEGMENTS];
	double length_m; /* the sum of the segments */
	int lanes;
	double lane_width_m;
	enum hl_marking edge, separator; /* edge lines; lines between lanes */
	double edge_line_width_m, separator_line_width_m;
	double dash_m, gap_m; /* dashed lines */
	double post_spacing_m; /* 0: no posts */
	double post_offset_m; /* beyond the road edge */
	double post_height_m;
};

/* A speed profile: piecewise linear in time, held before the first and after the last point. */
struct hl_speed_profile {
	int n; /* >= 1; a constant speed is one point */
	double t_s[HL_SCN_MAX_POINTS];
	double v_mps[HL_SCN_MAX_POINTS];
	double dist_m[HL_SCN_MAX_POINTS]; /* derived: distance from t_s[0] to t_s[i] */
};

struct hl_waypoint {
	double t_s, x_m, y_m;
	double heading_rad; /* derived: of the leg that ends here (the first: of the first move) */
};

enum hl_path_kind { HL_PATH_LANE, HL_PATH_WAYPOINTS };

struct hl_path {
	enum hl_path_kind kind;
	/* lane: along the road, toward increasing s (-1: decreasing, oncoming) */
	int lane;
	double offset_m; /* extra lateral offset from the lane centre, positive left of the road */
	double start_s_m; /* s at scenario time 0 (of the vehicle's front) */
	int direction;
	struct hl_speed_profile speed;
	/* waypoints: world x, y at strictly increasing times, linear between, held at the ends */
	int n_waypoints;
	struct hl_waypoint wp[HL_SCN_MAX_POINTS];
};

/* A position on the ground and a heading (radians, counter-clockwise from world +x). */
struct hl_pose2 {
	double x_m, y_m;
	double heading_rad;
};

/* A body (the ego vehicle, a road user) at a time: its frame's origin and heading. */
struct hl_body_pose {
	double pos_m[3]; /* world; z 0 */
	double heading_rad; /* the body's +x */
	double s_m; /* road s of the origin on a lane path; NAN on waypoints */
	double speed_mps;
};

/* Derives each segment's start (s, position, heading) and the road's length. */
void hl_road_layout(struct hl_road *road);
/*
 * Makes the road's centre line the polyline through xy[0 .. n - 1] (world, metres): s = 0 at
 * xy[0], heading0 that of the first leg, one straight segment per leg with the heading change
 * at each vertex as its kink. The points are first simplified (Douglas-Peucker: every point
 * dropped lies within tol_m of the leg that replaces it; the first and last point are kept)
 * and legs of zero length dropped, so that it fits HL_SCN_MAX_SEGMENTS. Only the geometry
 * (start, segments, length) is set, and laid out; lanes, markings and posts are left as they
 * are. 0; -EINVAL for a non-finite coordinate, fewer than 2 distinct points or tol_m < 0;
 * -E2BIG when more than HL_SCN_MAX_SEGMENTS legs remain. The road is untouched on failure.
 * Allocates nothing.
 */
int hl_road_set_polyline(struct hl_road *road, const double (*xy)[2], int n, double tol_m);
/*
 * Derives a speed profile's distances, and a waypoint path's headings: each waypoint's is that
 * of the leg ending there (a standing leg keeps the one before); before the first move,
 * heading_rad, or with NAN the first move's heading (0 for a path that never moves).
 */
void hl_speed_layout(struct hl_speed_profile *sp);
void hl_waypoints_layout(struct hl_path *path, double heading_rad);

/* The centre line at s. */
void hl_road_centre(const struct hl_road *road, double s_m, struct hl_pose2 *ret);
/* The ground point at s, d metres to the left of the centre line (z = 0). */
void hl_road_point(const struct hl_road *road, double s_m, double d_m, double ret[3]);
/*
 * The inverse of hl_road_point(): the road coordinates (s, d) of the ground point (x, y) (world,
 * metres), exactly: the foot of the perpendicular on the nearest part of the centre line (a
 * segment, or the straight run-on before s = 0 or after the road's end); in the wedge outside a
 * kink the vertex (see above). An arc's points are measured by the angle about its centre
 * (arcs up to a full turn). Allocates nothing and needs no table (each part is made on the
 * fly).
 */
void hl_road_project(const struct hl_road *road, double x_m, double y_m, double *ret_s_m,
		     double *ret_d_m);

/*
 * The same in two steps over a table made once per road, for many points (a ray cast frame):
 * the lateral offset d and the part of the road nearest (no atan2), then s only where it is
 * needed. The parts are the run-on before s = 0, the one after the end, and the segments; the
 * segments in blocks of HL_ROAD_PROJ_BLOCK with a circle holding them, so that the search for
 * the nearest skips far blocks whole. The table is large (tens of kB): make it once, keep it
 * off the stack.
 */
#define HL_ROAD_PROJ_BLOCK 16 /* segments per block */
#define HL_ROAD_PROJ_MAX_BLOCKS \
	((HL_SCN_MAX_SEGMENTS + HL_ROAD_PROJ_BLOCK - 1) / HL_ROAD_PROJ_BLOCK)

struct hl_road_proj_part {
	bool arc;
	int turn; /* arc: +1 left, -1 right */
	/*
	 * At an end (0: start, 1: end) that is a kink's vertex: the sign of d beyond it (the
	 * outside of the turn), d there being the distance to the vertex; 0 elsewhere.
	 */
	int out0, out1;
	double s0_m, lo_m, hi_m; /* s = s0 + u, u in [lo, hi] along the part */
	double x0_m, y0_m, c, s; /* start and cos, sin of its heading there */
	double x1_m, y1_m; /* end (a segment) */
	double mid_x_m, mid_y_m, half_m; /* middle and half the length (run-ons: infinite) */
	double cx_m, cy_m, r0_m, mx, my, cos_half; /* arc: centre, radius, middle's direction */
};

struct hl_road_proj_block {
	int first, n; /* parts first .. first + n - 1 */
	double cx_m, cy_m, r_m; /* every point of them lies within r of (cx, cy) */
};

struct hl_road_proj {
	int n;
	struct hl_road_proj_part part[HL_SCN_MAX_SEGMENTS + 2];
	int n_blocks;
	struct hl_road_proj_block block[HL_ROAD_PROJ_MAX_BLOCKS];
};

void hl_road_proj_init(const struct hl_road *road, struct hl_road_proj *ret);
/*
 * d of (x, y) and the index of the nearest part (ties: the lower index). hint: a part to try
 * first (e.g. the previous point's), or -1.
 */
int hl_road_proj_lateral(const struct hl_road_proj *p, double x_m, double y_m, int hint,
			 double *ret_d_m);
/*
 * The parts that can be nearest to some point of the segment (ax, ay)-(bx, by) (e.g. the
 * ground points of a run of pixels in one image row, which lie on a line), in index order,
 * into ret (room for p->n); returns how many (at least one). A distance is 1-Lipschitz: for a
 * point q of the segment of length L, |D_i(q) - D_i(a)| <= |qa|, so D_i(q) >= (D_i(a) +
 * D_i(b) - L) / 2 and D_i(q) <= (D_i(a) + D_i(b) + L) / 2; a part whose lower bound exceeds
 * the least upper bound is never the nearest (nor tied with it). A block of segments is judged
 * first by its circle (the same bound with D >= |q - c| - r) and skipped whole when it is
 * beyond; the blocks nearest by that bound are judged first.
 */
int hl_road_proj_candidates(const struct hl_road_proj *p, double ax, double ay, double bx,
			    double by, int *ret);
/* Squared distance from (x, y) to part pp and the lateral offset d (inline: per pixel). */
static inline double hl_road_part_dist2(const struct hl_road_proj_part *pp, double x, double y,
					double *ret_d)
{
	if (!pp->arc) {
		const double dx = x - pp->x0_m, dy = y - pp->y0_m;
		const double u = dx * pp->c + dy * pp->s, d = -dx * pp->s + dy * pp->c;
		const double uc = u < pp->lo_m ? pp->lo_m : u > pp->hi_m ? pp->hi_m : u;
		const double dist2 = (u - uc) * (u - uc) + d * d;
		const int out = u < pp->lo_m ? pp->out0 : u > pp->hi_m ? pp->out1 : 0;

		*ret_d = out ? out * sqrt(dist2) : d;
		return dist2;
	}
	const double vx = x - pp->cx_m, vy = y - pp->cy_m, r = sqrt(vx * vx + vy * vy);

	*ret_d = pp->turn * (pp->r0_m - r);
	/* Within the arc's sector: the angle from its middle at most half its sweep. */
	if (vx * pp->mx + vy * pp->my >= r * pp->cos_half)
		return *ret_d * *ret_d;
	/* Beyond an end: the nearer end point is the nearest point of this arc. */
	{
		const double a = (x - pp->x0_m) * (x - pp->x0_m) + (y - pp->y0_m) * (y - pp->y0_m);
		const double b = (x - pp->x1_m) * (x - pp->x1_m) + (y - pp->y1_m) * (y - pp->y1_m);
		const int out = a < b ? pp->out0 : pp->out1;

		if (out)
			*ret_d = out * sqrt(a < b ? a : b);
		return a < b ? a : b;
	}
}

/*
 * As hl_road_proj_lateral() among the parts cand[0 .. n_cand - 1] (index order) only: the
 * same result for any point of the segment they were chosen for. Inline: a ray cast calls it
 * per pixel.
 */
static inline int hl_road_proj_lateral_among(const struct hl_road_proj *p, const int *cand,
					     int n_cand, double x_m, double y_m, int hint,
					     double *ret_d_m)
{
	double best = INFINITY, d;
	int k = -1;

	for (int j = 0; j < n_cand; j++)
		if (cand[j] == hint) {
			best = hl_road_part_dist2(&p->part[hint], x_m, y_m, &d);
			k = hint;
			*ret_d_m = d;
			break;
		}
	for (int j = 0; j < n_cand; j++) {
		const int i = cand[j];
		double dist2;

		if (i == hint)
			continue;
		dist2 = hl_road_part_dist2(&p->part[i], x_m, y_m, &d);
		if (dist2 < best || (dist2 == best && i < k)) {
			best = dist2;
			k = i;
			*ret_d_m = d;
		}
	}
	return k;
}

/* s of (x, y) on part (as hl_road_proj_lateral() returned it). */
double hl_road_proj_s(const struct hl_road_proj *p, int part, double x_m, double y_m);
/* Lateral offset of lane (1.. from the right edge)'s centre line from the road's centre. */
double hl_road_lane_offset(const struct hl_road *road, int lane);
/* Half the road's width: its edges are at d = ±this. */
double hl_road_half_width(const struct hl_road *road);
/* Posts per edge (at s = spacing, 2 spacing, ... up to the road's length); 0 without posts. */
int hl_road_post_count(const struct hl_road *road);
/*
 * The foot of post k (0-based) on side +1 (left edge) or -1 (right edge): hl_road_point(), but
 * on the inside of a kink, nearer the vertex than where the two legs' offset lines cross, at
 * that crossing (not on the other leg's road).
 */
void hl_road_post(const struct hl_road *road, int k, int side, double ret[3]);

/* Distance covered from time 0 to t (negative before 0) under the profile; speed at t. */
double hl_speed_distance(const struct hl_speed_profile *sp, double t_s);
double hl_speed_at(const struct hl_speed_profile *sp, double t_s);

/* Where a path puts its body at t on this road. */
void hl_path_pose(const struct hl_road *road, const struct hl_path *path, double t_s,
		  struct hl_body_pose *ret);
/* A point given in a body's frame (x forward, y left, z up) in world coordinates. */
void hl_body_to_world(const struct hl_body_pose *pose, const double local_m[3], double ret[3]);

#endif
