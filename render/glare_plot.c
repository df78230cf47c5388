/* SPDX-License-Identifier: MIT */
/* The glare timeline: half the pair's intensity with its limit, and lux at the eye, over time. */
#include "render/glare_plot.h"

#include <assert.h>
#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/font.h"
#include "render/plot.h"

#define LEFT 64 /* pixels left of the panels: the value labels */
#define PLOT_W 740
#define TOP 40
#define CD_H 250 /* the intensity panel */
#define GAP 34 /* between the panels: the lower panel's title */
#define LX_H 200 /* the illuminance panel */
#define TRACK_PITCH 14 /* one status track per road user */
#define TRACK_H 8
#define MAX_DECADES 6 /* shown below the decade above the largest value */

static const uint8_t fail_rgb[3] = HL_GLARE_PLOT_FAIL_RGB;
static const uint8_t pass_rgb[3] = HL_GLARE_PLOT_PASS_RGB;
static const uint8_t none_rgb[3] = { 95, 95, 95 };
static const uint8_t text_rgb[3] = { 235, 235, 235 };
static const uint8_t grid_rgb[3] = { 55, 55, 55 };
static const uint8_t axis_rgb[3] = { 150, 150, 150 };
static const uint8_t panel_rgb[3] = { 10, 10, 10 };
static const uint8_t fail_tint_rgb[3] = { 60, 16, 16 }; /* behind a failing stretch */

/* Road users' colours: none of them the pass or fail colour. */
static const uint8_t actor_rgb[][3] = {
	{ 80, 160, 255 }, { 255, 170, 40 },  { 220, 100, 255 }, { 60, 220, 220 },
	{ 250, 240, 90 }, { 240, 240, 240 }, { 190, 140, 90 },	{ 150, 150, 255 },
};
#define N_COLOURS (sizeof(actor_rgb) / sizeof(actor_rgb[0]))

struct canvas {
	uint8_t *rgb;
	int w, h;
	double t0, t1; /* the time axis, s */
};

/* A log axis on a panel: decades lo_dec .. hi_dec over [top, top + ph). */
struct panel {
	int top, ph;
	int lo_dec, hi_dec;
};

static void put(struct canvas *c, int x, int y, const uint8_t col[3])
{
	if (x < 0 || y < 0 || x >= c->w || y >= c->h)
		return;
	memcpy(c->rgb + 3 * ((size_t)y * c->w + x), col, 3);
}

static void fill(struct canvas *c, int x0, int y0, int x1, int y1, const uint8_t col[3])
{
	for (int y = y0; y < y1; y++)
		for (int x = x0; x < x1; x++)
			put(c, x, y, col);
}

/* dash: 0 solid, else on for dash pixels, off for dash pixels. */
static void line(struct canvas *c, double x0, double y0, double x1, double y1, int thick, int dash,
		 const uint8_t col[3])
{
	const int n = (int)ceil(fmax(fabs(x1 - x0), fabs(y1 - y0))) + 1;

	for (int k = 0; k <= n; k++) {
		const double t = (double)k / n;
		const int x = (int)lround(x0 + t * (x1 - x0)), y = (int)lround(y0 + t * (y1 - y0));

		if (dash && (k / dash) % 2)
			continue;
		for (int dy = -(thick / 2); dy <= thick / 2; dy++)
			for (int dx = -(thick / 2); dx <= thick / 2; dx++)
				put(c, x + dx, y + dy, col);
	}
}

static double tx(const struct canvas *c, double t)
{
	return LEFT + (t - c->t0) / (c->t1 - c->t0) * (PLOT_W - 1);
}

/* The row of value v (v <= 0 or below the axis: its bottom). */
static double vy(const struct panel *p, double v)
{
	double d = v > 0.0 ? log10(v) : p->lo_dec;

	d = fmin(fmax(d, p->lo_dec), p->hi_dec);
	return p->top + (p->hi_dec - d) / (p->hi_dec - p->lo_dec) * (p->ph - 1);
}

/* Decades from the largest value down: the decade above it, MAX_DECADES below at most, and no
 * lower than the decade of the smallest positive value. */
