/* SPDX-License-Identifier: MIT */
#include "lamp/model.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/*
 * A source is a window in (H, V) with smoothstep edges (soft_deg wide, centred on the edge, so
 * neighbours overlap by that much), times an optional Gaussian that shapes the peak.
 */
/* Scales every source so the low-beam preset peaks near 25 kcd (docs/design.md §1). */
#define MODEL_SCALE 1.75f

struct source_spec {
	const char *name;
	float h0, h1, v0, v1; /* window edges, degrees */
	float soft_h, soft_top, soft_bottom; /* edge widths, degrees */
	float peak_cd;
	float hc, vc, sh, sv; /* Gaussian centre and widths, degrees; sh/sv 0 = flat */
	bool mirror; /* outboard/inboard geometry: mirrored about H = 0 for the right lamp */
};

static float smooth(float t)
{
	if (t <= 0.0f)
		return 0.0f;
	if (t >= 1.0f)
		return 1.0f;
	return t * t * (3.0f - 2.0f * t);
}

/* 1 inside [a, b], soft edges of width sa (at a) and sb (at b), 0 beyond. */
static float window(float x, float a, float b, float sa, float sb)
{
	return smooth((x - (a - sa / 2)) / sa) * smooth(((b + sb / 2) - x) / sb);
}

static float spec_at(const struct source_spec *s, float h, float v)
{
	float f = window(h, s->h0, s->h1, s->soft_h, s->soft_h) *
		  window(v, s->v0, s->v1, s->soft_bottom, s->soft_top);

	if (f == 0.0f)
		return 0.0f;
	if (s->sh > 0.0f)
		f *= expf(-(h - s->hc) * (h - s->hc) / (s->sh * s->sh));
	if (s->sv > 0.0f)
		f *= expf(-(v - s->vc) * (v - s->vc) / (s->sv * s->sv));
	return MODEL_SCALE * s->peak_cd * f;
}

static void mirror_spec(struct source_spec *s)
{
	float h0 = s->h0;

	s->h0 = -s->h1;
	s->h1 = -h0;
	s->hc = -s->hc;
}

void hl_model_default_grid(struct hl_lid_grid *g)
{
	*g = (struct hl_lid_grid){
		.width = 900,
		.height = 250,
		.angles = HL_ANGLES_A,
		.h_first_deg = -89.9f,
		.h_last_deg = 89.9f,
		.v_first_deg = -29.9f,
		.v_last_deg = 19.9f,
	};
}

static int set_from_spec(struct hl_lid *lid, int k, const struct source_spec *s, float *dense)
{
	const struct hl_lid_grid *g = hl_lid_grid(lid);
	int rc;

	for (int y = 0; y < g->height; y++) {
		const float v = hl_lid_grid_v_deg(g, y);

		for (int x = 0; x < g->width; x++)
			dense[(size_t)y * g->width + x] = spec_at(s, hl_lid_grid_h_deg(g, x), v);
	}
	rc = hl_lid_set_source(lid, k, dense);
	if (rc == 0)
		rc = hl_lid_set_name(lid, k, s->name);
	return rc;
}

/* Matrix rows: row 1 (LEDs 1-28) near field, row 2 low-beam range, row 3 high beam. */
struct row_spec {
	float h_min, h_max; /* span of the 28 windows */
	float v0, v1, soft_top, soft_bottom;
	float peak_cd, vc, sv;
};

static const struct row_spec rows[3] = {
	{ -30.0f, 30.0f, -6.0f, -0.8f, 0.4f, 2.0f, 4200.0f, -1.8f, 2.6f },
	{ -20.0f, 20.0f, -2.2f, 1.0f, 0.3f, 0.8f, 7000.0f, -0.6f, 1.8f },
	{ -20.0f, 20.0f, -0.8f, 4.5f, 0.6f, 0.8f, 11000.0f, 1.0f, 1.8f },
};

