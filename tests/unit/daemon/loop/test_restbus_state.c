/* SPDX-License-Identifier: MIT */
/*
 * What the restbus sends for a scenario instant, against closed forms: the box angles of road
 * users from the box corners that bound them (worked out by hand for each layout), their
 * distance, class, order, clipping and the reasons others are not sent; the vehicle state on
 * an arc (yaw rate v / R, the single-track steering angle).
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "daemon/loop/restbus_state.h"

#define DEG (M_PI / 180.0)

static struct hl_scenario *parse(const char *text)
{
	struct hl_scenario *sc = NULL;
	struct hl_json_error err;

	if (hl_scenario_parse(text, "test.json", &sc, &err) < 0) {
		char msg[512];

		hl_json_error_format(&err, msg, sizeof(msg));
		fail_msg("%s", msg);
	}
	return sc;
}

/* Ego in lane 1 (d = -1.75 m) at s = 0 heading +x: its origin at (0, -1.75). Cars 4.5 x 1.8 x
 * 1.45 m, the pedestrian 0.3 x 0.5 x 1.75 m (the defaults of docs/scenarios.md). */
static const char straight[] =
	"{\"version\": 1, \"duration_s\": 10,"
	" \"road\": {\"segments\": [{\"kind\": \"straight\", \"length_m\": 400}]},"
	" \"ego\": {\"start_s_m\": 0, \"speed_mps\": 20},"
	" \"actors\": ["
	"  {\"id\": \"oncoming\", \"kind\": \"car\", \"role\": \"oncoming\","
	"   \"path\": {\"lane\": 2, \"start_s_m\": 100, \"speed_mps\": 10}},"
	"  {\"id\": \"ahead\", \"kind\": \"car\", \"role\": \"preceding\","
	"   \"path\": {\"lane\": 1, \"start_s_m\": 50, \"speed_mps\": 20}},"
	"  {\"id\": \"far\", \"kind\": \"pedestrian\", \"role\": \"roadside\","
	"   \"path\": {\"waypoints\": [{\"t_s\": 0, \"x_m\": 300, \"y_m\": -4}], \"heading_deg\": 90}},"
	"  {\"id\": \"behind\", \"kind\": \"car\", \"role\": \"preceding\","
	"   \"path\": {\"lane\": 1, \"start_s_m\": -20, \"speed_mps\": 20}},"
	"  {\"id\": \"aside\", \"kind\": \"car\", \"role\": \"roadside\","
	"   \"path\": {\"waypoints\": [{\"t_s\": 0, \"x_m\": 20, \"y_m\": 40}], \"heading_deg\": 0}},"
	"  {\"id\": \"edge\", \"kind\": \"car\", \"role\": \"roadside\","
	"   \"path\": {\"waypoints\": [{\"t_s\": 0, \"x_m\": 15, \"y_m\": 3.5}], \"heading_deg\": 180}}"
	" ]}";

static const struct hl_restbus_camera cam = {
	.pos_m = { -1.8, 0, 1.3 }, /* world (-1.8, -1.75, 1.3) at t = 0 */
	.fov_h_deg = 30,
	.fov_v_deg = 20,
	.range_m = 250,
};

static void near(double got, double want, const char *what)
{
	if (fabs(got - want) > 1e-9)
		fail_msg("%s: %.12f, expected %.12f", what, got, want);
}

static void expect_box(const struct hl_camera_object *o, double hl, double hr, double vb, double vt,
		       double dist)
{
	near(o->h_left_deg, hl / DEG, "h_left");
	near(o->h_right_deg, hr / DEG, "h_right");
	near(o->v_bottom_deg, vb / DEG, "v_bottom");
	near(o->v_top_deg, vt / DEG, "v_top");
	near(o->distance_m, dist, "distance");
}

static void restbus_objects_closed_form(void **state)
{
	struct hl_scenario *sc = parse(straight);
	struct hl_world_state w;
	struct hl_camera_objects o;
	struct hl_restbus_unseen un;

	(void)state;
	hl_world_at(sc, 0, &w);
	hl_restbus_objects(sc, &w, &cam, 8, &o, &un);
	assert_int_equal(o.n, 3);
	assert_int_equal(un.behind, 1);
	assert_int_equal(un.beyond_range, 1);
	assert_int_equal(un.outside_fov, 1);
	assert_int_equal(un.over_max, 0);
	/*
	 * The nearest first. "edge": heading 180 at (15, 3.5): x 15..19.5 ahead f = 16.8..21.3,
	 * y 2.6..4.4, so right r = -(y + 1.75) = -4.35..-6.15; left edge atan2(-6.15, 16.8) =
	 * -20.1 deg is clipped to -15; right edge at the far corner atan2(-4.35, 21.3); bottom and
	 * top at the nearest corner hypot(4.35, 16.8), u = -1.3 and 1.45 - 1.3.
	 */
	assert_int_equal(o.obj[0].id, 6);
	assert_int_equal(o.obj[0].cls, HL_OBJECT_ONCOMING);
	expect_box(&o.obj[0], -15 * DEG, atan2(-4.35, 21.3), atan2(-1.3, hypot(4.35, 16.8)),
		   atan2(0.15, hypot(4.35, 16.8)), hypot(16.8, 4.35));
	/* "ahead": x 45.5..50, f 47.3..51.8, r -0.9..0.9; nearest point straight ahead 47.3 m */
	assert_int_equal(o.obj[1].id, 2);
	assert_int_equal(o.obj[1].cls, HL_OBJECT_PRECEDING);
	expect_box(&o.obj[1], atan2(-0.9, 47.3), atan2(0.9, 47.3), atan2(-1.3, hypot(0.9, 47.3)),
		   atan2(0.15, hypot(0.9, 47.3)), 47.3);
	/* "oncoming": x 100..104.5 (f 101.8..106.3), y 0.85..2.65 (r -2.6..-4.4) */
	assert_int_equal(o.obj[2].id, 1);
	assert_int_equal(o.obj[2].cls, HL_OBJECT_ONCOMING);
	expect_box(&o.obj[2], atan2(-4.4, 101.8), atan2(-2.6, 106.3),
		   atan2(-1.3, hypot(2.6, 101.8)), atan2(0.15, hypot(2.6, 101.8)),
		   hypot(101.8, 2.6));
	near(o.obj[2].confidence, 1, "confidence");
	/*
	 * At t = 2 s the ego is 40 m on (camera at x 38.2) and the oncoming car 20 m back: x
	 * 80..84.5, f 41.8..46.3, now the nearest; "edge" and "aside" are behind the camera, the
	 * pedestrian 262 m away beyond range.
	 */
	hl_world_at(sc, 2, &w);
	hl_restbus_objects(sc, &w, &cam, 8, &o, &un);
	assert_int_equal(o.n, 2);
	assert_int_equal(un.behind, 3);
	assert_int_equal(un.beyond_range, 1);
	assert_int_equal(o.obj[0].id, 1);
	expect_box(&o.obj[0], atan2(-4.4, 41.8), atan2(-2.6, 46.3), atan2(-1.3, hypot(2.6, 41.8)),
		   atan2(0.15, hypot(2.6, 41.8)), hypot(41.8, 2.6));
	/* one slot: only the nearest, the others counted */
	hl_world_at(sc, 0, &w);
	hl_restbus_objects(sc, &w, &cam, 1, &o, &un);
	assert_int_equal(o.n, 1);
	assert_int_equal(o.obj[0].id, 6);
	assert_int_equal(un.over_max, 2);
	hl_scenario_free(sc);
}

