/* SPDX-License-Identifier: MIT */
/*
 * The 5 x 7 plot font: the exact pixels of a glyph at scale 1 and 2, lower case as upper, blanks
 * that still advance, clipping at every edge (nothing written outside the image), and widths.
 */
#include <setjmp.h>
#include <stdbool.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "render/font.h"

#define W 24
#define H 16
#define GUARD 64

static const uint8_t ink[3] = { 200, 100, 50 };

/* The image with guard bytes on both sides, all 7. */
struct canvas {
	uint8_t before[GUARD], rgb[W * H * 3], after[GUARD];
};

static void clear(struct canvas *c)
{
	memset(c, 7, sizeof(*c));
}

static bool inked(const struct canvas *c, int x, int y)
{
	const uint8_t *p = c->rgb + 3 * (y * W + x);

	if (memcmp(p, ink, 3) == 0)
		return true;
	assert_int_equal(p[0], 7); /* untouched, never half written */
	assert_int_equal(p[1], 7);
	assert_int_equal(p[2], 7);
	return false;
}

static void guards_untouched(const struct canvas *c)
{
	for (int i = 0; i < GUARD; i++) {
		assert_int_equal(c->before[i], 7);
		assert_int_equal(c->after[i], 7);
	}
}

/* The glyph "1" (font.c's rows) drawn at (x0, y0), scale s: exactly its '#' cells. */
static const char *const one[HL_FONT_H] = { "..#..", ".##..", "..#..", "..#..",
					    "..#..", "..#..", ".###." };

static void expect_one(const struct canvas *c, int x0, int y0, int s, int cells)
{
	int n = 0;

	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			const int gx = (x - x0), gy = (y - y0);
			const bool in = gx >= 0 && gy >= 0 && gx < HL_FONT_W * s &&
					gy < HL_FONT_H * s && one[gy / s][gx / s] == '#';

			assert_int_equal(inked(c, x, y), in);
			n += in;
		}
	assert_int_equal(n, cells * s * s);
}

static void font_glyph_one_exact_pixels_at_scale_1(void **state)
{
	struct canvas c;
	(void)state;

	clear(&c);
	hl_font_draw(c.rgb, W, H, 3, 2, 1, "1", ink);
	expect_one(&c, 3, 2, 1, 10); /* "1" has 10 cells */
	guards_untouched(&c);
}

static void font_scale_2_makes_each_cell_a_2x2_block(void **state)
{
	struct canvas c;
	(void)state;

	clear(&c);
	hl_font_draw(c.rgb, W, H, 1, 1, 2, "1", ink);
	expect_one(&c, 1, 1, 2, 10);
	guards_untouched(&c);
}

static void font_lower_case_is_drawn_as_upper(void **state)
{
	struct canvas a, b;
	(void)state;

	clear(&a);
	clear(&b);
	hl_font_draw(a.rgb, W, H, 0, 0, 1, "hz", ink);
	hl_font_draw(b.rgb, W, H, 0, 0, 1, "HZ", ink);
	assert_memory_equal(a.rgb, b.rgb, sizeof(a.rgb));
	/* 'H' row 3 is "#####": the bar across at y = 3 */
	for (int x = 0; x < 5; x++)
		assert_true(inked(&a, x, 3));
	assert_false(inked(&a, 5, 3)); /* the gap between characters */
}

static void font_space_and_unknown_characters_are_blank_but_advance(void **state)
{
	struct canvas c;
	(void)state;

	clear(&c);
	/* '~', '\x7f' and a byte >= 0x80 are not in the font: blank like ' ' */
	hl_font_draw(c.rgb, W, H, 0, 0, 1, " ~\x7f\xe9", ink);
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++)
			assert_false(inked(&c, x, y));
	/* "  1": the "1" lands two advances (12 px) to the right */
	hl_font_draw(c.rgb, W, H, 0, 3, 1, "  1", ink);
	expect_one(&c, 2 * HL_FONT_ADVANCE, 3, 1, 10);
	guards_untouched(&c);
}

static void font_clips_at_every_edge_and_writes_nothing_outside(void **state)
{
	struct canvas c;
	(void)state;

	clear(&c);
	/* "1" hanging over the left and top edges by 2 columns and 3 rows */
	hl_font_draw(c.rgb, W, H, -2, -3, 1, "1", ink);
	expect_one(&c, -2, -3, 1, 5); /* rows 3..6, columns 2..4 */
	clear(&c);
	/* over the right and bottom edges, and a string far outside */
	hl_font_draw(c.rgb, W, H, W - 3, H - 4, 1, "1", ink);
	expect_one(&c, W - 3, H - 4, 1, 5); /* rows 0..3, columns 0..2 */
	hl_font_draw(c.rgb, W, H, -1000, -1000, 3, "888", ink);
	hl_font_draw(c.rgb, W, H, W, 0, 1, "888", ink);
	hl_font_draw(c.rgb, W, H, 0, H, 1, "888", ink);
	expect_one(&c, W - 3, H - 4, 1, 5); /* rows 0..3, columns 0..2 */
	guards_untouched(&c);
}

static void font_width_is_advance_times_n_minus_the_last_gap(void **state)
{
	(void)state;
	assert_int_equal(hl_font_width("", 1), 0);
	assert_int_equal(hl_font_width("", 3), 0);
	assert_int_equal(hl_font_width("A", 1), 5);
	assert_int_equal(hl_font_width("AB", 1), 11);
	assert_int_equal(hl_font_width("AB", 2), 22);
	assert_int_equal(hl_font_width("H [DEG]", 1), 41);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(font_glyph_one_exact_pixels_at_scale_1),
		cmocka_unit_test(font_scale_2_makes_each_cell_a_2x2_block),
		cmocka_unit_test(font_lower_case_is_drawn_as_upper),
		cmocka_unit_test(font_space_and_unknown_characters_are_blank_but_advance),
		cmocka_unit_test(font_clips_at_every_edge_and_writes_nothing_outside),
		cmocka_unit_test(font_width_is_advance_times_n_minus_the_last_gap),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