static void matrix_spec(int led, struct source_spec *s, char *name)
{
	const int r = (led - 1) / HL_HD84_ROW_LEDS, j = (led - 1) % HL_HD84_ROW_LEDS;
	const struct row_spec *row = &rows[r];
	const float w = (row->h_max - row->h_min) / HL_HD84_ROW_LEDS;
	const float hc = row->h_min + (j + 0.5f) * w;

	/* Brighter in the centre of the field, as real matrix optics are. */
	const float centre = 0.35f + 0.65f * expf(-hc * hc / (9.0f * 9.0f));

	sprintf(name, "row%d_led%02d", r + 1, j + 1);
	*s = (struct source_spec){
		.name = name,
		.h0 = hc - w / 2,
		.h1 = hc + w / 2,
		.v0 = row->v0,
		.v1 = row->v1,
		.soft_h = 0.45f * w,
		.soft_top = row->soft_top,
		.soft_bottom = row->soft_bottom,
		.peak_cd = row->peak_cd * centre,
		.vc = row->vc,
		.sv = row->sv,
	};
}

/* Sources 85..95 of the left lamp. */
static const struct source_spec extras[11] = {
	{ "apron", -45, 40, -15, -3, 6, 3, 4, 900, -5, -8, 30, 0, true },
	{ "bend_left", -40, -12, -5, -0.8f, 4, 0.4f, 2, 5000, -26, -2, 12, 2.5f, true },
	{ "bend_right", 12, 40, -5, -0.8f, 4, 0.4f, 2, 3000, 26, -2, 12, 2.5f, true },
	{ "hb_spot", -4, 4, -0.6f, 2.4f, 1.5f, 1, 0.6f, 26000, 0, 0.8f, 2.0f, 0.9f, false },
	{ "hb_wide", -25, 25, -1, 5, 4, 1.5f, 0.8f, 5000, 0, 1.2f, 14, 2.5f, false },
	{ "lb_base", -35, 35, -8, -1.0f, 5, 0.3f, 3, 3500, 0, -2.2f, 20, 3, false },
	{ "lb_rise", 0, 8, -1.0f, 0.6f, 0.6f, 0.3f, 0.6f, 6000, 3, -0.3f, 4, 1.2f, false },
	{ "town", -50, 50, -10, -0.8f, 8, 0.4f, 4, 600, 0, -3, 35, 5, false },
	{ "corner", -70, -35, -10, -1, 6, 0.5f, 4, 1600, -52, -4, 14, 4, true },
	{ "motorway", -6, 6, -1.2f, -0.6f, 1.5f, 0.2f, 0.4f, 6000, 0, -0.9f, 4, 0.6f, false },
	{ "sign", -15, 15, 1, 4, 3, 1, 1, 300, 0, 2.5f, 0, 0, false },
};

int hl_model_hd84(enum hl_side side, struct hl_lid **ret)
{
	struct hl_lid_grid grid;
	struct hl_lid *lid;
	float *dense;
	int rc;

	hl_model_default_grid(&grid);
	rc = hl_lid_new(HL_HD84_SOURCES, &grid, false, &lid);
	if (rc < 0)
		return rc;
	dense = malloc(sizeof(float) * grid.width * grid.height);
	if (!dense) {
		rc = -ENOMEM;
		goto err_free;
	}
	/* The matrix field is symmetric, numbered by increasing H in both lamps. */
	for (int led = 1; led <= HL_HD84_MATRIX && rc == 0; led++) {
		struct source_spec s;
		char name[32];

		matrix_spec(led, &s, name);
		rc = set_from_spec(lid, led - 1, &s, dense);
	}
	for (int e = 0; e < 11 && rc == 0; e++) {
		struct source_spec s = extras[e];

		/*
		 * The right lamp is the left one mirrored where the geometry is outboard/inboard
		 * (apron, bend, corner); its bend_left is then the former bend_right, so each name
		 * keeps its direction. Traffic-side asymmetry (lb_rise) is never mirrored.
		 */
		if (side == HL_SIDE_RIGHT && s.mirror) {
			int from = e;

			if (e == HL_HD84_BEND_LEFT - 85)
				from = HL_HD84_BEND_RIGHT - 85;
			else if (e == HL_HD84_BEND_RIGHT - 85)
				from = HL_HD84_BEND_LEFT - 85;
			s = extras[from];
			mirror_spec(&s);
			s.name = extras[e].name;
		}
		rc = set_from_spec(lid, HL_HD84_MATRIX + e, &s, dense);
	}
	free(dense);
	if (rc < 0)
		goto err_free;
	*ret = lid;
	return 0;

err_free:
	hl_lid_free(lid);
	return rc;
}

