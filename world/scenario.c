/* SPDX-License-Identifier: MIT */
/* Scenario files (docs/scenarios.md) read with jansson and checked key by key. */
#include "world/scenario.h"
#include "world/track.h"

#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/json_check.h"
#include "base/share_dir.h"
#include "world/road.h"

#define DEG (M_PI / 180.0)
#define FORMAT_VERSION 1
#define MAX_DURATION_S 3600.0
#define MAX_S_M 100000.0 /* road coordinates and world positions, |value| */
#define MAX_SPEED_MPS 100.0
#define CONNECT_TOL_M 1e-3 /* a segment's stated start_s_m against the previous end */

static const struct hl_json_range r_length = { 0.0, MAX_S_M, true, "m" };
static const struct hl_json_range r_s = { -MAX_S_M, MAX_S_M, false, "m" };
static const struct hl_json_range r_time = { 0.0, MAX_DURATION_S, false, "s" };
static const struct hl_json_range r_speed = { 0.0, MAX_SPEED_MPS, false, "m/s" };
static const struct hl_json_range r_heading = { -360.0, 360.0, false, "degrees" };
static const struct hl_json_range r_vehicle[3] = { { -30.0, 20.0, false, "m" },
						   { -5.0, 5.0, false, "m" },
						   { 0.0, 5.0, false, "m" } };

#define MAX_POLYLINE_POINTS 100000
#define POLYLINE_TOL_M 0.01 /* default simplification tolerance of a polyline */

/* The segment at path p, {"kind": "polyline", "points_m": [[x, y], ...], "tolerance_m"}. */
static int parse_polyline(const struct hl_json_ctx *c, const char *p, const struct json_t *o,
			  struct hl_road *road)
{
	static const char *const keys[] = { "kind", "points_m", "tolerance_m", NULL };
	static const struct hl_json_range r_tol = { 0.0, 1.0, false, "m" };
	const struct json_t *pts = json_object_get(o, "points_m");
	char sub[HL_JSON_PATH_MAX], q[HL_JSON_PATH_MAX];
	double tol = POLYLINE_TOL_M, (*xy)[2];
	size_t n;
	int rc;

	if (hl_json_check_object(c, p, o, keys) < 0 ||
	    hl_json_get_number(c, p, o, "tolerance_m", false, &r_tol, &tol) < 0)
		return -EBADMSG;
	hl_json_join(sub, sizeof(sub), p, "points_m");
	if (!pts)
		return hl_json_fail(c, sub, "missing: expected [[x, y], ...] in m, 2 to %d points",
				    MAX_POLYLINE_POINTS);
	n = json_is_array(pts) ? json_array_size(pts) : 0;
	if (!json_is_array(pts) || n < 2 || n > MAX_POLYLINE_POINTS)
		return hl_json_fail(c, sub, "expected [[x, y], ...] in m, 2 to %d points, found %s",
				    MAX_POLYLINE_POINTS,
				    json_is_array(pts) ? "too few or too many" :
							 hl_json_type_name(pts));
	xy = malloc(sizeof(*xy) * n);
	if (!xy)
		return -ENOMEM;
	for (size_t i = 0; i < n; i++) {
		const struct json_t *pt = json_array_get(pts, i);

		hl_json_index(q, sizeof(q), sub, i);
		if (!json_is_array(pt) || json_array_size(pt) != 2) {
			free(xy);
			return hl_json_fail(c, q, "expected a point [x, y] in m, found %s",
					    json_is_array(pt) ? "another number of values" :
								hl_json_type_name(pt));
		}
		for (size_t k = 0; k < 2; k++) {
			char r[HL_JSON_PATH_MAX];

			hl_json_index(r, sizeof(r), q, k);
			if (hl_json_number(c, r, json_array_get(pt, k), &r_s, &xy[i][k]) < 0) {
				free(xy);
				return -EBADMSG;
			}
		}
	}
	rc = hl_road_set_polyline(road, (const double(*)[2])xy, (int)n, tol);
	free(xy);
	if (rc == -EINVAL)
		return hl_json_fail(c, sub, "fewer than 2 distinct points: the road has no length");
	if (rc == -E2BIG)
		return hl_json_fail(c, sub,
				    "more than %d legs remain after simplifying within %g m: "
				    "raise tolerance_m or give fewer points",
				    HL_SCN_MAX_SEGMENTS, tol);
	return rc;
}

