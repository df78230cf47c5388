/* SPDX-License-Identifier: MIT */
/*
 * world/track.c: a recorded world's states pushed strictly in time order (an equal, earlier or
 * NaN time refused), looked up before the first, between, exactly at and after the last, over
 * many states; a scenario carrying a track answers hl_world_at() and the pose functions from it
 * and frees it.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>
#include <errno.h>

#include "world/scenario.h"
#include "world/track.h"
#include "world/world.h"

/* Two road users; their paths put them nowhere near where the track does. */
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

/* A state at t_s told apart by its values: the ego at x = 1000 + t, road user i at 2000 + t. */
static struct hl_world_state state_at(double t_s)
{
	struct hl_world_state st = { .t_s = t_s, .n_actors = 2, .lamps_on = 0x1, .present = 0x3 };

	st.ego = (struct hl_body_pose){ .pos_m = { 1000.0 + t_s, -1.75, 0.0 },
					.heading_rad = 0.1,
					.s_m = NAN,
					.speed_mps = 20.0 };
	for (int i = 0; i < 2; i++)
		st.actor[i] = (struct hl_body_pose){ .pos_m = { 2000.0 + t_s, 1.75 * i, 0.0 },
						     .heading_rad = M_PI,
						     .s_m = NAN,
						     .speed_mps = 10.0 + i };
	return st;
}

static struct hl_world_track *track_of(const double *t_s, int n)
{
	struct hl_world_track *t = NULL;

	assert_int_equal(hl_world_track_new(&t), 0);
	for (int i = 0; i < n; i++) {
		const struct hl_world_state st = state_at(t_s[i]);

		assert_int_equal(hl_world_track_push(t, &st), 0);
	}
	return t;
}

static void track_push_strictly_increasing(void **state)
{
	(void)state;
	static const double t_s[] = { -0.5, 0.0, 0.02 };
	struct hl_world_track *t = track_of(t_s, 3);
	struct hl_world_state st;

	assert_int_equal(hl_world_track_count(t), 3);
	st = state_at(0.02); /* equal */
	assert_int_equal(hl_world_track_push(t, &st), -EINVAL);
	st = state_at(0.01); /* earlier */
	assert_int_equal(hl_world_track_push(t, &st), -EINVAL);
	st = state_at(NAN);
	assert_int_equal(hl_world_track_push(t, &st), -EINVAL);
	assert_int_equal(hl_world_track_count(t), 3);
	st = state_at(0.020000001);
	assert_int_equal(hl_world_track_push(t, &st), 0);
	assert_int_equal(hl_world_track_count(t), 4);
	for (size_t i = 0; i < 3; i++)
		assert_float_equal(hl_world_track_state(t, i)->t_s, t_s[i], 0.0);
	assert_null(hl_world_track_state(t, 4));
	assert_null(hl_world_track_state(t, (size_t)-1));
	hl_world_track_free(t);
	hl_world_track_free(NULL);
}

static void track_lookup_before_between_at_after(void **state)
{
	(void)state;
	static const double t_s[] = { 1.0, 2.0, 3.5 };
	static const struct {
		double t_s;
		size_t index;
	} cases[] = {
		{ -100.0, 0 },	 { 0.999, 0 },	   { 1.0, 0 }, { 1.5, 0 }, { 1.999999, 0 },
		{ 2.0, 1 },	 { 3.0, 1 },	   { 3.5, 2 }, { 3.6, 2 }, { 1e9, 2 },
		{ INFINITY, 2 }, { -INFINITY, 0 }, { NAN, 0 },
	};
	struct hl_world_track *t = track_of(t_s, 3);

	for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
		struct hl_world_state st;
		size_t k = hl_world_track_index(t, cases[i].t_s);

		if (k != cases[i].index)
			fail_msg("t %g: index %zu, expected %zu", cases[i].t_s, k, cases[i].index);
		/* the state, its time the one asked */
		hl_world_track_at(t, cases[i].t_s, &st);
		if (isnan(cases[i].t_s))
			assert_true(isnan(st.t_s));
		else
			assert_float_equal(st.t_s, cases[i].t_s, 0.0);
		/* positions 1000 + t, 2000 + t at each state: interpolated in between, held
		 * before the first and after the last */
		{
			const double tc = isnan(cases[i].t_s) ?
						  t_s[0] :
						  fmin(fmax(cases[i].t_s, t_s[0]), t_s[2]);

			assert_float_equal(st.ego.pos_m[0], 1000.0 + tc, 1e-9);
			assert_float_equal(st.actor[1].pos_m[0], 2000.0 + tc, 1e-9);
		}
		assert_float_equal(st.actor[1].speed_mps, 11.0, 0.0);
		assert_int_equal(st.n_actors, 2);
		assert_int_equal(st.present, 0x3);
		assert_int_equal(st.lamps_on, 0x1);
	}
	hl_world_track_free(t);
}