static void decades(const double *v, size_t n, struct panel *p)
{
	double hi = 0.0, lo = INFINITY;

	for (size_t i = 0; i < n; i++) {
		if (!(v[i] > 0.0) || !isfinite(v[i]))
			continue;
		hi = fmax(hi, v[i]);
		lo = fmin(lo, v[i]);
	}
	if (hi <= 0.0) {
		p->lo_dec = -1;
		p->hi_dec = 0;
		return;
	}
	p->hi_dec = (int)ceil(log10(hi) + 1e-9);
	p->lo_dec = (int)floor(log10(lo));
	if (p->lo_dec < p->hi_dec - MAX_DECADES)
		p->lo_dec = p->hi_dec - MAX_DECADES;
	if (p->lo_dec >= p->hi_dec)
		p->lo_dec = p->hi_dec - 1;
}

static void fmt_decade(int d, char *buf, size_t size)
{
	if (d >= 6)
		snprintf(buf, size, "%.0fM", pow(10.0, d - 6));
	else if (d >= 3)
		snprintf(buf, size, "%.0fK", pow(10.0, d - 3));
	else if (d >= 0)
		snprintf(buf, size, "%.0f", pow(10.0, d));
	else
		snprintf(buf, size, "%.*f", -d, pow(10.0, d));
}

static void draw_panel(struct canvas *c, const struct panel *p, const char *title)
{
	char buf[32];

	fill(c, LEFT, p->top, LEFT + PLOT_W, p->top + p->ph, panel_rgb);
	for (int d = p->lo_dec; d <= p->hi_dec; d++) {
		const double y = vy(p, pow(10.0, d));

		line(c, LEFT, y, LEFT + PLOT_W - 1, y, 1, 0, grid_rgb);
		fmt_decade(d, buf, sizeof(buf));
		hl_font_draw(c->rgb, c->w, c->h, LEFT - 6 - hl_font_width(buf, 1),
			     (int)lround(y) - 3, 1, buf, text_rgb);
	}
	hl_font_draw(c->rgb, c->w, c->h, LEFT, p->top - 11, 1, title, text_rgb);
}

/* A "nice" tick step for span seconds: 1, 2 or 5 times a power of ten, about 8 ticks. */
static double tick_step(double span)
{
	const double raw = span / 8.0, mag = pow(10.0, floor(log10(raw))), f = raw / mag;

	return mag * (f < 1.5 ? 1.0 : f < 3.5 ? 2.0 : f < 7.5 ? 5.0 : 10.0);
}

static void time_grid(struct canvas *c, const struct panel *p, bool labels)
{
	const double step = tick_step(c->t1 - c->t0);
	char buf[32];

	for (double t = ceil(c->t0 / step - 1e-9) * step; t <= c->t1 + 1e-9 * step; t += step) {
		const double x = tx(c, t);

		line(c, x, p->top, x, p->top + p->ph - 1, 1, 0, grid_rgb);
		if (!labels)
			continue;
		snprintf(buf, sizeof(buf), "%g", fabs(t) < 1e-9 * step ? 0.0 : t);
		hl_font_draw(c->rgb, c->w, c->h, (int)lround(x) - hl_font_width(buf, 1) / 2,
			     p->top + p->ph + 4, 1, buf, text_rgb);
	}
}

/* The time stretch frame f owns: halfway to its neighbours, the axis' ends at the ends. */
static void stretch(const struct canvas *c, const struct hl_glare_result *rows, int n_frames,
		    int n_actors, int f, double *ret_a, double *ret_b)
{
	const double t = rows[(size_t)f * n_actors].t_s;

	*ret_a = f > 0 ? 0.5 * (rows[(size_t)(f - 1) * n_actors].t_s + t) : c->t0;
	*ret_b = f + 1 < n_frames ? 0.5 * (t + rows[(size_t)(f + 1) * n_actors].t_s) : c->t1;
}

static bool fails(const struct hl_glare_result *r)
{
	return !isnan(r->limit.max_cd) && !r->pass;
}

enum field { HALF_PAIR_CD, LIMIT_CD, EYE_LX };

static double value(const struct hl_glare_result *r, enum field which)
{
	return which == HALF_PAIR_CD ? r->pair_half_cd :
	       which == LIMIT_CD     ? r->limit.max_cd :
				       r->illuminance_lx;
}

