/* SPDX-License-Identifier: MIT */
/*
 * world/road.c: the road, paths and poses of a scenario against an independent
 * computation written here in closed form (circle maths, the integral of a piecewise-linear
 * speed), within 1 mm; and no allocation in the per-frame calls.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "alloc_count.h"
#include "world/scenario.h"
#include "world/road.h"
#include "world/world.h"

#define MM 1e-3
#define DEG (M_PI / 180.0)

static struct hl_scenario *load(const char *text)
{
	struct hl_scenario *sc = NULL;
	struct hl_json_error err;
	char buf[1024];

	if (hl_scenario_parse(text, "geom.json", &sc, &err) < 0)
		fail_msg("%s", hl_json_error_format(&err, buf, sizeof(buf)));
	return sc;
}

static void near(const char *what, double s, double got, double want, double tol)
{
	if (!(fabs(got - want) <= tol))
		fail_msg("%s at %g: got %.9f, want %.9f (off by %.3g)", what, s, got, want,
			 got - want);
}

static void near_point(const char *what, double s, const double got[3], double x, double y,
		       double z)
{
	near(what, s, got[0], x, MM);
	near(what, s, got[1], y, MM);
	near(what, s, got[2], z, MM);
}

/* Headings equal modulo a full turn. */
static void near_heading(const char *what, double s, double got, double want)
{
	near(what, s, remainder(got - want, 2 * M_PI), 0.0, 1e-9);
}

/* A 250 m arc, left and right: points (s, d) on circles about (0, ±250). */
static void road_points_on_250m_arc(void **state)
{
	(void)state;
	static const char *const turns[] = { "left", "right" };
	static const double s_list[] = { 0.0, 0.001, 10.0, 100.0, 250.0, M_PI / 2 * 250, 600.0 };
	static const double d_list[] = { 0.0, 1.75, -1.75, -4.25, 4.25 };
	const double R = 250.0;
	char text[512];

	for (int k = 0; k < 2; k++) {
		const double sign = k ? -1.0 : 1.0; /* left: centre (0, R); right: (0, -R) */
		struct hl_scenario *sc;

		snprintf(text, sizeof(text),
			 "{\"version\": 1, \"duration_s\": 1, \"road\": {\"segments\": [{\"kind\": "
			 "\"arc\", \"length_m\": 600, \"radius_m\": 250, \"turn\": \"%s\"}]}}",
			 turns[k]);
		sc = load(text);
		near("length", 0, sc->road.length_m, 600.0, 1e-9);
		for (size_t i = 0; i < sizeof(s_list) / sizeof(s_list[0]); i++) {
			const double s = s_list[i], phi = s / R;
			struct hl_pose2 c;

			hl_road_centre(&sc->road, s, &c);
			near("centre x", s, c.x_m, R * sin(phi), MM);
			near("centre y", s, c.y_m, sign * (R - R * cos(phi)), MM);
			near_heading("heading", s, c.heading_rad, sign * phi);
			for (size_t j = 0; j < sizeof(d_list) / sizeof(d_list[0]); j++) {
				/* d to the left: a circle of radius R - d (left) or R + d (right) */
				const double d = d_list[j], r = R - sign * d;
				double p[3];

				hl_road_point(&sc->road, s, d, p);
				near_point("point", s, p, r * sin(phi), sign * (R - r * cos(phi)),
					   0.0);
			}
		}
		hl_scenario_free(sc);
	}
}

/*
 * A road that starts at (10, -5) heading 30°: 100 m straight, a right arc of 150 m radius over
 * 200 m, 50 m straight. Computed in the road's own frame (start at the origin, along +x), then
 * turned by 30° and moved.
 */
static void local_to_world(double lx, double ly, double ret[2])
{
	const double h = 30.0 * DEG;

	ret[0] = 10.0 + lx * cos(h) - ly * sin(h);
	ret[1] = -5.0 + lx * sin(h) + ly * cos(h);
}

