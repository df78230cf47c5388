/* SPDX-License-Identifier: MIT */
/*
 * The ground of a moving scene, a run of pixels at a time: a camera looking straight down so
 * that pixel col meets the ground at a known lateral offset, on the default two-lane road
 * (3.5 m lanes, 0.15 m edge lines one width inside the edges, a 0.12 m dashed centre line 3 m
 * on, 6 m off): each surface and albedo where it must be, uniform runs inside one surface and
 * split runs across a bound, equal pixel for pixel to one-pixel runs; the end of the ground at
 * 40 m; rays that miss the ground and a camera below it; the pose moving the road under it.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "render/scene_layout.h"
#include "render/world_ground.h"

static struct hl_scenario *sc;

static int setup(void **state)
{
	struct hl_json_error err;

	(void)state;
	return hl_scenario_parse("{\"version\": 1, \"duration_s\": 1, \"road\": {\"segments\": "
				 "[{\"kind\": \"straight\", \"length_m\": 400}]}}",
				 "ground.json", &sc, &err);
}

static int teardown(void **state)
{
	(void)state;
	hl_scenario_free(sc);
	return 0;
}

static const struct hl_ground_pose identity = { 0.0, 0.0, 1.0, 0.0 };

/*
 * 1 m above the ground looking straight down: d = (sy, -sx, -1), so pixel col meets the
 * ground at x = sy, y = -(col + 0.5 - half_w) tx (left of the road's centre line is +y).
 */
static struct hl_ground_view down(double half_w, double tx)
{
	return (struct hl_ground_view){ .o = { 0, 0, 1 },
					.f = { 0, 0, -1 },
					.r = { 0, -1, 0 },
					.u = { 1, 0, 0 },
					.half_w = half_w,
					.tx = tx };
}

/* Pixel c of a run of n starting at col0 (its lateral offset y, at x = sy). */
static void one(const struct hl_ground *g, const struct hl_ground_view *v, double sy, int col,
		enum hl_surface *id, double *albedo, bool *hit)
{
	struct hl_ground_run r;
	int hint = -1;

	hl_ground_run(g, v, &identity, sy, col, 1, &hint, &r);
	*hit = hl_ground_hit(g, &r, 0, id, albedo);
}

static void expect_at(const struct hl_ground *g, double x, double y, bool hit, enum hl_surface id,
		      double albedo)
{
	/* pixel 0 with half_w 0: sx = 0.5 tx, so tx = -2 y puts it at y */
	const struct hl_ground_view v = down(0.0, -2.0 * y);
	enum hl_surface got = HL_SURF_NONE;
	double a = -1.0;
	bool h;

	one(g, &v, x, 0, &got, &a, &h);
	if (h != hit || (hit && (got != id || a != albedo)))
		fail_msg("(%g, %g): hit %d id %d albedo %g, expected %d %d %g", x, y, h, got, a,
			 hit, id, albedo);
}

static void ground_cross_section_of_the_default_road(void **state)
{
	struct hl_ground g;
	(void)state;

	assert_int_equal(hl_ground_init(&sc->road, &g), 0);
	/* s = 1 m: on a dash of the centre line */
	expect_at(&g, 1.0, 0.0, true, HL_SURF_MARKING, HL_ALBEDO_MARKING);
	expect_at(&g, 1.0, 0.05, true, HL_SURF_MARKING, HL_ALBEDO_MARKING);
	expect_at(&g, 1.0, -0.07, true, HL_SURF_ROAD, HL_ALBEDO_ROAD);
	expect_at(&g, 1.0, 1.75, true, HL_SURF_ROAD, HL_ALBEDO_ROAD);
	/* edge lines: centre 3.35 m, 0.15 m wide, both sides */
	expect_at(&g, 1.0, 3.35, true, HL_SURF_MARKING, HL_ALBEDO_MARKING);
	expect_at(&g, 1.0, -3.3, true, HL_SURF_MARKING, HL_ALBEDO_MARKING);
	expect_at(&g, 1.0, 3.26, true, HL_SURF_ROAD, HL_ALBEDO_ROAD);
	expect_at(&g, 1.0, -3.45, true, HL_SURF_ROAD, HL_ALBEDO_ROAD); /* outside the line */
	expect_at(&g, 1.0, 3.5, true, HL_SURF_ROAD, HL_ALBEDO_ROAD); /* |d| <= W/2 is road */
	expect_at(&g, 1.0, 3.6, true, HL_SURF_SHOULDER, HL_ALBEDO_SHOULDER);
	expect_at(&g, 1.0, -39.9, true, HL_SURF_SHOULDER, HL_ALBEDO_SHOULDER);
	expect_at(&g, 1.0, 40.1, false, HL_SURF_NONE, 0.0); /* the ground has ended */
	/* s = 4 m and 13 m: the gap after the dash, and the next period's gap */
	expect_at(&g, 4.0, 0.0, true, HL_SURF_ROAD, HL_ALBEDO_ROAD);
	expect_at(&g, 13.0, 0.0, true, HL_SURF_ROAD, HL_ALBEDO_ROAD);
	expect_at(&g, 10.0, 0.0, true, HL_SURF_MARKING, HL_ALBEDO_MARKING);
	hl_ground_free(&g);
	assert_null(g.bounds);
	assert_null(g.dashed);
}

