/* SPDX-License-Identifier: MIT */
/*
 * lamp/angles.c: the type A and B angle systems (H, V) of a lamp-space direction and back, and
 * the basis of a mount turned by yaw then pitch with points carried into it.
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "lamp/angles.h"

#define DEG (M_PI / 180.0)

/* cmocka's assert_float_equal compares floats: doubles are checked here. */
#define assert_near(a, b, tol) expect_near((a), (b), (tol), #a, __LINE__)

static void expect_near(double a, double b, double tol, const char *what, int line)
{
	if (!(fabs(a - b) <= tol))
		fail_msg("line %d: %s = %.17g, expected %.17g within %g", line, what, a, b, tol);
}

static void expect_vec(const double v[3], double x, double y, double z, double tol)
{
	if (fabs(v[0] - x) > tol || fabs(v[1] - y) > tol || fabs(v[2] - z) > tol)
		fail_msg("(%.17g, %.17g, %.17g), expected (%.17g, %.17g, %.17g)", v[0], v[1], v[2],
			 x, y, z);
}

static void expect_angles(enum hl_angles sys, const double d[3], double h, double v)
{
	double gh = NAN, gv = NAN;

	hl_angles_from_dir(sys, d, &gh, &gv);
	if (fabs(gh - h) > 1e-15 || fabs(gv - v) > 1e-15)
		fail_msg("system %d: (%.17g, %.17g), expected (%.17g, %.17g)", (int)sys, gh, gv, h,
			 v);
}

/* On the axes both systems agree; the length of d does not count; off the axes they differ
 * exactly as the header's formulas say. */
static void angles_from_dir_follow_the_formulas_of_each_system(void **state)
{
	const double fwd[3] = { 0, 0, 5 }, right[3] = { 2, 0, 0 }, up[3] = { 0, 0.5, 0 };
	const double down_left[3] = { -1, -1, 1 }, back[3] = { 0, 0, -1 };

	(void)state;
	for (int s = 0; s < 2; s++) {
		expect_angles((enum hl_angles)s, fwd, 0.0, 0.0);
		expect_angles((enum hl_angles)s, right, M_PI / 2, 0.0);
		expect_angles((enum hl_angles)s, up, 0.0, M_PI / 2);
	}
	/* A: turn then elevate */
	expect_angles(HL_ANGLES_A, down_left, -M_PI / 4, -atan2(1.0, sqrt(2.0)));
	/* B: tilt then turn */
	expect_angles(HL_ANGLES_B, down_left, -atan2(1.0, sqrt(2.0)), -M_PI / 4);
	/* straight back: A turns H by 180 degrees, B tilts V by 180 degrees */
	expect_angles(HL_ANGLES_A, back, M_PI, 0.0);
	expect_angles(HL_ANGLES_B, back, 0.0, M_PI);
}

/* to_dir gives unit vectors, the exact values on the axes, and from_dir inverts it over the
 * front half space. */
static void angles_to_dir_is_unit_and_from_dir_inverts_it(void **state)
{
	double d[3], h, v;

	(void)state;
	hl_angles_to_dir(HL_ANGLES_A, 0.0, 0.0, d);
	expect_vec(d, 0.0, 0.0, 1.0, 0.0);
	hl_angles_to_dir(HL_ANGLES_A, 30 * DEG, 0.0, d);
	expect_vec(d, 0.5, 0.0, sqrt(3.0) / 2, 1e-15);
	hl_angles_to_dir(HL_ANGLES_B, 0.0, 30 * DEG, d);
	expect_vec(d, 0.0, 0.5, sqrt(3.0) / 2, 1e-15);
	/* (30, 30): A elevates after turning, B turns after tilting */
	hl_angles_to_dir(HL_ANGLES_A, 30 * DEG, 30 * DEG, d);
	expect_vec(d, sqrt(3.0) / 4, 0.5, 0.75, 1e-15);
	hl_angles_to_dir(HL_ANGLES_B, 30 * DEG, 30 * DEG, d);
	expect_vec(d, 0.5, sqrt(3.0) / 4, 0.75, 1e-15);
	for (int s = 0; s < 2; s++)
		for (int hd = -89; hd <= 89; hd += 7)
			for (int vd = -89; vd <= 89; vd += 11) {
				hl_angles_to_dir((enum hl_angles)s, hd * DEG, vd * DEG, d);
				assert_near(d[0] * d[0] + d[1] * d[1] + d[2] * d[2], 1.0, 1e-15);
				hl_angles_from_dir((enum hl_angles)s, d, &h, &v);
				assert_near(h, hd * DEG, 1e-13);
				assert_near(v, vd * DEG, 1e-13);
			}
}