static void road_straight_then_arc(void **state)
{
	(void)state;
	static const char text[] =
		"{\"version\": 1, \"duration_s\": 1, \"road\": {\n"
		" \"start\": {\"x_m\": 10, \"y_m\": -5, \"heading_deg\": 30},\n"
		" \"lanes\": {\"count\": 3, \"width_m\": 3.0},\n"
		" \"posts\": {\"spacing_m\": 25, \"offset_m\": 1.0},\n"
		" \"segments\": [{\"kind\": \"straight\", \"length_m\": 100},\n"
		"  {\"kind\": \"arc\", \"length_m\": 200, \"radius_m\": 150, \"turn\": \"right\"},\n"
		"  {\"kind\": \"straight\", \"length_m\": 50, \"start_s_m\": 300}]}}";
	static const double s_list[] = { -20.0,	  0.0,	 50.0,	100.0, 130.0, 235.6,
					 299.999, 300.0, 320.0, 350.0, 400.0 };
	const double R = 150.0, phi_end = 200.0 / R;
	struct hl_scenario *sc = load(text);

	/* three lanes of 3 m: centres at d = -3, 0, +3 from the right */
	near("lane 1", 1, hl_road_lane_offset(&sc->road, 1), -3.0, 1e-12);
	near("lane 2", 2, hl_road_lane_offset(&sc->road, 2), 0.0, 1e-12);
	near("lane 3", 3, hl_road_lane_offset(&sc->road, 3), 3.0, 1e-12);
	for (size_t i = 0; i < sizeof(s_list) / sizeof(s_list[0]); i++) {
		const double s = s_list[i], d = 2.5;
		double lx, ly, lh, w[2], p[3];

		if (s <= 100.0) { /* the first straight, and before the start */
			lx = s;
			ly = d;
			lh = 0.0;
		} else if (s <= 300.0) { /* right arc: centre (100, -R), radius R + d */
			const double phi = (s - 100.0) / R;

			lx = 100.0 + (R + d) * sin(phi);
			ly = -R + (R + d) * cos(phi);
			lh = -phi;
		} else { /* the last straight and beyond: from the arc's end along -phi_end */
			const double u = s - 300.0;

			lx = 100.0 + R * sin(phi_end) + u * cos(phi_end) + d * sin(phi_end);
			ly = -R + R * cos(phi_end) - u * sin(phi_end) + d * cos(phi_end);
			lh = -phi_end;
		}
		local_to_world(lx, ly, w);
		hl_road_point(&sc->road, s, d, p);
		near_point("point", s, p, w[0], w[1], 0.0);
		{
			struct hl_pose2 c;

			hl_road_centre(&sc->road, s, &c);
			near_heading("heading", s, c.heading_rad, lh + 30.0 * DEG);
		}
	}
	/* posts every 25 m up to 350 m, 1 m beyond the edges (half width 4.5 m) */
	assert_int_equal(hl_road_post_count(&sc->road), 14);
	{
		const double phi = (150.0 - 100.0) / R;
		double w[2], p[3];

		/* post 5 is at s = 150 on the arc; left side d = +5.5 */
		local_to_world(100.0 + (R + 5.5) * sin(phi), -R + (R + 5.5) * cos(phi), w);
		hl_road_post(&sc->road, 5, +1, p);
		near_point("post left", 150, p, w[0], w[1], 0.0);
		local_to_world(100.0 + (R - 5.5) * sin(phi), -R + (R - 5.5) * cos(phi), w);
		hl_road_post(&sc->road, 5, -1, p);
		near_point("post right", 150, p, w[0], w[1], 0.0);
	}
	hl_scenario_free(sc);
}

/* The integral of the profile (1 s, 20), (4 s, 10), (10 s, 10), (12 s, 0), by hand. */
static double distance_by_hand(double t)
{
	if (t <= 1.0)
		return 20.0 * t; /* held at 20 m/s before the first point */
	if (t <= 4.0) { /* v = 20 - (10/3) tau */
		const double tau = t - 1.0;

		return 20.0 + 20.0 * tau - 5.0 / 3.0 * tau * tau;
	}
	if (t <= 10.0)
		return 65.0 + 10.0 * (t - 4.0);
	if (t <= 12.0) { /* v = 10 - 5 tau */
		const double tau = t - 10.0;

		return 125.0 + 10.0 * tau - 2.5 * tau * tau;
	}
	return 135.0;
}