/* A road user's limit as a dashed step line: each frame's limit over the stretch it owns. */
static void limit_steps(struct canvas *c, const struct panel *p, const struct hl_glare_result *rows,
			int n_frames, int n_actors, int i)
{
	const uint8_t *col = actor_rgb[i % N_COLOURS];
	double prev_y = NAN;

	for (int f = 0; f < n_frames; f++) {
		const struct hl_glare_result *r = &rows[(size_t)f * n_actors + i];
		double a, b, y;

		if (isnan(r->limit.max_cd)) {
			prev_y = NAN;
			continue;
		}
		stretch(c, rows, n_frames, n_actors, f, &a, &b);
		y = vy(p, r->limit.max_cd);
		if (!isnan(prev_y))
			line(c, tx(c, a), prev_y, tx(c, a), y, 1, 3, col);
		line(c, tx(c, a), y, tx(c, b), y, 1, 3, col);
		prev_y = y;
	}
}

/*
 * A road user's values joined frame to frame, a segment in the failure colour when the road user
 * fails at both its ends; a single frame as a short bar over its stretch.
 */
static void curve(struct canvas *c, const struct panel *p, const struct hl_glare_result *rows,
		  int n_frames, int n_actors, int i, enum field which)
{
	const uint8_t *col = actor_rgb[i % N_COLOURS];

	if (n_frames == 1) {
		const double y = vy(p, value(&rows[i], which));

		line(c, tx(c, c->t0 + 0.25), y, tx(c, c->t1 - 0.25), y, 3, 0,
		     fails(&rows[i]) ? fail_rgb : col);
		return;
	}
	for (int f = 0; f + 1 < n_frames; f++) {
		const struct hl_glare_result *r = &rows[(size_t)f * n_actors + i];
		const struct hl_glare_result *n = &rows[(size_t)(f + 1) * n_actors + i];

		line(c, tx(c, r->t_s), vy(p, value(r, which)), tx(c, n->t_s),
		     vy(p, value(n, which)), 3, 0, fails(r) && fails(n) ? fail_rgb : col);
	}
}