/* A whole row of 32 pixels equals its pixels one by one; uniform exactly when one surface. */
static void ground_runs_equal_their_pixels_and_uniform_only_within_a_surface(void **state)
{
	struct hl_ground g;
	(void)state;

	assert_int_equal(hl_ground_init(&sc->road, &g), 0);
	/* tx 0.05: 32 pixels span 1.6 m; start the row at lateral offsets across the road */
	for (double y0 = -41.0; y0 <= 41.0; y0 += 0.37) {
		for (int k = 0; k < 3; k++) {
			const double sy = 19.0 + 4.0 * k; /* s mod 9: 1 (dash), 5, 0 (dash) */
			struct hl_ground_view v = down(0.0, 0.05);
			struct hl_ground_run r;
			enum hl_surface first = HL_SURF_NONE;
			bool same = true;
			int hint = -1;

			v.half_w = y0 / 0.05; /* pixel c's centre at y0 - (c + 0.5) 0.05 */
			hl_ground_run(&g, &v, &identity, sy, 0, HL_GROUND_RUN_PX, &hint, &r);
			assert_true(hint >= 0); /* the part the run ended on */
			for (int c = 0; c < HL_GROUND_RUN_PX; c++) {
				enum hl_surface id1 = HL_SURF_NONE, id2 = HL_SURF_NONE;
				double a1 = -1, a2 = -1;
				bool h1 = hl_ground_hit(&g, &r, c, &id1, &a1), h2;

				one(&g, &v, sy, c, &id2, &a2, &h2);
				assert_int_equal(h1, h2);
				if (h1) {
					assert_int_equal(id1, id2);
					assert_true(a1 == a2);
				}
				if (c == 0)
					first = h1 ? id1 : HL_SURF_NONE;
				same = same && (h1 ? id1 : HL_SURF_NONE) == first;
			}
			/* uniform promises one surface; a run it could not prove so is split */
			if (r.uniform)
				assert_true(same);
			/* 1.6 m of road inside a lane, clear of every line: uniform */
			if ((y0 - 1.6 > 0.07 && y0 < 3.27) || (y0 < -0.07 && y0 - 1.6 > -3.27))
				if (!r.uniform)
					fail_msg("y0 %g sy %g: not uniform", y0, sy);
		}
	}
	/* the run 0.5 .. 2.1 m left of the centre line is road, one surface */
	{
		struct hl_ground_view v = down(2.1 / 0.05, 0.05);
		struct hl_ground_run r;
		int hint = -1;

		hl_ground_run(&g, &v, &identity, 19.0, 0, HL_GROUND_RUN_PX, &hint, &r);
		assert_true(r.uniform);
		assert_int_equal(r.id, HL_SURF_ROAD);
		assert_true(r.albedo == HL_ALBEDO_ROAD);
	}
	/* across the centre line: not uniform */
	{
		struct hl_ground_view v = down(16.0, 0.05);
		struct hl_ground_run r;
		int hint = -1;

		hl_ground_run(&g, &v, &identity, 19.0, 0, HL_GROUND_RUN_PX, &hint, &r);
		assert_false(r.uniform);
	}
	hl_ground_free(&g);
}

