/* SPDX-License-Identifier: MIT */
/*
 * world/osi_world.c: OSI messages (frames filled by hand) as hdlamp's world: every type of the
 * kind table, the pose below the front face and its inverse, the host as the ego, roles from the
 * relative heading, lamps, road users leaving and coming back, objects left out and counted,
 * hosts refused with the field named, the road from lane boundaries or the base scenario, and
 * the reasons' names.
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

#include "osi_fixture.h"
#include "scenario_util.h"
#include "world/osi_msg.h"
#include "world/osi_world.h"
#include "world/scenario.h"
#include "world/world.h"

#define DEG (M_PI / 180.0)

static struct hl_osi_world *world_of(const struct hl_osi_frame *f, const struct hl_scenario *base)
{
	struct hl_osi_world *w = NULL;
	char why[256] = "";

	if (hl_osi_world_new(f, base, &w, why, sizeof(why)) < 0)
		fail_msg("hl_osi_world_new: %s", why);
	return w;
}

static void map_ok(const struct hl_osi_world *w, const struct hl_osi_frame *f, double t_s,
		   struct hl_world_state *st, uint64_t counts[HL_OSI_REASONS])
{
	char why[256] = "";

	if (hl_osi_world_map(w, f, t_s, st, counts, why, sizeof(why)) != HL_OSI_OK)
		fail_msg("hl_osi_world_map: %s", why);
}

static void expect_why(const char *why, const char *part)
{
	if (!strstr(why, part))
		fail_msg("why '%s' lacks '%s'", why, part);
}

static void osi_world_kind_table(void **state)
{
	(void)state;
	static const struct {
		int type;
		bool has_classification;
		int vehicle_type;
		int kind; /* -1: unknown_type */
	} cases[] = {
		{ HL_OSI_TYPE_UNKNOWN, false, 0, -1 },
		{ HL_OSI_TYPE_OTHER, false, 0, -1 },
		{ HL_OSI_TYPE_ANIMAL, false, 0, -1 },
		{ 5, false, 0, -1 }, /* a later OSI's type */
		{ HL_OSI_TYPE_PEDESTRIAN, false, 0, HL_ACTOR_PEDESTRIAN },
		{ HL_OSI_TYPE_VEHICLE, false, 0, HL_ACTOR_CAR },
		{ HL_OSI_TYPE_VEHICLE, true, HL_OSI_VEHICLE_UNKNOWN, HL_ACTOR_CAR },
		{ HL_OSI_TYPE_VEHICLE, true, HL_OSI_VEHICLE_OTHER, HL_ACTOR_CAR },
		{ HL_OSI_TYPE_VEHICLE, true, HL_OSI_VEHICLE_SMALL_CAR, HL_ACTOR_CAR },
		{ HL_OSI_TYPE_VEHICLE, true, HL_OSI_VEHICLE_COMPACT_CAR, HL_ACTOR_CAR },
		{ HL_OSI_TYPE_VEHICLE, true, HL_OSI_VEHICLE_MEDIUM_CAR, HL_ACTOR_CAR },
		{ HL_OSI_TYPE_VEHICLE, true, HL_OSI_VEHICLE_LUXURY_CAR, HL_ACTOR_CAR },
		{ HL_OSI_TYPE_VEHICLE, true, HL_OSI_VEHICLE_DELIVERY_VAN, HL_ACTOR_CAR },
		{ HL_OSI_TYPE_VEHICLE, true, HL_OSI_VEHICLE_HEAVY_TRUCK, HL_ACTOR_TRUCK },
		{ HL_OSI_TYPE_VEHICLE, true, HL_OSI_VEHICLE_SEMITRAILER, HL_ACTOR_TRUCK },
		{ HL_OSI_TYPE_VEHICLE, true, HL_OSI_VEHICLE_TRAILER, HL_ACTOR_TRUCK },
		{ HL_OSI_TYPE_VEHICLE, true, HL_OSI_VEHICLE_MOTORBIKE, HL_ACTOR_MOTORBIKE },
		{ HL_OSI_TYPE_VEHICLE, true, HL_OSI_VEHICLE_BICYCLE, HL_ACTOR_CYCLIST },
		{ HL_OSI_TYPE_VEHICLE, true, HL_OSI_VEHICLE_BUS, HL_ACTOR_TRUCK },
		{ HL_OSI_TYPE_VEHICLE, true, HL_OSI_VEHICLE_TRAM, HL_ACTOR_TRUCK },
		{ HL_OSI_TYPE_VEHICLE, true, HL_OSI_VEHICLE_TRAIN, HL_ACTOR_TRUCK },
		{ HL_OSI_TYPE_VEHICLE, true, HL_OSI_VEHICLE_WHEELCHAIR, HL_ACTOR_PEDESTRIAN },
		{ HL_OSI_TYPE_VEHICLE, true, 16, HL_ACTOR_TRUCK }, /* semitractor */
		{ HL_OSI_TYPE_VEHICLE, true, 17, -1 }, /* stand-up scooter */
		{ HL_OSI_TYPE_VEHICLE, true, 99, -1 },
		{ HL_OSI_TYPE_VEHICLE, true, -1, -1 },
	};
	const double dim[3] = { 6.0, 2.1, 2.5 };

	for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
		struct hl_osi_frame *f = osi_message(0);
		struct hl_osi_object *o = osi_add(f, 7, cases[i].type, 30.0, 1.75, M_PI);
		uint64_t counts[HL_OSI_REASONS] = { 0 };
		const struct hl_scenario *sc;
		struct hl_world_state st;
		struct hl_osi_world *w;

		o->has_classification = cases[i].has_classification;
		o->vehicle_type = cases[i].vehicle_type;
		memcpy(o->dim_m, dim, sizeof(dim));
		w = world_of(f, NULL);
		sc = hl_osi_world_scenario(w);
		map_ok(w, f, 0.0, &st, counts);
		if (cases[i].kind < 0) {
			if (sc->n_actors != 0 || counts[HL_OSI_UNKNOWN_TYPE] != 1)
				fail_msg("case %zu: type %d, vehicle type %d: %d road users, "
					 "unknown_type %llu; expected left out and counted",
					 i, cases[i].type, cases[i].vehicle_type, sc->n_actors,
					 (unsigned long long)counts[HL_OSI_UNKNOWN_TYPE]);
			assert_int_equal(st.n_actors, 0);
		} else {
			if (sc->n_actors != 1 || (int)sc->actor[0].kind != cases[i].kind)
				fail_msg("case %zu: type %d, vehicle type %d: %d road users, kind "
					 "%s; expected %s",
					 i, cases[i].type, cases[i].vehicle_type, sc->n_actors,
					 sc->n_actors ? hl_actor_kind_name(sc->actor[0].kind) : "-",
					 hl_actor_kind_name((enum hl_actor_kind)cases[i].kind));
			assert_string_equal(sc->actor[0].id, "osi-7");
			/* the body is the message's dimension */
			for (int k = 0; k < 3; k++)
				assert_float_equal(sc->actor[0].size_m[k], dim[k], 0.0);
			assert_int_equal(counts[HL_OSI_UNKNOWN_TYPE], 0);
			assert_true(hl_world_present(&st, 0));
		}
		for (int r = 0; r < HL_OSI_REASONS; r++)
			if (r != HL_OSI_UNKNOWN_TYPE)
				assert_int_equal(counts[r], 0);
		hl_osi_world_free(w);
		hl_osi_frame_free(f);
	}
}