static void track_one_state_holds_everywhere(void **state)
{
	(void)state;
	static const double t_s[] = { 5.0 };
	struct hl_world_track *t = track_of(t_s, 1);

	assert_int_equal(hl_world_track_index(t, 0.0), 0);
	assert_int_equal(hl_world_track_index(t, 5.0), 0);
	assert_int_equal(hl_world_track_index(t, 50.0), 0);
	hl_world_track_free(t);
}

/* 10007 states at 50 Hz (past the first allocation several times): every lookup exact. */
static void track_many_states(void **state)
{
	(void)state;
	enum { N = 10007 };
	struct hl_world_track *t = NULL;
	struct hl_world_state st;

	assert_int_equal(hl_world_track_new(&t), 0);
	for (int i = 0; i < N; i++) {
		st = state_at(i * 0.02);
		assert_int_equal(hl_world_track_push(t, &st), 0);
	}
	assert_int_equal(hl_world_track_count(t), N);
	for (size_t i = 0; i < N; i++) {
		const double ti = hl_world_track_state(t, i)->t_s;

		assert_int_equal(hl_world_track_index(t, ti), i);
		assert_int_equal(hl_world_track_index(t, ti + 0.01), i);
		if (i)
			assert_int_equal(hl_world_track_index(t, nextafter(ti, -INFINITY)), i - 1);
	}
	hl_world_track_free(t);
}

static void track_carried_by_a_scenario(void **state)
{
	(void)state;
	static const double t_s[] = { 0.0, 0.5, 1.25 };
	struct hl_scenario *sc = NULL;
	struct hl_world_state st, want;
	struct hl_body_pose pose, path_pose;
	struct hl_lamp_pose lamps[2], lamps_want[2];
	struct hl_json_error err;
	double eye[3], eye_want[3];

	if (hl_scenario_parse(text, "t.json", &sc, &err) < 0)
		fail_msg("%s:%d:%d: %s", err.file, err.line, err.column, err.msg);
	hl_world_actor_pose_at(sc, 0, 0.5, &path_pose);
	sc->track = track_of(t_s, 3);
	/* at a state's own time: that state (between two: interpolated, tested above) */
	hl_world_at(sc, 0.5, &st);
	want = state_at(0.5);
	want.t_s = 0.5;
	assert_float_equal(st.t_s, want.t_s, 0.0);
	assert_int_equal(st.n_actors, want.n_actors);
	assert_int_equal(st.present, want.present);
	assert_int_equal(st.lamps_on, want.lamps_on);
	assert_memory_equal(&st.ego, &want.ego, sizeof(st.ego));
	assert_memory_equal(st.actor, want.actor, 2 * sizeof(st.actor[0]));
	hl_world_ego_pose_at(sc, 0.5, &pose);
	assert_memory_equal(&pose, &want.ego, sizeof(pose));
	hl_world_actor_pose_at(sc, 0, 0.5, &pose);
	assert_memory_equal(&pose, &want.actor[0], sizeof(pose));
	assert_true(fabs(pose.pos_m[0] - path_pose.pos_m[0]) > 100.0); /* not the path's */
	hl_world_actor_pose_at(sc, 1, 0.5, &pose);
	assert_memory_equal(&pose, &want.actor[1], sizeof(pose));
	/* before the first: the first; after the last: the last */
	hl_world_at(sc, -3.0, &st);
	assert_float_equal(st.t_s, -3.0, 0.0);
	assert_float_equal(st.ego.pos_m[0], 1000.0, 0.0);
	hl_world_ego_pose_at(sc, 99.0, &pose);
	assert_float_equal(pose.pos_m[0], 1001.25, 0.0);
	hl_world_actor_pose_at(sc, 1, 1.25, &pose);
	assert_float_equal(pose.pos_m[0], 2001.25, 0.0);
	/* lamps and eyes follow the track's poses */
	hl_world_ego_lamps_at(sc, 0.5, lamps);
	hl_world_ego_lamps(sc, &want.ego, lamps_want);
	assert_memory_equal(lamps, lamps_want, sizeof(lamps));
	hl_world_actor_eye_at(sc, 1, 0.5, eye);
	hl_world_actor_eye(sc, 1, &want.actor[1], eye_want);
	assert_memory_equal(eye, eye_want, sizeof(eye));
	hl_scenario_free(sc); /* frees the track: the sanitizer build sees no leak */
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(track_push_strictly_increasing),
		cmocka_unit_test(track_lookup_before_between_at_after),
		cmocka_unit_test(track_one_state_holds_everywhere),
		cmocka_unit_test(track_many_states),
		cmocka_unit_test(track_carried_by_a_scenario),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