int hl_glare_plot_rgb(const struct hl_scenario *sc, const struct hl_glare_result *rows,
		      int n_frames, const char *title, uint8_t **ret_rgb, int *ret_w, int *ret_h)
{
	const int n = sc->n_actors;
	struct canvas c = { .w = HL_GLARE_PLOT_W };
	struct panel cd = { .top = TOP, .ph = CD_H }, lx = { .top = TOP + CD_H + GAP, .ph = LX_H };
	const int tracks_top = lx.top + LX_H + 40;
	double *v;
	char buf[256];
	int n_fail = 0;

	if (n_frames < 1 || n < 1)
		return -EINVAL;
	for (int f = 1; f < n_frames; f++)
		if (!(rows[(size_t)f * n].t_s > rows[(size_t)(f - 1) * n].t_s))
			return -EINVAL;
	c.t0 = rows[0].t_s;
	c.t1 = rows[(size_t)(n_frames - 1) * n].t_s;
	if (n_frames == 1) {
		c.t0 -= 0.5;
		c.t1 += 0.5;
	}
	c.h = tracks_top + TRACK_PITCH * n + 8;
	assert(c.h == HL_GLARE_PLOT_H(n));
	v = malloc(sizeof(double) * 2 * (size_t)n_frames * n);
	c.rgb = malloc((size_t)c.w * c.h * 3);
	if (!v || !c.rgb) {
		free(v);
		free(c.rgb);
		return -ENOMEM;
	}
	memset(c.rgb, 24, (size_t)c.w * c.h * 3);
	/* the axes' ranges: intensities with their limits, illuminances */
	for (size_t k = 0; k < (size_t)n_frames * n; k++) {
		v[2 * k] = rows[k].pair_half_cd;
		v[2 * k + 1] = rows[k].limit.max_cd;
	}
	decades(v, 2 * (size_t)n_frames * n, &cd);
	for (size_t k = 0; k < (size_t)n_frames * n; k++)
		v[k] = rows[k].illuminance_lx;
	decades(v, (size_t)n_frames * n, &lx);
	free(v);

	draw_panel(&c, &cd, "INTENSITY TOWARD THE EYE, HALF THE PAIR SUM (CD) - DASHED: ITS LIMIT");
	draw_panel(&c, &lx, "ILLUMINANCE AT THE EYE, BOTH LAMPS (LX)");
	/* failing stretches behind the curves */
	for (int f = 0; f < n_frames; f++)
		for (int i = 0; i < n; i++) {
			double a, b;

			if (!fails(&rows[(size_t)f * n + i]))
				continue;
			n_fail++;
			stretch(&c, rows, n_frames, n, f, &a, &b);
			fill(&c, (int)lround(tx(&c, a)), cd.top, (int)lround(tx(&c, b)) + 1,
			     cd.top + cd.ph, fail_tint_rgb);
		}
	time_grid(&c, &cd, false);
	time_grid(&c, &lx, true);
	for (int d = cd.lo_dec; d <= cd.hi_dec; d++)
		line(&c, LEFT, vy(&cd, pow(10.0, d)), LEFT + PLOT_W - 1, vy(&cd, pow(10.0, d)), 1,
		     0, grid_rgb);
	for (int i = 0; i < n; i++) {
		limit_steps(&c, &cd, rows, n_frames, n, i);
		curve(&c, &cd, rows, n_frames, n, i, HALF_PAIR_CD);
		curve(&c, &lx, rows, n_frames, n, i, EYE_LX);
	}
	line(&c, LEFT - 1, cd.top, LEFT - 1, cd.top + cd.ph - 1, 1, 0, axis_rgb);
	line(&c, LEFT - 1, lx.top, LEFT - 1, lx.top + lx.ph - 1, 1, 0, axis_rgb);
	line(&c, LEFT - 1, lx.top + lx.ph, LEFT + PLOT_W - 1, lx.top + lx.ph, 1, 0, axis_rgb);
	hl_font_draw(c.rgb, c.w, c.h, LEFT + PLOT_W / 2 - hl_font_width("SCENARIO TIME (S)", 1) / 2,
		     lx.top + lx.ph + 16, 1, "SCENARIO TIME (S)", text_rgb);
	/* status tracks: fail, pass, no limit; the id at the right */
	hl_font_draw(c.rgb, c.w, c.h, LEFT, tracks_top - 12, 1,
		     "OVER THE LIMIT (RED), UNDER (GREEN), NO LIMIT (GREY)", text_rgb);
	for (int i = 0; i < n; i++) {
		const int y = tracks_top + TRACK_PITCH * i;

		for (int f = 0; f < n_frames; f++) {
			const struct hl_glare_result *r = &rows[(size_t)f * n + i];
			double a, b;

			stretch(&c, rows, n_frames, n, f, &a, &b);
			fill(&c, (int)lround(tx(&c, a)), y, (int)lround(tx(&c, b)) + 1, y + TRACK_H,
			     isnan(r->limit.max_cd) ? none_rgb :
			     r->pass		    ? pass_rgb :
						      fail_rgb);
		}
		hl_font_draw(c.rgb, c.w, c.h, LEFT + PLOT_W + 10, y, 1, sc->actor[i].id,
			     actor_rgb[i % N_COLOURS]);
	}
	/* legend: each road user's colour and id */
	for (int i = 0; i < n; i++) {
		const int y = cd.top + 4 + 14 * i;

		line(&c, LEFT + PLOT_W + 10, y + 3, LEFT + PLOT_W + 28, y + 3, 3, 0,
		     actor_rgb[i % N_COLOURS]);
		snprintf(buf, sizeof(buf), "%s %s", sc->actor[i].id,
			 hl_actor_role_name(sc->actor[i].role));
		hl_font_draw(c.rgb, c.w, c.h, LEFT + PLOT_W + 34, y, 1, buf,
			     actor_rgb[i % N_COLOURS]);
	}
	snprintf(buf, sizeof(buf), "%s%s%d ROAD USERS, %d FRAMES, %d OVER THE LIMIT",
		 title ? title : "", title ? "  " : "", n, n_frames, n_fail);
	hl_font_draw(c.rgb, c.w, c.h, LEFT, 8, 1, buf, n_fail ? fail_rgb : text_rgb);
	*ret_rgb = c.rgb;
	*ret_w = c.w;
	*ret_h = c.h;
	return 0;
}

int hl_glare_plot_png(const struct hl_scenario *sc, const struct hl_glare_result *rows,
		      int n_frames, const char *title, const char *path)
{
	uint8_t *rgb;
	int w, h, rc;

	rc = hl_glare_plot_rgb(sc, rows, n_frames, title, &rgb, &w, &h);
	if (rc < 0)
		return rc;
	rc = hl_png_write_rgb(path, rgb, w, h);
	free(rgb);
	return rc;
}
