/* SPDX-License-Identifier: MIT */
/*
 * world/world.c: the scene at one instant: every pose from the scenario's paths (the same as
 * the scenario's own geometry gives), the road users' lamps lit, the ego lamps and the road
 * users' eyes carried into the world by a pose.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "world/world.h"

/* A straight road along +x (two lanes of 3.5 m), the ego in lane 1 at 20 m/s, an oncoming car
 * and a crossing pedestrian. */
static const char text[] =
	"{\"version\": 1, \"title\": \"t\", \"duration_s\": 10,\n"
	" \"road\": {\"segments\": [{\"kind\": \"straight\", \"length_m\": 400}],\n"
	"          \"lanes\": {\"count\": 2, \"width_m\": 3.5}},\n"
	" \"ego\": {\"start_s_m\": 10, \"lane\": 1, \"speed_mps\": 20},\n"
	" \"actors\": [\n"
	"  {\"id\": \"car\", \"kind\": \"car\", \"role\": \"oncoming\",\n"
	"   \"path\": {\"lane\": 2, \"start_s_m\": 300, \"speed_mps\": 10}},\n"
	"  {\"id\": \"ped\", \"kind\": \"pedestrian\", \"role\": \"crossing\",\n"
	"   \"path\": {\"waypoints\": [{\"t_s\": 0, \"x_m\": 60, \"y_m\": -5},\n"
	"                            {\"t_s\": 4, \"x_m\": 60, \"y_m\": 5}]}}]}\n";

static struct hl_scenario *parse(const char *t)
{
	struct hl_scenario *sc = NULL;
	struct hl_json_error err;

	if (hl_scenario_parse(t, "w.json", &sc, &err) < 0)
		fail_msg("%s:%d:%d: %s: %s", err.file, err.line, err.column, err.key, err.msg);
	return sc;
}

static void expect_near(double a, double b, double tol, const char *what)
{
	if (!(fabs(a - b) <= tol))
		fail_msg("%s = %.17g, expected %.17g within %g", what, a, b, tol);
}

/* Every pose is the scenario geometry's at t (bit for bit), the time and count are set and
 * every road user's lamps are lit; the values are where the paths put them. */
static void world_at_takes_every_pose_from_the_paths(void **state)
{
	struct hl_scenario *sc = parse(text);
	struct hl_world_state w;

	(void)state;
	for (double t = 0.0; t <= 10.0; t += 1.25) {
		struct hl_body_pose want;

		memset(&w, 0xa5, sizeof(w));
		hl_world_at(sc, t, &w);
		assert_true(w.t_s == t);
		assert_int_equal(w.n_actors, 2);
		assert_int_equal(w.lamps_on, 0x3);
		hl_world_ego_pose_at(sc, t, &want);
		assert_memory_equal(&w.ego, &want, sizeof(want));
		for (int i = 0; i < 2; i++) {
			hl_world_actor_pose_at(sc, i, t, &want);
			assert_memory_equal(&w.actor[i], &want, sizeof(want));
		}
	}
	hl_world_at(sc, 2.0, &w);
	/* ego: s = 10 + 20 * 2, in the middle of lane 1, right of the centre line */
	expect_near(w.ego.s_m, 50.0, 1e-12, "ego s");
	expect_near(w.ego.pos_m[0], 50.0, 1e-12, "ego x");
	expect_near(w.ego.pos_m[1], -1.75, 1e-12, "ego y");
	expect_near(w.ego.heading_rad, 0.0, 1e-15, "ego heading");
	expect_near(w.ego.speed_mps, 20.0, 1e-12, "ego speed");
	/* oncoming: s = 300 - 10 * 2 in lane 2, heading back */
	expect_near(w.actor[0].s_m, 280.0, 1e-12, "car s");
	expect_near(w.actor[0].pos_m[1], 1.75, 1e-12, "car y");
	expect_near(fabs(w.actor[0].heading_rad), M_PI, 1e-12, "car heading");
	/* the pedestrian half way: (60, 0), walking +y */
	expect_near(w.actor[1].pos_m[0], 60.0, 1e-12, "ped x");
	expect_near(w.actor[1].pos_m[1], 0.0, 1e-12, "ped y");
	expect_near(w.actor[1].heading_rad, M_PI / 2, 1e-12, "ped heading");
	assert_true(isnan(w.actor[1].s_m));
	hl_scenario_free(sc);
}

/* Bit i for road user i: none, one, the most a scenario may have. */
static void world_at_lights_every_road_users_lamps(void **state)
{
	char big[8192];
	size_t n;
	struct hl_scenario *sc;
	struct hl_world_state w;

	(void)state;
	sc = parse("{\"version\": 1, \"duration_s\": 5, \"road\": {\"segments\": "
		   "[{\"kind\": \"straight\", \"length_m\": 100}]}}");
	memset(&w, 0xa5, sizeof(w));
	hl_world_at(sc, 1.0, &w);
	assert_int_equal(w.n_actors, 0);
	assert_int_equal(w.lamps_on, 0);
	hl_scenario_free(sc);

	n = (size_t)snprintf(big, sizeof(big),
			     "{\"version\": 1, \"duration_s\": 5, \"road\": {\"segments\": "
			     "[{\"kind\": \"straight\", \"length_m\": 500}]}, \"actors\": [");
	for (int i = 0; i < HL_SCN_MAX_ACTORS; i++)
		n += (size_t)snprintf(big + n, sizeof(big) - n,
				      "%s{\"id\": \"c%d\", \"kind\": \"car\", \"role\": "
				      "\"oncoming\", \"path\": {\"start_s_m\": %d, "
				      "\"speed_mps\": 10}}",
				      i ? ", " : "", i, 100 + 20 * i);
	snprintf(big + n, sizeof(big) - n, "]}");
	sc = parse(big);
	hl_world_at(sc, 0.5, &w);
	assert_int_equal(w.n_actors, HL_SCN_MAX_ACTORS);
	assert_int_equal(w.lamps_on, (1u << HL_SCN_MAX_ACTORS) - 1u);
	for (int i = 0; i < HL_SCN_MAX_ACTORS; i++)
		expect_near(w.actor[i].s_m, 100.0 + 20.0 * i - 5.0, 1e-12, "s");
	hl_scenario_free(sc);
}

