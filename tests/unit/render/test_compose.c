/* SPDX-License-Identifier: MIT */
/*
 * render/compose.c: a frame's pixels from a known G-buffer and illuminance, byte for byte: the
 * display band, the glow boxes cleared, a road user's lamp drawn with its box, the HDR view
 * packed into half floats.
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "render/compose.h"

/* A w x h G-buffer: every pixel a hit (surface 1) of albedo 0.5. */
static struct hl_gbuffer *flat_gbuffer(int w, int h)
{
	struct hl_gbuffer *gb;

	assert_int_equal(hl_gbuffer_new(w, h, &gb), 0);
	for (int i = 0; i < w * h; i++) {
		gb->albedo[i] = 0.5f;
		gb->nrm[4 * i + 3] = 1.0f;
	}
	return gb;
}

/*
 * Only the band's pixels are written: x = albedo E 2^EV / pi = 0.5 * 2 pi / pi = 1 tone maps to
 * x / (1 + x) = 0.5, sRGB 0.7354, level 188 in every channel; E = 0 is black; the rest keep what they held.
 */
static void display_band_writes_only_its_pixels(void **state)
{
	struct hl_gbuffer *gb = flat_gbuffer(4, 1);
	const float lux[4] = { 2.0f * (float)M_PI, 2.0f * (float)M_PI, 0.0f, 2.0f * (float)M_PI };
	uint8_t rgb[12];
	struct hl_compose_display d = { gb, 0.0, rgb };
	const uint8_t want[12] = { 0xab, 0xab, 0xab, 188, 188, 188, 0, 0, 0, 0xab, 0xab, 0xab };

	(void)state;
	memset(rgb, 0xab, sizeof(rgb));
	hl_compose_display_band(&d, lux, 1, 2);
	assert_memory_equal(rgb, want, sizeof(want));
	hl_gbuffer_free(gb);
}

/* Two boxes (inclusive corners) of a 4 x 3 image black, every other byte untouched. */
static void clear_boxes_blacks_out_exactly_the_boxes(void **state)
{
	const int boxes[2][4] = { { 1, 0, 2, 1 }, { 3, 2, 3, 2 } };
	uint8_t rgb[4 * 3 * 3];

	(void)state;
	memset(rgb, 0xab, sizeof(rgb));
	hl_compose_clear_boxes(rgb, 4, boxes, 2);
	for (int y = 0; y < 3; y++)
		for (int x = 0; x < 4; x++) {
			const bool in = (x >= 1 && x <= 2 && y <= 1) || (x == 3 && y == 2);

			for (int c = 0; c < 3; c++)
				if (rgb[3 * (y * 4 + x) + c] != (in ? 0 : 0xab))
					fail_msg("pixel %d,%d channel %d: %u", x, y, c,
						 rgb[3 * (y * 4 + x) + c]);
		}
	/* no boxes: nothing changes */
	hl_compose_clear_boxes(rgb, 4, boxes, 0);
	assert_int_equal(rgb[0], 0xab);
}

/*
 * A car ahead in the ego's lane, a tail lamp of 1000 cd (red: the default colour)
 * beside its body facing the ego (and a headlamp facing away): one glow, red only (G and B stay 0), every pixel drawn inside
 * the one box returned, the same bytes as hl_world_emitters_draw() writes, and the box cleared
 * gives the black image back.
 */
