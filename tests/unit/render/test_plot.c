/* SPDX-License-Identifier: MIT */
/*
 * The plot helpers: the turbo colours at known t (and clamped outside 0..1), PNG in memory and
 * on disk read back byte for byte (rows of any stride), their refusals, and the H-V diagram of
 * a made-up distribution read back pixel by pixel: sample colours on the log scale, black below
 * it, the axes' blend, the legend's ends, the title's first glyph.
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

#include "render/plot.h"
#include "testutil.h"

static void expect_rgb(const uint8_t *p, int r, int g, int b)
{
	assert_int_equal(p[0], r);
	assert_int_equal(p[1], g);
	assert_int_equal(p[2], b);
}

static void plot_colour_turbo_at_known_points_and_clamped(void **state)
{
	uint8_t c[3], d[3];
	(void)state;

	hl_plot_colour(0.0f, c);
	expect_rgb(c, 35, 23, 27);
	hl_plot_colour(0.25f, c);
	expect_rgb(c, 38, 189, 225);
	hl_plot_colour(0.5f, c);
	expect_rgb(c, 150, 250, 80);
	hl_plot_colour(0.75f, c);
	expect_rgb(c, 255, 128, 29);
	hl_plot_colour(1.0f, c);
	expect_rgb(c, 144, 13, 0);
	/* outside 0..1: the ends */
	hl_plot_colour(-3.0f, d);
	expect_rgb(d, 35, 23, 27);
	hl_plot_colour(7.5f, d);
	expect_rgb(d, 144, 13, 0);
	hl_plot_colour(-INFINITY, d);
	expect_rgb(d, 35, 23, 27);
	hl_plot_colour(INFINITY, d);
	expect_rgb(d, 144, 13, 0);
}

/* A w x h RGB8 PNG (memory or file) decoded into a malloc'd buffer. */
static uint8_t *decode(const uint8_t *data, size_t size, const char *path, int *w, int *h)
{
	png_image img;
	uint8_t *rgb;

	memset(&img, 0, sizeof(img));
	img.version = PNG_IMAGE_VERSION;
	if (path)
		assert_true(png_image_begin_read_from_file(&img, path));
	else
		assert_true(png_image_begin_read_from_memory(&img, data, size));
	assert_int_equal(img.format & PNG_FORMAT_FLAG_COLOR, PNG_FORMAT_FLAG_COLOR);
	assert_int_equal(img.format & PNG_FORMAT_FLAG_ALPHA, 0);
	img.format = PNG_FORMAT_RGB;
	rgb = malloc(PNG_IMAGE_SIZE(img));
	assert_non_null(rgb);
	assert_true(png_image_finish_read(&img, NULL, rgb, 0, NULL));
	*w = (int)img.width;
	*h = (int)img.height;
	return rgb;
}

static void png_encode_rows_of_any_stride_read_back_exactly(void **state)
{
	enum { W = 7, H = 5, STRIDE = 3 * W + 5 };
	uint8_t src[H * STRIDE], *data = NULL, *back;
	size_t size = 0;
	int w, h;
	(void)state;

	for (int i = 0; i < H * STRIDE; i++)
		src[i] = (uint8_t)(i * 37 + 11);
	assert_int_equal(hl_png_encode_rgb(src, W, H, STRIDE, &data, &size), 0);
	assert_non_null(data);
	assert_true(size > 8);
	assert_memory_equal(data, "\x89PNG\r\n\x1a\n", 8);
	back = decode(data, size, NULL, &w, &h);
	assert_int_equal(w, W);
	assert_int_equal(h, H);
	for (int y = 0; y < H; y++)
		assert_memory_equal(back + 3 * W * y, src + STRIDE * y, 3 * W);
	free(back);
	free(data);
}

static void png_encode_refuses_empty_images_and_short_strides(void **state)
{
	uint8_t px[12] = { 0 }, *data = (uint8_t *)px;
	size_t size = 12345;
	(void)state;

	assert_int_equal(hl_png_encode_rgb(px, 0, 1, 3, &data, &size), -EINVAL);
	assert_int_equal(hl_png_encode_rgb(px, 1, 0, 3, &data, &size), -EINVAL);
	assert_int_equal(hl_png_encode_rgb(px, -4, 1, 12, &data, &size), -EINVAL);
	assert_int_equal(hl_png_encode_rgb(px, 4, 1, 11, &data, &size), -EINVAL);
	/* untouched on failure */
	assert_ptr_equal(data, px);
	assert_int_equal(size, 12345);
}

