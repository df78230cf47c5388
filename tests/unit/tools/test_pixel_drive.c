/* SPDX-License-Identifier: MIT */
/* The pixel lamp's drive (tools/pixel_drive.c) on the layout of hdlamp model --sources 1024. */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "tools/pixel_drive.h"

static void pixel_layout_1024_is_12_rows_of_86(void **state)
{
	struct hl_pixel_layout l;
	float h0, h1, v0, v1;
	(void)state;

	assert_int_equal(hl_model_pixel_layout(0, &l), -EINVAL);
	assert_int_equal(hl_model_pixel_layout(4097, &l), -EINVAL);
	assert_int_equal(hl_model_pixel_layout(1024, &l), 0);
	assert_int_equal(l.rows, 12);
	assert_int_equal(l.cols, 86);
	/* source 1: top left; source 87: first of row 2; source 1024: column 78 of row 12 */
	hl_model_pixel_cell(&l, 0, &h0, &h1, &v0, &v1);
	assert_float_equal(h0, -20.0f, 1e-5);
	assert_float_equal(h1, -20.0f + 40.0f / 86, 1e-5);
	assert_float_equal(v1, 4.0f, 1e-5);
	assert_float_equal(v0, 3.5f, 1e-5);
	hl_model_pixel_cell(&l, 86, &h0, &h1, &v0, &v1);
	assert_float_equal(h0, -20.0f, 1e-5);
	assert_float_equal(v1, 3.5f, 1e-5);
	hl_model_pixel_cell(&l, 1023, &h0, &h1, &v0, &v1);
	assert_float_equal(h0, -20.0f + 77 * 40.0f / 86, 1e-4);
	assert_float_equal(v0, -2.0f, 1e-5);
}

static void pixel_drive_glarefree_window_is_dark_and_moves(void **state)
{
	struct hl_pixel_layout l;
	struct hl_preset *p;
	(void)state;

	assert_int_equal(hl_model_pixel_layout(1024, &l), 0);
	assert_int_equal(hl_preset_new(1024, &p), 0);
	for (int c = 0; c < 20; c++) {
		const float centre = hl_pixel_drive_window_deg(c, 20);
		int dark = 0;

		assert_int_equal(hl_pixel_drive(&l, HL_PIXEL_GLAREFREE, c, 20, p), 0);
		for (int k = 0; k < 1024; k++) {
			float h0, h1, v0, v1;
			bool in_window;

			hl_model_pixel_cell(&l, k, &h0, &h1, &v0, &v1);
			in_window = h1 > centre - 2.0f && h0 < centre + 2.0f &&
				    v1 > HL_GLAREFREE_V_MIN && v0 < HL_GLAREFREE_V_MAX;
			assert_int_equal(p->dim[0][k], p->dim[1][k]);
			if (in_window) {
				assert_int_equal(p->dim[0][k], 0);
				dark++;
			} else {
				assert_true(p->dim[0][k] >= 12 && p->dim[0][k] <= 63);
			}
		}
		/* rows 5..9 (V -0.5..+2); 4° is 9 or 10 columns of 40/86°, half at the edges */
		assert_true(dark >= 5 * 5 && dark <= 5 * 10);
		if (c > 1 && c < 18)
			assert_true(dark >= 5 * 9);
	}
	assert_float_equal(hl_pixel_drive_window_deg(0, 20), -20.0f, 1e-6);
	assert_float_equal(hl_pixel_drive_window_deg(19, 20), 20.0f, 1e-6);
	hl_preset_free(p);
}

static void pixel_drive_sweep_bar_crosses_from_left_to_right(void **state)
{
	struct hl_pixel_layout l;
	struct hl_preset *p;
	(void)state;

	assert_int_equal(hl_model_pixel_layout(1024, &l), 0);
	assert_int_equal(hl_preset_new(1024, &p), 0);
	for (int c = 0; c < 20; c++) {
		const int bar = c * (86 - 3) / 19;

		assert_int_equal(hl_pixel_drive(&l, HL_PIXEL_SWEEP, c, 20, p), 0);
		/* the bar: full in every row (the short last row included) */
		for (int k = 0; k < 1024; k++) {
			const int col = k % 86;

			if (col >= bar && col < bar + 3)
				assert_int_equal(p->dim[0][k], 63);
			else
				assert_true(p->dim[0][k] < 63);
			assert_int_equal(p->dim[1][k], p->dim[0][k]);
		}
	}
	/* beside the bar: low beam, off above V +1 and on below the horizon */
	assert_int_equal(hl_pixel_drive(&l, HL_PIXEL_SWEEP, 0, 20, p), 0);
	assert_int_equal(p->dim[0][10], 0); /* row 1, V +3.5..+4 */
	assert_true(p->dim[0][11 * 86 + 40] > 0); /* row 12, V -2..-1.5 */
	hl_preset_free(p);
}

static void pixel_drive_ramp_has_every_value_and_mirrors_right(void **state)
{
	struct hl_pixel_layout l;
	struct hl_preset *p, *q;
	(void)state;

	assert_int_equal(hl_model_pixel_layout(1024, &l), 0);
	assert_int_equal(hl_preset_new(1024, &p), 0);
	assert_int_equal(hl_preset_new(95, &q), 0);
	assert_int_equal(hl_pixel_drive(&l, HL_PIXEL_RAMP, 5, 16, p), 0);
	for (int k = 0; k < 1024; k++) {
		assert_int_equal(p->dim[0][k], (k + 5) % 64);
		assert_int_equal(p->dim[1][k], 63 - (k + 5) % 64);
	}
	/* wrong sizes and cycles are refused */
	assert_int_equal(hl_pixel_drive(&l, HL_PIXEL_RAMP, 0, 16, q), -EINVAL);
	assert_int_equal(hl_pixel_drive(&l, HL_PIXEL_RAMP, 16, 16, p), -EINVAL);
	assert_int_equal(hl_pixel_drive(&l, HL_PIXEL_RAMP, -1, 16, p), -EINVAL);
	assert_int_equal(hl_pixel_drive(&l, (enum hl_pixel_phase)7, 0, 16, p), -EINVAL);
	hl_preset_free(q);
	hl_preset_free(p);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(pixel_layout_1024_is_12_rows_of_86),
		cmocka_unit_test(pixel_drive_glarefree_window_is_dark_and_moves),
		cmocka_unit_test(pixel_drive_sweep_bar_crosses_from_left_to_right),
		cmocka_unit_test(pixel_drive_ramp_has_every_value_and_mirrors_right),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
