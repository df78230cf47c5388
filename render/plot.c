/* SPDX-License-Identifier: MIT */
#include "render/plot.h"

#include <errno.h>
#include <math.h>
#include <png.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/font.h"

#define DECADES 5 /* colour scale span */

static uint8_t to8(float x)
{
	x = x < 0.0f ? 0.0f : (x > 1.0f ? 1.0f : x);
	return (uint8_t)lroundf(x * 255.0f);
}

void hl_plot_colour(float t, uint8_t rgb[3])
{
	/* Polynomial fit of the turbo colour map. */
	t = t < 0.0f ? 0.0f : (t > 1.0f ? 1.0f : t);
	rgb[0] = to8(0.13572138f +
		     t * (4.61539260f +
			  t * (-42.66032258f +
			       t * (132.13108234f + t * (-152.94239396f + t * 59.28637943f)))));
	rgb[1] = to8(0.09140261f +
		     t * (2.19418839f +
			  t * (4.84296658f +
			       t * (-14.18503333f + t * (4.27729857f + t * 2.82956604f)))));
	rgb[2] = to8(0.10667330f +
		     t * (12.64194608f +
			  t * (-60.58204836f +
			       t * (110.36276771f + t * (-89.90310912f + t * 27.34824973f)))));
}

int hl_png_write_rgb(const char *path, const uint8_t *rgb, int w, int h)
{
	FILE *f = fopen(path, "wbe");
	png_structp png;
	png_infop info;

	if (!f)
		return -errno;
	png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
	info = png ? png_create_info_struct(png) : NULL;
	if (!png || !info || setjmp(png_jmpbuf(png))) {
		png_destroy_write_struct(&png, &info);
		fclose(f);
		return -EIO;
	}
	png_init_io(png, f);
	png_set_IHDR(png, info, w, h, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
		     PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
	png_write_info(png, info);
	for (int y = 0; y < h; y++)
		png_write_row(png, (png_const_bytep)(rgb + (size_t)y * w * 3));
	png_write_end(png, NULL);
	png_destroy_write_struct(&png, &info);
	return fclose(f) == 0 ? 0 : -EIO;
}

struct png_mem {
	uint8_t *data;
	size_t size, cap;
	bool failed;
};

static void png_mem_write(png_structp png, png_bytep bytes, png_size_t n)
{
	struct png_mem *m = png_get_io_ptr(png);

	if (m->failed)
		return;
	if (m->size + n > m->cap) {
		size_t cap = m->cap ? m->cap : 4096;
		uint8_t *d;

		while (cap < m->size + n)
			cap *= 2;
		d = realloc(m->data, cap);
		if (!d) {
			m->failed = true;
			return;
		}
		m->data = d;
		m->cap = cap;
	}
	memcpy(m->data + m->size, bytes, n);
	m->size += n;
}

static void png_mem_flush(png_structp png)
{
	(void)png;
}

int hl_png_encode_rgb(const uint8_t *rgb, int w, int h, size_t stride, uint8_t **ret_data,
		      size_t *ret_size)
{
	struct png_mem m = { 0 };
	png_structp png;
	png_infop info;

	if (w < 1 || h < 1 || stride < (size_t)w * 3)
		return -EINVAL;
	png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
	info = png ? png_create_info_struct(png) : NULL;
	if (!png || !info || setjmp(png_jmpbuf(png))) {
		png_destroy_write_struct(&png, &info);
		free(m.data);
		return -EIO;
	}
	png_set_write_fn(png, &m, png_mem_write, png_mem_flush);
	/* Live frames: speed over size (level 1 is ~3x faster than the default here). */
	png_set_compression_level(png, 1);
	png_set_IHDR(png, info, w, h, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
		     PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
	png_write_info(png, info);
	for (int y = 0; y < h; y++)
		png_write_row(png, (png_const_bytep)(rgb + (size_t)y * stride));
	png_write_end(png, NULL);
	png_destroy_write_struct(&png, &info);
	if (m.failed) {
		free(m.data);
		return -ENOMEM;
	}
	*ret_data = m.data;
	*ret_size = m.size;
	return 0;
}

struct canvas {
	uint8_t *rgb;
	int w, h;
};

static void blend(struct canvas *c, int x, int y, const uint8_t col[3], float a)
{
	uint8_t *p;

	if (x < 0 || y < 0 || x >= c->w || y >= c->h)
		return;
	p = c->rgb + 3 * ((size_t)y * c->w + x);
	for (int i = 0; i < 3; i++)
		p[i] = (uint8_t)lroundf(p[i] * (1.0f - a) + col[i] * a);
}

static void text(struct canvas *c, int x, int y, const char *s)
{
	static const uint8_t white[3] = { 230, 230, 230 };

	hl_font_draw(c->rgb, c->w, c->h, x, y, 1, s, white);
}

static void decade_label(double v, char *buf, size_t size)
{
	if (v >= 1e6)
		snprintf(buf, size, "%gM", v / 1e6);
	else if (v >= 1e3)
		snprintf(buf, size, "%gK", v / 1e3);
	else
		snprintf(buf, size, "%g", v);
}

int hl_plot_lid_png(const struct hl_lid_grid *g, const float *dense, const char *title,
		    const char *path)
{
	const int s = g->width < 600 ? (600 + g->width - 1) / g->width : 1;
	const int pw = g->width * s, ph = g->height * s;
	const int left = 48, right = 110, top = 30, bottom = 40;
	const float dh = (g->h_last_deg - g->h_first_deg) / (g->width - 1);
	const float dv = (g->v_last_deg - g->v_first_deg) / (g->height - 1);
	struct canvas c = { NULL, left + pw + right, top + ph + bottom };
	float peak = 0.0f;
	int peak_x = 0, peak_y = 0, rc;
	double hi, lo;
	char buf[256];

	for (int y = 0; y < g->height; y++)
		for (int x = 0; x < g->width; x++)
			if (dense[(size_t)y * g->width + x] > peak) {
				peak = dense[(size_t)y * g->width + x];
				peak_x = x;
				peak_y = y;
			}
	hi = peak > 0.0f ? pow(10.0, ceil(log10(peak))) : 1.0;
	lo = hi / pow(10.0, DECADES);

	c.rgb = calloc((size_t)c.w * c.h, 3);
	if (!c.rgb)
		return -ENOMEM;
	memset(c.rgb, 24, (size_t)c.w * c.h * 3);

	for (int py = 0; py < ph; py++) {
		for (int px = 0; px < pw; px++) {
			const float v = dense[(size_t)(py / s) * g->width + px / s];
			uint8_t *p = c.rgb + 3 * ((size_t)(top + py) * c.w + left + px);

			if (v < lo) {
				memset(p, 0, 3);
				continue;
			}
			hl_plot_colour((float)(log10(v / lo) / DECADES), p);
		}
	}

	/* Grid every 10° H and 5° V, the axes brighter; tick labels outside. */
	for (int a = (int)ceilf(g->h_first_deg / 10) * 10; a <= g->h_last_deg; a += 10) {
		const int px = left + (int)lroundf((a - g->h_first_deg) / dh * s);
		static const uint8_t grey[3] = { 255, 255, 255 };

		for (int py = top; py < top + ph; py++)
			blend(&c, px, py, grey, a == 0 ? 0.6f : 0.25f);
		if (a % 20 == 0 || pw / ((g->h_last_deg - g->h_first_deg) / 10) > 60) {
			snprintf(buf, sizeof(buf), "%d", a);
			text(&c, px - hl_font_width(buf, 1) / 2, top + ph + 5, buf);
		}
	}
	for (int a = (int)ceilf(g->v_first_deg / 5) * 5; a <= g->v_last_deg; a += 5) {
		const int py = top + (int)lroundf((g->v_last_deg - a) / dv * s);
		static const uint8_t grey[3] = { 255, 255, 255 };

		for (int px = left; px < left + pw; px++)
			blend(&c, px, py, grey, a == 0 ? 0.6f : 0.25f);
		snprintf(buf, sizeof(buf), "%d", a);
		text(&c, left - 6 - hl_font_width(buf, 1), py - 3, buf);
	}
	text(&c, left + pw / 2 - hl_font_width("H [DEG]", 1) / 2, top + ph + 20, "H [DEG]");
	text(&c, 4, top - 12, "V [DEG]");

	/* Title and the peak. */
	snprintf(buf, sizeof(buf), "%s  PEAK %.0f CD AT H %.1f V %.1f", title ? title : "", peak,
		 hl_lid_grid_h_deg(g, peak_x), hl_lid_grid_v_deg(g, peak_y));
	text(&c, left, 8, buf);

	/* Legend: a vertical colour bar with decade labels. */
	{
		const int bx = left + pw + 18, bw = 14;

		for (int py = 0; py < ph; py++) {
			uint8_t col[3];

			hl_plot_colour(1.0f - (float)py / (ph - 1), col);
			for (int px = bx; px < bx + bw; px++)
				memcpy(c.rgb + 3 * ((size_t)(top + py) * c.w + px), col, 3);
		}
		for (int d = 0; d <= DECADES; d++) {
			const int py =
				top + (int)lroundf((float)(DECADES - d) / DECADES * (ph - 1));
			static const uint8_t white[3] = { 230, 230, 230 };

			for (int px = bx + bw; px < bx + bw + 4; px++)
				blend(&c, px, py, white, 1.0f);
			decade_label(lo * pow(10.0, d), buf, sizeof(buf));
			text(&c, bx + bw + 7, py - 3, buf);
		}
		text(&c, bx, top + ph + 5, "CD (LOG)");
	}

	rc = hl_png_write_rgb(path, c.rgb, c.w, c.h);
	free(c.rgb);
	return rc;
}