/* Yaw 0, pitch 0 looks along the vehicle's +x with x to its right (-y) and y up (+z); yaw
 * turns left, pitch up; y is x cross z, all three unit and orthogonal. */
static void mount_basis_turns_by_yaw_then_pitch(void **state)
{
	double x[3], y[3], z[3];

	(void)state;
	hl_mount_basis(0.0, 0.0, x, y, z);
	expect_vec(z, 1.0, 0.0, 0.0, 0.0);
	expect_vec(x, 0.0, -1.0, 0.0, 0.0);
	expect_vec(y, 0.0, 0.0, 1.0, 0.0);
	hl_mount_basis(90.0, 0.0, x, y, z);
	expect_vec(z, 0.0, 1.0, 0.0, 1e-15);
	expect_vec(x, 1.0, 0.0, 0.0, 1e-15);
	expect_vec(y, 0.0, 0.0, 1.0, 1e-15);
	hl_mount_basis(0.0, 30.0, x, y, z);
	expect_vec(z, sqrt(3.0) / 2, 0.0, 0.5, 1e-15);
	expect_vec(x, 0.0, -1.0, 0.0, 0.0);
	expect_vec(y, -0.5, 0.0, sqrt(3.0) / 2, 1e-15); /* tilted back by the pitch */
	for (int yaw = -180; yaw <= 180; yaw += 45)
		for (int pitch = -60; pitch <= 60; pitch += 20) {
			hl_mount_basis(yaw, pitch, x, y, z);
			assert_near(x[0] * x[0] + x[1] * x[1] + x[2] * x[2], 1.0, 1e-15);
			assert_near(y[0] * y[0] + y[1] * y[1] + y[2] * y[2], 1.0, 1e-15);
			assert_near(z[0] * z[0] + z[1] * z[1] + z[2] * z[2], 1.0, 1e-15);
			assert_near(x[0] * y[0] + x[1] * y[1] + x[2] * y[2], 0.0, 1e-15);
			assert_near(x[0] * z[0] + x[1] * z[1] + x[2] * z[2], 0.0, 1e-15);
			assert_near(y[0] * z[0] + y[1] * z[1] + y[2] * z[2], 0.0, 1e-15);
			assert_true(x[2] == 0.0); /* no roll: x stays horizontal */
			assert_near(y[0], x[1] * z[2] - x[2] * z[1], 1e-15);
			assert_near(y[1], x[2] * z[0] - x[0] * z[2], 1e-15);
			assert_near(y[2], x[0] * z[1] - x[1] * z[0], 1e-15);
		}
}

/* A point in the vehicle frame, relative to the mount, on the mount's axes. */
static void mount_to_local_measures_from_the_mount_along_its_axes(void **state)
{
	const double pos[3] = { 1.0, 2.0, 3.0 };
	const double ahead[3] = { 11.0, 2.0, 3.0 }, right[3] = { 1.0, 1.5, 3.0 };
	const double above[3] = { 1.0, 2.0, 3.25 }, left[3] = { 1.0, 7.0, 3.0 };
	double r[3];

	(void)state;
	hl_mount_to_local(pos, 0.0, 0.0, ahead, r);
	expect_vec(r, 0.0, 0.0, 10.0, 0.0);
	hl_mount_to_local(pos, 0.0, 0.0, right, r);
	expect_vec(r, 0.5, 0.0, 0.0, 0.0);
	hl_mount_to_local(pos, 0.0, 0.0, above, r);
	expect_vec(r, 0.0, 0.25, 0.0, 0.0);
	hl_mount_to_local(pos, 0.0, 0.0, pos, r);
	expect_vec(r, 0.0, 0.0, 0.0, 0.0);
	/* turned 90 degrees left, the vehicle's left is straight ahead */
	hl_mount_to_local(pos, 90.0, 0.0, left, r);
	expect_vec(r, 0.0, 0.0, 5.0, 1e-15);
	/* pitched down 45 degrees, a point 1 m ahead and 1 m below is on the axis */
	{
		const double p[3] = { 2.0, 2.0, 2.0 };

		hl_mount_to_local(pos, 0.0, -45.0, p, r);
		expect_vec(r, 0.0, 0.0, sqrt(2.0), 1e-15);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(angles_from_dir_follow_the_formulas_of_each_system),
		cmocka_unit_test(angles_to_dir_is_unit_and_from_dir_inverts_it),
		cmocka_unit_test(mount_basis_turns_by_yaw_then_pitch),
		cmocka_unit_test(mount_to_local_measures_from_the_mount_along_its_axes),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
