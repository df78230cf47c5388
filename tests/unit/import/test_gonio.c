/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "import/gonio.h"
#include "import/text.h"

static const float four[] = { 1, 2, 3, 4 };

/* Bilinear in the table's own angles, non-uniform spacing, zero outside. */
static void gonio_interpolates_bilinearly_and_is_zero_outside(void **state)
{
	const double planes[] = { -10.0, 0.0, 30.0 }, in[] = { -5.0, 5.0 };
	const float v[] = { 0, 10, 20, 40, 100, 200 };
	struct hl_gonio *g;

	(void)state;
	assert_int_equal(hl_gonio_new(HL_GONIO_A, 3, planes, 2, in, v, &g), 0);
	assert_true(hl_gonio_lookup(g, -10.0, -5.0) == 0.0);
	assert_true(hl_gonio_lookup(g, 30.0, 5.0) == 200.0);
	assert_true(hl_gonio_lookup(g, 15.0, 0.0) == 0.5 * (30.0 + 150.0));
	assert_true(hl_gonio_lookup(g, -5.0, 5.0) == 25.0);
	assert_true(hl_gonio_lookup(g, -10.001, 0.0) == 0.0);
	assert_true(hl_gonio_lookup(g, 0.0, 5.001) == 0.0);
	assert_true(hl_gonio_lookup(g, NAN, 0.0) == 0.0);
	assert_true(hl_gonio_peak_cd(g) == 200.0f);
	hl_gonio_free(g);
	hl_gonio_free(NULL);
}

static void gonio_refuses_bad_tables(void **state)
{
	const double ok[] = { 0.0, 10.0 }, down[] = { 10.0, 0.0 }, same[] = { 5.0, 5.0 };
	const double wide[] = { -100.0, 0.0 }, nan2[] = { 0.0, NAN };
	const float neg[] = { 1, -1, 1, 1 }, inf[] = { 1, INFINITY, 1, 1 };
	struct hl_gonio *g = NULL;

	(void)state;
	assert_int_equal(hl_gonio_new(HL_GONIO_A, 2, down, 2, ok, four, &g), -EINVAL);
	assert_int_equal(hl_gonio_new(HL_GONIO_A, 2, same, 2, ok, four, &g), -EINVAL);
	assert_int_equal(hl_gonio_new(HL_GONIO_A, 2, ok, 2, wide, four, &g), -EINVAL);
	assert_int_equal(hl_gonio_new(HL_GONIO_B, 2, wide, 2, ok, four, &g), -EINVAL);
	assert_int_equal(hl_gonio_new(HL_GONIO_C, 2, wide, 2, ok, four, &g), -EINVAL);
	assert_int_equal(hl_gonio_new(HL_GONIO_A, 2, ok, 2, nan2, four, &g), -EINVAL);
	assert_int_equal(hl_gonio_new(HL_GONIO_A, 2, ok, 2, ok, neg, &g), -EINVAL);
	assert_int_equal(hl_gonio_new(HL_GONIO_A, 2, ok, 2, ok, inf, &g), -EINVAL);
	assert_int_equal(hl_gonio_new(HL_GONIO_A, 1, ok, 2, ok, four, &g), -EINVAL);
	/* symmetries need their planes */
	assert_int_equal(hl_gonio_new_c(HL_GONIO_CSYM_QUADRANT, 2, ok, 2, ok, four, &g), -EINVAL);
	assert_int_equal(hl_gonio_new_c(HL_GONIO_CSYM_C0_C180, 2, ok, 2, ok, four, &g), -EINVAL);
	assert_int_equal(hl_gonio_new_c(HL_GONIO_CSYM_NONE, 2, ok, 2, ok, four, &g), -EINVAL);
	assert_int_equal(hl_gonio_new_c(HL_GONIO_CSYM_ROTATIONAL, 2, ok, 2, ok, four, &g), -EINVAL);
	assert_int_equal(hl_gonio_new_lateral(HL_GONIO_C, 2, ok, 2, ok, four, &g), -EINVAL);
	assert_int_equal(hl_gonio_new_lateral(HL_GONIO_A, 2, down, 2, ok, four, &g), -EINVAL);
	assert_null(g);
}

/* The C90-C270 expansion spans 90..450 and wraps: C 0 is the mirror of C 180. */
static void gonio_c90_c270_wraps(void **state)
{
	const double planes[] = { 90.0, 180.0, 270.0 }, in[] = { 0.0, 180.0 };
	const float v[] = { 1, 1, 2, 2, 3, 3 };
	struct hl_gonio *g;

	(void)state;
	assert_int_equal(hl_gonio_new_c(HL_GONIO_CSYM_C90_C270, 3, planes, 2, in, v, &g), 0);
	assert_int_equal(hl_gonio_n_planes(g), 5);
	assert_true(hl_gonio_planes(g)[4] == 450.0);
	assert_true(hl_gonio_lookup(g, 0.0, 90.0) == 2.0);
	assert_true(hl_gonio_lookup(g, -720.0, 90.0) == 2.0);
	assert_true(hl_gonio_lookup(g, 315.0, 90.0) == 2.5);
	hl_gonio_free(g);
}

/* Strict numbers: decimal only, finite only, the whole token. */
static void numbers_are_strict(void **state)
{
	static const char *const good[] = { "0", "-1", "+2.5", ".5", "5.", "1e3", "-1.5E-2" };
	static const double want[] = { 0, -1, 2.5, 0.5, 5, 1000, -0.015 };
	static const char *const bad[] = { "",	  "-",	 ".",	"nan", "inf",	"0x10", "1e",
					   "1e+", "1,5", "1 5", "12a", "1e999", "--1",	"\x01" };
	double v;

	(void)state;
	for (size_t i = 0; i < sizeof(good) / sizeof(good[0]); i++) {
		assert_int_equal(hl_number_parse(good[i], strlen(good[i]), &v), 0);
		assert_true(v == want[i]);
	}
	for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++)
		assert_int_equal(hl_number_parse(bad[i], strlen(bad[i]), &v), -EBADMSG);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(gonio_interpolates_bilinearly_and_is_zero_outside),
		cmocka_unit_test(gonio_refuses_bad_tables),
		cmocka_unit_test(gonio_c90_c270_wraps),
		cmocka_unit_test(numbers_are_strict),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
