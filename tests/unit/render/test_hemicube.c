/* SPDX-License-Identifier: MIT */
/*
 * The hemicube: its refusals, the exact projected solid angles of the 2 x 2 cube worked out by
 * hand (front texel atan(1/sqrt 2)/sqrt 2, side texel (pi/4 - that)/2), weights summing to pi,
 * the centre directions and sub-sample directions of every face agreeing texel by texel, and
 * the tangent frame.
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "render/hemicube.h"

/* a within eps of b, in double precision, naming both when not */
#define assert_near(a, b, eps)                                                                   \
	do {                                                                                     \
		const double a_ = (a), b_ = (b);                                                 \
		if (!(fabs(a_ - b_) <= (eps)))                                                   \
			fail_msg("%s = %.17g, expected %.17g +- %g", #a, a_, b_, (double)(eps)); \
	} while (0)

static void hemicube_refuses_odd_small_and_huge_sizes(void **state)
{
	struct hl_hemicube *h = (struct hl_hemicube *)(uintptr_t)1;
	(void)state;

	assert_int_equal(hl_hemicube_new(0, &h), -EINVAL);
	assert_int_equal(hl_hemicube_new(1, &h), -EINVAL);
	assert_int_equal(hl_hemicube_new(3, &h), -EINVAL);
	assert_int_equal(hl_hemicube_new(-2, &h), -EINVAL);
	assert_int_equal(hl_hemicube_new(HL_HEMICUBE_MAX_SIZE + 2, &h), -EINVAL);
	assert_int_equal(hl_hemicube_new(HL_HEMICUBE_MAX_SIZE + 1, &h), -EINVAL);
	assert_ptr_equal(h, (struct hl_hemicube *)(uintptr_t)1); /* untouched */
	hl_hemicube_free(NULL);
}

static void hemicube_size_2_weights_are_the_closed_forms(void **state)
{
	struct hl_hemicube *h;
	const double front = atan(M_SQRT1_2) * M_SQRT1_2;
	const double side = 0.5 * (M_PI / 4 - front);
	const double *w;
	double sum = 0.0;
	(void)state;

	assert_int_equal(hl_hemicube_new(2, &h), 0);
	assert_int_equal(hl_hemicube_size(h), 2);
	assert_int_equal(hl_hemicube_texels(h), 12);
	w = hl_hemicube_weights(h);
	for (int i = 0; i < 4; i++)
		assert_near(w[i], front, 1e-15);
	for (int i = 4; i < 12; i++)
		assert_near(w[i], side, 1e-15);
	for (int i = 0; i < 12; i++)
		sum += w[i];
	assert_near(sum, M_PI, 1e-14);
	/* the same from the patch functions over whole faces */
	assert_near(hl_hemicube_front_patch(-1, 1, -1, 1), 4 * front, 1e-15);
	assert_near(hl_hemicube_side_patch(-1, 1, 0, 1), 2 * side, 1e-15);
	/* an empty patch, and a reversed one negative */
	assert_near(hl_hemicube_front_patch(0.3, 0.3, -1, 1), 0.0, 1e-15);
	assert_near(hl_hemicube_side_patch(1, -1, 0, 1), -2 * side, 1e-15);
	assert_near(hl_hemicube_texel_radius(h), M_SQRT2 / 2, 1e-15);
	hl_hemicube_free(h);
}

static void hemicube_size_2_directions_face_by_face(void **state)
{
	static const double want[12][3] = {
		/* front z = 1, row-major from (-x, -y) */
		{ -0.5, -0.5, 1 },
		{ 0.5, -0.5, 1 },
		{ -0.5, 0.5, 1 },
		{ 0.5, 0.5, 1 },
		/* x = +1, x = -1, y = +1, y = -1: u along the face, height 0.5 */
		{ 1, -0.5, 0.5 },
		{ 1, 0.5, 0.5 },
		{ -1, -0.5, 0.5 },
		{ -1, 0.5, 0.5 },
		{ -0.5, 1, 0.5 },
		{ 0.5, 1, 0.5 },
		{ -0.5, -1, 0.5 },
		{ 0.5, -1, 0.5 },
	};
	struct hl_hemicube *h;
	const float *d;
	(void)state;

	assert_int_equal(hl_hemicube_new(2, &h), 0);
	d = hl_hemicube_dirs(h);
	for (int i = 0; i < 12; i++) {
		const double r = sqrt(want[i][0] * want[i][0] + want[i][1] * want[i][1] +
				      want[i][2] * want[i][2]);

		for (int j = 0; j < 3; j++)
			assert_near(d[3 * i + j], want[i][j] / r, 1e-7);
	}
	hl_hemicube_free(h);
}

/* Sub-sample (0, 0) of 1 is the texel's centre; of a 2 x 2 grid they average to it. */
static void hemicube_subdirs_agree_with_centres_on_every_face(void **state)
{
	struct hl_hemicube *h;
	const float *d;
	size_t n;
	(void)state;

	assert_int_equal(hl_hemicube_new(6, &h), 0);
	n = hl_hemicube_texels(h);
	assert_int_equal(n, 3 * 36);
	d = hl_hemicube_dirs(h);
	for (size_t i = 0; i < n; i++) {
		double c[3], m[3] = { 0, 0, 0 }, r;

		hl_hemicube_subdir(h, i, 0, 0, 1, c);
		r = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
		for (int j = 0; j < 3; j++)
			assert_near(c[j] / r, d[3 * i + j], 1e-6);
		/* on the cube: one coordinate is exactly +-1, the height is inside [0, 1] */
		assert_true(c[2] >= 0.0 && c[2] <= 1.0);
		assert_true(fabs(c[0]) == 1.0 || fabs(c[1]) == 1.0 || c[2] == 1.0);
		for (int sv = 0; sv < 2; sv++)
			for (int su = 0; su < 2; su++) {
				double s[3];

				hl_hemicube_subdir(h, i, su, sv, 2, s);
				for (int j = 0; j < 3; j++)
					m[j] += s[j] / 4;
			}
		for (int j = 0; j < 3; j++)
			assert_near(m[j], c[j], 1e-12);
	}
	/* texel 36 (x = +1 face, col 0, row 0): sub-sample (1, 1) of 2 at u = -1 + 0.25, z 0.25 */
	{
		double s[3];

		hl_hemicube_subdir(h, 36, 1, 1, 2, s);
		assert_near(s[0], 1.0, 1e-15);
		assert_near(s[1], -1.0 + 0.25, 1e-15);
		assert_near(s[2], 0.25, 1e-15);
	}
	hl_hemicube_free(h);
}

/* A uniform sky of luminance L: sum F L = pi L at every size. */
static void hemicube_weights_sum_to_pi_at_every_size(void **state)
{
	(void)state;
	for (int size = 2; size <= 64; size += 2) {
		struct hl_hemicube *h;
		double sum = 0.0;

		assert_int_equal(hl_hemicube_new(size, &h), 0);
		for (size_t i = 0; i < hl_hemicube_texels(h); i++) {
			assert_true(hl_hemicube_weights(h)[i] > 0.0);
			sum += hl_hemicube_weights(h)[i];
		}
		assert_near(sum, M_PI, 1e-12);
		hl_hemicube_free(h);
	}
}

static void hemicube_frame_is_orthonormal_right_handed_and_repeatable(void **state)
{
	const double up[3] = { 0, 0, 1 };
	double t[3], b[3];
	(void)state;

	/* n = +z: x is least aligned, t = x cross n = -y, b = n cross t = +x */
	hl_hemicube_frame(up, t, b);
	assert_near(t[0], 0.0, 1e-15);
	assert_near(t[1], -1.0, 1e-15);
	assert_near(t[2], 0.0, 1e-15);
	assert_near(b[0], 1.0, 1e-15);
	assert_near(b[1], 0.0, 1e-15);
	assert_near(b[2], 0.0, 1e-15);
	for (int k = 0; k < 50; k++) {
		const double a = 0.37 * k, e = 0.11 * k - 2.0;
		const double n[3] = { cos(a) * cos(e), sin(a) * cos(e), sin(e) };
		double t2[3], b2[3], c[3];

		hl_hemicube_frame(n, t, b);
		hl_hemicube_frame(n, t2, b2);
		assert_memory_equal(t, t2, sizeof(t));
		assert_memory_equal(b, b2, sizeof(b));
		assert_near(t[0] * t[0] + t[1] * t[1] + t[2] * t[2], 1.0, 1e-12);
		assert_near(b[0] * b[0] + b[1] * b[1] + b[2] * b[2], 1.0, 1e-12);
		assert_near(t[0] * n[0] + t[1] * n[1] + t[2] * n[2], 0.0, 1e-12);
		assert_near(b[0] * n[0] + b[1] * n[1] + b[2] * n[2], 0.0, 1e-12);
		/* t cross b = n */
		c[0] = t[1] * b[2] - t[2] * b[1];
		c[1] = t[2] * b[0] - t[0] * b[2];
		c[2] = t[0] * b[1] - t[1] * b[0];
		for (int j = 0; j < 3; j++)
			assert_near(c[j], n[j], 1e-12);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(hemicube_refuses_odd_small_and_huge_sizes),
		cmocka_unit_test(hemicube_size_2_weights_are_the_closed_forms),
		cmocka_unit_test(hemicube_size_2_directions_face_by_face),
		cmocka_unit_test(hemicube_subdirs_agree_with_centres_on_every_face),
		cmocka_unit_test(hemicube_weights_sum_to_pi_at_every_size),
		cmocka_unit_test(hemicube_frame_is_orthonormal_right_handed_and_repeatable),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