static void osi_world_pose_below_front_face(void **state)
{
	(void)state;
	struct hl_osi_frame *f = osi_message(0);
	struct hl_osi_object *host = &f->object[0];
	struct hl_osi_object *o = osi_add_vehicle(f, 2, HL_OSI_VEHICLE_MEDIUM_CAR, 40.0, 1.75, 3.5);
	const struct hl_scenario *sc;
	struct hl_world_state st;
	struct hl_osi_world *w;
	double pos[3], yaw;

	/* the host: its centre at (10, -1.5, 0.9), 0.3 rad, rolled and pitched, moving up */
	host->pos_m[0] = 10.0;
	host->pos_m[1] = -1.5;
	host->pos_m[2] = 0.9;
	host->rpy_rad[0] = 0.05;
	host->rpy_rad[1] = -0.02;
	host->rpy_rad[2] = 0.3;
	host->vel_mps[0] = 3.0;
	host->vel_mps[1] = 4.0;
	host->vel_mps[2] = 12.0; /* not in the ground plane: no speed */
	o->dim_m[0] = 5.0;
	o->vel_mps[0] = -12.0;
	o->vel_mps[1] = NAN; /* a missing component counts as 0 */
	w = world_of(f, NULL);
	sc = hl_osi_world_scenario(w);
	assert_int_equal(sc->n_actors, 1); /* the host is the ego, not a road user */
	assert_string_equal(sc->actor[0].id, "osi-2");
	map_ok(w, f, 2.5, &st, NULL);
	assert_float_equal(st.t_s, 2.5, 0.0);
	assert_int_equal(st.n_actors, 1);
	assert_float_equal(st.ego.pos_m[0], 10.0 + 2.25 * cos(0.3), 1e-12);
	assert_float_equal(st.ego.pos_m[1], -1.5 + 2.25 * sin(0.3), 1e-12);
	assert_float_equal(st.ego.pos_m[2], 0.0, 0.0);
	assert_float_equal(st.ego.heading_rad, 0.3, 1e-15);
	assert_float_equal(st.ego.speed_mps, 5.0, 1e-12);
	assert_true(isnan(st.ego.s_m));
	/* 3.5 rad: heading wrapped into [-pi, pi] */
	assert_float_equal(st.actor[0].heading_rad, 3.5 - 2 * M_PI, 1e-12);
	assert_float_equal(st.actor[0].pos_m[0], 40.0 + 2.5 * cos(3.5), 1e-12);
	assert_float_equal(st.actor[0].pos_m[1], 1.75 + 2.5 * sin(3.5), 1e-12);
	assert_float_equal(st.actor[0].pos_m[2], 0.0, 0.0);
	assert_float_equal(st.actor[0].speed_mps, 12.0, 1e-12);
	/* the inverse: back to the box's centre (z from the height: the box stands on z = 0) */
	hl_osi_pose_to_centre(&st.ego, host->dim_m, pos, &yaw);
	assert_float_equal(pos[0], 10.0, 1e-12);
	assert_float_equal(pos[1], -1.5, 1e-12);
	assert_float_equal(pos[2], 0.75, 1e-12);
	assert_float_equal(yaw, 0.3, 1e-12);
	hl_osi_pose_to_centre(&st.actor[0], o->dim_m, pos, &yaw);
	assert_float_equal(pos[0], 40.0, 1e-12);
	assert_float_equal(pos[1], 1.75, 1e-12);
	assert_float_equal(pos[2], 0.75, 1e-12);
	assert_float_equal(yaw, 3.5 - 2 * M_PI, 1e-12);
	/* the inverse first: a pose made a centre maps back to the same pose */
	{
		const struct hl_body_pose p = { .pos_m = { -12.5, 3.25, 0.0 },
						.heading_rad = -2.0,
						.s_m = NAN,
						.speed_mps = 0.0 };

		hl_osi_pose_to_centre(&p, osi_car_dim, o->pos_m, &o->rpy_rad[2]);
		memcpy(o->dim_m, osi_car_dim, sizeof(osi_car_dim));
		o->vel_mps[0] = o->vel_mps[1] = 0.0;
		map_ok(w, f, 2.6, &st, NULL);
		assert_float_equal(st.actor[0].pos_m[0], p.pos_m[0], 1e-12);
		assert_float_equal(st.actor[0].pos_m[1], p.pos_m[1], 1e-12);
		assert_float_equal(st.actor[0].heading_rad, p.heading_rad, 1e-12);
		assert_float_equal(o->pos_m[2], 0.75, 1e-12);
	}
	hl_osi_world_free(w);
	hl_osi_frame_free(f);
}

