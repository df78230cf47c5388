/* SPDX-License-Identifier: MIT */
/*
 * import/typec.c: type C angles (C, gamma) in lamp space: gamma from the nadir, C = 0 on the
 * optical axis growing counter-clockwise seen from above (C = 90 the lamp's left, -x), C in
 * [0, 2 pi) and gamma in [0, pi].
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "import/typec.h"

#define DEG (M_PI / 180.0)

static void expect_near(double a, double b, double tol, const char *what)
{
	if (!(fabs(a - b) <= tol))
		fail_msg("%s = %.17g, expected %.17g within %g", what, a, b, tol);
}

static void expect_cg(double x, double y, double z, double c, double g)
{
	const double d[3] = { x, y, z };
	double gc = NAN, gg = NAN;

	hl_typec_from_dir(d, &gc, &gg);
	expect_near(gc, c, 1e-15, "C");
	expect_near(gg, g, 1e-15, "gamma");
}

/* The named directions of the header: nadir, zenith, the axis, left, right, back. */
static void typec_from_dir_names_the_header_directions(void **state)
{
	(void)state;
	expect_cg(0, 0, 1, 0.0, M_PI / 2); /* the optical axis: (0, 90) */
	expect_cg(-1, 0, 0, M_PI / 2, M_PI / 2); /* left */
	expect_cg(0, 0, -1, M_PI, M_PI / 2); /* back */
	expect_cg(1, 0, 0, 3 * M_PI / 2, M_PI / 2); /* right */
	expect_cg(0, -1, 0, 0.0, 0.0); /* straight down */
	expect_cg(0, 1, 0, 0.0, M_PI); /* straight up */
	expect_cg(0, -3, 3, 0.0, M_PI / 4); /* length does not count */
	expect_cg(-2, 0, 2, M_PI / 4, M_PI / 2);
}

/* C stays in [0, 2 pi): just right of the axis is just under 2 pi, never 2 pi itself, even
 * where 2 pi - tiny rounds to 2 pi. */
static void typec_c_stays_below_two_pi(void **state)
{
	const double tiny[3] = { 1e-300, 0.0, 1.0 }, small[3] = { 1e-3, 0.0, 1.0 };
	double c, g;

	(void)state;
	hl_typec_from_dir(tiny, &c, &g);
	assert_true(c >= 0.0 && c < 2.0 * M_PI);
	assert_true(c == 0.0);
	hl_typec_from_dir(small, &c, &g);
	expect_near(c, 2.0 * M_PI - atan(1e-3), 1e-15, "C");
	assert_true(c < 2.0 * M_PI);
	for (int i = 0; i < 64; i++) {
		const double d[3] = { ldexp(1.0, -i), -0.25, 1.0 };

		hl_typec_from_dir(d, &c, &g);
		assert_true(c >= 0.0 && c < 2.0 * M_PI);
	}
}

/* to_dir is the header's formula, unit length, and from_dir inverts it away from the poles. */
static void typec_to_dir_is_the_formula_and_from_dir_inverts_it(void **state)
{
	double d[3], c, g;

	(void)state;
	hl_typec_to_dir(0.0, M_PI / 2, d);
	expect_near(d[0], 0.0, 0.0, "x");
	expect_near(d[1], 0.0, 1e-16, "y");
	expect_near(d[2], 1.0, 0.0, "z");
	hl_typec_to_dir(30 * DEG, 60 * DEG, d);
	expect_near(d[0], -sqrt(3.0) / 4, 1e-15, "x");
	expect_near(d[1], -0.5, 1e-15, "y");
	expect_near(d[2], 0.75, 1e-15, "z");
	for (int cd = 0; cd < 360; cd += 15)
		for (int gd = 5; gd < 180; gd += 10) {
			hl_typec_to_dir(cd * DEG, gd * DEG, d);
			expect_near(d[0] * d[0] + d[1] * d[1] + d[2] * d[2], 1.0, 1e-15, "|d|^2");
			hl_typec_from_dir(d, &c, &g);
			expect_near(c, cd * DEG, 1e-13, "C");
			expect_near(g, gd * DEG, 1e-13, "gamma");
		}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(typec_from_dir_names_the_header_directions),
		cmocka_unit_test(typec_c_stays_below_two_pi),
		cmocka_unit_test(typec_to_dir_is_the_formula_and_from_dir_inverts_it),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