/* 0, or 1 when the road is a polyline. */
static int parse_segments(const struct hl_json_ctx *c, const struct json_t *j, struct hl_road *road)
{
	static const char *const keys[] = { "kind", "length_m",	 "radius_m",
					    "turn", "start_s_m", NULL };
	static const char *const kinds[] = { "straight", "arc", "polyline", NULL };
	static const char *const turns[] = { "left", "right", NULL };
	static const struct hl_json_range r_radius = { 10.0, MAX_S_M, false, "m" };
	const char *path = "road.segments";
	char p[HL_JSON_PATH_MAX], sub[HL_JSON_PATH_MAX];
	double end_m = 0.0;

	if (!json_is_array(j))
		return hl_json_fail(c, path, "expected an array of 1 to %d segments, found %s",
				    HL_SCN_MAX_SEGMENTS, hl_json_type_name(j));
	if (json_array_size(j) == 0)
		return hl_json_fail(
			c, path, "the road has no segments: expected an array of 1 to %d segments",
			HL_SCN_MAX_SEGMENTS);
	if (json_array_size(j) > HL_SCN_MAX_SEGMENTS)
		return hl_json_fail(c, path, "%zu segments: expected at most %d",
				    json_array_size(j), HL_SCN_MAX_SEGMENTS);
	for (size_t i = 0; i < json_array_size(j); i++) {
		const struct json_t *o = json_array_get(j, i);
		struct hl_road_segment *seg = &road->seg[i];
		int kind = 0, turn = 0;
		double start = NAN;

		hl_json_index(p, sizeof(p), path, i);
		if (json_is_object(o) && hl_json_get_enum(c, p, o, "kind", true, kinds, &kind) < 0)
			return -EBADMSG;
		if (kind == 2) {
			if (json_array_size(j) != 1)
				return hl_json_fail(
					c, hl_json_join(sub, sizeof(sub), p, "kind"),
					"a polyline is the road's only segment: expected "
					"no other segments, found %zu",
					json_array_size(j) - 1);
			return parse_polyline(c, p, o, road) < 0 ? -EBADMSG : 1;
		}
		if (hl_json_check_object(c, p, o, keys) < 0 ||
		    hl_json_get_enum(c, p, o, "kind", true, kinds, &kind) < 0 ||
		    hl_json_get_number(c, p, o, "length_m", true, &r_length, &seg->length_m) < 0 ||
		    hl_json_get_number(c, p, o, "start_s_m", false, &r_s, &start) < 0)
			return -EBADMSG;
		seg->kind = kind ? HL_SEG_ARC : HL_SEG_STRAIGHT;
		if (seg->kind == HL_SEG_STRAIGHT) {
			for (int k = 2; k <= 3; k++)
				if (json_object_get(o, keys[k]))
					return hl_json_fail(
						c, hl_json_join(sub, sizeof(sub), p, keys[k]),
						"a straight segment has no '%s'", keys[k]);
		} else if (hl_json_get_number(c, p, o, "radius_m", true, &r_radius,
					      &seg->radius_m) < 0 ||
			   hl_json_get_enum(c, p, o, "turn", true, turns, &turn) < 0) {
			return -EBADMSG;
		}
		seg->turn = turn ? -1 : 1;
		if (!isnan(start) && fabs(start - end_m) > CONNECT_TOL_M) {
			char prev[48] = "the road's start";

			if (i > 0)
				snprintf(prev, sizeof(prev), "where segment %zu ends", i - 1);
			return hl_json_fail(
				c, hl_json_join(sub, sizeof(sub), p, "start_s_m"),
				"the road does not connect: this segment starts at s = %g m, "
				"expected %g m (%s)",
				start, end_m, prev);
		}
		end_m += seg->length_m;
		road->n_segments++;
	}
	return 0;
}