static void osi_world_roles_from_relative_heading(void **state)
{
	(void)state;
	struct hl_osi_frame *f = osi_message(0);
	static const struct {
		int type;
		double yaw_deg; /* the host's is 20 */
		enum hl_actor_role role;
	} cases[] = {
		{ HL_OSI_TYPE_VEHICLE, 200.0, HL_ROLE_ONCOMING },
		{ HL_OSI_TYPE_VEHICLE, 20.0 + 140.0, HL_ROLE_ONCOMING },
		{ HL_OSI_TYPE_VEHICLE, 20.0 - 150.0, HL_ROLE_ONCOMING },
		{ HL_OSI_TYPE_VEHICLE, 20.0 + 130.0, HL_ROLE_CROSSING },
		{ HL_OSI_TYPE_VEHICLE, 20.0 + 90.0, HL_ROLE_CROSSING },
		{ HL_OSI_TYPE_VEHICLE, 20.0 - 90.0, HL_ROLE_CROSSING },
		{ HL_OSI_TYPE_VEHICLE, 20.0 + 50.0, HL_ROLE_CROSSING },
		{ HL_OSI_TYPE_VEHICLE, 20.0 + 40.0, HL_ROLE_PRECEDING },
		{ HL_OSI_TYPE_VEHICLE, 20.0 - 40.0, HL_ROLE_PRECEDING },
		{ HL_OSI_TYPE_VEHICLE, 20.0 + 360.0, HL_ROLE_PRECEDING },
		{ HL_OSI_TYPE_PEDESTRIAN, 20.0, HL_ROLE_ROADSIDE },
		{ HL_OSI_TYPE_PEDESTRIAN, 200.0, HL_ROLE_ROADSIDE },
	};
	const int n = (int)(sizeof(cases) / sizeof(cases[0]));
	const struct hl_scenario *sc;
	struct hl_osi_world *w;

	f->object[0].rpy_rad[2] = 20.0 * DEG;
	for (int i = 0; i < n; i++)
		osi_add(f, 10 + (uint64_t)i, cases[i].type, 10.0 * i, 1.75, cases[i].yaw_deg * DEG);
	w = world_of(f, NULL);
	sc = hl_osi_world_scenario(w);
	assert_int_equal(sc->n_actors, n);
	for (int i = 0; i < n; i++)
		if (sc->actor[i].role != cases[i].role)
			fail_msg("%d: %g deg: %s, expected %s", i, cases[i].yaw_deg,
				 hl_actor_role_name(sc->actor[i].role),
				 hl_actor_role_name(cases[i].role));
	hl_osi_world_free(w);
	hl_osi_frame_free(f);
}

