/* SPDX-License-Identifier: MIT */
/*
 * The glare timeline: its size, refusals, and the status tracks' colours over exactly the time
 * each frame owns (halfway to its neighbours), on rows made up here so the answer is known.
 */
#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "render/glare_plot.h"

#define N_FRAMES 5
#define N_ACTORS 2

static const uint8_t fail_rgb[3] = HL_GLARE_PLOT_FAIL_RGB;
static const uint8_t pass_rgb[3] = HL_GLARE_PLOT_PASS_RGB;

/* Frames at t 0..4 s: road user 0 (oncoming, limit 625 cd) over it at 0 and 1 s, under it
 * after; road user 1 (roadside) without a limit. */
static void make(struct hl_scenario *sc, struct hl_glare_result *rows)
{
	memset(sc, 0, sizeof(*sc));
	sc->n_actors = N_ACTORS;
	strcpy(sc->actor[0].id, "car");
	sc->actor[0].role = HL_ROLE_ONCOMING;
	strcpy(sc->actor[1].id, "walker");
	sc->actor[1].role = HL_ROLE_ROADSIDE;
	memset(rows, 0, sizeof(*rows) * N_FRAMES * N_ACTORS);
	for (int f = 0; f < N_FRAMES; f++) {
		struct hl_glare_result *a = &rows[f * N_ACTORS], *b = a + 1;

		a->actor = 0;
		b->actor = 1;
		a->t_s = b->t_s = f;
		a->pair_half_cd = f < 2 ? 5000.0 : 100.0;
		a->illuminance_lx = f < 2 ? 2.0 : 0.01;
		a->limit = (struct hl_glare_limit){ 625.0, 50.0, 0 };
		a->pass = f >= 2;
		b->pair_half_cd = 300.0;
		b->illuminance_lx = 0.5;
		b->limit = (struct hl_glare_limit){ NAN, NAN, -1 };
		b->pass = true;
	}
}

static bool is(const uint8_t *p, const uint8_t rgb[3])
{
	return !memcmp(p, rgb, 3);
}

static void glare_plot_tracks_over_each_frames_stretch(void **state)
{
	static const uint8_t grey[3] = { 95, 95, 95 };
	struct hl_scenario *sc = malloc(sizeof(*sc));
	struct hl_glare_result rows[N_FRAMES * N_ACTORS];
	uint8_t *rgb;
	int w, h, band[N_ACTORS], n_band = 0, x0 = -1, x1 = -1, last_fail = -1;
	(void)state;

	assert_non_null(sc);
	make(sc, rows);
	assert_int_equal(hl_glare_plot_rgb(sc, rows, N_FRAMES, "T", &rgb, &w, &h), 0);
	assert_int_equal(w, HL_GLARE_PLOT_W);
	assert_int_equal(h, HL_GLARE_PLOT_H(N_ACTORS));
	/* the tracks: bands of rows whose middle pixel is a track colour, top down */
	for (int y = 0, prev = 0; y < h; y++) {
		const uint8_t *p = rgb + 3 * ((size_t)y * w + w / 2);
		const int on = is(p, fail_rgb) || is(p, pass_rgb) || is(p, grey);

		if (on && !prev && n_band < N_ACTORS)
			band[n_band++] = y;
		prev = on;
	}
	assert_int_equal(n_band, N_ACTORS);
	for (int x = 0; x < w; x++) {
		const uint8_t *p = rgb + 3 * ((size_t)band[0] * w + x);

		if (is(p, fail_rgb) || is(p, pass_rgb)) {
			x0 = x0 < 0 ? x : x0;
			x1 = x;
		}
		if (is(p, fail_rgb))
			last_fail = x;
	}
	/* road user 0: failure colour from the axis' start to 1.5 s of 4, then the pass colour */
	assert_true(x0 > 0 && x1 > x0 + 100);
	/* (the pixel the boundary falls in goes to the later frame) */
	assert_true(fabs(last_fail - (x0 + 1.5 / 4.0 * (x1 - x0))) <= 1.5);
	for (int x = x0; x <= x1; x++)
		assert_true(is(rgb + 3 * ((size_t)band[0] * w + x),
			       x <= last_fail ? fail_rgb : pass_rgb));
	/* road user 1: no limit over the whole axis */
	for (int x = x0; x <= x1; x++)
		assert_true(is(rgb + 3 * ((size_t)band[1] * w + x), grey));
	free(rgb);
	free(sc);
}

static void glare_plot_refuses_what_it_cannot_draw(void **state)
{
	struct hl_scenario *sc = malloc(sizeof(*sc));
	struct hl_glare_result rows[N_FRAMES * N_ACTORS];
	static uint8_t untouched[] = "untouched";
	uint8_t *rgb = untouched;
	int w = -1, h = -1;
	(void)state;

	assert_non_null(sc);
	make(sc, rows);
	assert_int_equal(hl_glare_plot_rgb(sc, rows, 0, NULL, &rgb, &w, &h), -EINVAL);
	rows[2 * N_ACTORS].t_s = rows[1 * N_ACTORS].t_s; /* times not increasing */
	assert_int_equal(hl_glare_plot_rgb(sc, rows, N_FRAMES, NULL, &rgb, &w, &h), -EINVAL);
	sc->n_actors = 0;
	assert_int_equal(hl_glare_plot_rgb(sc, rows, N_FRAMES, NULL, &rgb, &w, &h), -EINVAL);
	assert_ptr_equal(rgb, untouched);
	assert_int_equal(w, -1);
	assert_int_equal(h, -1);
	/* one frame: drawn at full size */
	make(sc, rows);
	assert_int_equal(hl_glare_plot_rgb(sc, rows, 1, NULL, &rgb, &w, &h), 0);
	assert_int_equal(h, HL_GLARE_PLOT_H(N_ACTORS));
	free(rgb);
	free(sc);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(glare_plot_tracks_over_each_frames_stretch),
		cmocka_unit_test(glare_plot_refuses_what_it_cannot_draw),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