static double speed_by_hand(double t)
{
	if (t <= 1.0)
		return 20.0;
	if (t <= 4.0)
		return 20.0 - 10.0 / 3.0 * (t - 1.0);
	if (t <= 10.0)
		return 10.0;
	if (t <= 12.0)
		return 10.0 - 5.0 * (t - 10.0);
	return 0.0;
}

/*
 * Oncoming cars on a straight-then-250 m-left-arc road, lane 2 (d = +1.75): one from s = 400 m
 * under that profile (default eye), one from 520 m at 20 m/s (eye given); pose and eye at
 * several times.
 */
static void oncoming_car_under_piecewise_linear_speed(void **state)
{
	(void)state;
	static const char text[] =
		"{\"version\": 1, \"duration_s\": 20, \"road\": {\"segments\": [\n"
		"  {\"kind\": \"straight\", \"length_m\": 100},\n"
		"  {\"kind\": \"arc\", \"length_m\": 500, \"radius_m\": 250, \"turn\": \"left\"}]},\n"
		" \"actors\": [\n"
		"  {\"id\": \"a\", \"kind\": \"car\", \"role\": \"oncoming\", \"path\": {\"lane\": 2,\n"
		"   \"start_s_m\": 400, \"speed_mps\": [{\"t_s\": 1, \"v_mps\": 20},\n"
		"   {\"t_s\": 4, \"v_mps\": 10}, {\"t_s\": 10, \"v_mps\": 10},\n"
		"   {\"t_s\": 12, \"v_mps\": 0}]}},\n"
		"  {\"id\": \"b\", \"kind\": \"car\", \"role\": \"oncoming\", \"eye_m\": [-2.0, 0.4, 1.3],\n"
		"   \"path\": {\"start_s_m\": 520, \"speed_mps\": 20}}]}";
	static const double t_list[] = {
		0.0, 0.5, 1.0, 2.5, 4.0, 7.0, 10.0, 11.0, 12.0, 13.0, 20.0
	};
	const double R = 250.0, d = 1.75;
	struct hl_scenario *sc = load(text);
	struct hl_world_state w;

	for (size_t i = 0; i < sizeof(t_list) / sizeof(t_list[0]); i++) {
		const double t = t_list[i];

		for (int a = 0; a < 2; a++) {
			const double dist = a ? 20.0 * t : distance_by_hand(t);
			const double s = (a ? 520.0 : 400.0) - dist, phi = (s - 100.0) / R;
			/* on the arc (s >= 100 throughout): centre (100, R), radius R - d */
			const double x = 100.0 + (R - d) * sin(phi), y = R - (R - d) * cos(phi);
			/* driving toward decreasing s: forward (-cos phi, -sin phi), left
			 * (sin phi, -cos phi) */
			const double ex = a ? -2.0 : -1.8, ey = a ? 0.4 : 0.37, ez = a ? 1.3 : 1.1;
			struct hl_body_pose pose;
			double eye[3];

			assert_true(s >= 100.0);
			hl_world_actor_pose_at(sc, a, t, &pose);
			near("s", t, pose.s_m, s, MM);
			near("speed", t, pose.speed_mps, a ? 20.0 : speed_by_hand(t), 1e-9);
			near_point("position", t, pose.pos_m, x, y, 0.0);
			near_heading("heading", t, pose.heading_rad, phi + M_PI);
			hl_world_actor_eye_at(sc, a, t, eye);
			near_point("eye", t, eye, x - ex * cos(phi) + ey * sin(phi),
				   y - ex * sin(phi) - ey * cos(phi), ez);
			/* the world state of that instant: the same pose, the same eye */
			hl_world_at(sc, t, &w);
			assert_int_equal(w.n_actors, 2);
			assert_int_equal(w.lamps_on, 3);
			near("world t", t, w.t_s, t, 0.0);
			near_point("world position", t, w.actor[a].pos_m, x, y, 0.0);
			near_heading("world heading", t, w.actor[a].heading_rad, phi + M_PI);
			hl_world_actor_eye(sc, a, &w.actor[a], eye);
			near_point("world eye", t, eye, x - ex * cos(phi) + ey * sin(phi),
				   y - ex * sin(phi) - ey * cos(phi), ez);
		}
	}
	hl_scenario_free(sc);
}