static void png_write_file_reads_back_and_reports_errno(void **state)
{
	enum { W = 3, H = 2 };
	static const uint8_t src[W * H * 3] = { 255, 0, 0, 0, 255, 0, 0,   0,	255,
						1,   2, 3, 4, 5,   6, 250, 251, 252 };
	char path[512];
	uint8_t *back;
	int w, h;
	(void)state;

	test_path(path, sizeof(path), "plot.png");
	assert_int_equal(hl_png_write_rgb(path, src, W, H), 0);
	back = decode(NULL, 0, path, &w, &h);
	assert_int_equal(w, W);
	assert_int_equal(h, H);
	assert_memory_equal(back, src, sizeof(src));
	free(back);
	unlink(path);
	assert_int_equal(hl_png_write_rgb("/nonexistent-dir/x.png", src, W, H), -ENOENT);
	/* libpng refuses a 0 x 0 image: -EIO, and the file is closed (no leak under ASan) */
	test_path(path, sizeof(path), "empty.png");
	assert_int_equal(hl_png_write_rgb(path, src, 0, 0), -EIO);
	unlink(path);
}

/*
 * A 61 x 21 grid (H -30..30, V -10..10, 1 degree): scale 10 px per sample, 768 x 280 image,
 * the diagram at (48, 30). Peak 1000 cd at H 5 V 3: the scale spans 1e-2 .. 1e3 cd.
 */
static void plot_lid_png_samples_axes_legend_and_title(void **state)
{
	const struct hl_lid_grid g = { .width = 61,
				       .height = 21,
				       .angles = HL_ANGLES_A,
				       .h_first_deg = -30,
				       .h_last_deg = 30,
				       .v_first_deg = -10,
				       .v_last_deg = 10 };
	float *dense = calloc(61 * 21, sizeof(float));
	char path[512];
	uint8_t *rgb, c[3];
	int w, h;
#define PX(x, y) (rgb + 3 * ((size_t)(y)*w + (x)))
#define SAMPLE(col, row) PX(48 + 10 * (col) + 5, 30 + 10 * (row) + 5)
	(void)state;

	assert_non_null(dense);
	dense[7 * 61 + 35] = 1000.0f; /* H 5, V 3 */
	dense[15 * 61 + 10] = 10.0f; /* H -20, V -5: t = 3/5 */
	dense[2 * 61 + 50] = 0.001f; /* below the scale: black */
	test_path(path, sizeof(path), "lid.png");
	assert_int_equal(hl_plot_lid_png(&g, dense, "t", path), 0);
	rgb = decode(NULL, 0, path, &w, &h);
	assert_int_equal(w, 48 + 610 + 110);
	assert_int_equal(h, 30 + 210 + 40);
	expect_rgb(PX(0, 0), 24, 24, 24); /* background */
	hl_plot_colour(1.0f, c);
	expect_rgb(SAMPLE(35, 7), c[0], c[1], c[2]);
	expect_rgb(SAMPLE(10, 15), 223, 220, 50);
	expect_rgb(SAMPLE(50, 2), 0, 0, 0);
	expect_rgb(SAMPLE(0, 0), 0, 0, 0);
	/* H = 0 axis (column 48 + 300) over black: white at 0.6; H = 10 at 0.25 */
	expect_rgb(PX(348, 30 + 10 * 12 + 5), 153, 153, 153);
	expect_rgb(PX(448, 30 + 10 * 12 + 5), 64, 64, 64);
	/* V = 5 line (row 30 + 50) at 0.25 */
	expect_rgb(PX(48 + 10 * 3 + 5, 80), 64, 64, 64);
	/* the legend bar at x 676..689: the top is t = 1, the bottom t = 0 */
	expect_rgb(PX(676, 30), 144, 13, 0);
	expect_rgb(PX(689, 239), 35, 23, 27);
	/* the title "T  PEAK ..." at (48, 8): T's top row is 5 pixels of text white */
	for (int x = 48; x < 53; x++)
		expect_rgb(PX(x, 8), 230, 230, 230);
	expect_rgb(PX(53, 8), 24, 24, 24);
	free(rgb);
	unlink(path);
	assert_int_equal(hl_plot_lid_png(&g, dense, NULL, "/nonexistent-dir/lid.png"), -ENOENT);
	free(dense);
#undef SAMPLE
#undef PX
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(plot_colour_turbo_at_known_points_and_clamped),
		cmocka_unit_test(png_encode_rows_of_any_stride_read_back_exactly),
		cmocka_unit_test(png_encode_refuses_empty_images_and_short_strides),
		cmocka_unit_test(png_write_file_reads_back_and_reports_errno),
		cmocka_unit_test(plot_lid_png_samples_axes_legend_and_title),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
