/* SPDX-License-Identifier: MIT */
/*
 * The verdict's isocandela diagram read back pixel by pixel: a grid H -20..20, V -10..10 and
 * requirements inside +-8 H, +-3 V show H -10..10, V -5..5 at 70 px per degree (1400 x 700 at
 * (50, 34)); a flat 1000 cd distribution is the dimmed top colour with no isocandela line; a
 * passing point's green cross, a failing point's red one and its line in the list, a segment to
 * an open end, the grid lines, the title's colour; left-hand traffic mirrors H; an unwritable
 * path's -errno.
 */
#include <errno.h>
#include <math.h>
#include <png.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "render/font.h"
#include "render/plot.h"
#include "render/verdict_plot.h"
#include "testutil.h"

static const uint8_t pass_rgb[3] = { 60, 230, 90 }, fail_rgb[3] = { 255, 50, 50 };
static const uint8_t grey[3] = { 110, 110, 110 };

static const struct hl_lid_grid grid = { .width = 41,
					 .height = 21,
					 .angles = HL_ANGLES_A,
					 .h_first_deg = -20,
					 .h_last_deg = 20,
					 .v_first_deg = -10,
					 .v_last_deg = 10 };

static struct hl_regulation *reg;
static struct hl_req_result results[3];

static int setup(void **state)
{
	(void)state;
	reg = calloc(1, sizeof(*reg));
	if (!reg)
		return -1;
	strcpy(reg->id, "test-set");
	reg->n_requirements = 3;
	strcpy(reg->req[0].id, "P1");
	reg->req[0].kind = HL_REQ_POINT;
	reg->req[0].n_pts = 1;
	reg->req[0].pts[0][0] = 2.5;
	reg->req[0].pts[0][1] = 1.5;
	strcpy(reg->req[1].id, "P2");
	reg->req[1].kind = HL_REQ_POINT;
	reg->req[1].n_pts = 1;
	reg->req[1].pts[0][0] = -3.5;
	reg->req[1].pts[0][1] = -2.5;
	strcpy(reg->req[2].id, "S1");
	reg->req[2].kind = HL_REQ_SEGMENT;
	reg->req[2].n_pts = 2;
	reg->req[2].pts[0][0] = HL_REG_OPEN_LEFT;
	reg->req[2].pts[0][1] = 0.5;
	reg->req[2].pts[1][0] = 0.0;
	reg->req[2].pts[1][1] = 0.5;
	results[0] = (struct hl_req_result){ 1000, 2.5, 1.5, 100, NAN, 9.0, 0, true };
	results[1] = (struct hl_req_result){ 500, -3.5, -2.5, 1000, NAN, -0.5, 0, false };
	results[2] = (struct hl_req_result){ 1000, NAN, NAN, NAN, 2000, 0.5, 0, true };
	return 0;
}

static int teardown(void **state)
{
	(void)state;
	free(reg);
	return 0;
}

static uint8_t *decode(const char *path, int *w, int *h)
{
	png_image img;
	uint8_t *rgb;

	memset(&img, 0, sizeof(img));
	img.version = PNG_IMAGE_VERSION;
	assert_true(png_image_begin_read_from_file(&img, path));
	img.format = PNG_FORMAT_RGB;
	rgb = malloc(PNG_IMAGE_SIZE(img));
	assert_non_null(rgb);
	assert_true(png_image_finish_read(&img, NULL, rgb, 0, NULL));
	*w = (int)img.width;
	*h = (int)img.height;
	return rgb;
}

static uint8_t *plot(const float *dense, enum hl_traffic traffic, int *w, int *h)
{
	const struct hl_verdict_options opts = { traffic, 0.0, 0.0 };
	char path[512];
	uint8_t *rgb;

	test_path(path, sizeof(path), "verdict.png");
	assert_int_equal(hl_plot_verdict_png(&grid, dense, reg, &opts, results, "T", path), 0);
	rgb = decode(path, w, h);
	unlink(path);
	return rgb;
}

#define X(hdeg) (50 + (int)lround(((hdeg) + 10.0) * 70))
#define Y(vdeg) (34 + (int)lround((5.0 - (vdeg)) * 70))
#define PX(x, y) (rgb + 3 * ((size_t)(y)*w + (x)))

static void expect(const uint8_t *p, const uint8_t rgb[3])
{
	assert_int_equal(p[0], rgb[0]);
	assert_int_equal(p[1], rgb[1]);
	assert_int_equal(p[2], rgb[2]);
}

static float *flat(float cd)
{
	float *d = malloc(sizeof(float) * 41 * 21);

	assert_non_null(d);
	for (int i = 0; i < 41 * 21; i++)
		d[i] = cd;
	return d;
}

