/* SPDX-License-Identifier: MIT */
/*
 * The geometry of a scenario (render/scenario.h, docs/scenarios.md): the road's centre line as
 * a function of the distance s along it, lanes and posts, and where the ego vehicle, its lamps
 * and camera, each road user and its eye are at scenario time t. Exact closed forms in double
 * precision: arcs by their chord, a piecewise-linear speed integrated to a piecewise-quadratic
 * distance.
 *
 * Beyond its ends the road runs on straight: before s = 0 back along the start heading, after
 * its length along the end heading.
 *
 * None of the per-frame calls allocates; a road laid out by hl_road_layout() (the parser does
 * it) is needed. Thread-safety: pure functions of read-only data; any thread.
 */
#ifndef HL_RENDER_SCENARIO_GEOM_H
#define HL_RENDER_SCENARIO_GEOM_H

#include <stdbool.h>

#include "render/camera.h"
#include "render/scenario.h"

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
 * segment, or the straight run-on before s = 0 or after the road's end). An arc's points are
 * measured by the angle about its centre (arcs up to a full turn). Allocates nothing.
 */
void hl_road_project(const struct hl_road *road, double x_m, double y_m, double *ret_s_m,
		     double *ret_d_m);

/*
 * The same in two steps over a table made once per road, for many points (a ray cast frame):
 * the lateral offset d and the part of the road nearest (no atan2), then s only where it is
 * needed. The parts are the run-on before s = 0, the one after the end, and the segments.
 */
struct hl_road_proj_part {
	bool arc;
	int turn; /* arc: +1 left, -1 right */
	double s0_m, lo_m, hi_m; /* s = s0 + u, u in [lo, hi] along the part */
	double x0_m, y0_m, c, s; /* start and cos, sin of its heading there */
	double x1_m, y1_m; /* end (a segment) */
	double mid_x_m, mid_y_m, half_m; /* middle and half the length (run-ons: infinite) */
	double cx_m, cy_m, r0_m, mx, my, cos_half; /* arc: centre, radius, middle's direction */
};

struct hl_road_proj {
	int n;
	struct hl_road_proj_part part[HL_SCN_MAX_SEGMENTS + 2];
};

void hl_road_proj_init(const struct hl_road *road, struct hl_road_proj *ret);
/*
 * d of (x, y) and the index of the nearest part (ties: the lower index). hint: a part to try
 * first (e.g. the previous point's), or -1.
 */
int hl_road_proj_lateral(const struct hl_road_proj *p, double x_m, double y_m, int hint,
			 double *ret_d_m);
/* s of (x, y) on part (as hl_road_proj_lateral() returned it). */
double hl_road_proj_s(const struct hl_road_proj *p, int part, double x_m, double y_m);
/* Lateral offset of lane (1.. from the right edge)'s centre line from the road's centre. */
double hl_road_lane_offset(const struct hl_road *road, int lane);
/* Half the road's width: its edges are at d = ±this. */
double hl_road_half_width(const struct hl_road *road);
/* Posts per edge (at s = spacing, 2 spacing, ... up to the road's length); 0 without posts. */
int hl_road_post_count(const struct hl_road *road);
/* The foot of post k (0-based) on side +1 (left edge) or -1 (right edge). */
void hl_road_post(const struct hl_road *road, int k, int side, double ret[3]);

/* Distance covered from time 0 to t (negative before 0) under the profile; speed at t. */
double hl_speed_distance(const struct hl_speed_profile *sp, double t_s);
double hl_speed_at(const struct hl_speed_profile *sp, double t_s);

/* Where a path puts its body at t on this road. */
void hl_path_pose(const struct hl_road *road, const struct hl_path *path, double t_s,
		  struct hl_body_pose *ret);
/* A point given in a body's frame (x forward, y left, z up) in world coordinates. */
void hl_body_to_world(const struct hl_body_pose *pose, const double local_m[3], double ret[3]);

void hl_scenario_ego_pose(const struct hl_scenario *sc, double t_s, struct hl_body_pose *ret);
/* The ego lamps' poses in the world frame (position world, yaw from world +x). */
void hl_scenario_ego_lamps(const struct hl_scenario *sc, double t_s, struct hl_lamp_pose ret[2]);
/* The driver's camera in the world frame at width x height. */
void hl_scenario_ego_camera(const struct hl_scenario *sc, double t_s, int width, int height,
			    struct hl_camera *ret);
/* Road user i (0-based, < n_actors) at t, and its eye point in the world. */
void hl_scenario_actor_pose(const struct hl_scenario *sc, int i, double t_s,
			    struct hl_body_pose *ret);
void hl_scenario_actor_eye(const struct hl_scenario *sc, int i, double t_s, double ret[3]);

#endif
