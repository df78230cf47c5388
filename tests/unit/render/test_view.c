/* SPDX-License-Identifier: MIT */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "render/scene.h"
#include "render/view.h"

#define W 64
#define H 48

/* A G-buffer of one surface (albedo 0.5) with a sky band in the top rows. */
static struct hl_gbuffer *flat(void)
{
	struct hl_gbuffer *gb;

	assert_int_equal(hl_gbuffer_new(W, H, &gb), 0);
	for (int i = 0; i < W * H; i++) {
		const bool sky = i < W * 4;

		gb->pos[4 * i + 3] = sky ? 0.0f : 0.5f;
		gb->albedo[i] = sky ? 0.0f : 0.5f;
		gb->nrm[4 * i + 3] = sky ? HL_SURF_NONE : HL_SURF_ROAD;
	}
	return gb;
}

static void view_hdr_is_diffuse_luminance(void **state)
{
	struct hl_gbuffer *gb = flat();
	float lux[W * H], rgba[4 * W * H], l[W * H];

	(void)state;
	for (int i = 0; i < W * H; i++)
		lux[i] = (float)i;
	hl_view_hdr(gb, lux, rgba);
	hl_view_luminance(gb, lux, l);
	assert_float_equal(rgba[4 * 1000], 0.5 * 1000 / M_PI, 1e-3);
	assert_float_equal(rgba[4 * 1000 + 3], 1.0, 0.0);
	assert_float_equal(rgba[4 * 10 + 3], 0.0, 0.0); /* sky */
	assert_float_equal(l[1000], rgba[4 * 1000], 0.0);
	hl_gbuffer_free(gb);
}

static void view_display_tone_maps_with_exposure(void **state)
{
	struct hl_gbuffer *gb = flat();
	float lux[W * H];
	uint8_t a[3 * W * H], b[3 * W * H];
	const int p = 10 * W + 5, q = 20 * W + 5;

	(void)state;
	for (int i = 0; i < W * H; i++)
		lux[i] = (float)(i % W) * 0.5f;
	lux[q] = 2.0f * lux[p];
	hl_view_display(gb, lux, 0.0, a);
	hl_view_display(gb, lux, 1.0, b);
	/* +1 EV is twice the light; zero light is black; brighter is never darker. */
	assert_int_equal(b[3 * p], a[3 * q]);
	assert_int_equal(a[3 * (10 * W)], 0);
	for (int x = 1; x < W; x++)
		assert_true(a[3 * (30 * W + x)] >= a[3 * (30 * W + x - 1)]);
	assert_true(a[3 * (30 * W + W - 1)] > 200);
	/* 1 cd/m^2 at 0 EV: x / (1 + x) = 0.5, sRGB 188. */
	lux[p] = (float)(M_PI / 0.5);
	hl_view_display(gb, lux, 0.0, a);
	assert_true(abs(a[3 * p] - 188) <= 1);
	hl_gbuffer_free(gb);
}

static void view_lux_false_colour_iso_lines_and_legend(void **state)
{
	struct hl_gbuffer *gb = flat();
	struct hl_view_lux_opts o;
	float lux[W * H];
	uint8_t rgb[3 * W * H];
	int white = 0;

	(void)state;
	hl_view_lux_defaults(&o);
	assert_int_equal(o.n_iso, 6);
	assert_float_equal(o.iso_lx[3], 10.0, 0.0);
	o.legend = false;
	/* Left half 20 lx, right half 2 lx: a 3, 5, 10 and 20 lx line at the step. */
	for (int i = 0; i < W * H; i++)
		lux[i] = (i % W) < W / 2 ? 20.0f : 2.0f;
	lux[40 * W + 40] = 0.01f; /* below the scale: black */
	hl_view_lux(gb, lux, &o, rgb);
	for (int y = 4; y < H; y++) {
		const uint8_t *edge = rgb + 3 * (y * W + W / 2 - 1);

		assert_true(edge[0] == 255 && edge[1] == 255 && edge[2] == 255);
	}
	for (int i = 0; i < W * H; i++)
		white += rgb[3 * i] == 255 && rgb[3 * i + 1] == 255 && rgb[3 * i + 2] == 255;
	assert_true(white < W * H / 4);
	assert_int_equal(rgb[3 * (40 * W + 40)], 0);
	/* Left and right halves differ in colour; sky keeps its own colour. */
	assert_memory_not_equal(rgb + 3 * (20 * W + 5), rgb + 3 * (20 * W + W - 5), 3);
	assert_int_equal(rgb[3 * 5 + 2], 28);
	/* The legend paints a colour bar at the right. */
	o.legend = true;
	{
		uint8_t with[3 * W * H];

		hl_view_lux(gb, lux, &o, with);
		assert_memory_not_equal(with, rgb, sizeof(with));
	}
	assert_int_equal(hl_view_from_name("lux"), HL_VIEW_LUX);
	assert_true(hl_view_from_name("x") < 0);
	hl_gbuffer_free(gb);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(view_hdr_is_diffuse_luminance),
		cmocka_unit_test(view_display_tone_maps_with_exposure),
		cmocka_unit_test(view_lux_false_colour_iso_lines_and_legend),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