int hl_model_pixel_layout(int n, struct hl_pixel_layout *ret)
{
	struct hl_pixel_layout l = {
		.n = n,
		.h_min_deg = -20.0f,
		.h_max_deg = 20.0f,
		.v_min_deg = -2.0f,
		.v_max_deg = 4.0f,
	};

	if (n < 1 || n > HL_LID_MAX_SOURCES)
		return -EINVAL;
	/* cells about square in degrees */
	l.rows = (int)lroundf(sqrtf(n * (l.v_max_deg - l.v_min_deg) / (l.h_max_deg - l.h_min_deg)));
	if (l.rows < 1)
		l.rows = 1;
	l.cols = (n + l.rows - 1) / l.rows;
	*ret = l;
	return 0;
}

void hl_model_pixel_cell(const struct hl_pixel_layout *l, int k, float *ret_h0, float *ret_h1,
			 float *ret_v0, float *ret_v1)
{
	const float w = (l->h_max_deg - l->h_min_deg) / l->cols;
	const float h = (l->v_max_deg - l->v_min_deg) / l->rows;
	const int r = k / l->cols, c = k % l->cols;

	*ret_h0 = l->h_min_deg + c * w;
	*ret_h1 = *ret_h0 + w;
	*ret_v1 = l->v_max_deg - r * h;
	*ret_v0 = *ret_v1 - h;
}

int hl_model_pixel(int n, struct hl_lid **ret)
{
	struct hl_pixel_layout lay;
	struct hl_lid_grid grid;
	struct hl_lid *lid;
	int rc;
	float *dense;

	if (hl_model_pixel_layout(n, &lay) < 0)
		return -EINVAL;
	hl_model_default_grid(&grid);
	rc = hl_lid_new(n, &grid, false, &lid);
	if (rc < 0)
		return rc;
	dense = malloc(sizeof(float) * grid.width * grid.height);
	if (!dense) {
		hl_lid_free(lid);
		return -ENOMEM;
	}
	for (int k = 0; k < n && rc == 0; k++) {
		const float w = (lay.h_max_deg - lay.h_min_deg) / lay.cols;
		const float h = (lay.v_max_deg - lay.v_min_deg) / lay.rows;
		const int r = k / lay.cols, c = k % lay.cols;
		const float hc = lay.h_min_deg + (c + 0.5f) * w;
		const float vc = lay.v_max_deg - (r + 0.5f) * h;
		char name[32];
		struct source_spec s = {
			.name = name,
			.h0 = hc - w / 2,
			.h1 = hc + w / 2,
			.v0 = vc - h / 2,
			.v1 = vc + h / 2,
			/* at least two samples of soft edge so every pixel hits the grid */
			.soft_h = fmaxf(0.5f * w, 0.4f),
			.soft_top = fmaxf(0.5f * h, 0.4f),
			.soft_bottom = fmaxf(0.5f * h, 0.4f),
			.peak_cd = 20000.0f * (0.3f + 0.7f * expf(-hc * hc / 100.0f)),
		};

		sprintf(name, "pixel_r%03d_c%03d", r + 1, c + 1);
		rc = set_from_spec(lid, k, &s, dense);
	}
	free(dense);
	if (rc < 0) {
		hl_lid_free(lid);
		return rc;
	}
	*ret = lid;
	return 0;
}

const char *const hl_model_preset_names[] = { "low",	   "high",	 "glarefree",
					      "bend_left", "bend_right", NULL };

/* Row 1: all on, edges dimmed (LED 1 at 3 %). */
static const uint8_t row1[HL_HD84_ROW_LEDS] = { 2,  10, 25, 45, 63, 63, 63, 63, 63, 63,
						63, 63, 63, 63, 63, 63, 63, 63, 63, 63,
						63, 63, 63, 63, 45, 25, 10, 2 };
/* Row 2 low beam: the right half (H > 0, LEDs 43..56) on, LED 45 at 24 %, edges graded. */
static const uint8_t row2_low[HL_HD84_ROW_LEDS] = { 0,	0,  0,	0,  0,	0,  0,	0,  0,	0,
						    0,	0,  0,	0,  63, 63, 15, 63, 63, 60,
						    55, 50, 45, 40, 32, 24, 16, 8 };