static int parse_road(const struct hl_json_ctx *c, const struct json_t *j, struct hl_road *road)
{
	static const char *const keys[] = {
		"start", "segments", "lanes", "markings", "posts", NULL
	};
	static const char *const start_keys[] = { "x_m", "y_m", "heading_deg", NULL };
	static const char *const lane_keys[] = { "count", "width_m", NULL };
	static const char *const mark_keys[] = {
		"edge", "separator", "edge_width_m", "separator_width_m", "dash_m", "gap_m", NULL
	};
	static const char *const post_keys[] = { "spacing_m", "offset_m", "height_m", NULL };
	static const char *const edge_kinds[] = { "none", "solid", NULL };
	static const char *const sep_kinds[] = { "none", "solid", "dashed", NULL };
	static const struct hl_json_range r_lane = { 2.0, 6.0, false, "m" };
	static const struct hl_json_range r_line = { 0.05, 0.5, false, "m" };
	static const struct hl_json_range r_dash = { 0.0, 100.0, true, "m" };
	static const struct hl_json_range r_spacing = { 1.0, 1000.0, false, "m" };
	static const struct hl_json_range r_offset = { 0.0, 20.0, false, "m" };
	static const struct hl_json_range r_height = { 0.0, 5.0, true, "m" };
	const struct json_t *o;
	double heading_deg = 0.0;
	int edge = HL_MARK_SOLID, sep = HL_MARK_DASHED, polyline;

	*road = (struct hl_road){
		.lanes = 2,
		.lane_width_m = 3.5,
		.edge_line_width_m = 0.15,
		.separator_line_width_m = 0.12,
		.dash_m = 3.0,
		.gap_m = 6.0,
	};
	if (hl_json_check_object(c, "road", j, keys) < 0)
		return -EBADMSG;
	o = json_object_get(j, "start");
	if (o && (hl_json_check_object(c, "road.start", o, start_keys) < 0 ||
		  hl_json_get_number(c, "road.start", o, "x_m", false, &r_s, &road->x0_m) < 0 ||
		  hl_json_get_number(c, "road.start", o, "y_m", false, &r_s, &road->y0_m) < 0 ||
		  hl_json_get_number(c, "road.start", o, "heading_deg", false, &r_heading,
				     &heading_deg) < 0))
		return -EBADMSG;
	road->heading0_rad = heading_deg * DEG;
	if (!json_object_get(j, "segments"))
		return hl_json_fail(
			c, "road.segments",
			"missing: the road has no segments: expected an array of 1 to %d",
			HL_SCN_MAX_SEGMENTS);
	polyline = parse_segments(c, json_object_get(j, "segments"), road);
	if (polyline < 0)
		return -EBADMSG;
	if (polyline && json_object_get(j, "start"))
		return hl_json_fail(
			c, "road.start",
			"a polyline road starts at its first point: expected no 'start'");
	o = json_object_get(j, "lanes");
	if (o && (hl_json_check_object(c, "road.lanes", o, lane_keys) < 0 ||
		  hl_json_get_int(c, "road.lanes", o, "count", false, 1, 8, &road->lanes) < 0 ||
		  hl_json_get_number(c, "road.lanes", o, "width_m", false, &r_lane,
				     &road->lane_width_m) < 0))
		return -EBADMSG;
	o = json_object_get(j, "markings");
	if (o &&
	    (hl_json_check_object(c, "road.markings", o, mark_keys) < 0 ||
	     hl_json_get_enum(c, "road.markings", o, "edge", false, edge_kinds, &edge) < 0 ||
	     hl_json_get_enum(c, "road.markings", o, "separator", false, sep_kinds, &sep) < 0 ||
	     hl_json_get_number(c, "road.markings", o, "edge_width_m", false, &r_line,
				&road->edge_line_width_m) < 0 ||
	     hl_json_get_number(c, "road.markings", o, "separator_width_m", false, &r_line,
				&road->separator_line_width_m) < 0 ||
	     hl_json_get_number(c, "road.markings", o, "dash_m", false, &r_dash, &road->dash_m) <
		     0 ||
	     hl_json_get_number(c, "road.markings", o, "gap_m", false, &r_dash, &road->gap_m) < 0))
		return -EBADMSG;
	road->edge = (enum hl_marking)edge;
	road->separator = (enum hl_marking)sep;
	o = json_object_get(j, "posts");
	road->post_offset_m = 0.75; /* as the built-in road scene: 4.25 m beside a 3.5 m lane */
	road->post_height_m = 1.0;
	if (o && (hl_json_check_object(c, "road.posts", o, post_keys) < 0 ||
		  hl_json_get_number(c, "road.posts", o, "spacing_m", true, &r_spacing,
				     &road->post_spacing_m) < 0 ||
		  hl_json_get_number(c, "road.posts", o, "offset_m", false, &r_offset,
				     &road->post_offset_m) < 0 ||
		  hl_json_get_number(c, "road.posts", o, "height_m", false, &r_height,
				     &road->post_height_m) < 0))
		return -EBADMSG;
	if (!polyline) /* a polyline's was laid out by hl_road_set_polyline() */
		hl_road_layout(road);
	return 0;
}