/* Waypoints: linear between, held at both ends, heading of the leg; a standing start faces
 * heading_deg. */
static void waypoint_path(void **state)
{
	(void)state;
	static const char text[] =
		"{\"version\": 1, \"duration_s\": 20, \"road\": {\"segments\": [\n"
		"  {\"kind\": \"straight\", \"length_m\": 100}]},\n"
		" \"actors\": [{\"id\": \"p\", \"kind\": \"pedestrian\", \"role\": \"crossing\",\n"
		"  \"path\": {\"heading_deg\": 90, \"waypoints\": [\n"
		"   {\"t_s\": 2, \"x_m\": 30, \"y_m\": -5}, {\"t_s\": 3, \"x_m\": 30, \"y_m\": -5},\n"
		"   {\"t_s\": 7, \"x_m\": 33, \"y_m\": -1}, {\"t_s\": 9, \"x_m\": 33, \"y_m\": -1}]}}]}";
	static const struct {
		double t, x, y, heading_deg;
	} want[] = {
		{ 0.0, 30.0, -5.0, 90.0 }, /* before the first: held, facing heading_deg */
		{ 2.5, 30.0, -5.0, 90.0 }, /* standing */
		{ 5.0, 31.5, -3.0, 53.130102354 }, /* halfway along (3, 4) */
		{ 8.0, 33.0, -1.0, 53.130102354 }, /* standing: keeps the leg's heading */
		{ 15.0, 33.0, -1.0, 53.130102354 },
	};
	struct hl_scenario *sc = load(text);

	for (size_t i = 0; i < sizeof(want) / sizeof(want[0]); i++) {
		struct hl_body_pose pose;
		double eye[3];

		hl_world_actor_pose_at(sc, 0, want[i].t, &pose);
		near_point("position", want[i].t, pose.pos_m, want[i].x, want[i].y, 0.0);
		near_heading("heading", want[i].t, pose.heading_rad, want[i].heading_deg * DEG);
		/* a pedestrian's eye: over the middle of its 0.3 m body, 1.6 m up */
		hl_world_actor_eye_at(sc, 0, want[i].t, eye);
		near_point("eye", want[i].t, eye, want[i].x - 0.15 * cos(want[i].heading_deg * DEG),
			   want[i].y - 0.15 * sin(want[i].heading_deg * DEG), 1.6);
	}
	hl_scenario_free(sc);
}