static void osi_world_lamps_lit_unless_head_light_off(void **state)
{
	(void)state;
	struct hl_osi_frame *f = osi_message(0);
	struct hl_world_state st;
	struct hl_osi_world *w;

	osi_add_vehicle(f, 2, HL_OSI_VEHICLE_MEDIUM_CAR, 30, 1.75, M_PI)->head_light =
		HL_OSI_LIGHT_OFF;
	osi_add_vehicle(f, 3, HL_OSI_VEHICLE_MEDIUM_CAR, 40, 1.75, M_PI)->head_light =
		HL_OSI_LIGHT_ON;
	osi_add_vehicle(f, 4, HL_OSI_VEHICLE_MEDIUM_CAR, 50, 1.75, M_PI)->head_light =
		HL_OSI_LIGHT_UNKNOWN;
	osi_add_vehicle(f, 5, HL_OSI_VEHICLE_MEDIUM_CAR, 60, 1.75, M_PI)->head_light =
		HL_OSI_LIGHT_OTHER;
	osi_add(f, 6, HL_OSI_TYPE_VEHICLE, 70, 1.75, M_PI); /* no classification */
	osi_add(f, 7, HL_OSI_TYPE_PEDESTRIAN, 80, 5.0, 0.0);
	osi_add_vehicle(f, 8, HL_OSI_VEHICLE_BICYCLE, 90, -1.75, 0.0)->head_light =
		4; /* flashing */
	w = world_of(f, NULL);
	map_ok(w, f, 0.0, &st, NULL);
	assert_int_equal(st.n_actors, 7);
	assert_int_equal(st.present, 0x7f);
	assert_int_equal(st.lamps_on, 0x7e);
	/* switched off later: that message's state */
	f->object[3].head_light = HL_OSI_LIGHT_OFF;
	map_ok(w, f, 0.1, &st, NULL);
	assert_int_equal(st.lamps_on, 0x7a);
	hl_osi_world_free(w);
	hl_osi_frame_free(f);
}

static void osi_world_road_user_leaves_and_comes_back(void **state)
{
	(void)state;
	struct hl_osi_frame *f = osi_message(0);
	struct hl_world_state st;
	struct hl_osi_world *w;

	osi_add_vehicle(f, 2, HL_OSI_VEHICLE_MEDIUM_CAR, 30, 1.75, M_PI);
	osi_add_vehicle(f, 3, HL_OSI_VEHICLE_HEAVY_TRUCK, 60, 1.75, M_PI);
	w = world_of(f, NULL);
	map_ok(w, f, 0.0, &st, NULL);
	assert_true(hl_world_present(&st, 0));
	assert_true(hl_world_present(&st, 1));
	assert_false(hl_world_present(&st, 2));
	assert_false(hl_world_present(&st, -1));
	/* 2 gone: 3 keeps its slot */
	f->object[1] = f->object[2];
	f->n_objects = 2;
	map_ok(w, f, 0.1, &st, NULL);
	assert_int_equal(st.n_actors, 2);
	assert_false(hl_world_present(&st, 0));
	assert_true(hl_world_present(&st, 1));
	assert_int_equal(st.present, 0x2);
	assert_int_equal(st.lamps_on, 0x2);
	assert_true(isnan(st.actor[0].s_m));
	assert_float_equal(st.actor[1].pos_m[0], 60.0 - 2.25, 1e-12);
	/* back, listed after 3, moved */
	osi_add_vehicle(f, 2, HL_OSI_VEHICLE_MEDIUM_CAR, 20, 1.75, M_PI);
	map_ok(w, f, 0.2, &st, NULL);
	assert_int_equal(st.present, 0x3);
	assert_int_equal(st.lamps_on, 0x3);
	assert_float_equal(st.actor[0].pos_m[0], 20.0 - 2.25, 1e-12);
	hl_osi_world_free(w);
	hl_osi_frame_free(f);
}