/* path.key: a constant speed (a number) or a profile [{"t_s", "v_mps"}, ...]. */
static int parse_speed(const struct hl_json_ctx *c, const char *path, const struct json_t *obj,
		       bool required, struct hl_speed_profile *sp)
{
	static const char *const keys[] = { "t_s", "v_mps", NULL };
	const struct json_t *j = json_object_get(obj, "speed_mps");
	char sub[HL_JSON_PATH_MAX], p[HL_JSON_PATH_MAX];

	hl_json_join(sub, sizeof(sub), path, "speed_mps");
	*sp = (struct hl_speed_profile){ .n = 1 };
	if (!j) {
		if (required)
			return hl_json_fail(
				c, sub,
				"missing: expected a speed in m/s or [{\"t_s\": T, \"v_mps\": V}, "
				"...]");
		hl_speed_layout(sp);
		return 0;
	}
	if (json_is_number(j)) {
		if (hl_json_number(c, sub, j, &r_speed, &sp->v_mps[0]) < 0)
			return -EBADMSG;
		hl_speed_layout(sp);
		return 0;
	}
	if (!json_is_array(j) || json_array_size(j) < 1 || json_array_size(j) > HL_SCN_MAX_POINTS)
		return hl_json_fail(
			c, sub,
			"expected a speed in m/s or an array of 1 to %d points {\"t_s\": T, "
			"\"v_mps\": V}, found %s",
			HL_SCN_MAX_POINTS,
			json_is_array(j) ? "another size" : hl_json_type_name(j));
	sp->n = (int)json_array_size(j);
	for (int i = 0; i < sp->n; i++) {
		const struct json_t *o = json_array_get(j, i);

		hl_json_index(p, sizeof(p), sub, i);
		if (hl_json_check_object(c, p, o, keys) < 0 ||
		    hl_json_get_number(c, p, o, "t_s", true, &r_time, &sp->t_s[i]) < 0 ||
		    hl_json_get_number(c, p, o, "v_mps", true, &r_speed, &sp->v_mps[i]) < 0)
			return -EBADMSG;
		if (i > 0 && !(sp->t_s[i] > sp->t_s[i - 1]))
			return hl_json_fail(
				c, hl_json_join(sub, sizeof(sub), p, "t_s"),
				"%g s is not after the previous point's %g s: expected strictly "
				"increasing times",
				sp->t_s[i], sp->t_s[i - 1]);
	}
	hl_speed_layout(sp);
	return 0;
}

static int parse_waypoints(const struct hl_json_ctx *c, const char *path, const struct json_t *j,
			   struct hl_path *pa)
{
	static const char *const keys[] = { "t_s", "x_m", "y_m", NULL };
	char p[HL_JSON_PATH_MAX], sub[HL_JSON_PATH_MAX];

	if (!json_is_array(j) || json_array_size(j) < 1 || json_array_size(j) > HL_SCN_MAX_POINTS)
		return hl_json_fail(
			c, path,
			"expected an array of 1 to %d waypoints {\"t_s\", \"x_m\", \"y_m\"}, "
			"found %s",
			HL_SCN_MAX_POINTS,
			json_is_array(j) ? "another size" : hl_json_type_name(j));
	pa->n_waypoints = (int)json_array_size(j);
	for (int i = 0; i < pa->n_waypoints; i++) {
		const struct json_t *o = json_array_get(j, i);
		struct hl_waypoint *w = &pa->wp[i];

		hl_json_index(p, sizeof(p), path, i);
		if (hl_json_check_object(c, p, o, keys) < 0 ||
		    hl_json_get_number(c, p, o, "t_s", true, &r_time, &w->t_s) < 0 ||
		    hl_json_get_number(c, p, o, "x_m", true, &r_s, &w->x_m) < 0 ||
		    hl_json_get_number(c, p, o, "y_m", true, &r_s, &w->y_m) < 0)
			return -EBADMSG;
		if (i > 0 && !(w->t_s > pa->wp[i - 1].t_s))
			return hl_json_fail(
				c, hl_json_join(sub, sizeof(sub), p, "t_s"),
				"%g s is not after the previous waypoint's %g s: expected "
				"strictly increasing times",
				w->t_s, pa->wp[i - 1].t_s);
	}
	return 0;
}

/*
 * A path: along a lane (lane, offset_m, start_s_m, speed_mps) or by waypoints (waypoints,
 * heading_deg). direction: +1 toward increasing s, -1 oncoming.
 */
static int parse_path(const struct hl_json_ctx *c, const char *path, const struct json_t *j,
		      const struct hl_road *road, int default_lane, int direction,
		      struct hl_path *pa)
{
	static const char *const lane_keys[] = { "lane", "offset_m", "start_s_m", "speed_mps",
						 NULL };
	static const char *const wp_keys[] = { "waypoints", "heading_deg", NULL };
	static const struct hl_json_range r_offset = { -20.0, 20.0, false, "m" };
	char sub[HL_JSON_PATH_MAX];
	double heading_deg = NAN;

