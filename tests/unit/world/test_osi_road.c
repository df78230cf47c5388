/* SPDX-License-Identifier: MIT */
/*
 * world/osi_road.c: OSI lane boundaries (frames filled by hand) made into a road: a straight
 * two-lane road, a 50 m left curve against the true centre, the same road from boundaries
 * listed in another order or direction, and bad inputs refused with a reason.
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

#include "world/osi_msg.h"
#include "world/osi_road.h"
#include "world/road.h"

#define DEG (M_PI / 180.0)

/* Appends a boundary of n points p(i) (reversed: listed from the last). */
static void add(struct hl_osi_frame *f, uint64_t id, int type, int n, bool reversed,
		void (*p)(int i, double lat, double ret[3]), double lat)
{
	struct hl_osi_boundary *b = &f->boundary[f->n_boundaries++];

	b->id = id;
	b->type = type;
	b->first = f->n_points;
	b->n = n;
	for (int i = 0; i < n; i++)
		p(reversed ? n - 1 - i : i, lat, f->point[f->n_points++]);
}

/* Along +x from x = -50 every 10 m, y = lat. */
static void straight(int i, double lat, double ret[3])
{
	ret[0] = -50.0 + 10.0 * i;
	ret[1] = lat;
	ret[2] = 0.3; /* ignored */
}

/* A left curve about (0, 50) every degree from -20° to 110°, lat left of the 50 m centre. */
static void curve(int i, double lat, double ret[3])
{
	const double phi = (-20.0 + i) * DEG, r = 50.0 - lat;

	ret[0] = r * sin(phi);
	ret[1] = 50.0 - r * cos(phi);
	ret[2] = 0.0;
}

static struct hl_osi_frame *frame(void)
{
	struct hl_osi_frame *f = calloc(1, sizeof(*f));

	assert_non_null(f);
	return f;
}

static void osi_road_straight_two_lanes(void **state)
{
	(void)state;
	struct hl_osi_frame *f = frame();
	struct hl_road *road = calloc(1, sizeof(*road));
	struct hl_pose2 c;
	char why[256] = "";
	double s, d;

	add(f, 11, HL_OSI_BOUNDARY_SOLID_LINE, 26, false, straight, -3.5);
	add(f, 12, HL_OSI_BOUNDARY_DASHED_LINE, 26, false, straight, 0.0);
	add(f, 13, HL_OSI_BOUNDARY_SOLID_LINE, 26, false, straight, 3.5);
	add(f, 14, HL_OSI_BOUNDARY_ROAD_EDGE, 26, false, straight, 40.0); /* another road */
	assert_int_equal(hl_osi_road(f, 10.0, -1.75, 0.0, road, why, sizeof(why)), 0);
	assert_int_equal(road->lanes, 2);
	assert_float_equal(road->lane_width_m, 3.5, 1e-12);
	assert_int_equal(road->edge, HL_MARK_SOLID);
	assert_int_equal(road->separator, HL_MARK_DASHED);
	assert_int_equal(road->post_spacing_m, 0);
	assert_int_equal(road->n_segments, 1);
	assert_float_equal(road->length_m, 250.0, 1e-9);
	hl_road_centre(road, 60.0, &c);
	assert_float_equal(c.x_m, 10.0, 1e-9);
	assert_float_equal(c.y_m, 0.0, 1e-9);
	assert_float_equal(c.heading_rad, 0.0, 1e-12);
	hl_road_project(road, 10.0, -1.75, &s, &d);
	assert_float_equal(s, 60.0, 1e-9);
	assert_float_equal(d, -1.75, 1e-9);
	/* driving the other way (the left lane, heading -x): s runs along -x */
	assert_int_equal(hl_osi_road(f, 10.0, 1.75, M_PI, road, why, sizeof(why)), 0);
	hl_road_centre(road, 60.0, &c);
	assert_float_equal(c.x_m, 140.0, 1e-9);
	assert_float_equal(cos(c.heading_rad), -1.0, 1e-12);
	hl_road_project(road, 10.0, 1.75, &s, &d);
	assert_float_equal(d, -1.75, 1e-9);
	/* edges without paint */
	f->boundary[0].type = HL_OSI_BOUNDARY_CURB;
	f->boundary[2].type = HL_OSI_BOUNDARY_NO_LINE;
	f->boundary[1].type = HL_OSI_BOUNDARY_SOLID_LINE;
	assert_int_equal(hl_osi_road(f, 10.0, -1.75, 0.0, road, why, sizeof(why)), 0);
	assert_int_equal(road->edge, HL_MARK_NONE);
	assert_int_equal(road->separator, HL_MARK_SOLID);
	free(road);
	free(f);
}

