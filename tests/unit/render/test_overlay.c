/* SPDX-License-Identifier: MIT */
/*
 * The bird view's labels on a synthetic frame: a camera straight down on the ground, lux
 * falling with x so the iso-lux lines are known columns; the lines sit exactly there, only on
 * the ground, in their colours, each with its label beside it, and the distance labels centred
 * on their lines' image points.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "render/font.h"
#include "render/overlay.h"

#define W 400
#define H 200

/* 1 px = 0.25 m: x = 0 at column 0 (left edge), y = 0 at the middle row. */
static struct hl_camera camera(void)
{
	const double t = tan(30.0 * M_PI / 360.0);

	return (struct hl_camera){ .pos_m = { 50.0, 0.0, 25.0 / t },
				   .dir = { 0.0, 0.0, -1.0 },
				   .up = { 0.0, 1.0, 0.0 },
				   .fov_y_deg = 30.0,
				   .width = W,
				   .height = H };
}

/* The ground everywhere except a "post" (normal sideways) at columns 300..309, rows 10..19. */
static struct hl_gbuffer *ground(void)
{
	struct hl_gbuffer *gb;

	assert_int_equal(hl_gbuffer_new(W, H, &gb), 0);
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			const size_t i = (size_t)y * W + x;
			const bool post = x >= 300 && x < 310 && y >= 10 && y < 20;

			gb->pos[4 * i + 0] = (float)((x + 0.5) * 0.25);
			gb->pos[4 * i + 2] = post ? 0.5f : 0.0f;
			gb->nrm[4 * i + 0] = post ? -1.0f : 0.0f;
			gb->nrm[4 * i + 2] = post ? 0.0f : 1.0f;
			gb->nrm[4 * i + 3] = (float)(post ? HL_SURF_POST : HL_SURF_ROAD);
			gb->albedo[i] = 0.2f;
		}
	return gb;
}

/* 100 lx at column 0 falling by 1 lx per column: E >= L up to column 100 - L; the post 50 lx. */
static void ramp(float *lux)
{
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++)
			lux[y * W + x] =
				x >= 300 && x < 310 && y >= 10 && y < 20 ? 50.0f : (float)(100 - x);
}

static bool is(const uint8_t *rgb, int x, int y, const uint8_t c[3])
{
	return memcmp(rgb + 3 * ((size_t)y * W + x), c, 3) == 0;
}

static int count(const uint8_t *rgb, int x0, int y0, int x1, int y1, const uint8_t c[3])
{
	int n = 0;

	for (int y = y0; y < y1; y++)
		for (int x = x0; x < x1; x++)
			n += is(rgb, x, y, c);
	return n;
}

static void overlay_iso_lines_at_their_levels_with_labels(void **state)
{
	const struct hl_camera cam = camera();
	struct hl_gbuffer *gb = ground();
	static float lux[W * H];
	static uint8_t rgb[3 * W * H];
	struct hl_overlay_opts o;
	uint8_t c[2][3];

	(void)state;
	ramp(lux);
	memset(rgb, 128, sizeof(rgb));
	hl_overlay_defaults(&o);
	o.n_iso = 2;
	o.iso_lx[0] = 10.0;
	o.iso_lx[1] = 30.0;
	o.distance_step_m = 0.0;
	o.scale = 1;
	hl_overlay_iso_colour(0, c[0]);
	hl_overlay_iso_colour(1, c[1]);
	assert_memory_not_equal(c[0], c[1], 3);
	hl_overlay_draw(&cam, gb, lux, &o, rgb);
	/* 10 lx: the last column at or above it is 90, a full-height line (label aside). */
	assert_true(is(rgb, 90, H - 1, c[0]) && is(rgb, 90, 0, c[0]));
	assert_int_equal(count(rgb, 91, 0, 92, H, c[0]), 0);
	assert_int_equal(count(rgb, 89, 0, 90, H, c[0]), 0);
	assert_true(is(rgb, 70, H - 1, c[1]));
	/* no line around the post, though its 50 lx stand out from the ground's 0 or less */
	assert_int_equal(count(rgb, 295, 5, 315, 25, c[0]), 0);
	assert_int_equal(count(rgb, 295, 5, 315, 25, c[1]), 0);
	/* the labels: "10 LX" right of its line, in its colour, on black */
	{
		const int tw = hl_font_width("10 LX", 1);
		const uint8_t black[3] = { 0, 0, 0 };

		assert_true(count(rgb, 91, 0, 91 + 3 + 2 * 2 + tw + 2, H, c[0]) > 20);
		assert_true(count(rgb, 91, 0, 91 + 3 + 2 * 2 + tw + 2, H, black) > 50);
		assert_true(count(rgb, 71, 0, 71 + 3 + 2 * 2 + tw + 2, H, c[1]) > 20);
	}
	hl_gbuffer_free(gb);
}

