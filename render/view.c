/* SPDX-License-Identifier: MIT */
#include "render/view.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "render/font.h"
#include "render/pixel.h"
#include "render/plot.h"

#define LUT_SIZE 16384 /* display tone-map table: < 0.25 sRGB levels per step, fits L1 */

static const char *const names[] = { "display", "hdr", "lux", "lid" };

int hl_view_from_name(const char *name)
{
	for (size_t i = 0; i < sizeof(names) / sizeof(names[0]); i++)
		if (strcmp(name, names[i]) == 0)
			return (int)i;
	return -EINVAL;
}

const char *hl_view_name(enum hl_view_kind kind)
{
	return names[kind];
}

void hl_view_lux_defaults(struct hl_view_lux_opts *o)
{
	static const double iso[] = { 1, 3, 5, 10, 20, 50 };

	*o = (struct hl_view_lux_opts){ .min_lx = 0.1, .max_lx = 1000.0, .legend = true };
	o->n_iso = (int)(sizeof(iso) / sizeof(iso[0]));
	memcpy(o->iso_lx, iso, sizeof(iso));
}

void hl_view_luminance(const struct hl_gbuffer *gb, const float *lux, float *ret)
{
	const size_t n = (size_t)gb->width * gb->height;

	for (size_t i = 0; i < n; i++)
		ret[i] = gb->albedo[i] * lux[i] * (float)M_1_PI;
}

void hl_view_hdr(const struct hl_gbuffer *gb, const float *lux, float *ret)
{
	const size_t n = (size_t)gb->width * gb->height;

	for (size_t i = 0; i < n; i++) {
		const float l = gb->albedo[i] * lux[i] * (float)M_1_PI;

		ret[4 * i + 0] = l;
		ret[4 * i + 1] = l;
		ret[4 * i + 2] = l;
		ret[4 * i + 3] = gb->nrm[4 * i + 3] != (float)HL_SURF_NONE ? 1.0f : 0.0f;
	}
}

void hl_view_display(const struct hl_gbuffer *gb, const float *lux, double exposure_ev,
		     uint8_t *ret)
{
	hl_view_display_range(gb, lux, exposure_ev, 0, (size_t)gb->width * gb->height, ret);
}

void hl_view_display_range(const struct hl_gbuffer *gb, const float *lux, double exposure_ev,
			   size_t first, size_t count, uint8_t *ret)
{
	const size_t n = first + count;
	const float scale = (float)(exp2(exposure_ev) * M_1_PI);
	/* Per thread, built on first use: the views stay callable from any thread. */
	static _Thread_local uint8_t lut[LUT_SIZE];
	static _Thread_local bool lut_ready;

	/*
	 * x / (1 + x) lies in [0, 1): a table keeps powf out of the pixel loop. It is fine enough
	 * that the dark end, where sRGB is steepest (12.92), moves less than a level per step.
	 */
	for (int i = 0; !lut_ready && i < LUT_SIZE; i++)
		lut[i] = hl_pixel_srgb8((i + 0.5f) / LUT_SIZE);
	lut_ready = true;
	for (size_t i = first; i < n; i++) {
		const float x = gb->albedo[i] * lux[i] * scale;
		const float t = x / (1.0f + x);
		const int j = (int)(t * LUT_SIZE);

		memset(ret + 3 * i, x > 0.0f ? lut[j < LUT_SIZE ? j : LUT_SIZE - 1] : 0, 3);
	}
}

static float scale_pos(const struct hl_view_lux_opts *o, double e)
{
	return (float)(log10(e / o->min_lx) / log10(o->max_lx / o->min_lx));
}

static void put(uint8_t *rgb, int w, int h, int x, int y, const uint8_t c[3])
{
	if (x >= 0 && y >= 0 && x < w && y < h)
		memcpy(rgb + 3 * ((size_t)y * w + x), c, 3);
}