	pa->lane = default_lane;
	pa->direction = direction;
	if (json_is_object(j) && json_object_get(j, "waypoints")) {
		pa->kind = HL_PATH_WAYPOINTS;
		if (hl_json_check_object(c, path, j, wp_keys) < 0 ||
		    hl_json_get_number(c, path, j, "heading_deg", false, &r_heading, &heading_deg) <
			    0 ||
		    parse_waypoints(c, hl_json_join(sub, sizeof(sub), path, "waypoints"),
				    json_object_get(j, "waypoints"), pa) < 0)
			return -EBADMSG;
		hl_waypoints_layout(pa, heading_deg * DEG);
		return 0;
	}
	pa->kind = HL_PATH_LANE;
	if (hl_json_check_object(c, path, j, lane_keys) < 0 ||
	    hl_json_get_int(c, path, j, "lane", false, 1, road->lanes, &pa->lane) < 0 ||
	    hl_json_get_number(c, path, j, "offset_m", false, &r_offset, &pa->offset_m) < 0 ||
	    hl_json_get_number(c, path, j, "start_s_m", true, &r_s, &pa->start_s_m) < 0 ||
	    parse_speed(c, path, j, true, &pa->speed) < 0)
		return -EBADMSG;
	if (pa->lane > road->lanes)
		return hl_json_fail(c, hl_json_join(sub, sizeof(sub), path, "lane"),
				    "lane %d: the road has %d lanes", pa->lane, road->lanes);
	return 0;
}

static int parse_lamp_pose(const struct hl_json_ctx *c, const char *path, const struct json_t *j,
			   struct hl_lamp_pose *pose)
{
	static const char *const keys[] = { "pos_m", "yaw_deg", "pitch_deg", NULL };
	static const struct hl_json_range r_yaw = { -90.0, 90.0, false, "degrees" };
	static const struct hl_json_range r_pitch = { -30.0, 30.0, false, "degrees" };

	if (hl_json_check_object(c, path, j, keys) < 0 ||
	    hl_json_get_vec3(c, path, j, "pos_m", false, r_vehicle, pose->pos_m) < 0 ||
	    hl_json_get_number(c, path, j, "yaw_deg", false, &r_yaw, &pose->yaw_deg) < 0 ||
	    hl_json_get_number(c, path, j, "pitch_deg", false, &r_pitch, &pose->pitch_deg) < 0)
		return -EBADMSG;
	return 0;
}

static int parse_camera(const struct hl_json_ctx *c, const struct json_t *j, struct hl_camera *cam)
{
	static const char *const keys[] = { "pos_m", "yaw_deg", "pitch_deg", "fov_y_deg", NULL };
	static const struct hl_json_range r_yaw = { -180.0, 180.0, false, "degrees" };
	static const struct hl_json_range r_pitch = { -89.0, 89.0, false, "degrees" };
	static const struct hl_json_range r_fov = { 1.0, 170.0, false, "degrees" };
	/* Today's road-scene driver's eye (render/scene.c): 1.8 m behind, 0.37 m left, 1.2 m up,
	 * looking 3 % down, 36° high. */
	double yaw = 0.0, pitch = atan(-0.03) / DEG;

	*cam = (struct hl_camera){ .pos_m = { -1.8, 0.37, 1.2 },
				   .up = { 0, 0, 1 },
				   .fov_y_deg = 36.0 };
	if (j &&
	    (hl_json_check_object(c, "ego.camera", j, keys) < 0 ||
	     hl_json_get_vec3(c, "ego.camera", j, "pos_m", false, r_vehicle, cam->pos_m) < 0 ||
	     hl_json_get_number(c, "ego.camera", j, "yaw_deg", false, &r_yaw, &yaw) < 0 ||
	     hl_json_get_number(c, "ego.camera", j, "pitch_deg", false, &r_pitch, &pitch) < 0 ||
	     hl_json_get_number(c, "ego.camera", j, "fov_y_deg", false, &r_fov, &cam->fov_y_deg) <
		     0))
		return -EBADMSG;
	cam->dir[0] = cos(pitch * DEG) * cos(yaw * DEG);
	cam->dir[1] = cos(pitch * DEG) * sin(yaw * DEG);
	cam->dir[2] = sin(pitch * DEG);
	return 0;
}