static void osi_world_new_object_counted_and_cast(void **state)
{
	(void)state;
	struct hl_osi_frame *f = osi_message(0);
	uint64_t counts[HL_OSI_REASONS] = { 0 };
	struct hl_world_state st;
	struct hl_osi_world *w;

	osi_add_vehicle(f, 2, HL_OSI_VEHICLE_MEDIUM_CAR, 30, 1.75, M_PI);
	w = world_of(f, NULL);
	osi_add_vehicle(f, 99, HL_OSI_VEHICLE_MEDIUM_CAR, 50, 1.75, M_PI);
	/* live: not cast, left out, counted in every message it is in */
	map_ok(w, f, 0.1, &st, counts);
	map_ok(w, f, 0.2, &st, counts);
	assert_int_equal(counts[HL_OSI_NEW_OBJECT], 2);
	assert_int_equal(st.n_actors, 1);
	assert_int_equal(st.present, 0x1);
	/* a trace casts it */
	hl_osi_world_cast(w, f, counts);
	assert_int_equal(counts[HL_OSI_NEW_OBJECT], 2);
	assert_int_equal(hl_osi_world_scenario(w)->n_actors, 2);
	assert_string_equal(hl_osi_world_scenario(w)->actor[1].id, "osi-99");
	map_ok(w, f, 0.3, &st, counts);
	assert_int_equal(counts[HL_OSI_NEW_OBJECT], 2);
	assert_int_equal(st.n_actors, 2);
	assert_int_equal(st.present, 0x3);
	assert_float_equal(st.actor[1].pos_m[0], 50.0 - 2.25, 1e-12);
	/* a message of another host casts nothing */
	osi_add_vehicle(f, 98, HL_OSI_VEHICLE_MEDIUM_CAR, 70, 1.75, M_PI);
	f->host_id = 2;
	hl_osi_world_cast(w, f, counts);
	assert_int_equal(hl_osi_world_scenario(w)->n_actors, 2);
	hl_osi_world_free(w);
	hl_osi_frame_free(f);
}

/* The host's field set bad: world_new refuses, map refuses and leaves the state as it was. */
static void expect_bad_host(struct hl_osi_world *w, struct hl_osi_frame *f, const char *part)
{
	struct hl_world_state st = { .t_s = -7.0, .n_actors = 3 };
	struct hl_osi_world *w2 = NULL;
	char why[256] = "";

	assert_int_equal(hl_osi_world_new(f, NULL, &w2, why, sizeof(why)), -EINVAL);
	assert_null(w2);
	expect_why(why, part);
	why[0] = '\0';
	assert_int_equal(hl_osi_world_map(w, f, 1.0, &st, NULL, why, sizeof(why)),
			 HL_OSI_BAD_VALUE);
	expect_why(why, part);
	assert_float_equal(st.t_s, -7.0, 0.0);
	assert_int_equal(st.n_actors, 3);
}

static void osi_world_bad_host_names_the_field(void **state)
{
	(void)state;
	struct hl_osi_frame *f = osi_message(0);
	struct hl_osi_object *h = &f->object[0];
	const struct hl_osi_object good = *h;
	struct hl_osi_world *w = world_of(f, NULL);

	h->pos_m[0] = NAN;
	expect_bad_host(w, f, "object 1: base.position.x nan");
	*h = good;
	h->pos_m[1] = -2e5;
	expect_bad_host(w, f, "object 1: base.position.y -200000");
	*h = good;
	h->pos_m[2] = INFINITY;
	expect_bad_host(w, f, "base.position.z inf");
	*h = good;
	h->dim_m[0] = 0.0;
	expect_bad_host(w, f, "object 1: base.dimension.length 0: expected 0 < length <= 100 m");
	*h = good;
	h->dim_m[1] = 101.0;
	expect_bad_host(w, f, "base.dimension.width 101");
	*h = good;
	h->dim_m[2] = NAN;
	expect_bad_host(w, f, "base.dimension.height nan");
	*h = good;
	h->rpy_rad[2] = NAN;
	expect_bad_host(w, f, "object 1: base.orientation.yaw nan");
	/* the limits themselves are sane */
	*h = good;
	h->pos_m[0] = -1e5 + 10.0;
	h->dim_m[0] = 100.0;
	{
		struct hl_world_state st;

		map_ok(w, f, 0.0, &st, NULL);
		assert_float_equal(st.ego.pos_m[0], -1e5 + 60.0, 1e-9);
	}
	hl_osi_world_free(w);
	hl_osi_frame_free(f);
}

