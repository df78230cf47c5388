/* SPDX-License-Identifier: MIT */
/* Camera to lamp angles (ecu/parallax.c) against plain trigonometry (ecu_naive.h). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "ecu/parallax.h"
#include "ecu_naive.h"
#include "testutil.h"

static const struct hl_ecu_mount camera = { .pos_m = { -1.5, 0.0, 1.3 } };
static const struct hl_ecu_mount left_lamp = { .pos_m = { 0.0, 0.7, 0.65 } };
static const struct hl_ecu_mount right_lamp = { .pos_m = { 0.0, -0.7, 0.65 } };

/* A point dead ahead of the camera at 50 m is right of the left lamp and above it. */
static void parallax_point_ahead_by_hand(void **state)
{
	(void)state;
	double p[3], h, v;

	hl_ecu_mount_point(&camera, 0.0, 0.0, 50.0, p);
	assert_float_equal(p[0], 48.5, 1e-12);
	assert_float_equal(p[1], 0.0, 1e-12);
	assert_float_equal(p[2], 1.3, 1e-12);
	hl_ecu_mount_angles(&left_lamp, HL_ANGLES_A, p, &h, &v);
	assert_float_equal(h, atan2(0.7, 48.5) * 180 / M_PI, 1e-12); /* 0.827° right */
	assert_float_equal(v, atan2(0.65, hypot(0.7, 48.5)) * 180 / M_PI, 1e-12);
	hl_ecu_mount_angles(&right_lamp, HL_ANGLES_A, p, &h, &v);
	assert_float_equal(h, -atan2(0.7, 48.5) * 180 / M_PI, 1e-12);
	/* nearer, larger: 4° at 10 m */
	hl_ecu_mount_point(&camera, 0.0, 0.0, 10.0, p);
	hl_ecu_mount_angles(&left_lamp, HL_ANGLES_A, p, &h, &v);
	assert_float_equal(h, atan2(0.7, 8.5) * 180 / M_PI, 1e-12);
}

/* Random points, a pitched camera and a turned and pitched lamp, against the written-out geometry. */
static void parallax_random_points(void **state)
{
	(void)state;
	unsigned long long seed = 0x5eed;

	for (int i = 0; i < 2000; i++) {
		struct hl_ecu_mount cam = camera, lamp = left_lamp;
		double p[3], h, v, wh, wv;
		double hc = -30 + 60 * test_uniform(&seed), vc = -10 + 20 * test_uniform(&seed);
		double r = 5 + 200 * test_uniform(&seed);

		cam.pitch_deg = -3 + 6 * test_uniform(&seed);
		cam.pos_m[1] = -0.5 + test_uniform(&seed);
		lamp.yaw_deg = -10 + 20 * test_uniform(&seed);
		lamp.pitch_deg = -2 + 4 * test_uniform(&seed);
		hl_ecu_mount_point(&cam, hc, vc, r, p);
		hl_ecu_mount_angles(&lamp, HL_ANGLES_A, p, &h, &v);
		naive_parallax_pitched(cam.pos_m, cam.pitch_deg, hc, vc, r, lamp.pos_m,
				       lamp.yaw_deg, lamp.pitch_deg, &wh, &wv);
		assert_float_equal(h, wh, 1e-9);
		assert_float_equal(v, wv, 1e-9);
	}
}

/* Type B differs from A off the axes: V = atan2(y, z), H = atan2(x, hypot(y, z)). */
static void parallax_angle_system_b(void **state)
{
	(void)state;
	const struct hl_ecu_mount lamp = { .pos_m = { 0, 0, 0 } };
	const double p[3] = { 10.0, -3.0, 2.0 }; /* lamp space x 3 (right), y 2, z 10 */
	double h, v;

	hl_ecu_mount_angles(&lamp, HL_ANGLES_B, p, &h, &v);
	assert_float_equal(v, atan2(2.0, 10.0) * 180 / M_PI, 1e-12);
	assert_float_equal(h, atan2(3.0, hypot(2.0, 10.0)) * 180 / M_PI, 1e-12);
	hl_ecu_mount_angles(&lamp, HL_ANGLES_A, p, &h, &v);
	assert_float_equal(h, atan2(3.0, 10.0) * 180 / M_PI, 1e-12);
	assert_float_equal(v, atan2(2.0, hypot(3.0, 10.0)) * 180 / M_PI, 1e-12);
}

/* An oncoming car's box at 40 m: the lamp's box bounds the nine points of the camera's box. */
static void parallax_box_bounds_its_points(void **state)
{
	(void)state;
	const double hl = -4.0, hr = -1.5, vb = -1.8, vt = 0.2, r = 40.0;
	const struct hl_ecu_mount *lamps[2] = { &left_lamp, &right_lamp };

	for (int l = 0; l < 2; l++) {
		struct hl_ecu_box b;
		double h0 = INFINITY, h1 = -INFINITY, v0 = INFINITY, v1 = -INFINITY;

		hl_ecu_box_to_lamp(&camera, lamps[l], HL_ANGLES_A, hl, hr, vb, vt, r, &b);
		for (int i = 0; i < 3; i++) {
			for (int j = 0; j < 3; j++) {
				const double h = hl + i * (hr - hl) / 2, v = vb + j * (vt - vb) / 2;
				double wh, wv;

				naive_parallax(camera.pos_m, 0.0, h, v, r, lamps[l]->pos_m, 0.0,
					       &wh, &wv);
				h0 = fmin(h0, wh);
				h1 = fmax(h1, wh);
				v0 = fmin(v0, wv);
				v1 = fmax(v1, wv);
			}
		}
		assert_float_equal(b.h0_deg, h0, 1e-9);
		assert_float_equal(b.h1_deg, h1, 1e-9);
		assert_float_equal(b.v0_deg, v0, 1e-9);
		assert_float_equal(b.v1_deg, v1, 1e-9);
	}
	/* the left lamp sees the car further right than the right lamp does */
	{
		struct hl_ecu_box a, b;

		hl_ecu_box_to_lamp(&camera, &left_lamp, HL_ANGLES_A, hl, hr, vb, vt, r, &a);
		hl_ecu_box_to_lamp(&camera, &right_lamp, HL_ANGLES_A, hl, hr, vb, vt, r, &b);
		assert_true(a.h0_deg > b.h0_deg + 1.5 && a.h1_deg > b.h1_deg + 1.5);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(parallax_point_ahead_by_hand),
		cmocka_unit_test(parallax_random_points),
		cmocka_unit_test(parallax_angle_system_b),
		cmocka_unit_test(parallax_box_bounds_its_points),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
