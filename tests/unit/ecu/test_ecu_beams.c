/* SPDX-License-Identifier: MIT */
/* The ECU's default beams (ecu/beams.c): the HD84 presets, and the rule for other lamps. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "ecu/beams.h"
#include "ecu_naive.h"
#include "lamp/model.h"

static void beams_hd84_are_its_presets(void **state)
{
	(void)state;
	struct hl_preset *p;
	struct hl_lid *const none[2] = { NULL, NULL };

	assert_int_equal(hl_preset_new(HL_HD84_SOURCES, &p), 0);
	for (int s = 0; s < 2; s++) {
		struct hl_lid *lid;
		float low[HL_HD84_SOURCES], high[HL_HD84_SOURCES];

		assert_int_equal(hl_model_hd84(s, &lid), 0);
		assert_true(hl_ecu_beams_is_hd84(lid));
		assert_int_equal(hl_ecu_beams_default(lid, s, 0.05, low, high), 0);
		assert_int_equal(hl_model_hd84_preset("low", none, p), 0);
		for (int k = 0; k < HL_HD84_SOURCES; k++)
			assert_true(low[k] == p->dim[s][k] / 63.0f);
		assert_int_equal(hl_model_hd84_preset("high", none, p), 0);
		for (int k = 0; k < HL_HD84_SOURCES; k++)
			assert_true(high[k] == p->dim[s][k] / 63.0f);
		/* spot checks from docs/design.md §1: LED 1 at 3 % in the low beam, row 3 off;
		 * LED 45 at 80 % in the high beam */
		assert_float_equal(low[0], 2.0 / 63.0, 1e-7);
		assert_true(low[60] == 0.0f);
		assert_float_equal(high[44], 50.0 / 63.0, 1e-7);
		hl_lid_free(lid);
	}
	hl_preset_free(p);
}

/* 95 sources that are not the HD84 (unnamed): the rule for other lamps. */
static void beams_unnamed_95_sources_take_the_rule(void **state)
{
	(void)state;
	struct hl_lid *lid;
	float low[95], high[95];
	struct hl_ecu_window w[95];
	int n_low = 0;

	assert_int_equal(hl_model_pixel(95, &lid), 0);
	assert_false(hl_ecu_beams_is_hd84(lid));
	assert_int_equal(hl_ecu_beams_default(lid, HL_SIDE_RIGHT, 0.05, low, high), 0);
	assert_int_equal(naive_windows(lid, high, 0.05, w), 0);
	for (int k = 0; k < 95; k++) {
		assert_true(high[k] == 1.0f);
		assert_true(low[k] == (!w[k].empty && w[k].v1_deg <= 0.0 ? 1.0f : 0.0f));
		n_low += low[k] == 1.0f;
	}
	/* the pixel field spans V -2..+4: the cells wholly below the horizon, a third or less */
	assert_true(n_low > 0 && n_low <= 95 / 3);
	hl_lid_free(lid);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(beams_hd84_are_its_presets),
		cmocka_unit_test(beams_unnamed_95_sources_take_the_rule),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