static void expect_no_host(struct hl_osi_world *w, struct hl_osi_frame *f, const char *part)
{
	struct hl_world_state st = { .t_s = -7.0 };
	struct hl_osi_world *w2 = NULL;
	char why[256] = "";

	assert_int_equal(hl_osi_world_new(f, NULL, &w2, why, sizeof(why)), -EINVAL);
	assert_null(w2);
	expect_why(why, part);
	why[0] = '\0';
	assert_int_equal(hl_osi_world_map(w, f, 1.0, &st, NULL, why, sizeof(why)), HL_OSI_NO_HOST);
	expect_why(why, part);
	assert_float_equal(st.t_s, -7.0, 0.0);
}

static void osi_world_no_host(void **state)
{
	(void)state;
	struct hl_osi_frame *f = osi_message(0);
	struct hl_osi_world *w;
	struct hl_world_state st = { .t_s = -7.0 };
	char why[256] = "";

	osi_add_vehicle(f, 2, HL_OSI_VEHICLE_MEDIUM_CAR, 30, 1.75, M_PI);
	w = world_of(f, NULL);
	f->has_host = false;
	expect_no_host(w, f, "no host_vehicle_id");
	f->has_host = true;
	f->host_id = 42;
	expect_no_host(w, f, "host_vehicle_id 42 is none of the 2 moving objects");
	/* the host's id without has_id is no host either */
	f->host_id = OSI_HOST;
	f->object[0].has_id = false;
	expect_no_host(w, f, "host_vehicle_id 1 is none of the 2 moving objects");
	f->object[0].has_id = true;
	/* another host than the world's ego: map refuses it */
	f->host_id = 2;
	assert_int_equal(hl_osi_world_map(w, f, 1.0, &st, NULL, why, sizeof(why)), HL_OSI_NO_HOST);
	expect_why(why, "host_vehicle_id 2: the source's ego is 1");
	assert_float_equal(st.t_s, -7.0, 0.0);
	hl_osi_world_free(w);
	hl_osi_frame_free(f);
}

static void osi_world_bad_object_left_out_and_counted(void **state)
{
	(void)state;
	struct hl_osi_frame *f = osi_message(0);
	uint64_t counts[HL_OSI_REASONS] = { 0 };
	struct hl_world_state st;
	struct hl_osi_world *w;

	osi_add_vehicle(f, 2, HL_OSI_VEHICLE_MEDIUM_CAR, 30, 1.75, M_PI);
	osi_add_vehicle(f, 3, HL_OSI_VEHICLE_MEDIUM_CAR, NAN, 1.75, M_PI);
	osi_add_vehicle(f, 4, HL_OSI_VEHICLE_MEDIUM_CAR, 50, 1.75, M_PI)->dim_m[0] = 200.0;
	osi_add_vehicle(f, 5, HL_OSI_VEHICLE_MEDIUM_CAR, 60, 1.75, NAN);
	osi_add_vehicle(f, 6, HL_OSI_VEHICLE_MEDIUM_CAR, 70, 1.75, M_PI)->has_id = false;
	w = world_of(f, NULL);
	assert_int_equal(hl_osi_world_scenario(w)->n_actors, 1);
	map_ok(w, f, 0.0, &st, counts);
	assert_int_equal(counts[HL_OSI_OBJECT_BAD_VALUE], 3);
	assert_int_equal(counts[HL_OSI_UNKNOWN_TYPE], 1); /* no id: nothing to cast it by */
	assert_int_equal(counts[HL_OSI_NEW_OBJECT], 0);
	assert_int_equal(st.present, 0x1);
	/* the cast road user gone bad: absent in that message, counted */
	f->object[1].pos_m[1] = NAN;
	map_ok(w, f, 0.1, &st, counts);
	assert_int_equal(counts[HL_OSI_OBJECT_BAD_VALUE], 7);
	assert_int_equal(st.present, 0x0);
	assert_false(hl_world_present(&st, 0));
	hl_osi_world_free(w);
	hl_osi_frame_free(f);
}