static int parse_ego(const struct hl_json_ctx *c, const struct json_t *j,
		     const struct hl_road *road, struct hl_ego *ego)
{
	static const char *const keys[] = { "start_s_m", "lane",   "offset_m", "speed_mps",
					    "lamps",	 "camera", NULL };
	static const struct hl_json_range r_offset = { -20.0, 20.0, false, "m" };
	const struct json_t *lamps = json_object_get(j, "lamps");
	char p[HL_JSON_PATH_MAX];

	hl_lamp_pose_default(0, &ego->lamp[0]);
	hl_lamp_pose_default(1, &ego->lamp[1]);
	ego->path = (struct hl_path){ .kind = HL_PATH_LANE, .lane = 1, .direction = 1 };
	ego->path.speed.n = 1; /* standing */
	hl_speed_layout(&ego->path.speed);
	if (!j)
		return parse_camera(c, NULL, &ego->camera);
	if (hl_json_check_object(c, "ego", j, keys) < 0 ||
	    hl_json_get_number(c, "ego", j, "start_s_m", false, &r_s, &ego->path.start_s_m) < 0 ||
	    hl_json_get_int(c, "ego", j, "lane", false, 1, road->lanes, &ego->path.lane) < 0 ||
	    hl_json_get_number(c, "ego", j, "offset_m", false, &r_offset, &ego->path.offset_m) <
		    0 ||
	    parse_speed(c, "ego", j, false, &ego->path.speed) < 0)
		return -EBADMSG;
	if (lamps) {
		if (!json_is_array(lamps) || json_array_size(lamps) != 2)
			return hl_json_fail(
				c, "ego.lamps",
				"expected an array of 2 lamp poses (left, right), found %s",
				json_is_array(lamps) ? "another size" : hl_json_type_name(lamps));
		for (int l = 0; l < 2; l++)
			if (parse_lamp_pose(c, hl_json_index(p, sizeof(p), "ego.lamps", l),
					    json_array_get(lamps, l), &ego->lamp[l]) < 0)
				return -EBADMSG;
	}
	return parse_camera(c, json_object_get(j, "camera"), &ego->camera);
}

/* Defaults per kind: body, eye and lamps (docs/scenarios.md says where the numbers come from). */
struct kind_defaults {
	double size_m[3];
	double reflectance;
	double eye_m[3]; /* a car's; pedestrians and cyclists: over the middle of the body */
};

static const struct kind_defaults defaults[] = {
	[HL_ACTOR_CAR] = { { 4.5, 1.8, 1.45 }, 0.3, { -1.8, 0.37, 1.1 } },
	[HL_ACTOR_PEDESTRIAN] = { { 0.3, 0.5, 1.75 }, 0.2, { -0.15, 0.0, 1.6 } },
	[HL_ACTOR_CYCLIST] = { { 1.8, 0.6, 1.75 }, 0.2, { -1.0, 0.0, 1.6 } },
	[HL_ACTOR_TRUCK] = { { 12.0, 2.55, 3.8 }, 0.3, { -1.2, 0.6, 2.5 } },
	[HL_ACTOR_MOTORBIKE] = { { 2.2, 0.8, 1.4 }, 0.2, { -1.3, 0.0, 1.45 } },
};

static const char *const kind_names[] = {
	"car", "pedestrian", "cyclist", "truck", "motorbike", NULL
};
static const char *const role_names[] = { "oncoming", "preceding", "crossing", "roadside", NULL };
static const char *const emitter_names[] = { "headlamp", "tail", NULL };
static const char *const colour_names[] = { "white", "red", "amber", NULL };
static const double colours[][3] = { { 1.0, 1.0, 1.0 }, { 1.0, 0.0, 0.0 }, { 1.0, 0.5, 0.0 } };

#define HEADLAMP_CD 350.0 /* UN R149 class C passing beam at B50L, the oncoming driver: max */
#define TAIL_CD 10.0 /* a rear position lamp */

/*
 * A vehicle's default lamps: two headlamps at the front and two tail lamps at the back (a car's
 * 1.3 m apart, a truck's 2.0 m), a motorbike's one of each on its axis; none for the others.
 */
static void kind_lamps(struct hl_actor *a)
{
	const int two = a->kind == HL_ACTOR_CAR || a->kind == HL_ACTOR_TRUCK;
	const double half = a->kind == HL_ACTOR_TRUCK ? 1.0 : 0.65;
	const double z_head = a->kind == HL_ACTOR_TRUCK ? 1.0 : 0.65;

	if (!two && a->kind != HL_ACTOR_MOTORBIKE) {
		a->n_lamps = 0;
		return;
	}
	a->n_lamps = two ? 4 : 2;
	for (int l = 0; l < (two ? 2 : 1); l++) {
		const double y = two ? (l ? -half : half) : 0.0;

		a->lamp[l] = (struct hl_emitter){ HL_EMITTER_HEADLAMP,
						  { 0.0, y, two ? z_head : 1.0 },
						  HEADLAMP_CD,
						  { 1.0, 1.0, 1.0 } };
		a->lamp[(two ? 2 : 1) + l] =
			(struct hl_emitter){ HL_EMITTER_TAIL,
					     { -a->size_m[0], y, two ? 0.8 : 0.9 },
					     TAIL_CD,
					     { 1.0, 0.0, 0.0 } };
	}
}