/* Where the legend goes: false when the image is too small for one. */
static bool legend_geometry(int w, int h, int *bar_w, int *bar_h, int *x0, int *y0)
{
	*bar_h = h * 3 / 5;
	*bar_w = w / 80 > 6 ? w / 80 : 6;
	*x0 = w - *bar_w - hl_font_width("1000", 1) - 10;
	*y0 = (h - *bar_h) / 2;
	return *bar_h >= 20 && *x0 >= 0;
}

void hl_view_lux_legend_box(int w, int h, int ret_box[4])
{
	int bar_w, bar_h, x0, y0;

	memset(ret_box, 0, sizeof(int) * 4);
	if (!legend_geometry(w, h, &bar_w, &bar_h, &x0, &y0))
		return;
	/* the black backing, and the unit below it */
	ret_box[0] = x0 - 2;
	ret_box[1] = y0 - 2;
	ret_box[2] = w;
	ret_box[3] = y0 + bar_h + 4 + HL_FONT_H;
}

static void legend(const struct hl_view_lux_opts *o, int w, int h, uint8_t *rgb)
{
	static const uint8_t white[3] = { 240, 240, 240 }, black[3] = { 0, 0, 0 };
	const int label_w = hl_font_width("1000", 1);
	int bar_w, bar_h, x0, y0;
	char buf[32];

	if (!legend_geometry(w, h, &bar_w, &bar_h, &x0, &y0))
		return;
	for (int y = -2; y < bar_h + 2; y++)
		for (int x = -2; x < bar_w + label_w + 8; x++)
			put(rgb, w, h, x0 + x, y0 + y, black);
	for (int y = 0; y < bar_h; y++) {
		uint8_t c[3];

		hl_plot_colour(1.0f - (float)y / (bar_h - 1), c);
		for (int x = 0; x < bar_w; x++)
			put(rgb, w, h, x0 + x, y0 + y, c);
	}
	/* Labels at each decade; ticks at the iso levels. */
	for (double e = o->min_lx; e <= o->max_lx * 1.0001; e *= 10.0) {
		const int y = y0 + (int)lroundf((1.0f - scale_pos(o, e)) * (bar_h - 1));

		snprintf(buf, sizeof(buf), "%g", e);
		hl_font_draw(rgb, w, h, x0 + bar_w + 3, y - 3, 1, buf, white);
	}
	for (int i = 0; i < o->n_iso; i++) {
		const float t = scale_pos(o, o->iso_lx[i]);
		const int y = y0 + (int)lroundf((1.0f - t) * (bar_h - 1));

		if (t < 0.0f || t > 1.0f)
			continue;
		for (int x = -2; x < bar_w + 2; x++)
			put(rgb, w, h, x0 + x, y, white);
	}
	hl_font_draw(rgb, w, h, x0, y0 + bar_h + 4, 1, "LX", white);
}

void hl_view_lux(const struct hl_gbuffer *gb, const float *lux, const struct hl_view_lux_opts *o,
		 uint8_t *ret)
{
	static const uint8_t sky[3] = { 16, 16, 28 }, white[3] = { 255, 255, 255 };
	const int w = gb->width, h = gb->height;

	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			const size_t i = (size_t)y * w + x;
			uint8_t *p = ret + 3 * i;

			if (gb->nrm[4 * i + 3] == (float)HL_SURF_NONE)
				memcpy(p, sky, 3);
			else if (lux[i] < o->min_lx)
				memset(p, 0, 3);
			else
				hl_plot_colour(scale_pos(o, lux[i]), p);
		}
	/* Iso-lux lines: a pixel at or above the level next to one below it. */
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			const size_t i = (size_t)y * w + x;

			for (int k = 0; k < o->n_iso; k++) {
				const float l = (float)o->iso_lx[k];

				if (lux[i] >= l &&
				    ((x + 1 < w && lux[i + 1] < l) ||
				     (y + 1 < h && lux[i + w] < l) || (x > 0 && lux[i - 1] < l) ||
				     (y > 0 && lux[i - w] < l))) {
					memcpy(ret + 3 * i, white, 3);
					break;
				}
			}
		}
	if (o->legend)
		legend(o, w, h, ret);
}
