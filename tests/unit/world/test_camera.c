/* SPDX-License-Identifier: MIT */
/*
 * world/camera.c: the pinhole camera (basis, rays through pixels, projection back, the OpenEXR
 * worldToCamera and worldToNDC matrices) and the lamp pose (defaults, lamp-space axes, points
 * carried into lamp space).
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "world/camera.h"

#define DEG (M_PI / 180.0)

static void expect_near(double a, double b, double tol, const char *what)
{
	if (!(fabs(a - b) <= tol))
		fail_msg("%s = %.17g, expected %.17g within %g", what, a, b, tol);
}

static void expect_vec(const double v[3], double x, double y, double z, double tol)
{
	expect_near(v[0], x, tol, "x");
	expect_near(v[1], y, tol, "y");
	expect_near(v[2], z, tol, "z");
}

static double dot(const double a[3], const double b[3])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Looking along +x with z up: right is -y (ISO 8855: y left), up +z; any dir and a rough up
 * give an orthonormal basis with up on the side of the given up. */
static void camera_basis_is_right_up_forward(void **state)
{
	struct hl_camera cam = { { 0, 0, 1.2 }, { 3, 0, 0 }, { 0, 0, 1 }, 60.0, 200, 100 };
	double r[3], u[3], f[3];

	(void)state;
	hl_camera_basis(&cam, r, u, f);
	expect_vec(f, 1, 0, 0, 0);
	expect_vec(r, 0, -1, 0, 0);
	expect_vec(u, 0, 0, 1, 0);
	/* looking down 45 degrees to the left, with a tilted up */
	cam.dir[0] = 1;
	cam.dir[1] = 1;
	cam.dir[2] = -1.4142135623730951;
	cam.up[0] = 0.3;
	hl_camera_basis(&cam, r, u, f);
	expect_vec(f, 0.5, 0.5, -M_SQRT1_2, 1e-15);
	expect_near(dot(r, r), 1, 1e-15, "|r|^2");
	expect_near(dot(u, u), 1, 1e-15, "|u|^2");
	expect_near(dot(r, u), 0, 1e-15, "r.u");
	expect_near(dot(r, f), 0, 1e-15, "r.f");
	expect_near(dot(u, f), 0, 1e-15, "u.f");
	assert_true(dot(u, cam.up) > 0.0);
}

/* The centre pixel looks along the axis; the image corners at the field of view; projecting
 * a point on a pixel's ray gives that pixel back. */
static void camera_ray_and_project_are_inverse(void **state)
{
	const struct hl_camera cam = { { 1, 2, 3 }, { 1, 0, 0 }, { 0, 0, 1 }, 90.0, 200, 100 };
	double d[3], p[3], x, y;

	(void)state;
	hl_camera_ray(&cam, 100.0, 50.0, d);
	expect_vec(d, 1, 0, 0, 1e-15);
	/* top-left corner: tan(45) = 1 up, aspect 2 to the left */
	hl_camera_ray(&cam, 0.0, 0.0, d);
	expect_vec(d, 1, 2, 1, 1e-15);
	hl_camera_ray(&cam, 200.0, 100.0, d);
	expect_vec(d, 1, -2, -1, 1e-15);
	for (double px = 0.5; px < 200; px += 13.25)
		for (double py = 0.5; py < 100; py += 7.5) {
			hl_camera_ray(&cam, px, py, d);
			for (int i = 0; i < 3; i++)
				p[i] = cam.pos_m[i] + 7.0 * d[i];
			assert_int_equal(hl_camera_project(&cam, p, &x, &y), 0);
			expect_near(x, px, 1e-11, "x");
			expect_near(y, py, 1e-11, "y");
		}
}

/* Behind the camera, on its plane, or not a number: -EDOM, the outputs untouched. */
static void camera_project_refuses_points_not_in_front(void **state)
{
	const struct hl_camera cam = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 0, 1 }, 60.0, 64, 48 };
	const double behind[3] = { -1, 0, 0 }, beside[3] = { 0, 5, 1 };
	const double nan_point[3] = { NAN, 0, 0 }, ahead[3] = { 1e-9, 0, 0 };
	double x = -1, y = -1;

	(void)state;
	assert_int_equal(hl_camera_project(&cam, behind, &x, &y), -EDOM);
	assert_int_equal(hl_camera_project(&cam, beside, &x, &y), -EDOM);
	assert_int_equal(hl_camera_project(&cam, nan_point, &x, &y), -EDOM);
	assert_true(x == -1 && y == -1);
	assert_int_equal(hl_camera_project(&cam, ahead, &x, &y), 0);
	assert_true(x == 32.0 && y == 24.0);
}