/* The road from a curve's boundaries (as given, or reversed, or listed the other way). */
static void curve_road(bool reversed, bool backwards, struct hl_road *road)
{
	struct hl_osi_frame *f = frame();
	static const double lat[3] = { -3.5, 0.0, 3.5 };
	static const int type[3] = { HL_OSI_BOUNDARY_SOLID_LINE, HL_OSI_BOUNDARY_DASHED_LINE,
				     HL_OSI_BOUNDARY_SOLID_LINE };
	const double phi = 10.0 * DEG, r = 51.75; /* the ego in lane 1 at 10° */
	char why[256] = "";

	for (int k = 0; k < 3; k++) {
		const int j = backwards ? 2 - k : k;

		add(f, 20 + (uint64_t)j, type[j], 131, reversed != (j == 1), curve, lat[j]);
	}
	if (hl_osi_road(f, r * sin(phi), 50.0 - r * cos(phi), phi, road, why, sizeof(why)) < 0)
		fail_msg("%s", why);
	free(f);
}

static void osi_road_50m_left_curve(void **state)
{
	(void)state;
	struct hl_road *road = calloc(4, sizeof(*road));
	double s, d;

	curve_road(false, false, &road[0]);
	curve_road(true, false, &road[1]);
	curve_road(false, true, &road[2]);
	curve_road(true, true, &road[3]);
	assert_int_equal(road[0].lanes, 2);
	assert_float_equal(road[0].lane_width_m, 3.5, 1e-3);
	assert_true(road[0].n_segments > 10);
	/* the ends' feet on the other boundary's 1° chords are off the radius by ~3.5 cm */
	assert_float_equal(road[0].length_m, 130.0 * DEG * 50.0, 0.1);
	for (double t = 0.0; t <= road[0].length_m; t += 0.5) {
		struct hl_pose2 c;

		hl_road_centre(&road[0], t, &c);
		if (!(fabs(hypot(c.x_m, c.y_m - 50.0) - 50.0) <= 0.02))
			fail_msg("s %g: centre (%g, %g) is %g m off the true centre", t, c.x_m,
				 c.y_m, hypot(c.x_m, c.y_m - 50.0) - 50.0);
	}
	/* the ego at 10° in lane 1 */
	hl_road_project(&road[0], 51.75 * sin(10 * DEG), 50.0 - 51.75 * cos(10 * DEG), &s, &d);
	assert_float_equal(s, 30.0 * DEG * 50.0, 0.1);
	assert_float_equal(d, -1.75, 0.02);
	/* the same road however the boundaries are listed */
	for (int k = 1; k < 4; k++) {
		assert_int_equal(road[k].lanes, 2);
		assert_int_equal(road[k].separator, HL_MARK_DASHED);
		assert_float_equal(road[k].length_m, road[0].length_m, 0.02);
		for (double t = 0.0; t <= road[0].length_m; t += 5.0) {
			struct hl_pose2 a, b;

			hl_road_centre(&road[0], t, &a);
			hl_road_centre(&road[k], t, &b);
			assert_float_equal(a.x_m, b.x_m, 0.04);
			assert_float_equal(a.y_m, b.y_m, 0.04);
		}
	}
	free(road);
}

static void expect_refused(const struct hl_osi_frame *f, double x, double y, double h, int rc,
			   const char *reason)
{
	struct hl_road *road = calloc(1, sizeof(*road));
	char why[256] = "";

	road->lanes = 7;
	assert_int_equal(hl_osi_road(f, x, y, h, road, why, sizeof(why)), rc);
	if (!strstr(why, reason))
		fail_msg("why '%s' lacks '%s'", why, reason);
	assert_int_equal(road->lanes, 7); /* untouched */
	free(road);
}

static void osi_road_refuses_bad_input(void **state)
{
	(void)state;
	struct hl_osi_frame *f = frame();

	add(f, 31, HL_OSI_BOUNDARY_SOLID_LINE, 26, false, straight, -3.5);
	add(f, 32, HL_OSI_BOUNDARY_SOLID_LINE, 26, false, straight, 3.5);
	/* a NaN, a coordinate beyond 1e5 m: named by the boundary's id */
	f->point[30][1] = NAN;
	expect_refused(f, 0, 0, 0, -EINVAL, "lane boundary 32: point 4: y = nan");
	f->point[30][1] = 3.5;
	f->point[3][0] = 2e5;
	expect_refused(f, 0, 0, 0, -EINVAL, "lane boundary 31: point 3: x = 200000");
	f->point[3][0] = -20.0;
	/* the ego beside the road, crossing it, beyond its end */
	expect_refused(f, 0, 10, 0, -EINVAL, "expected the ego between two");
	expect_refused(f, 0, 0, M_PI / 2, -EINVAL, "0 lane boundaries run alongside");
	expect_refused(f, 300, 0, 0, -EINVAL, "0 lane boundaries run alongside");
	/* one lane of 10.5 m: the left boundary at 7 m */
	for (int i = 0; i < 26; i++)
		f->point[26 + i][1] = 7.0;
	expect_refused(f, 0, 0, 0, -EINVAL, "1 lanes of 10.5 m: expected 2 to 6 m");
	/* points beyond the frame's */
	f->boundary[1].n = 2000;
	expect_refused(f, 0, 0, 0, -EINVAL, "lane boundary 32: points 26..2025 beyond");
	free(f);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(osi_road_straight_two_lanes),
		cmocka_unit_test(osi_road_50m_left_curve),
		cmocka_unit_test(osi_road_refuses_bad_input),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
