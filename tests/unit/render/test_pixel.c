/* SPDX-License-Identifier: MIT */
/* render/pixel.c: sRGB8, the display tone map and half floats, value by value. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "render/pixel.h"

static void srgb8_ends_and_known_points(void **state)
{
	(void)state;
	assert_int_equal(hl_pixel_srgb8(0.0f), 0);
	assert_int_equal(hl_pixel_srgb8(-1.0f), 0);
	assert_int_equal(hl_pixel_srgb8(NAN), 0);
	assert_int_equal(hl_pixel_srgb8(1.0f), 255);
	assert_int_equal(hl_pixel_srgb8(2.0f), 255);
	assert_int_equal(hl_pixel_srgb8(INFINITY), 255);
	/* linear segment: 12.92 x, so 1/(12.92 * 255) is level 1 */
	assert_int_equal(hl_pixel_srgb8(1.0f / (12.92f * 255.0f)), 1);
	assert_int_equal(hl_pixel_srgb8(0.0031308f), 10); /* the knee: 0.04045 * 255 = 10.3 */
	/* the curve: 0.5 -> 0.7354 (187.5), mid grey 0.2158605 -> 128, 0.0508761 -> 64 */
	assert_int_equal(hl_pixel_srgb8(0.5f), 188);
	assert_int_equal(hl_pixel_srgb8(0.2158605f), 128);
	assert_int_equal(hl_pixel_srgb8(0.0508761f), 64);
}

static void srgb8_is_monotonic(void **state)
{
	uint8_t prev = 0;

	(void)state;
	for (int i = 0; i <= 100000; i++) {
		const uint8_t v = hl_pixel_srgb8((float)i / 100000.0f);

		assert_true(v >= prev);
		prev = v;
	}
	assert_int_equal(prev, 255);
}

static void display8_tone_maps_luminance(void **state)
{
	(void)state;
	assert_int_equal(hl_pixel_display8(0.0f), 0);
	assert_int_equal(hl_pixel_display8(-5.0f), 0);
	assert_int_equal(hl_pixel_display8(NAN), 0);
	/* L = π cd/m²: x = 1, x / (1 + x) = 0.5, sRGB 188 */
	assert_int_equal(hl_pixel_display8((float)M_PI), 188);
	assert_int_equal(hl_pixel_display8(1e30f), 255);
}

static void half_from_float_exact(void **state)
{
	(void)state;
	assert_int_equal(hl_pixel_half_from_float(0.0f), 0x0000);
	assert_int_equal(hl_pixel_half_from_float(-0.0f), 0x8000);
	assert_int_equal(hl_pixel_half_from_float(1.0f), 0x3c00);
	assert_int_equal(hl_pixel_half_from_float(-2.0f), 0xc000);
	assert_int_equal(hl_pixel_half_from_float(0.1f), 0x2e66);
	assert_int_equal(hl_pixel_half_from_float(65504.0f), 0x7bff); /* the largest half */
	assert_int_equal(hl_pixel_half_from_float(65519.0f), 0x7bff); /* below the midpoint */
	assert_int_equal(hl_pixel_half_from_float(65520.0f), 0x7c00); /* rounds to infinity */
	assert_int_equal(hl_pixel_half_from_float(1e10f), 0x7c00);
	assert_int_equal(hl_pixel_half_from_float(-1e10f), 0xfc00);
}

static void half_from_float_subnormals(void **state)
{
	(void)state;
	assert_int_equal(hl_pixel_half_from_float(ldexpf(1.0f, -14)), 0x0400); /* smallest normal */
	assert_int_equal(hl_pixel_half_from_float(ldexpf(1.0f, -15)), 0x0200);
	assert_int_equal(hl_pixel_half_from_float(ldexpf(1.0f, -24)), 0x0001); /* smallest */
	assert_int_equal(hl_pixel_half_from_float(ldexpf(1023.0f, -24)), 0x03ff); /* largest */
	/* half of the smallest: a tie, to even (0) */
	assert_int_equal(hl_pixel_half_from_float(ldexpf(1.0f, -25)), 0x0000);
	/* 1.5 of the smallest: a tie, to even (2) */
	assert_int_equal(hl_pixel_half_from_float(ldexpf(3.0f, -25)), 0x0002);
	/* just above half the smallest: up to 1 */
	assert_int_equal(hl_pixel_half_from_float(ldexpf(1.0f, -25) * 1.0001f), 0x0001);
	assert_int_equal(hl_pixel_half_from_float(1e-9f), 0x0000);
	assert_int_equal(hl_pixel_half_from_float(-ldexpf(1.0f, -24)), 0x8001);
}