/* The ego on a 250 m left arc: its lamps' world poses and its camera. */
static void ego_lamps_and_camera(void **state)
{
	(void)state;
	static const char text[] =
		"{\"version\": 1, \"duration_s\": 20, \"road\": {\"segments\": [\n"
		"  {\"kind\": \"arc\", \"length_m\": 900, \"radius_m\": 250, \"turn\": \"left\"}]},\n"
		" \"ego\": {\"start_s_m\": 10, \"speed_mps\": 15,\n"
		"  \"lamps\": [{\"pos_m\": [-0.2, 0.75, 0.7], \"yaw_deg\": 2, \"pitch_deg\": -1},\n"
		"             {\"pos_m\": [-0.2, -0.75, 0.7], \"yaw_deg\": -2}],\n"
		"  \"camera\": {\"pos_m\": [-2, 0.4, 1.25], \"yaw_deg\": 0, \"pitch_deg\": 0}}}";
	const double R = 250.0, d = -1.75; /* lane 1 of 2 */
	struct hl_scenario *sc = load(text);

	for (double t = 0.0; t <= 20.0; t += 2.5) {
		const double phi = (10.0 + 15.0 * t) / R;
		const double x = (R - d) * sin(phi), y = R - (R - d) * cos(phi);
		const double fx = cos(phi), fy = sin(phi), lx = -sin(phi), ly = cos(phi);
		struct hl_lamp_pose lamps[2];
		struct hl_camera cam;
		double ax[3], ay[3], az[3];

		hl_world_ego_lamps_at(sc, t, lamps);
		near_point("left lamp", t, lamps[0].pos_m, x - 0.2 * fx + 0.75 * lx,
			   y - 0.2 * fy + 0.75 * ly, 0.7);
		near_point("right lamp", t, lamps[1].pos_m, x - 0.2 * fx - 0.75 * lx,
			   y - 0.2 * fy - 0.75 * ly, 0.7);
		near_heading("left yaw", t, lamps[0].yaw_deg * DEG, phi + 2.0 * DEG);
		near_heading("right yaw", t, lamps[1].yaw_deg * DEG, phi - 2.0 * DEG);
		near("left pitch", t, lamps[0].pitch_deg, -1.0, 1e-12);
		/* the right lamp's pitch is the default aim, 1 % down */
		near("right pitch", t, lamps[1].pitch_deg, -atan(0.01) / DEG, 1e-12);
		/* its optical axis in the world */
		hl_lamp_basis(&lamps[0], ax, ay, az);
		near("axis x", t, az[0], cos(-1.0 * DEG) * cos(phi + 2.0 * DEG), 1e-9);
		near("axis y", t, az[1], cos(-1.0 * DEG) * sin(phi + 2.0 * DEG), 1e-9);
		near("axis z", t, az[2], sin(-1.0 * DEG), 1e-9);

		hl_world_ego_camera_at(sc, t, 64, 36, &cam);
		assert_int_equal(cam.width, 64);
		near_point("camera", t, cam.pos_m, x - 2.0 * fx + 0.4 * lx, y - 2.0 * fy + 0.4 * ly,
			   1.25);
		near("camera dir x", t, cam.dir[0] / hypot(cam.dir[0], cam.dir[1]), fx, 1e-9);
		near("camera dir y", t, cam.dir[1] / hypot(cam.dir[0], cam.dir[1]), fy, 1e-9);
		near("camera dir z", t, cam.dir[2], 0.0, 1e-12);
	}
	hl_scenario_free(sc);
}

/* The per-frame calls allocate nothing. */
static void per_frame_calls_allocate_nothing(void **state)
{
	(void)state;
	struct hl_scenario *sc;
	struct hl_json_error err;
	char path[1024], buf[1024];
	const char *src = getenv("HL_SOURCE_DIR");

	if (!HL_COUNT_ALLOCS)
		skip();
	assert_non_null(src);
	snprintf(path, sizeof(path), "%s/scenarios/demo-drive.json", src);
	if (hl_scenario_read(path, &sc, &err) < 0)
		fail_msg("%s", hl_json_error_format(&err, buf, sizeof(buf)));
	allocs = 0;
	for (double t = 0.0; t <= sc->duration_s; t += 0.02) {
		struct hl_body_pose pose;
		struct hl_lamp_pose lamps[2];
		struct hl_camera cam;
		double eye[3], p[3];

		hl_world_ego_pose_at(sc, t, &pose);
		hl_world_ego_lamps_at(sc, t, lamps);
		hl_world_ego_camera_at(sc, t, 1280, 720, &cam);
		for (int a = 0; a < sc->n_actors; a++) {
			hl_world_actor_pose_at(sc, a, t, &pose);
			hl_world_actor_eye_at(sc, a, t, eye);
		}
		hl_road_point(&sc->road, t * 40.0, 1.0, p);
	}
	assert_int_equal(allocs, 0);
	allocs = -1;
	hl_scenario_free(sc);
}