/* The unclipped projection sees the edge car's full box and nothing behind the camera. */
static void restbus_object_unclipped_and_behind(void **state)
{
	struct hl_scenario *sc = parse(straight);
	struct hl_world_state w;
	struct hl_camera_object o;

	(void)state;
	hl_world_at(sc, 0, &w);
	assert_true(hl_restbus_object(sc, &w, 5, &cam, &o));
	near(o.h_left_deg, atan2(-6.15, 16.8) / DEG, "h_left");
	assert_false(hl_restbus_object(sc, &w, 3, &cam, &o));
	assert_true(hl_restbus_object(sc, &w, 2, &cam, &o));
	assert_int_equal(o.cls, HL_OBJECT_PEDESTRIAN);
	assert_true(hl_restbus_object(sc, &w, 4, &cam, &o));
	assert_int_equal(o.cls, HL_OBJECT_PRECEDING); /* heading 0: the ego's */
	hl_scenario_free(sc);
}

static const char arc[] =
	"{\"version\": 1, \"duration_s\": 10,"
	" \"road\": {\"segments\": [{\"kind\": \"straight\", \"length_m\": 50},"
	"  {\"kind\": \"arc\", \"length_m\": 400, \"radius_m\": 250, \"turn\": \"left\"}]},"
	" \"ego\": {\"start_s_m\": 100, \"speed_mps\": %s}}";

static void restbus_vehicle_on_an_arc(void **state)
{
	char text[sizeof(arc) + 16];
	struct hl_scenario *sc;
	struct hl_world_state w;
	struct hl_vehicle_state vs;

	(void)state;
	snprintf(text, sizeof(text), arc, "20");
	sc = parse(text);
	hl_world_at(sc, 1, &w);
	hl_restbus_vehicle(sc, &w, HL_SWITCH_HIGH, true, &vs);
	near(vs.speed_mps, 20, "speed");
	/* the lane path's heading is the centre line's at s: it turns at v / R */
	if (fabs(vs.yaw_rate_rad_s - 20.0 / 250) > 1e-6)
		fail_msg("yaw rate %.9f, expected %.9f", vs.yaw_rate_rad_s, 20.0 / 250);
	if (fabs(vs.steering_rad - 15 * atan(2.8 / 250)) > 1e-5)
		fail_msg("steering %.9f, expected %.9f", vs.steering_rad, 15 * atan(2.8 / 250));
	assert_int_equal(vs.light_switch, HL_SWITCH_HIGH);
	assert_true(vs.adb_enable);
	hl_scenario_free(sc);
	/* standing on the arc: no yaw rate, the wheel still turned for the road's curvature */
	snprintf(text, sizeof(text), arc, "0");
	sc = parse(text);
	hl_world_at(sc, 1, &w);
	hl_restbus_vehicle(sc, &w, HL_SWITCH_AUTO, false, &vs);
	near(vs.speed_mps, 0, "speed");
	near(vs.yaw_rate_rad_s, 0, "yaw rate");
	if (fabs(vs.steering_rad - 15 * atan(2.8 / 250)) > 1e-5)
		fail_msg("steering %.9f, expected %.9f", vs.steering_rad, 15 * atan(2.8 / 250));
	assert_false(vs.adb_enable);
	hl_scenario_free(sc);
	/* on the straight part: nothing */
	sc = parse(straight);
	hl_world_at(sc, 1, &w);
	hl_restbus_vehicle(sc, &w, HL_SWITCH_AUTO, true, &vs);
	near(vs.yaw_rate_rad_s, 0, "yaw rate");
	near(vs.steering_rad, 0, "steering");
	hl_scenario_free(sc);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(restbus_objects_closed_form),
		cmocka_unit_test(restbus_object_unclipped_and_behind),
		cmocka_unit_test(restbus_vehicle_on_an_arc),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
