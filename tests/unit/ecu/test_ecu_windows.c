/* SPDX-License-Identifier: MIT */
/* Source windows (ecu/windows.c) against the rule computed from the dense grids. */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "ecu/windows.h"
#include "ecu_naive.h"
#include "lamp/model.h"

/* A small grid: H -2..+2, V -1..+1 at 0.5°: 9 x 5 samples. */
static const struct hl_lid_grid small = {
	.width = 9,
	.height = 5,
	.angles = HL_ANGLES_A,
	.h_first_deg = -2.0f,
	.h_last_deg = 2.0f,
	.v_first_deg = -1.0f,
	.v_last_deg = 1.0f,
};

static void set(struct hl_lid *lid, int k, const float *v)
{
	assert_int_equal(hl_lid_set_source(lid, k, v), 0);
}

/* Hand-made sources: the windows are written down, not computed. */
static void windows_small_lamp_by_hand(void **state)
{
	(void)state;
	struct hl_lid *lid;
	float a[45] = { 0 }, b[45] = { 0 }, c[45] = { 0 };
	const float i_high[3] = { 1.0f, 1.0f, 0.0f };
	struct hl_ecu_window w[3];

	assert_int_equal(hl_lid_new(3, &small, false, &lid), 0);
	/* a: 100 cd over columns 1..3 of rows 1..2, and a 4 cd skirt at column 4 of row 1
	 * where b gives 100: 4 / 104 < 5 %, not in a's window */
	for (int y = 1; y <= 2; y++)
		for (int x = 1; x <= 3; x++)
			a[y * 9 + x] = 100.0f;
	a[1 * 9 + 4] = 4.0f;
	/* b: 100 cd over columns 4..7 of row 1; 10 cd at column 8 row 4 (alone there: counts) */
	for (int x = 4; x <= 7; x++)
		b[1 * 9 + x] = 100.0f;
	b[4 * 9 + 8] = 10.0f;
	/* c: off in the high beam, 6 cd beside a's 100: 6 > 5 % of 100 */
	c[2 * 9 + 2] = 6.0f;
	c[0 * 9 + 0] = 1.0f; /* where the high beam is dark: counts */
	set(lid, 0, a);
	set(lid, 1, b);
	set(lid, 2, c);
	assert_int_equal(hl_ecu_windows(lid, i_high, 0.05, w), 0);
	/* column x is at H -2 + 0.5 x; row y at V 1 - 0.5 y */
	assert_false(w[0].empty);
	assert_true(w[0].h0_deg == -1.5 && w[0].h1_deg == -0.5);
	assert_true(w[0].v0_deg == -0.0 && w[0].v1_deg == 0.5);
	assert_true(w[1].h0_deg == 0.0 && w[1].h1_deg == 2.0);
	assert_true(w[1].v0_deg == -1.0 && w[1].v1_deg == 0.5);
	assert_true(w[2].h0_deg == -2.0 && w[2].h1_deg == -1.0);
	assert_true(w[2].v0_deg == 0.0 && w[2].v1_deg == 1.0);
	/* at 50 %, c's 6 cd beside 100 no longer counts; its lone 1 cd still does */
	assert_int_equal(hl_ecu_windows(lid, i_high, 0.5, w), 0);
	assert_true(w[2].h0_deg == -2.0 && w[2].h1_deg == -2.0);
	assert_true(w[2].v0_deg == 1.0 && w[2].v1_deg == 1.0);
	hl_lid_free(lid);
}