static void verdict_plot_marks_each_requirement_where_it_is_measured(void **state)
{
	float *dense = flat(1000.0f);
	uint8_t top[3], dim[3], *rgb;
	int w, h, n_fail_px = 0;
	(void)state;

	rgb = plot(dense, HL_TRAFFIC_RIGHT, &w, &h);
	assert_int_equal(w, 50 + 1400 + 150);
	assert_int_equal(h, 34 + 700 + 44 + 12 * (3 / 4 + 2));
	/* the field: colour(1) dimmed to 45 %, the same everywhere (no isocandela line) */
	hl_plot_colour(1.0f, top);
	for (int i = 0; i < 3; i++)
		dim[i] = (uint8_t)(top[i] * 0.45);
	expect(PX(X(-9.3), Y(4.3)), dim);
	expect(PX(X(7.7), Y(-3.6)), dim);
	/* grid lines: H = 5 and V = 2 */
	expect(PX(X(5), Y(-4.1)), grey);
	expect(PX(X(8.7), Y(2)), grey);
	/* P1 passes: a green cross 9 px wide at (2.5, 1.5) */
	for (int dx = -4; dx <= 4; dx++)
		expect(PX(X(2.5) + dx, Y(1.5)), pass_rgb);
	for (int dy = -4; dy <= 4; dy++)
		expect(PX(X(2.5), Y(1.5) + dy), pass_rgb);
	expect(PX(X(2.5) + 5, Y(1.5) + 5), dim); /* off the cross */
	/* P2 fails: red */
	for (int dx = -4; dx <= 4; dx++)
		expect(PX(X(-3.5) + dx, Y(-2.5)), fail_rgb);
	/* S1 from the left edge to H 0 at V 0.5, 3 px thick, green */
	for (int dy = -1; dy <= 1; dy++) {
		expect(PX(X(-10) + 3, Y(0.5) + dy), pass_rgb);
		expect(PX(X(-4.5), Y(0.5) + dy), pass_rgb);
	}
	expect(PX(X(-4.5), Y(0.5) - 2), dim);
	expect(PX(X(0.5), Y(0.5)), dim); /* beyond its end at H 0 */
	/* the title in the fail colour, "T" first: its top row at (50..54, 10) */
	for (int x = 50; x < 55; x++)
		expect(PX(x, 10), fail_rgb);
	/* the list under the diagram: "P2 500 < 1000" in red at (50, 754); "P" starts "####." */
	for (int x = 50; x < 54; x++)
		expect(PX(x, 754), fail_rgb);
	for (int y = 754; y < 754 + HL_FONT_H; y++)
		for (int x = 50; x < 50 + hl_font_width("P2 500 < 1000", 1); x++)
			n_fail_px += memcmp(PX(x, y), fail_rgb, 3) == 0;
	assert_true(n_fail_px > 60);
	free(rgb);
	free(dense);
}

static void verdict_plot_left_traffic_mirrors_h_and_dark_is_black(void **state)
{
	float *dense = flat(0.0f);
	uint8_t *rgb;
	int w, h;
	static const uint8_t black[3] = { 0, 0, 0 };
	(void)state;

	rgb = plot(dense, HL_TRAFFIC_LEFT, &w, &h);
	/* nothing lit: below the scale, black */
	expect(PX(X(-9.3), Y(4.3)), black);
	/* P1 at H 2.5 is drawn at -2.5; nothing at +2.5 */
	for (int dx = -4; dx <= 4; dx++)
		expect(PX(X(-2.5) + dx, Y(1.5)), pass_rgb);
	expect(PX(X(2.5), Y(1.5)), black);
	/* S1's open left end is now the right edge: from H 0 to +10 */
	expect(PX(X(4.5), Y(0.5)), pass_rgb);
	expect(PX(X(-4.5), Y(0.5)), black);
	free(rgb);
	free(dense);
}

static void verdict_plot_unwritable_path_returns_errno(void **state)
{
	const struct hl_verdict_options opts = { HL_TRAFFIC_RIGHT, 0.0, 0.0 };
	float *dense = flat(10.0f);
	(void)state;

	assert_int_equal(hl_plot_verdict_png(&grid, dense, reg, &opts, results, NULL,
					     "/nonexistent-dir/v.png"),
			 -ENOENT);
	free(dense);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(verdict_plot_marks_each_requirement_where_it_is_measured),
		cmocka_unit_test(verdict_plot_left_traffic_mirrors_h_and_dark_is_black),
		cmocka_unit_test(verdict_plot_unwritable_path_returns_errno),
	};

	return cmocka_run_group_tests(tests, setup, teardown);
}
