/* SPDX-License-Identifier: MIT */
/* The bend light (ecu/bend.c): the swivel law and the matrix rows turned. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "ecu/bend.h"
#include "ecu/windows.h"
#include "lamp/model.h"

#define DEG (180.0 / M_PI)

static void bend_swivel_law(void **state)
{
	(void)state;
	struct hl_ecu_bend_config c;

	hl_ecu_bend_default(&c);
	/* 20 m/s, 0.1 rad/s left: R = 200 m, preview 2 s = 40 m, asin(40 / 400) */
	assert_float_equal(hl_ecu_bend_swivel_deg(&c, 20.0, 0.1), asin(0.1) * DEG, 1e-12);
	assert_float_equal(hl_ecu_bend_swivel_deg(&c, 20.0, -0.1), -asin(0.1) * DEG, 1e-12);
	/* 40 m/s: the preview is capped at 60 m; R = 400 m */
	assert_float_equal(hl_ecu_bend_swivel_deg(&c, 40.0, 0.1), asin(60.0 / 800.0) * DEG, 1e-12);
	/* 4 m/s: the preview is at least 10 m; R = 40 m */
	assert_float_equal(hl_ecu_bend_swivel_deg(&c, 4.0, 0.1), asin(10.0 / 80.0) * DEG, 1e-12);
	/* tight: capped at 15° */
	assert_float_equal(hl_ecu_bend_swivel_deg(&c, 10.0, 0.5), 15.0, 1e-12);
	assert_float_equal(hl_ecu_bend_swivel_deg(&c, 10.0, -0.5), -15.0, 1e-12);
	/* below 10 km/h, straight, nonsense: none */
	assert_true(hl_ecu_bend_swivel_deg(&c, 2.7, 0.3) == 0.0);
	assert_true(hl_ecu_bend_swivel_deg(&c, 20.0, 0.0) == 0.0);
	assert_true(hl_ecu_bend_swivel_deg(&c, NAN, 0.1) == 0.0);
	assert_true(hl_ecu_bend_swivel_deg(&c, 20.0, INFINITY) == 0.0);
	/* the swivel does not depend on the speed while the preview is 2 s: asin(w * 2 s / 2) */
	assert_float_equal(hl_ecu_bend_swivel_deg(&c, 15.0, 0.05),
			   hl_ecu_bend_swivel_deg(&c, 25.0, 0.05), 1e-12);
}

/* One row of 5 windows 2° apart (centres 0..8), a lone wide source, and a bend source. */
static void bend_row_turned_by_hand(void **state)
{
	(void)state;
	struct hl_ecu_window w[7];
	const char *names[7] = { "a", "b", "c", "d", "e", "wide", "bend_left" };
	const float in[7] = { 0.1f, 0.2f, 0.4f, 0.8f, 1.0f, 0.5f, 0.0f };
	struct hl_ecu_rows *r;
	float out[7];
	int n;
	const int *row;

	/* listed out of order: the row is sorted by H */
	const int at[5] = { 2, 0, 4, 1, 3 };

	for (int i = 0; i < 5; i++)
		w[at[i]] = (struct hl_ecu_window){
			.h0_deg = 2 * i - 1, .h1_deg = 2 * i + 1, .v0_deg = -1, .v1_deg = 2
		};
	w[5] = (struct hl_ecu_window){ .h0_deg = -20, .h1_deg = 20, .v0_deg = -1, .v1_deg = 2 };
	w[6] = (struct hl_ecu_window){ .h0_deg = -30, .h1_deg = -10, .v0_deg = -5, .v1_deg = 0 };
	assert_int_equal(hl_ecu_rows_new(w, names, 7, &r), 0);
	assert_int_equal(hl_ecu_rows_count(r), 1);
	row = hl_ecu_rows_row(r, 0, &n);
	assert_int_equal(n, 5);
	for (int i = 0; i < 5; i++)
		assert_int_equal(row[i], at[i]);
	/* values by H: in[at[i]] = 0.4, 0.1, 1.0, 0.2, 0.8 at 0, 2, 4, 6, 8 */
	/* 1° left: each source shows the value 1° to its right, the last keeps its own */
	hl_ecu_rows_turn(r, in, 1.0, 15.0, out);
	assert_float_equal(out[2], 0.25, 1e-6);
	assert_float_equal(out[0], 0.55, 1e-6);
	assert_float_equal(out[4], 0.6, 1e-6);
	assert_float_equal(out[1], 0.5, 1e-6);
	assert_float_equal(out[3], 0.8, 1e-6);
	assert_float_equal(out[5], 0.5, 1e-6); /* in no row */
	assert_float_equal(out[6], 1.0 / 15.0, 1e-6); /* bend_left at 1° of 15° */
	/* 2° right: the value 2° to the left; the first takes its own */
	hl_ecu_rows_turn(r, in, -2.0, 15.0, out);
	assert_float_equal(out[2], 0.4, 1e-6);
	assert_float_equal(out[0], 0.4, 1e-6);
	assert_float_equal(out[4], 0.1, 1e-6);
	assert_float_equal(out[1], 1.0, 1e-6);
	assert_float_equal(out[3], 0.2, 1e-6);
	assert_float_equal(out[6], 0.0, 1e-6); /* a right bend leaves bend_left alone */
	/* none */
	hl_ecu_rows_turn(r, in, 0.0, 15.0, out);
	assert_memory_equal(out, in, sizeof(in));
	hl_ecu_rows_free(r);
}

/* The HD84's three matrix rows are found from its windows, each LED in H order. */
static void bend_hd84_rows_are_its_matrix_rows(void **state)
{
	(void)state;
	struct hl_lid *lid;
	struct hl_preset *p;
	struct hl_lid *const none[2] = { NULL, NULL };
	float hi[HL_HD84_SOURCES];
	struct hl_ecu_window w[HL_HD84_SOURCES];
	const char *names[HL_HD84_SOURCES];
	struct hl_ecu_rows *r;

	assert_int_equal(hl_model_hd84(HL_SIDE_LEFT, &lid), 0);
	assert_int_equal(hl_preset_new(HL_HD84_SOURCES, &p), 0);
	assert_int_equal(hl_model_hd84_preset("high", none, p), 0);
	hl_preset_intensities(p, HL_SIDE_LEFT, hi);
	assert_int_equal(hl_ecu_windows(lid, hi, 0.05, w), 0);
	for (int k = 0; k < HL_HD84_SOURCES; k++)
		names[k] = hl_lid_name(lid, k);
	assert_int_equal(hl_ecu_rows_new(w, names, HL_HD84_SOURCES, &r), 0);
	assert_int_equal(hl_ecu_rows_count(r), 3);
	for (int i = 0; i < 3; i++) {
		int n;
		const int *row = hl_ecu_rows_row(r, i, &n);

		assert_int_equal(n, HL_HD84_ROW_LEDS);
		for (int j = 0; j < n; j++)
			assert_int_equal(row[j], i * HL_HD84_ROW_LEDS + j);
	}
	hl_ecu_rows_free(r);
	hl_preset_free(p);
	hl_lid_free(lid);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(bend_swivel_law),
		cmocka_unit_test(bend_row_turned_by_hand),
		cmocka_unit_test(bend_hd84_rows_are_its_matrix_rows),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