static void half_from_float_inf_nan(void **state)
{
	(void)state;
	assert_int_equal(hl_pixel_half_from_float(INFINITY), 0x7c00);
	assert_int_equal(hl_pixel_half_from_float(-INFINITY), 0xfc00);
	assert_int_equal(hl_pixel_half_from_float(NAN), 0x7e00);
	assert_int_equal(hl_pixel_half_from_float(-NAN) & 0x7fff, 0x7e00);
}

static void half_from_float_rounds_to_nearest_even(void **state)
{
	(void)state;
	/* halves near 1 are 2^-10 apart */
	assert_int_equal(hl_pixel_half_from_float(1.0f + ldexpf(1.0f, -11)),
			 0x3c00); /* tie: even */
	assert_int_equal(hl_pixel_half_from_float(1.0f + ldexpf(3.0f, -11)),
			 0x3c02); /* tie: even */
	assert_int_equal(hl_pixel_half_from_float(1.0f + ldexpf(1.0f, -11) + ldexpf(1.0f, -20)),
			 0x3c01);
	assert_int_equal(hl_pixel_half_from_float(1.0f + ldexpf(1.0f, -12)), 0x3c00);
	/* a carry out of the mantissa moves the exponent: 2 - 2^-12 -> 2.0 */
	assert_int_equal(hl_pixel_half_from_float(2.0f - ldexpf(1.0f, -12)), 0x4000);
}

static void half_to_float_exact(void **state)
{
	(void)state;
	assert_true(hl_pixel_half_to_float(0x3c00) == 1.0f);
	assert_true(hl_pixel_half_to_float(0xc000) == -2.0f);
	assert_true(hl_pixel_half_to_float(0x7bff) == 65504.0f);
	assert_true(hl_pixel_half_to_float(0x0001) == ldexpf(1.0f, -24));
	assert_true(hl_pixel_half_to_float(0x03ff) == ldexpf(1023.0f, -24));
	assert_true(hl_pixel_half_to_float(0x0400) == ldexpf(1.0f, -14));
	assert_true(hl_pixel_half_to_float(0x8000) == 0.0f &&
		    signbit(hl_pixel_half_to_float(0x8000)));
	assert_true(isinf(hl_pixel_half_to_float(0x7c00)) && hl_pixel_half_to_float(0x7c00) > 0);
	assert_true(isinf(hl_pixel_half_to_float(0xfc00)) && hl_pixel_half_to_float(0xfc00) < 0);
	assert_true(isnan(hl_pixel_half_to_float(0x7e00)));
}

static void half_round_trips_every_value(void **state)
{
	(void)state;
	for (uint32_t h = 0; h <= 0xffff; h++) {
		const float f = hl_pixel_half_to_float((uint16_t)h);

		if (isnan(f))
			continue;
		assert_int_equal(hl_pixel_half_from_float(f), h);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(srgb8_ends_and_known_points),
		cmocka_unit_test(srgb8_is_monotonic),
		cmocka_unit_test(display8_tone_maps_luminance),
		cmocka_unit_test(half_from_float_exact),
		cmocka_unit_test(half_from_float_subnormals),
		cmocka_unit_test(half_from_float_inf_nan),
		cmocka_unit_test(half_from_float_rounds_to_nearest_even),
		cmocka_unit_test(half_to_float_exact),
		cmocka_unit_test(half_round_trips_every_value),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