/*
 * A polyline with one left kink of 60°: (0, 0) -> (100, 0) -> 100 m on at 60°. Centre, points
 * and projections on both legs by hand; in the wedge outside the kink, the vertex; posts.
 */
static void road_polyline_one_kink(void **state)
{
	(void)state;
	const double c60 = cos(60 * DEG), s60 = sin(60 * DEG), c30 = cos(30 * DEG);
	const double xy[3][2] = { { 0, 0 }, { 100, 0 }, { 100 + 100 * c60, 100 * s60 } };
	struct hl_road *road = calloc(1, sizeof(*road));
	struct hl_pose2 c;
	double p[3], s, d;

	road->lanes = 2;
	road->lane_width_m = 3.5;
	road->post_spacing_m = 10.0;
	road->post_offset_m = 0.75;
	assert_int_equal(hl_road_set_polyline(road, xy, 3, 0.01), 0);
	assert_int_equal(road->n_segments, 2);
	near("length", 0, road->length_m, 200.0, 1e-9);
	near("kink", 100, road->seg[1].kink_rad, 60 * DEG, 1e-12);
	/* centre: before, on and after the legs; at the vertex the outgoing heading */
	hl_road_centre(road, -10, &c);
	near("x", -10, c.x_m, -10, 1e-9);
	near_heading("heading", -10, c.heading_rad, 0);
	hl_road_centre(road, 50, &c);
	near("x", 50, c.x_m, 50, 1e-9);
	near("y", 50, c.y_m, 0, 1e-9);
	hl_road_centre(road, 100, &c);
	near("x", 100, c.x_m, 100, 1e-9);
	near_heading("heading", 100, c.heading_rad, 60 * DEG);
	hl_road_centre(road, 150, &c);
	near("x", 150, c.x_m, 100 + 50 * c60, 1e-9);
	near("y", 150, c.y_m, 50 * s60, 1e-9);
	hl_road_centre(road, 230, &c);
	near("x", 230, c.x_m, 100 + 130 * c60, 1e-9);
	near("y", 230, c.y_m, 130 * s60, 1e-9);
	/* points and their projections: leg 1, leg 2, the inside near the vertex */
	hl_road_point(road, 150, -2, p);
	near_point("point", 150, p, 100 + 50 * c60 + 2 * s60, 50 * s60 - 2 * c60, 0);
	hl_road_project(road, p[0], p[1], &s, &d);
	near("s", 150, s, 150, 1e-9);
	near("d", 150, d, -2, 1e-9);
	hl_road_project(road, 50, 2, &s, &d);
	near("s", 50, s, 50, 1e-9);
	near("d", 50, d, 2, 1e-9);
	hl_road_project(road, 95, 3, &s, &d); /* nearer leg 1 (3 m) than leg 2 (5.83 m) */
	near("s", 95, s, 95, 1e-9);
	near("d", 95, d, 3, 1e-9);
	/* the wedge outside (right of) the vertex, between the legs' right normals */
	for (double a = -89.0; a <= -31.0; a += 29.0) {
		hl_road_project(road, 100 + 5 * cos(a * DEG), 5 * sin(a * DEG), &s, &d);
		near("wedge s", a, s, 100, 1e-9);
		near("wedge d", a, d, -5, 1e-9);
	}
	/* posts at s = 100, 4.25 m out: inside where the offset lines cross, outside on leg 2 */
	hl_road_post(road, 9, +1, p);
	near_point("post inside", 100, p, 100 - 4.25 / c30 * sin(30 * DEG), 4.25, 0);
	hl_road_post(road, 9, -1, p);
	near_point("post outside", 100, p, 100 + 4.25 * s60, -4.25 * c60, 0);
	hl_road_post(road, 8, +1, p); /* s = 90: 10 m before, beyond the crossing (2.45 m) */
	near_point("post inside", 90, p, 90, 4.25, 0);
	free(road);
}