static void emitters_draw_one_red_glow_in_its_box(void **state)
{
	static const char text[] =
		"{\"version\": 1, \"duration_s\": 10, \"road\": {\"segments\": ["
		"{\"kind\": \"straight\", \"length_m\": 400}]},"
		"\"actors\": [{\"id\": \"ahead\", \"kind\": \"car\", \"role\": \"preceding\","
		" \"path\": {\"lane\": 1, \"start_s_m\": 30, \"speed_mps\": 0},"
		" \"lamps\": [{\"kind\": \"headlamp\", \"pos_m\": [0, 1.5, 0.65], \"intensity_cd\": 1000},"
		"  {\"kind\": \"tail\", \"pos_m\": [0, 1.5, 0.65], \"intensity_cd\": 1000}]}]}";
	const int w = 160, h = 90;
	struct hl_scenario *sc = NULL;
	struct hl_json_error jerr;
	struct hl_world_scene *ws;
	struct hl_world_state st;
	struct hl_camera cam;
	struct hl_world_emitter e[4], e_ref[4];
	int boxes[4][4], n, lit = 0;
	uint8_t *rgb = calloc((size_t)3 * w * h, 1), *ref = calloc((size_t)3 * w * h, 1);
	char msg[512];

	(void)state;
	assert_non_null(rgb);
	assert_non_null(ref);
	if (hl_scenario_parse(text, "compose.json", &sc, &jerr) < 0)
		fail_msg("%s", hl_json_error_format(&jerr, msg, sizeof(msg)));
	cam = sc->ego.camera;
	cam.width = w;
	cam.height = h;
	assert_int_equal(hl_world_scene_new(sc, &ws), 0);
	hl_world_at(sc, 0.0, &st);
	n = hl_compose_emitters(ws, &st, &cam, 0.0, e, 4, rgb, boxes, 4);
	assert_int_equal(n, 1);
	/* the same bytes as the world scene's own drawing of the same emitters */
	assert_int_equal(hl_world_scene_emitters(ws, &st, &cam, e_ref, 4), 2);
	hl_world_emitters_draw(&cam, e_ref, 2, 0.0, ref);
	assert_memory_equal(rgb, ref, (size_t)3 * w * h);
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			const uint8_t *px = rgb + 3 * (y * w + x);
			const bool in = x >= boxes[0][0] && x <= boxes[0][2] && y >= boxes[0][1] &&
					y <= boxes[0][3];

			if ((px[0] || px[1] || px[2]) && !in)
				fail_msg("pixel %d,%d drawn outside the box", x, y);
			assert_int_equal(px[1], 0);
			assert_int_equal(px[2], 0);
			lit += px[0] != 0;
		}
	assert_true(lit > 0);
	/* the pixel under the lamp is its brightest */
	{
		const int cx = (int)e_ref[1].x_px, cy = (int)e_ref[1].y_px;
		const uint8_t centre = rgb[3 * (cy * w + cx)];

		for (int i = 0; i < w * h; i++)
			assert_true(rgb[3 * i] <= centre);
	}
	hl_compose_clear_boxes(rgb, w, (const int(*)[4])boxes, n);
	memset(ref, 0, (size_t)3 * w * h);
	assert_memory_equal(rgb, ref, (size_t)3 * w * h);
	free(rgb);
	free(ref);
	hl_world_scene_free(ws);
	hl_scenario_free(sc);
}

/*
 * Luminance 0.5 E / pi as half floats: E = 2 pi gives 1.0 (0x3c00), E = pi/2 gives 0.25
 * (0x3400), E = 0 gives 0; A is 1.0 on a hit and 0 where no surface was hit.
 */
static void hdr_packs_luminance_and_hit_as_halves(void **state)
{
	struct hl_gbuffer *gb = flat_gbuffer(3, 1);
	const float lux[3] = { 2.0f * (float)M_PI, 0.5f * (float)M_PI, 0.0f };
	float rgba[12];
	uint16_t half[12];
	const uint16_t want[12] = { 0x3c00, 0x3c00, 0x3c00, 0x3c00, 0x3400, 0x3400,
				    0x3400, 0x3c00, 0x0000, 0x0000, 0x0000, 0x0000 };

	(void)state;
	gb->nrm[4 * 2 + 3] = 0.0f; /* HL_SURF_NONE: a miss */
	hl_compose_hdr(gb, lux, rgba, half);
	assert_memory_equal(half, want, sizeof(want));
	hl_gbuffer_free(gb);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(display_band_writes_only_its_pixels),
		cmocka_unit_test(clear_boxes_blacks_out_exactly_the_boxes),
		cmocka_unit_test(emitters_draw_one_red_glow_in_its_box),
		cmocka_unit_test(hdr_packs_luminance_and_hit_as_halves),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