static void windows_empty_source_and_bad_input(void **state)
{
	(void)state;
	struct hl_lid *lid;
	float a[45] = { 0 };
	float i_high[2] = { 1.0f, 1.0f };
	struct hl_ecu_window w[2];

	assert_int_equal(hl_lid_new(2, &small, false, &lid), 0);
	a[22] = 5.0f;
	set(lid, 0, a);
	assert_int_equal(hl_ecu_windows(lid, i_high, 0.05, w), 0);
	assert_false(w[0].empty);
	assert_true(w[1].empty);
	assert_false(hl_ecu_window_overlaps(&w[1], -90, 90, -90, 90));
	assert_int_equal(hl_ecu_windows(lid, i_high, 0.0, w), -EINVAL);
	assert_int_equal(hl_ecu_windows(lid, i_high, 1.0, w), -EINVAL);
	i_high[1] = 1.5f;
	assert_int_equal(hl_ecu_windows(lid, i_high, 0.05, w), -EINVAL);
	i_high[1] = NAN;
	assert_int_equal(hl_ecu_windows(lid, i_high, 0.05, w), -EINVAL);
	hl_lid_free(lid);
}

static void windows_overlap_closed_intervals(void **state)
{
	(void)state;
	const struct hl_ecu_window w = { .h0_deg = -1, .h1_deg = 1, .v0_deg = 0, .v1_deg = 2 };

	assert_true(hl_ecu_window_overlaps(&w, 1, 3, 2, 4)); /* corners touch */
	assert_true(hl_ecu_window_overlaps(&w, -5, -1, -1, 0));
	assert_true(hl_ecu_window_overlaps(&w, -0.5, 0.5, 0.5, 1.5)); /* inside */
	assert_true(hl_ecu_window_overlaps(&w, -9, 9, -9, 9)); /* around */
	assert_false(hl_ecu_window_overlaps(&w, 1.0001, 3, 0, 2));
	assert_false(hl_ecu_window_overlaps(&w, -3, -1.0001, 0, 2));
	assert_false(hl_ecu_window_overlaps(&w, -1, 1, 2.0001, 3));
	assert_false(hl_ecu_window_overlaps(&w, -1, 1, -3, -0.0001));
}

/* Every source of both HD84 lamps against the dense, double-precision rule. */
static void windows_hd84_equal_the_dense_rule(void **state)
{
	(void)state;
	struct hl_preset *p;
	struct hl_lid *const none[2] = { NULL, NULL };
	float i_high[HL_HD84_SOURCES];
	struct hl_ecu_window got[HL_HD84_SOURCES], want[HL_HD84_SOURCES];

	assert_int_equal(hl_preset_new(HL_HD84_SOURCES, &p), 0);
	assert_int_equal(hl_model_hd84_preset("high", none, p), 0);
	for (int side = 0; side < 2; side++) {
		struct hl_lid *lid;
		int narrow = 0;

		assert_int_equal(hl_model_hd84(side, &lid), 0);
		hl_preset_intensities(p, side, i_high);
		assert_int_equal(hl_ecu_windows(lid, i_high, 0.05, got), 0);
		assert_int_equal(naive_windows(lid, i_high, 0.05, want), 0);
		for (int k = 0; k < HL_HD84_SOURCES; k++) {
			assert_int_equal(got[k].empty, want[k].empty);
			assert_float_equal(got[k].h0_deg, want[k].h0_deg, 1e-4);
			assert_float_equal(got[k].h1_deg, want[k].h1_deg, 1e-4);
			assert_float_equal(got[k].v0_deg, want[k].v0_deg, 1e-4);
			assert_float_equal(got[k].v1_deg, want[k].v1_deg, 1e-4);
		}
		/* the rule trims the skirts: a matrix LED of row 3 (28 windows over 40°) is
		 * narrower than its window plus its soft edges (1.43° + 0.64°) */
		for (int k = 56; k < 84; k++)
			narrow += got[k].h1_deg - got[k].h0_deg < 2.0;
		assert_int_equal(narrow, 28);
		hl_lid_free(lid);
	}
	hl_preset_free(p);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(windows_small_lamp_by_hand),
		cmocka_unit_test(windows_empty_source_and_bad_input),
		cmocka_unit_test(windows_overlap_closed_intervals),
		cmocka_unit_test(windows_hd84_equal_the_dense_rule),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