/*
 * A 60 m-radius left arc over 90° given as points 1 m apart: points (s, d) of the true arc
 * project with d within the simplification tolerance, and s too on the centre line; off it s
 * is also off by up to |d| times half the largest kink (the legs' normals turn at the
 * vertices, the arc's turn smoothly). Every given point lies within tol of the simplified
 * line; the ends are kept.
 */
static void road_polyline_of_60m_arc(void **state)
{
	(void)state;
	const double R = 60.0, tol = 0.05, len = M_PI / 2 * R;
	const int n = (int)floor(len) + 2;
	double(*xy)[2] = calloc((size_t)n, sizeof(*xy));
	struct hl_road *road = calloc(1, sizeof(*road));
	struct hl_pose2 end;
	double s, d, kink = 0.0;

	for (int i = 0; i < n; i++) {
		const double phi = (i < n - 1 ? i : len) / R;

		xy[i][0] = R * sin(phi);
		xy[i][1] = R - R * cos(phi);
	}
	assert_int_equal(hl_road_set_polyline(road, (const double(*)[2])xy, n, tol), 0);
	assert_true(road->n_segments < n / 3);
	near("start x", 0, road->x0_m, 0, 0);
	hl_road_centre(road, road->length_m, &end);
	near("end x", len, end.x_m, xy[n - 1][0], 1e-9);
	near("end y", len, end.y_m, xy[n - 1][1], 1e-9);
	for (int i = 1; i < road->n_segments; i++)
		kink = fmax(kink, fabs(road->seg[i].kink_rad));
	near("largest kink", 0, kink, 0.0, 0.1);
	for (int i = 0; i < n; i++) {
		hl_road_project(road, xy[i][0], xy[i][1], &s, &d);
		near("given point d", i, d, 0, tol);
	}
	for (double st = 0.0; st <= len; st += 2.5)
		for (double dt = -5.0; dt <= 5.0; dt += 2.5) {
			const double phi = st / R;

			hl_road_project(road, R * sin(phi) - dt * sin(phi),
					R - R * cos(phi) + dt * cos(phi), &s, &d);
			near("arc s", st, s, st, tol + fabs(dt) * kink / 2);
			near("arc d", st, d, dt, tol);
		}
	free(road);
	free(xy);
}

/* Simplification within tol, repeated points dropped; bad polylines refused, road untouched. */
static void road_polyline_simplify_and_refuse(void **state)
{
	(void)state;
	const double rep[5][2] = { { 0, 0 }, { 0, 0 }, { 10, 0 }, { 10, 0 }, { 20, 5 } };
	const double same[3][2] = { { 1, 2 }, { 1, 2 }, { 1, 2 } };
	const double bad[3][2] = { { 0, 0 }, { NAN, 1 }, { 5, 5 } };
	const double loop[3][2] = { { 0, 0 }, { 0.005, 0 }, { 0, 0 } };
	const double bump[3][2] = { { 0, 0 }, { 50, 0.3 }, { 100, 0 } };
	double zig[400][2];
	struct hl_road *road = calloc(1, sizeof(*road));

	assert_int_equal(hl_road_set_polyline(road, rep, 5, 0.0), 0);
	assert_int_equal(road->n_segments, 2);
	near("leg 1", 0, road->seg[0].length_m, 10, 1e-12);
	near("leg 2", 1, road->seg[1].length_m, hypot(10, 5), 1e-12);
	/* a bump of 0.3 m: kept under 0.29 m, dropped under 0.31 m */
	assert_int_equal(hl_road_set_polyline(road, bump, 3, 0.29), 0);
	assert_int_equal(road->n_segments, 2);
	assert_int_equal(hl_road_set_polyline(road, bump, 3, 0.31), 0);
	assert_int_equal(road->n_segments, 1);
	near("chord", 0, road->length_m, 100, 1e-12);
	for (int i = 0; i < 400; i++) {
		zig[i][0] = i;
		zig[i][1] = i % 2;
	}
	assert_int_equal(hl_road_set_polyline(road, zig, 400, 0.01), -E2BIG);
	assert_int_equal(road->n_segments, 1); /* untouched */
	assert_int_equal(hl_road_set_polyline(road, zig, 400, 1.0), 0);
	assert_int_equal(road->n_segments, 1);
	near("chord", 0, road->length_m, hypot(399, 1), 1e-12);
	assert_int_equal(hl_road_set_polyline(road, rep, 1, 0.01), -EINVAL);
	assert_int_equal(hl_road_set_polyline(road, same, 3, 0.01), -EINVAL);
	assert_int_equal(hl_road_set_polyline(road, bad, 3, 0.01), -EINVAL);
	assert_int_equal(hl_road_set_polyline(road, loop, 3, 0.01), -EINVAL);
	assert_int_equal(hl_road_set_polyline(road, bump, 3, -1.0), -EINVAL);
	near("untouched", 0, road->length_m, hypot(399, 1), 1e-12);
	free(road);
}

