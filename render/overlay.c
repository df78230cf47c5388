/* SPDX-License-Identifier: MIT */
#include "render/overlay.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "render/font.h"
#include "render/scene_layout.h"

#define MAX_LABELS 64 /* distance labels (15 on the road) and iso labels (16) with room */
#define PAD 2 /* pixels of black box around a label, at scale 1 */

struct box {
	int x0, y0, x1, y1; /* half-open */
};

/* The labels drawn so far, which later ones must not cover. */
struct placed {
	struct box boxes[MAX_LABELS];
	int n;
};

static const uint8_t iso_colours[][3] = {
	{ 0, 220, 255 }, /* cyan */
	{ 90, 255, 90 }, /* green */
	{ 255, 230, 0 }, /* yellow */
	{ 255, 140, 0 }, /* orange */
	{ 255, 60, 60 }, /* red */
	{ 255, 80, 255 }, /* magenta */
};

#define N_COLOURS (int)(sizeof(iso_colours) / sizeof(iso_colours[0]))

void hl_overlay_defaults(struct hl_overlay_opts *ret)
{
	*ret = (struct hl_overlay_opts){
		.n_iso = 4,
		.iso_lx = { 1.0, 3.0, 10.0, 30.0 },
		.iso_lines = true,
		.distance_step_m = GRID_STEP_M,
		.distance_last_m = HL_ROAD_LENGTH_M,
		.label_y_m = 12.0,
	};
}

void hl_overlay_iso_colour(int k, uint8_t ret_rgb[3])
{
	memcpy(ret_rgb, iso_colours[k % N_COLOURS], 3);
}

static bool overlaps(const struct box *a, const struct box *b)
{
	return a->x0 < b->x1 && b->x0 < a->x1 && a->y0 < b->y1 && b->y0 < a->y1;
}

static bool free_at(const struct placed *pl, const struct box *b)
{
	for (int i = 0; i < pl->n; i++)
		if (overlaps(&pl->boxes[i], b))
			return false;
	return true;
}

/* The box of text with its top-left corner at (x, y), padding included. */
static struct box text_box(const char *text, int scale, int x, int y)
{
	return (struct box){ x - PAD * scale, y - PAD * scale,
			     x + hl_font_width(text, scale) + PAD * scale,
			     y + HL_FONT_H * scale + PAD * scale };
}

static bool inside(const struct box *b, int w, int h)
{
	return b->x0 >= 0 && b->y0 >= 0 && b->x1 <= w && b->y1 <= h;
}

/* Black box, then the text; records the box. */
static void label(uint8_t *rgb, int w, int h, struct placed *pl, const struct box *b, int scale,
		  const char *text, const uint8_t colour[3])
{
	for (int y = b->y0 < 0 ? 0 : b->y0; y < b->y1 && y < h; y++)
		for (int x = b->x0 < 0 ? 0 : b->x0; x < b->x1 && x < w; x++)
			memset(rgb + 3 * ((size_t)y * w + x), 0, 3);
	hl_font_draw(rgb, w, h, b->x0 + PAD * scale, b->y0 + PAD * scale, scale, text, colour);
	if (pl->n < MAX_LABELS)
		pl->boxes[pl->n++] = *b;
}

static void distances(const struct hl_camera *cam, const struct hl_overlay_opts *o, int scale,
		      uint8_t *rgb, struct placed *pl)
{
	static const uint8_t white[3] = { 255, 255, 255 };
	const int w = cam->width, h = cam->height;

	for (int i = 1;
	     o->distance_step_m > 0.0 && i * o->distance_step_m <= o->distance_last_m + 1e-9; i++) {
		const double p[3] = { i * o->distance_step_m, o->label_y_m, 0.0 };
		char text[32];
		double px, py;
		struct box b;

		if (hl_camera_project(cam, p, &px, &py) < 0)
			continue;
		snprintf(text, sizeof(text), "%g M", p[0]);
		b = text_box(text, scale, (int)lround(px) - hl_font_width(text, scale) / 2,
			     (int)lround(py) - HL_FONT_H * scale / 2);
		if (inside(&b, w, h) && free_at(pl, &b))
			label(rgb, w, h, pl, &b, scale, text, white);
	}
}

/* Whether G-buffer entry i is the ground (z = 0, normal up): posts and sky are not. */
static bool ground(const struct hl_gbuffer *gb, size_t i)
{
	return gb->nrm[4 * i + 3] != (float)HL_SURF_NONE && gb->nrm[4 * i + 2] > 0.999f &&
	       fabsf(gb->pos[4 * i + 2]) < 1e-3f;
}

/* Whether ground pixel i is below level (anything else is neither below nor above). */
static bool below(const struct hl_gbuffer *gb, const float *lux, size_t i, float level)
{
	return lux[i] < level && ground(gb, i);
}