void hl_actor_init(struct hl_actor *a, const char *id, enum hl_actor_kind kind,
		   enum hl_actor_role role, const double size_m[3])
{
	*a = (struct hl_actor){ .kind = kind, .role = role };
	snprintf(a->id, sizeof(a->id), "%s", id);
	memcpy(a->size_m, size_m ? size_m : defaults[kind].size_m, sizeof(a->size_m));
	a->reflectance = defaults[kind].reflectance;
	memcpy(a->eye_m, defaults[kind].eye_m, sizeof(a->eye_m));
	if (kind == HL_ACTOR_PEDESTRIAN || kind == HL_ACTOR_CYCLIST)
		a->eye_m[0] = -a->size_m[0] / 2; /* over the middle of the body */
	kind_lamps(a);
	a->path = (struct hl_path){ .kind = HL_PATH_WAYPOINTS, .n_waypoints = 1 };
	a->path.speed.n = 1;
	hl_speed_layout(&a->path.speed);
	hl_waypoints_layout(&a->path, 0.0);
}

static int parse_emitters(const struct hl_json_ctx *c, const char *path, const struct json_t *j,
			  struct hl_actor *a)
{
	static const char *const keys[] = { "kind", "pos_m", "intensity_cd", "colour", NULL };
	static const struct hl_json_range r_cd = { 0.0, 1e6, false, "cd" };
	char p[HL_JSON_PATH_MAX];

	if (!json_is_array(j) || json_array_size(j) > HL_SCN_MAX_LAMPS)
		return hl_json_fail(c, path, "expected an array of 0 to %d lamps, found %s",
				    HL_SCN_MAX_LAMPS,
				    json_is_array(j) ? "more" : hl_json_type_name(j));
	a->n_lamps = (int)json_array_size(j);
	for (int i = 0; i < a->n_lamps; i++) {
		const struct json_t *o = json_array_get(j, i);
		struct hl_emitter *e = &a->lamp[i];
		int kind = 0, colour = -1;

		hl_json_index(p, sizeof(p), path, i);
		if (hl_json_check_object(c, p, o, keys) < 0 ||
		    hl_json_get_enum(c, p, o, "kind", true, emitter_names, &kind) < 0)
			return -EBADMSG;
		e->kind = (enum hl_emitter_kind)kind;
		e->intensity_cd = kind == HL_EMITTER_HEADLAMP ? HEADLAMP_CD : TAIL_CD;
		if (hl_json_get_vec3(c, p, o, "pos_m", true, r_vehicle, e->pos_m) < 0 ||
		    hl_json_get_number(c, p, o, "intensity_cd", false, &r_cd, &e->intensity_cd) <
			    0 ||
		    hl_json_get_enum(c, p, o, "colour", false, colour_names, &colour) < 0)
			return -EBADMSG;
		if (colour < 0)
			colour = kind == HL_EMITTER_HEADLAMP ? 0 : 1;
		memcpy(e->rgb, colours[colour], sizeof(e->rgb));
	}
	return 0;
}

static int parse_actor(const struct hl_json_ctx *c, const char *path, const struct json_t *j,
		       const struct hl_scenario *sc, struct hl_actor *a)
{
	static const char *const keys[] = { "id",   "kind",  "role",  "path",
					    "body", "lamps", "eye_m", NULL };
	static const char *const body_keys[] = { "size_m", "reflectance", NULL };
	static const struct hl_json_range r_size[3] = { { 0.1, 30.0, false, "m" },
							{ 0.1, 5.0, false, "m" },
							{ 0.1, 5.0, false, "m" } };
	static const struct hl_json_range r_refl = { 0.0, 1.0, false, "(reflectance)" };
	char sub[HL_JSON_PATH_MAX];
	const struct json_t *o;
	int kind = 0, role = 0;

	if (hl_json_check_object(c, path, j, keys) < 0 ||
	    hl_json_get_string(c, path, j, "id", true, a->id, sizeof(a->id)) < 0 ||
	    hl_json_get_enum(c, path, j, "kind", true, kind_names, &kind) < 0 ||
	    hl_json_get_enum(c, path, j, "role", true, role_names, &role) < 0)
		return -EBADMSG;
	for (int k = 0; k < sc->n_actors; k++)
		if (!strcmp(sc->actor[k].id, a->id))
			return hl_json_fail(
				c, hl_json_join(sub, sizeof(sub), path, "id"),
				"'%s' is the id of actors[%d] already: expected a new one", a->id,
				k);
	{
		char id[HL_SCN_ID_MAX];
		double size_m[3], refl;

		memcpy(size_m, defaults[kind].size_m, sizeof(size_m));
		refl = defaults[kind].reflectance;
		o = json_object_get(j, "body");
		if (o && (hl_json_check_object(c, hl_json_join(sub, sizeof(sub), path, "body"), o,
					       body_keys) < 0 ||
			  hl_json_get_vec3(c, sub, o, "size_m", false, r_size, size_m) < 0 ||
			  hl_json_get_number(c, sub, o, "reflectance", false, &r_refl, &refl) < 0))
			return -EBADMSG;
		memcpy(id, a->id, sizeof(id));
		hl_actor_init(a, id, (enum hl_actor_kind)kind, (enum hl_actor_role)role, size_m);
		a->reflectance = refl;
	}
	if (hl_json_get_vec3(c, path, j, "eye_m", false, r_vehicle, a->eye_m) < 0)
		return -EBADMSG;
	o = json_object_get(j, "lamps");
	if (o && parse_emitters(c, hl_json_join(sub, sizeof(sub), path, "lamps"), o, a) < 0)
		return -EBADMSG;
	o = json_object_get(j, "path");
	hl_json_join(sub, sizeof(sub), path, "path");
	if (!o)
		return hl_json_fail(c, sub,
				    "missing: expected a lane path {\"lane\", \"start_s_m\", "
				    "\"speed_mps\"} or {\"waypoints\": [...]}");
	if (parse_path(c, sub, o, &sc->road, role == HL_ROLE_ONCOMING ? sc->road.lanes : 1,
		       role == HL_ROLE_ONCOMING ? -1 : 1, &a->path) < 0)
		return -EBADMSG;
	if (role == HL_ROLE_CROSSING && a->path.kind != HL_PATH_WAYPOINTS)
		return hl_json_fail(
			c, sub,
			"a crossing road user crosses the road: expected {\"waypoints\": "
			"[...]}, not a lane path");
	return 0;
}