/* p M (row vectors): worldToCamera gives (right, up, forward) coordinates relative to the
 * camera; worldToNDC, divided by w, the projection over the image (0..1, y down). */
static void camera_exr_matrices_match_the_projection(void **state)
{
	const struct hl_camera cam = {
		{ 0, 0, 1.2 }, { 1, 0.1, -0.05 }, { 0, 0, 1 }, 40.0, 320, 240
	};
	const double pts[4][3] = { { 30, 0, 0 }, { 12, 3, 2 }, { 50, -8, 0.5 }, { 5, 1, 1.2 } };
	double r[3], u[3], f[3];
	float m[16], n[16];

	(void)state;
	hl_camera_world_to_camera(&cam, m);
	hl_camera_world_to_ndc(&cam, n);
	hl_camera_basis(&cam, r, u, f);
	assert_true(m[3] == 0.0f && m[7] == 0.0f && m[11] == 0.0f && m[15] == 1.0f);
	for (int k = 0; k < 4; k++) {
		const double *p = pts[k];
		double c[4] = { 0 }, h[4] = { 0 }, d[3], x, y;

		for (int j = 0; j < 4; j++)
			for (int i = 0; i < 4; i++) {
				const double pi = i < 3 ? p[i] : 1.0;

				c[j] += pi * m[i * 4 + j];
				h[j] += pi * n[i * 4 + j];
			}
		for (int i = 0; i < 3; i++)
			d[i] = p[i] - cam.pos_m[i];
		expect_near(c[0], dot(d, r), 1e-5, "camera x");
		expect_near(c[1], dot(d, u), 1e-5, "camera y");
		expect_near(c[2], dot(d, f), 1e-5, "camera z");
		expect_near(c[3], 1.0, 0, "camera w");
		assert_int_equal(hl_camera_project(&cam, p, &x, &y), 0);
		expect_near(h[0] / h[3], x / cam.width, 1e-5, "ndc x");
		expect_near(h[1] / h[3], y / cam.height, 1e-5, "ndc y");
		expect_near(h[3], c[2], 1e-5, "ndc w");
	}
}

/* Left (side 0) at y +0.7, right at y -0.7, 0.65 m up, aimed 1 % down; lamp space has z on
 * the optical axis, x to the right, y up. */
static void lamp_pose_default_is_aimed_one_percent_down(void **state)
{
	struct hl_lamp_pose left, right;
	double x[3], y[3], z[3], l[3];

	(void)state;
	hl_lamp_pose_default(0, &left);
	hl_lamp_pose_default(1, &right);
	expect_vec(left.pos_m, 0.0, HL_LAMP_Y_M, HL_LAMP_Z_M, 0);
	expect_vec(right.pos_m, 0.0, -HL_LAMP_Y_M, HL_LAMP_Z_M, 0);
	assert_true(left.yaw_deg == 0.0 && right.yaw_deg == 0.0);
	expect_near(left.pitch_deg, -0.57293869768349, 1e-12, "pitch");
	assert_true(right.pitch_deg == left.pitch_deg);
	hl_lamp_basis(&left, x, y, z);
	expect_near(z[2] / z[0], -0.01, 1e-15, "slope");
	expect_vec(x, 0, -1, 0, 0);
	/* 10 m ahead of the left lamp, 10 cm lower: on its axis */
	{
		const double p[3] = { 10.0, HL_LAMP_Y_M, HL_LAMP_Z_M - 0.1 };

		hl_lamp_to_lamp_space(&left, p, l);
		expect_vec(l, 0, 0, sqrt(100.01), 1e-12);
	}
	/* a point 1 m to the vehicle's right of the right lamp is +x in its space */
	{
		const struct hl_lamp_pose flat = { { 0, -0.7, 0.65 }, 0.0, 0.0 };
		const double p[3] = { 0.0, -1.7, 0.65 };

		hl_lamp_to_lamp_space(&flat, p, l);
		expect_vec(l, 1, 0, 0, 1e-15);
	}
	/* yaw 90 (turned left): the vehicle's +y is straight ahead */
	{
		const struct hl_lamp_pose turned = { { 1, 1, 1 }, 90.0, 0.0 };
		const double p[3] = { 1.0, 4.0, 1.0 };

		hl_lamp_to_lamp_space(&turned, p, l);
		expect_vec(l, 0, 0, 3, 1e-15);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(camera_basis_is_right_up_forward),
		cmocka_unit_test(camera_ray_and_project_are_inverse),
		cmocka_unit_test(camera_project_refuses_points_not_in_front),
		cmocka_unit_test(camera_exr_matrices_match_the_projection),
		cmocka_unit_test(lamp_pose_default_is_aimed_one_percent_down),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