/* A polyline road in a scenario file; and the rules for it, each refused where it is. */
static void road_polyline_in_a_scenario(void **state)
{
	(void)state;
	static const struct {
		const char *seg, *key, *msg;
		int line;
	} bad[] = {
		{ "\"segments\": [{\"kind\": \"polyline\", \"points_m\": [[0, 0], [0, 0]]}]",
		  "road.segments[0].points_m", "fewer than 2 distinct points", 1 },
		{ "\"segments\": [{\"kind\": \"polyline\", \"points_m\": [[0, 0], [1, 0, 2]]}]",
		  "road.segments[0].points_m[1]", "expected a point [x, y]", 1 },
		{ "\"segments\": [{\"kind\": \"straight\", \"length_m\": 5},\n"
		  "{\"kind\": \"polyline\", \"points_m\": [[0, 0], [1, 0]]}]",
		  "road.segments[1].kind", "the road's only segment", 2 },
		{ "\"start\": {\"x_m\": 1},\n"
		  "\"segments\": [{\"kind\": \"polyline\", \"points_m\": [[0, 0], [1, 0]]}]",
		  "road.start", "starts at its first point", 1 },
		{ "\"segments\": [{\"kind\": \"polyline\", \"length_m\": 5, \"points_m\": [[0, 0]]}]",
		  "road.segments[0].length_m", "unknown key", 1 },
	};
	char text[1024];
	struct hl_scenario *sc =
		load("{\"version\": 1, \"duration_s\": 1, \"road\": {\"segments\": "
		     "[{\"kind\": \"polyline\", \"points_m\": [[10, 5], [10, 5], "
		     "[10, 105], [0, 205]]}]}}");

	assert_int_equal(sc->road.n_segments, 2);
	near("x0", 0, sc->road.x0_m, 10, 0);
	near_heading("heading0", 0, sc->road.heading0_rad, 90 * DEG);
	near("length", 0, sc->road.length_m, 100 + hypot(10, 100), 1e-9);
	hl_scenario_free(sc);
	for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
		struct hl_json_error err;

		snprintf(text, sizeof(text), "{\"version\": 1, \"duration_s\": 1, \"road\": {%s}}",
			 bad[i].seg);
		assert_int_equal(hl_scenario_parse(text, "poly.json", &sc, &err), -EBADMSG);
		assert_string_equal(err.key, bad[i].key);
		assert_int_equal(err.line, bad[i].line);
		if (!strstr(err.msg, bad[i].msg))
			fail_msg("%s: '%s' lacks '%s'", err.key, err.msg, bad[i].msg);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(road_points_on_250m_arc),
		cmocka_unit_test(road_straight_then_arc),
		cmocka_unit_test(oncoming_car_under_piecewise_linear_speed),
		cmocka_unit_test(waypoint_path),
		cmocka_unit_test(ego_lamps_and_camera),
		cmocka_unit_test(per_frame_calls_allocate_nothing),
		cmocka_unit_test(road_polyline_one_kink),
		cmocka_unit_test(road_polyline_of_60m_arc),
		cmocka_unit_test(road_polyline_simplify_and_refuse),
		cmocka_unit_test(road_polyline_in_a_scenario),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