static void ground_misses_rays_up_and_a_camera_below(void **state)
{
	struct hl_ground g;
	struct hl_ground_view v = down(16.0, 0.05);
	struct hl_ground_run r;
	enum hl_surface id = HL_SURF_ROAD;
	double a = 7.0;
	int hint = -1;
	(void)state;

	assert_int_equal(hl_ground_init(&sc->road, &g), 0);
	/* looking up */
	v.f[2] = 1.0;
	hl_ground_run(&g, &v, &identity, 0.2, 0, HL_GROUND_RUN_PX, &hint, &r);
	assert_true(hl_ground_run_sky(&v, &r, HL_GROUND_RUN_PX));
	for (int c = 0; c < HL_GROUND_RUN_PX; c++) {
		assert_false(hl_ground_hit(&g, &r, c, &id, &a));
		assert_int_equal(r.part[c], -1);
	}
	assert_int_equal(id, HL_SURF_ROAD); /* untouched */
	assert_true(a == 7.0);
	/* looking down from below the ground */
	v = down(16.0, 0.05);
	v.o[2] = -0.5;
	hl_ground_run(&g, &v, &identity, 0.2, 0, HL_GROUND_RUN_PX, &hint, &r);
	assert_true(hl_ground_run_sky(&v, &r, HL_GROUND_RUN_PX));
	assert_false(hl_ground_hit(&g, &r, 5, &id, &a));
	/* the horizon within a run: the first rays look down, the others up */
	v = (struct hl_ground_view){ .o = { 0, 0, 1 },
				     .f = { 1, 0, 0 },
				     .r = { 0, 0, 1 },
				     .u = { 0, 1, 0 },
				     .half_w = 8.0,
				     .tx = 0.01 };
	hl_ground_run(&g, &v, &identity, 0.0, 0, 16, &hint, &r);
	assert_false(hl_ground_run_sky(&v, &r, 16));
	assert_true(hl_ground_run_sky(&v, &r, 0)); /* no rays: sky */
	for (int c = 0; c < 16; c++) {
		const bool hit = hl_ground_hit(&g, &r, c, &id, &a);

		assert_int_equal(hit, c < 8);
	}
	hl_ground_free(&g);
}

/* The ego 200 m along the road turned by 90 degrees: its own frame's -y is the road's +x. */
static void ground_pose_moves_the_road_under_the_camera(void **state)
{
	struct hl_ground g;
	const struct hl_ground_pose pose = { 200.0, 3.35, 0.0, 1.0 }; /* heading +90 degrees */
	struct hl_ground_view v = down(0.5, 1e-9);
	struct hl_ground_run r;
	enum hl_surface id;
	double a;
	int hint = -1;
	(void)state;

	assert_int_equal(hl_ground_init(&sc->road, &g), 0);
	/* straight below the ego: world (200, 3.35), on the left edge line */
	hl_ground_run(&g, &v, &pose, 0.0, 0, 1, &hint, &r);
	assert_true(hl_ground_hit(&g, &r, 0, &id, &a));
	assert_int_equal(id, HL_SURF_MARKING);
	assert_true(fabs(r.wx[0] - 200.0) < 1e-9);
	assert_true(fabs(r.wy[0] - 3.35) < 1e-9);
	/* 0.5 m ahead of the ego (its x): world y 3.85, the shoulder */
	hl_ground_run(&g, &v, &pose, 0.5, 0, 1, &hint, &r);
	assert_true(hl_ground_hit(&g, &r, 0, &id, &a));
	assert_int_equal(id, HL_SURF_SHOULDER);
	assert_true(a == HL_ALBEDO_SHOULDER);
	hl_ground_free(&g);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(ground_cross_section_of_the_default_road),
		cmocka_unit_test(ground_runs_equal_their_pixels_and_uniform_only_within_a_surface),
		cmocka_unit_test(ground_misses_rays_up_and_a_camera_below),
		cmocka_unit_test(ground_pose_moves_the_road_under_the_camera),
	};

	return cmocka_run_group_tests(tests, setup, teardown);
}