static void overlay_lux_view_lines_are_left_alone(void **state)
{
	const struct hl_camera cam = camera();
	struct hl_gbuffer *gb = ground();
	static float lux[W * H];
	static uint8_t rgb[3 * W * H];
	struct hl_overlay_opts o;
	const uint8_t grey[3] = { 128, 128, 128 }, white[3] = { 255, 255, 255 };

	(void)state;
	ramp(lux);
	memset(rgb, 128, sizeof(rgb));
	hl_overlay_defaults(&o);
	o.n_iso = 1;
	o.iso_lx[0] = 10.0;
	o.iso_lines = false;
	o.iso_white = true;
	o.distance_step_m = 0.0;
	o.scale = 1;
	hl_overlay_draw(&cam, gb, lux, &o, rgb);
	/* no line: column 90 keeps its grey where the label is not */
	assert_int_equal(count(rgb, 90, 0, 91, H, grey), H);
	/* only the white label beside it */
	assert_true(count(rgb, 91, 0, W, H, white) > 20);
	hl_gbuffer_free(gb);
}

static void overlay_distance_labels_centred_on_their_lines(void **state)
{
	const struct hl_camera cam = camera();
	struct hl_gbuffer *gb = ground();
	static float lux[W * H];
	static uint8_t rgb[3 * W * H];
	struct hl_overlay_opts o;
	const uint8_t white[3] = { 255, 255, 255 };
	double px, py;

	(void)state;
	memset(lux, 0, sizeof(lux));
	memset(rgb, 128, sizeof(rgb));
	hl_overlay_defaults(&o);
	o.n_iso = 0;
	o.label_y_m = 10.0;
	o.distance_last_m = 90.0;
	o.scale = 1;
	hl_overlay_draw(&cam, gb, lux, &o, rgb);
	/* 10 m is at column 40, y 10 m at row 60: "10 M" centred there, white on black */
	assert_int_equal(hl_camera_project(&cam, (double[3]){ 10.0, 10.0, 0.0 }, &px, &py), 0);
	assert_float_equal(px, 40.0, 1e-9);
	assert_float_equal(py, 60.0, 1e-9);
	for (int d = 10; d <= 90; d += 10) {
		const int x = d * 4, half = hl_font_width("10 M", 1) / 2;

		assert_true(count(rgb, x - half - 1, 56, x + half + 2, 64, white) > 20);
	}
	/* nothing but the labels' row */
	assert_int_equal(count(rgb, 0, 0, W, 50, white), 0);
	assert_int_equal(count(rgb, 0, 70, W, H, white), 0);
	hl_gbuffer_free(gb);
}

/* The white pixels of the distance labels of o into mask (1 byte per pixel). */
static void white_mask(const struct hl_camera *cam, const struct hl_gbuffer *gb,
		       const struct hl_overlay_opts *o, uint8_t *mask)
{
	static float lux[W * H];
	static uint8_t rgb[3 * W * H];
	const uint8_t white[3] = { 255, 255, 255 };

	memset(rgb, 128, sizeof(rgb));
	hl_overlay_draw(cam, gb, lux, o, rgb);
	for (int i = 0; i < W * H; i++)
		mask[i] = is(rgb, i % W, i / W, white);
}

static void overlay_distance_labels_never_overlap(void **state)
{
	const struct hl_camera cam = camera();
	struct hl_gbuffer *gb = ground();
	static uint8_t all[W * H], one[W * H], drawn[W * H];
	struct hl_overlay_opts o;
	int n = 0;

	(void)state;
	hl_overlay_defaults(&o);
	o.n_iso = 0;
	o.label_y_m = 10.0;
	o.scale = 1;
	o.distance_step_m = 2.0; /* 8 px apart: narrower than a label */
	o.distance_last_m = 98.0;
	white_mask(&cam, gb, &o, all);
	/*
	 * Each label alone (step d, last d: the label of d only): a label is either drawn whole
	 * (none drawn after it covered any of it) or left out, and the drawn ones are all there is.
	 */
	memset(drawn, 0, sizeof(drawn));
	for (int d = 2; d <= 98; d += 2) {
		bool whole = true;

		o.distance_step_m = o.distance_last_m = d;
		white_mask(&cam, gb, &o, one);
		for (int i = 0; i < W * H; i++)
			whole &= !one[i] || all[i];
		if (!whole)
			continue;
		n++;
		for (int i = 0; i < W * H; i++)
			drawn[i] |= one[i];
	}
	assert_memory_equal(drawn, all, sizeof(all));
	assert_true(n >= 8 && n < 49);
	hl_gbuffer_free(gb);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(overlay_iso_lines_at_their_levels_with_labels),
		cmocka_unit_test(overlay_lux_view_lines_are_left_alone),
		cmocka_unit_test(overlay_distance_labels_centred_on_their_lines),
		cmocka_unit_test(overlay_distance_labels_never_overlap),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