/* Row 3 high beam: all on, edges graded. */
static const uint8_t row3_high[HL_HD84_ROW_LEDS] = { 20, 30, 40, 50, 58, 63, 63, 63, 63, 63,
						     63, 63, 63, 63, 63, 63, 63, 63, 63, 63,
						     63, 63, 63, 58, 50, 40, 30, 20 };

static void fill_low(uint8_t *d)
{
	memset(d, 0, HL_HD84_SOURCES);
	memcpy(d, row1, HL_HD84_ROW_LEDS);
	memcpy(d + HL_HD84_ROW_LEDS, row2_low, HL_HD84_ROW_LEDS);
	d[HL_HD84_APRON - 1] = 40;
	d[HL_HD84_LB_BASE - 1] = 63;
	d[HL_HD84_LB_RISE - 1] = 63;
	d[HL_HD84_TOWN - 1] = 20;
	d[HL_HD84_SIGN - 1] = 30;
}

static void fill_high(uint8_t *d)
{
	fill_low(d);
	memset(d + HL_HD84_ROW_LEDS, 63, HL_HD84_ROW_LEDS);
	d[45 - 1] = 50; /* LED 45 at 80 % */
	memcpy(d + 2 * HL_HD84_ROW_LEDS, row3_high, HL_HD84_ROW_LEDS);
	d[HL_HD84_HB_SPOT - 1] = 63;
	d[HL_HD84_HB_WIDE - 1] = 63;
	d[HL_HD84_MOTORWAY - 1] = 63;
}

/* Does source k put any light into the oncoming vehicle's window? */
static bool lights_window(const struct hl_lid *lid, int k, float h_min, float h_max)
{
	const struct hl_lid_grid *g = hl_lid_grid(lid);
	struct hl_lid_box b;
	const float *s = hl_lid_source(lid, k, &b);

	for (int y = b.y0; s && y < b.y1; y++) {
		const float v = hl_lid_grid_v_deg(g, y);

		if (v < HL_GLAREFREE_V_MIN || v > HL_GLAREFREE_V_MAX)
			continue;
		for (int x = b.x0; x < b.x1; x++) {
			const float h = hl_lid_grid_h_deg(g, x);

			if (h >= h_min && h <= h_max &&
			    s[(size_t)(y - b.y0) * (b.x1 - b.x0) + (x - b.x0)] > 0.0f)
				return true;
		}
	}
	return false;
}

static void glarefree_side(const struct hl_lid *lid, float h_min, float h_max, uint8_t *d)
{
	fill_high(d);
	for (int k = 0; k < HL_HD84_SOURCES; k++)
		if (lights_window(lid, k, h_min, h_max))
			d[k] = 0;
}

void hl_model_hd84_glarefree(struct hl_lid *const lamps[2], float h_min_deg, float h_max_deg,
			     struct hl_preset *p)
{
	for (int side = 0; side < 2; side++)
		glarefree_side(lamps[side], h_min_deg, h_max_deg, p->dim[side]);
}

int hl_model_hd84_preset(const char *name, struct hl_lid *const lamps[2], struct hl_preset *p)
{
	if (p->n_sources != HL_HD84_SOURCES)
		return -EINVAL;
	for (int side = 0; side < 2; side++) {
		uint8_t *d = p->dim[side];

		if (strcmp(name, "low") == 0) {
			fill_low(d);
		} else if (strcmp(name, "high") == 0) {
			fill_high(d);
		} else if (strcmp(name, "glarefree") == 0) {
			glarefree_side(lamps[side], HL_GLAREFREE_H_MIN, HL_GLAREFREE_H_MAX, d);
		} else if (strcmp(name, "bend_left") == 0 || strcmp(name, "bend_right") == 0) {
			const bool left = strcmp(name, "bend_left") == 0;

			fill_low(d);
			d[(left ? HL_HD84_BEND_LEFT : HL_HD84_BEND_RIGHT) - 1] = 63;
			/* the corner light of the lamp on the inside of the bend */
			if (left == (side == HL_SIDE_LEFT))
				d[HL_HD84_CORNER - 1] = 63;
		} else {
			return -EINVAL;
		}
	}
	return 0;
}
