/* SPDX-License-Identifier: MIT */
/*
 * verdict/photometer.c against hand-computed geometry: two lamps of a uniform 10,000 cd
 * distribution (a bilinear grid reproduces it exactly), a photometer placed on a road user's
 * body (its pose's heading turns the point and the normal), E = sum I cos(theta) / r^2 with
 * theta between the light's direction and the plane's normal, computed in the test from the
 * coordinates; light from behind the plane counts 0; the range is horizontal from the lamps'
 * midpoint.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include "verdict/photometer.h"

#define I_CD 10000.0f

static const struct hl_lid_grid grid = { .width = 3,
					 .height = 3,
					 .angles = HL_ANGLES_A,
					 .h_first_deg = -90.0f,
					 .h_last_deg = 90.0f,
					 .v_first_deg = -90.0f,
					 .v_last_deg = 90.0f };
static const float uniform[9] = { I_CD, I_CD, I_CD, I_CD, I_CD, I_CD, I_CD, I_CD, I_CD };

static void lamps_at(struct hl_lamp_pose lamps[2])
{
	for (int l = 0; l < 2; l++) {
		lamps[l].pos_m[0] = 0.0;
		lamps[l].pos_m[1] = l ? -0.7 : 0.7;
		lamps[l].pos_m[2] = 0.65;
		lamps[l].yaw_deg = 0.0;
		lamps[l].pitch_deg = -0.573;
	}
}

/* The test's own sum: I (n . (lamp - p)) / r^3 per lamp, 0 from behind. */
static double expected(const struct hl_lamp_pose lamps[2], const double p[3], const double n[3])
{
	double e = 0.0;

	for (int l = 0; l < 2; l++) {
		const double dx = lamps[l].pos_m[0] - p[0], dy = lamps[l].pos_m[1] - p[1],
			     dz = lamps[l].pos_m[2] - p[2];
		const double r = sqrt(dx * dx + dy * dy + dz * dz);
		const double c = (n[0] * dx + n[1] * dy + n[2] * dz) / r;

		if (c > 0.0)
			e += I_CD * c / (r * r);
	}
	return e;
}

static void photometer_cos_theta_by_hand(void **state)
{
	(void)state;
	struct hl_lamp_pose lamps[2];
	const struct hl_lid_grid *grids[2] = { &grid, &grid };
	const float *dense[2] = { uniform, uniform };
	/* an oncoming car 30 m ahead in the next lane, facing the lamps (heading pi) */
	const struct hl_body_pose car = { .pos_m = { 30.0, 3.5, 0.0 }, .heading_rad = M_PI };
	const double pos[3] = { -1.8, 0.37, 1.1 }, fwd[3] = { 1.0, 0.0, 0.0 };
	struct hl_photometer_reading rd;
	double p[3], n[3], e;

	lamps_at(lamps);
	hl_photometer_place(&car, pos, fwd, p, n);
	/* body (-1.8, 0.37) turned by pi: world (30 + 1.8, 3.5 - 0.37); the normal (-1, 0) */
	assert_true(fabs(p[0] - 31.8) < 1e-12 && fabs(p[1] - 3.13) < 1e-12 && p[2] == 1.1);
	assert_true(fabs(n[0] + 1.0) < 1e-12 && fabs(n[1]) < 1e-12 && n[2] == 0.0);
	e = hl_photometer_read(lamps, grids, dense, p, n, &rd);
	assert_true(fabs(e - expected(lamps, p, n)) < 1e-12 * e);
	assert_true(e == rd.illuminance_lx);
	/* the left lamp: d = (31.8, 2.43, 0.45), cos = 31.8 / |d| */
	{
		const double r = sqrt(31.8 * 31.8 + 2.43 * 2.43 + 0.45 * 0.45);

		assert_true(fabs(rd.r_m[0] - r) < 1e-12);
		assert_true(fabs(rd.cos_theta[0] - 31.8 / r) < 1e-12);
		assert_true(fabs(rd.intensity_cd[0] - I_CD) < 1e-3);
	}
	/* the range: horizontal from the midpoint (0, 0) */
	assert_true(fabs(rd.range_m - hypot(31.8, 3.13)) < 1e-12);
	/* about 19.6 lx (10,000 cd at ~32 m, twice, nearly head on) */
	assert_true(e > 19.0 && e < 20.0);
}

static void photometer_tilted_plane(void **state)
{
	(void)state;
	struct hl_lamp_pose lamps[2];
	const struct hl_lid_grid *grids[2] = { &grid, &grid };
	const float *dense[2] = { uniform, uniform };
	/* a plane at 60 degrees: normal (-cos 60, sin 60, 0) */
	const double p[3] = { 20.0, 0.0, 0.65 }, n[3] = { -0.5, sqrt(3.0) / 2.0, 0.0 };
	struct hl_photometer_reading rd;
	double e;

	lamps_at(lamps);
	e = hl_photometer_read(lamps, grids, dense, p, n, &rd);

	assert_true(fabs(e - expected(lamps, p, n)) < 1e-12 * e);
	/* the left lamp at (0, 0.7, 0.65): d = (20, -0.7, 0) / r, cos = (10 + 0.7 * 0.866) / r */
	{
		const double r = hypot(20.0, 0.7);

		assert_true(fabs(rd.cos_theta[0] - (10.0 + 0.7 * sqrt(3.0) / 2.0) / r) < 1e-12);
		assert_true(fabs(rd.cos_theta[1] - (10.0 - 0.7 * sqrt(3.0) / 2.0) / r) < 1e-12);
	}
}

static void photometer_light_from_behind_counts_zero(void **state)
{
	(void)state;
	struct hl_lamp_pose lamps[2];
	const struct hl_lid_grid *grids[2] = { &grid, &grid };
	const float *dense[2] = { uniform, uniform };
	/* a preceding car's rear photometer turned the wrong way (facing forward, away) */
	const double p[3] = { 50.0, 0.0, 1.0 }, away[3] = { 1.0, 0.0, 0.0 };
	struct hl_photometer_reading rd;

	lamps_at(lamps);
	assert_true(hl_photometer_read(lamps, grids, dense, p, away, &rd) == 0.0);
	assert_true(rd.cos_theta[0] == 0.0 && rd.cos_theta[1] == 0.0);
	assert_true(rd.intensity_cd[0] > 0.0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(photometer_cos_theta_by_hand),
		cmocka_unit_test(photometer_tilted_plane),
		cmocka_unit_test(photometer_light_from_behind_counts_zero),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