/* Whether pixel (x, y) is ground at or above level with a 4-neighbour on the ground below it. */
static bool on_line(const struct hl_gbuffer *gb, const float *lux, int x, int y, float level)
{
	const int w = gb->width, h = gb->height;
	const size_t i = (size_t)y * w + x;

	return lux[i] >= level && ground(gb, i) &&
	       ((x + 1 < w && below(gb, lux, i + 1, level)) ||
		(y + 1 < h && below(gb, lux, i + w, level)) ||
		(x > 0 && below(gb, lux, i - 1, level)) || (y > 0 && below(gb, lux, i - w, level)));
}

static void put(uint8_t *rgb, int w, int h, int x, int y, const uint8_t c[3])
{
	if (x >= 0 && y >= 0 && x < w && y < h)
		memcpy(rgb + 3 * ((size_t)y * w + x), c, 3);
}

/* The line of level k; returns false when the image has none, else its rightmost point. */
static bool iso_line(const struct hl_gbuffer *gb, const float *lux, float level, bool draw,
		     bool thick, const uint8_t c[3], uint8_t *rgb, int *ret_x, int *ret_y)
{
	const int w = gb->width, h = gb->height;
	int tip_x = -1, tip_y0 = 0, tip_y1 = 0;

	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			const size_t i = (size_t)y * w + x;

			if (!on_line(gb, lux, x, y, level))
				continue;
			if (draw) {
				put(rgb, w, h, x, y, c);
				/* the outer side too: the neighbours below the level */
				if (thick) {
					if (x + 1 < w && below(gb, lux, i + 1, level))
						put(rgb, w, h, x + 1, y, c);
					if (y + 1 < h && below(gb, lux, i + w, level))
						put(rgb, w, h, x, y + 1, c);
					if (x > 0 && below(gb, lux, i - 1, level))
						put(rgb, w, h, x - 1, y, c);
					if (y > 0 && below(gb, lux, i - w, level))
						put(rgb, w, h, x, y - 1, c);
				}
			}
			if (x > tip_x) {
				tip_x = x;
				tip_y0 = tip_y1 = y;
			} else if (x == tip_x) {
				tip_y1 = y;
			}
		}
	*ret_x = tip_x;
	*ret_y = (tip_y0 + tip_y1) / 2;
	return tip_x >= 0;
}

/*
 * The label of an iso line beside its tip (x, y): to the right, else to the left, shifted down
 * and up by one and two label heights until it covers no other label; left out if it still does.
 */
static void iso_label(uint8_t *rgb, int w, int h, struct placed *pl, int scale, int x, int y,
		      double level, const uint8_t c[3])
{
	const int gap = 3 * scale, th = HL_FONT_H * scale, step = th + 2 * PAD * scale + 1;
	char text[32];

	snprintf(text, sizeof(text), "%g LX", level);
	for (int t = 0; t < 5; t++) {
		const int dy = (t % 2 ? 1 : -1) * ((t + 1) / 2) * step;
		struct box b = text_box(text, scale, x + gap + PAD * scale, y - th / 2 + dy);

		if (!inside(&b, w, h)) {
			const int tw = hl_font_width(text, scale);

			b = text_box(text, scale, x - gap - PAD * scale - tw, y - th / 2 + dy);
		}
		if (inside(&b, w, h) && free_at(pl, &b)) {
			label(rgb, w, h, pl, &b, scale, text, c);
			return;
		}
	}
}

void hl_overlay_draw(const struct hl_camera *cam, const struct hl_gbuffer *gb, const float *lux,
		     const struct hl_overlay_opts *o, uint8_t *rgb)
{
	static const uint8_t white[3] = { 255, 255, 255 };
	const int w = cam->width, h = cam->height;
	const int scale = o->scale > 0 ? o->scale : w >= 960 ? 2 : 1;
	struct placed pl = { .n = 0 };
	const struct box clear = { o->keep_clear[0], o->keep_clear[1], o->keep_clear[2],
				   o->keep_clear[3] };
	int tip_x[HL_OVERLAY_MAX_ISO], tip_y[HL_OVERLAY_MAX_ISO];
	bool has[HL_OVERLAY_MAX_ISO];
	const int n_iso = o->n_iso < HL_OVERLAY_MAX_ISO ? o->n_iso : HL_OVERLAY_MAX_ISO;

	/* Lines first, then every label on top of them. */
	for (int k = 0; k < n_iso; k++) {
		uint8_t c[3];

		hl_overlay_iso_colour(k, c);
		has[k] = iso_line(gb, lux, (float)o->iso_lx[k], o->iso_lines, scale >= 2,
				  o->iso_white ? white : c, rgb, &tip_x[k], &tip_y[k]);
	}
	if (clear.x0 < clear.x1 && clear.y0 < clear.y1)
		pl.boxes[pl.n++] = clear;
	distances(cam, o, scale, rgb, &pl);
	for (int k = 0; k < n_iso; k++) {
		uint8_t c[3];

		hl_overlay_iso_colour(k, c);
		if (has[k])
			iso_label(rgb, w, h, &pl, scale, tip_x[k], tip_y[k], o->iso_lx[k],
				  o->iso_white ? white : c);
	}
}