static void osi_world_more_objects_than_slots(void **state)
{
	(void)state;
	struct hl_osi_frame *f = osi_message(0);
	uint64_t counts[HL_OSI_REASONS] = { 0 };
	const int extra = 4;
	struct hl_world_state st;
	struct hl_osi_world *w;

	for (int i = 0; i < HL_SCN_MAX_ACTORS + extra; i++)
		osi_add_vehicle(f, 10 + (uint64_t)i, HL_OSI_VEHICLE_MEDIUM_CAR, 10.0 * i, 1.75,
				M_PI);
	w = world_of(f, NULL);
	assert_int_equal(hl_osi_world_scenario(w)->n_actors, HL_SCN_MAX_ACTORS);
	assert_string_equal(hl_osi_world_scenario(w)->actor[HL_SCN_MAX_ACTORS - 1].id, "osi-25");
	/* the extra: counted by a later cast (a trace's) and in every message (live) */
	hl_osi_world_cast(w, f, counts);
	assert_int_equal(counts[HL_OSI_NEW_OBJECT], extra);
	map_ok(w, f, 0.0, &st, counts);
	assert_int_equal(counts[HL_OSI_NEW_OBJECT], 2 * extra);
	assert_int_equal(st.n_actors, HL_SCN_MAX_ACTORS);
	assert_int_equal(st.present, (1u << HL_SCN_MAX_ACTORS) - 1u);
	hl_osi_world_free(w);
	hl_osi_frame_free(f);
}

static void osi_world_road_from_lane_boundaries(void **state)
{
	(void)state;
	struct hl_osi_frame *f = osi_message(0);
	struct hl_osi_world *w = world_of(f, NULL);
	const struct hl_scenario *sc = hl_osi_world_scenario(w);
	struct hl_scenario *dflt = NULL;
	struct hl_world_state st;
	double s, d;

	assert_int_equal(sc->road.lanes, 2);
	assert_float_equal(sc->road.lane_width_m, 3.5, 1e-12);
	assert_int_equal(sc->road.edge, HL_MARK_SOLID);
	assert_int_equal(sc->road.separator, HL_MARK_DASHED);
	assert_float_equal(sc->road.length_m, 250.0, 1e-9);
	assert_string_equal(sc->title, "ASAM OSI");
	assert_float_equal(sc->duration_s, 3600.0, 0.0);
	assert_null(sc->track);
	map_ok(w, f, 0.0, &st, NULL);
	hl_road_project(&sc->road, st.ego.pos_m[0], st.ego.pos_m[1], &s, &d);
	assert_float_equal(s, 50.0, 1e-9);
	assert_float_equal(d, -1.75, 1e-9);
	/* without a base: a scenario file's defaults for the ego's lamps and camera */
	assert_int_equal(hl_scenario_parse("{\"version\": 1, \"title\": \"x\", \"duration_s\": 1,"
					   " \"road\": {\"segments\": [{\"kind\": \"straight\","
					   " \"length_m\": 100}]}}",
					   "dflt", &dflt, NULL),
			 0);
	assert_memory_equal(sc->ego.lamp, dflt->ego.lamp, sizeof(dflt->ego.lamp));
	assert_memory_equal(&sc->ego.camera, &dflt->ego.camera, sizeof(dflt->ego.camera));
	hl_scenario_free(dflt);
	hl_osi_world_free(w);
	hl_osi_frame_free(f);
}

static void osi_world_road_refused(void **state)
{
	(void)state;
	struct hl_osi_frame *f = osi_message(0);
	struct hl_osi_world *w = NULL;
	char why[256] = "";

	/* no lane boundaries and no base */
	f->n_boundaries = 0;
	f->n_points = 0;
	assert_int_equal(hl_osi_world_new(f, NULL, &w, why, sizeof(why)), -ENOENT);
	assert_null(w);
	expect_why(why, "no lane boundaries in the first message and no scenario for the road");
	/* boundaries that make no road: one only */
	osi_add_boundary(f, 101, HL_OSI_BOUNDARY_SOLID_LINE, -3.5);
	assert_int_equal(hl_osi_world_new(f, NULL, &w, why, sizeof(why)), -EBADMSG);
	assert_null(w);
	expect_why(why, "expected");
	/* a boundary point NaN: refused, naming the boundary */
	osi_add_boundary(f, 102, HL_OSI_BOUNDARY_SOLID_LINE, 3.5);
	f->point[27][0] = NAN;
	assert_int_equal(hl_osi_world_new(f, NULL, &w, why, sizeof(why)), -EBADMSG);
	expect_why(why, "lane boundary 102");
	assert_null(w);
	hl_osi_frame_free(f);
}