/* The ego lamps: positions through the ego pose, yaw turned by its heading into (-180, 180];
 * at the scenario's own pose, what the scenario says. */
static void world_ego_lamps_turn_with_the_ego(void **state)
{
	struct hl_scenario *sc = parse(text);
	struct hl_body_pose ego = { { 10.0, 20.0, 0.0 }, M_PI / 2, NAN, 0.0 };
	struct hl_lamp_pose got[2], want[2];

	(void)state;
	sc->ego.lamp[0].yaw_deg = 5.0;
	sc->ego.lamp[1].yaw_deg = -3.0;
	hl_world_ego_lamps(sc, &ego, got);
	for (int l = 0; l < 2; l++) {
		const double *p = sc->ego.lamp[l].pos_m;

		/* heading 90 degrees: the body's x is the world's +y, its y (left) the world's -x */
		expect_near(got[l].pos_m[0], 10.0 - p[1], 1e-12, "lamp x");
		expect_near(got[l].pos_m[1], 20.0 + p[0], 1e-12, "lamp y");
		expect_near(got[l].pos_m[2], p[2], 0, "lamp z");
		assert_true(got[l].pitch_deg == sc->ego.lamp[l].pitch_deg);
	}
	expect_near(got[0].yaw_deg, 95.0, 1e-12, "left yaw");
	expect_near(got[1].yaw_deg, 87.0, 1e-12, "right yaw");
	/* heading 180 degrees: 185 is -175, -3 + 180 stays 177 */
	ego.heading_rad = M_PI;
	hl_world_ego_lamps(sc, &ego, got);
	expect_near(got[0].yaw_deg, -175.0, 1e-12, "left yaw");
	expect_near(got[1].yaw_deg, 177.0, 1e-12, "right yaw");
	ego.heading_rad = -M_PI / 2;
	hl_world_ego_lamps(sc, &ego, got);
	expect_near(got[0].yaw_deg, -85.0, 1e-12, "left yaw");

	sc->ego.lamp[0].yaw_deg = 0.0;
	sc->ego.lamp[1].yaw_deg = 0.0;
	for (double t = 0.0; t <= 10.0; t += 2.5) {
		hl_world_ego_pose_at(sc, t, &ego);
		hl_world_ego_lamps(sc, &ego, got);
		hl_world_ego_lamps_at(sc, t, want);
		for (int l = 0; l < 2; l++) {
			for (int i = 0; i < 3; i++)
				expect_near(got[l].pos_m[i], want[l].pos_m[i], 1e-12, "pos");
			expect_near(got[l].yaw_deg, want[l].yaw_deg, 1e-12, "yaw");
			expect_near(got[l].pitch_deg, want[l].pitch_deg, 0, "pitch");
		}
	}
	hl_scenario_free(sc);
}

/* A road user's eye: its own-frame point through the pose; at the scenario's pose, the
 * scenario's eye point. */
static void world_actor_eye_is_the_eye_point_through_the_pose(void **state)
{
	struct hl_scenario *sc = parse(text);
	const struct hl_body_pose pose = { { 100.0, 2.0, 0.0 }, M_PI, 280.0, 10.0 };
	double eye[3], want[3];

	(void)state;
	for (int i = 0; i < 2; i++) {
		const double *e = sc->actor[i].eye_m;

		hl_world_actor_eye(sc, i, &pose, eye);
		/* heading 180 degrees: forward is -x, left is -y */
		expect_near(eye[0], 100.0 - e[0], 1e-12, "eye x");
		expect_near(eye[1], 2.0 - e[1], 1e-12, "eye y");
		expect_near(eye[2], e[2], 0, "eye z");
		for (double t = 0.0; t <= 10.0; t += 2.5) {
			struct hl_body_pose p;

			hl_world_actor_pose_at(sc, i, t, &p);
			hl_world_actor_eye(sc, i, &p, eye);
			hl_world_actor_eye_at(sc, i, t, want);
			for (int k = 0; k < 3; k++)
				expect_near(eye[k], want[k], 1e-12, "eye");
		}
	}
	/* the car's driver sits above the road (default 1.1 m) */
	expect_near(sc->actor[0].eye_m[2], 1.1, 1e-12, "driver's eye height");
	hl_scenario_free(sc);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(world_at_takes_every_pose_from_the_paths),
		cmocka_unit_test(world_at_lights_every_road_users_lamps),
		cmocka_unit_test(world_ego_lamps_turn_with_the_ego),
		cmocka_unit_test(world_actor_eye_is_the_eye_point_through_the_pose),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