static int parse_root(const struct hl_json_ctx *c, const struct json_t *root,
		      struct hl_scenario *sc)
{
	static const char *const keys[] = { "version", "title",	 "duration_s", "road",
					    "ego",     "actors", NULL };
	static const struct hl_json_range r_duration = { 0.0, MAX_DURATION_S, true, "s" };
	const struct json_t *actors;
	char p[HL_JSON_PATH_MAX];
	int version = 0;

	if (hl_json_check_object(c, "", root, keys) < 0 ||
	    hl_json_get_int(c, "", root, "version", true, FORMAT_VERSION, FORMAT_VERSION,
			    &version) < 0 ||
	    hl_json_get_string(c, "", root, "title", false, sc->title, sizeof(sc->title)) < 0 ||
	    hl_json_get_number(c, "", root, "duration_s", true, &r_duration, &sc->duration_s) < 0)
		return -EBADMSG;
	if (!json_object_get(root, "road"))
		return hl_json_fail(c, "road",
				    "missing: expected the road {\"segments\": [...], ...}");
	if (parse_road(c, json_object_get(root, "road"), &sc->road) < 0 ||
	    parse_ego(c, json_object_get(root, "ego"), &sc->road, &sc->ego) < 0)
		return -EBADMSG;
	actors = json_object_get(root, "actors");
	if (!actors)
		return 0;
	if (!json_is_array(actors) || json_array_size(actors) > HL_SCN_MAX_ACTORS)
		return hl_json_fail(c, "actors",
				    "expected an array of 0 to %d road users, found %s",
				    HL_SCN_MAX_ACTORS,
				    json_is_array(actors) ? "more" : hl_json_type_name(actors));
	for (size_t i = 0; i < json_array_size(actors); i++) {
		if (parse_actor(c, hl_json_index(p, sizeof(p), "actors", i),
				json_array_get(actors, i), sc, &sc->actor[i]) < 0)
			return -EBADMSG;
		sc->n_actors++;
	}
	return 0;
}

/* parse_root for hl_json_parse_struct() */
static int parse_any(struct hl_json_ctx *c, json_t *root, void *out)
{
	return parse_root(c, root, out);
}

int hl_scenario_parse(const char *text, const char *name, struct hl_scenario **ret,
		      struct hl_json_error *err)
{
	return hl_json_parse_struct(text, name, sizeof(**ret), parse_any, (void **)ret, err);
}

int hl_scenario_read(const char *path, struct hl_scenario **ret, struct hl_json_error *err)
{
	return hl_json_read_struct(path, sizeof(**ret), parse_any, (void **)ret, err);
}

void hl_scenario_free(struct hl_scenario *sc)
{
	if (sc)
		hl_world_track_free(sc->track);
	free(sc);
}

int hl_scenario_default_dir(char *buf, size_t size)
{
	return hl_share_dir("scenarios", buf, size);
}

const char *hl_actor_kind_name(enum hl_actor_kind kind)
{
	return (unsigned)kind < HL_ACTOR_KINDS ? kind_names[kind] : "?";
}

const char *hl_actor_role_name(enum hl_actor_role role)
{
	return (unsigned)role < 4 ? role_names[role] : "?";
}