static void osi_world_base_scenario(void **state)
{
	(void)state;
	struct hl_scenario *base = shipped("preceding-car.json");
	struct hl_osi_frame *f = osi_message(0);
	struct hl_osi_world *w;
	struct hl_scenario *sc;

	assert_true(base->n_actors > 0);
	/* the lamps and camera made different from a file's defaults */
	base->ego.lamp[0].pitch_deg = -1.25;
	base->ego.camera.fov_y_deg = 33.0;
	osi_add_vehicle(f, 2, HL_OSI_VEHICLE_MEDIUM_CAR, 30, 1.75, M_PI);
	/* without lane boundaries: base's road, lamps and camera; OSI's cast */
	f->n_boundaries = 0;
	f->n_points = 0;
	w = world_of(f, base);
	sc = hl_osi_world_take_scenario(w);
	hl_osi_world_free(w);
	assert_memory_equal(&sc->road, &base->road, sizeof(base->road));
	assert_memory_equal(sc->ego.lamp, base->ego.lamp, sizeof(base->ego.lamp));
	assert_memory_equal(&sc->ego.camera, &base->ego.camera, sizeof(base->ego.camera));
	assert_int_equal(sc->n_actors, 1);
	assert_string_equal(sc->actor[0].id, "osi-2");
	assert_string_equal(sc->title, "ASAM OSI");
	assert_null(sc->track);
	hl_scenario_free(sc);
	/* with lane boundaries: theirs is the road, base's the lamps and camera */
	osi_add_boundary(f, 101, HL_OSI_BOUNDARY_SOLID_LINE, -3.5);
	osi_add_boundary(f, 102, HL_OSI_BOUNDARY_SOLID_LINE, 0.0);
	osi_add_boundary(f, 103, HL_OSI_BOUNDARY_SOLID_LINE, 3.5);
	osi_add_boundary(f, 104, HL_OSI_BOUNDARY_SOLID_LINE, 7.0);
	w = world_of(f, base);
	sc = hl_osi_world_take_scenario(w);
	hl_osi_world_free(w);
	assert_int_equal(sc->road.lanes, 3);
	assert_float_equal(sc->road.lane_width_m, 3.5, 1e-12);
	assert_int_equal(sc->road.separator, HL_MARK_SOLID);
	assert_memory_equal(sc->ego.lamp, base->ego.lamp, sizeof(base->ego.lamp));
	assert_memory_equal(&sc->ego.camera, &base->ego.camera, sizeof(base->ego.camera));
	hl_scenario_free(sc);
	hl_osi_frame_free(f);
	hl_scenario_free(base);
}

static void osi_world_reason_names(void **state)
{
	(void)state;
	static const char *const expected[HL_OSI_REASONS] = {
		"ok",		"malformed", "too_many",     "no_host",		 "bad_value",
		"no_timestamp", "no_road",   "past",	     "time_jump",	 "truncated",
		"bad_framing",	"too_large", "unknown_type", "object_bad_value", "new_object",
	};

	for (int r = 0; r < HL_OSI_REASONS; r++) {
		const char *name = hl_osi_reason_name((enum hl_osi_reason)r);

		assert_non_null(name);
		assert_string_equal(name, expected[r]);
		for (int q = 0; q < r; q++)
			assert_string_not_equal(name, hl_osi_reason_name((enum hl_osi_reason)q));
	}
	assert_string_equal(hl_osi_reason_name(HL_OSI_REASONS), "?");
	assert_string_equal(hl_osi_reason_name((enum hl_osi_reason) - 1), "?");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(osi_world_kind_table),
		cmocka_unit_test(osi_world_pose_below_front_face),
		cmocka_unit_test(osi_world_roles_from_relative_heading),
		cmocka_unit_test(osi_world_lamps_lit_unless_head_light_off),
		cmocka_unit_test(osi_world_road_user_leaves_and_comes_back),
		cmocka_unit_test(osi_world_new_object_counted_and_cast),
		cmocka_unit_test(osi_world_bad_host_names_the_field),
		cmocka_unit_test(osi_world_no_host),
		cmocka_unit_test(osi_world_bad_object_left_out_and_counted),
		cmocka_unit_test(osi_world_more_objects_than_slots),
		cmocka_unit_test(osi_world_road_from_lane_boundaries),
		cmocka_unit_test(osi_world_road_refused),
		cmocka_unit_test(osi_world_base_scenario),
		cmocka_unit_test(osi_world_reason_names),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
