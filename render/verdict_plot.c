/* SPDX-License-Identifier: MIT */
/* The verdict's H-V isocandela diagram with every requirement marked. */
#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/font.h"
#include "render/plot.h"
#include "render/verdict_plot.h"

#define MAX_PLOT_W 1400 /* pixels of the diagram itself */
#define MAX_SCALE 80.0 /* pixels per degree */
#define DECADES 5
#define PAD_DEG 2.0 /* around the requirements */

/* isocandela levels, cd */
static const double levels[] = { 100, 250, 625, 1750, 5000, 12500, 25000, 50000, 100000 };
#define N_LEVELS (sizeof(levels) / sizeof(levels[0]))

static const uint8_t pass_rgb[3] = { 60, 230, 90 };
static const uint8_t fail_rgb[3] = { 255, 50, 50 };
static const uint8_t text_rgb[3] = { 235, 235, 235 };

struct view {
	uint8_t *rgb;
	int w, h; /* whole image */
	int left, top, pw, ph; /* the diagram */
	double h0, h1, v0, v1, scale; /* degrees shown, pixels per degree */
};

static void put(struct view *c, int x, int y, const uint8_t col[3])
{
	if (x < 0 || y < 0 || x >= c->w || y >= c->h)
		return;
	memcpy(c->rgb + 3 * ((size_t)y * c->w + x), col, 3);
}

static double px(const struct view *c, double h)
{
	return c->left + (h - c->h0) * c->scale;
}

static double py(const struct view *c, double v)
{
	return c->top + (c->v1 - v) * c->scale;
}

static void line(struct view *c, double x0, double y0, double x1, double y1, int thick,
		 const uint8_t col[3])
{
	const int n = (int)ceil(fmax(fabs(x1 - x0), fabs(y1 - y0))) + 1;

	for (int k = 0; k <= n; k++) {
		const double t = (double)k / n;
		const int x = (int)lround(x0 + t * (x1 - x0)), y = (int)lround(y0 + t * (y1 - y0));

		for (int dy = -(thick / 2); dy <= thick / 2; dy++)
			for (int dx = -(thick / 2); dx <= thick / 2; dx++)
				put(c, x + dx, y + dy, col);
	}
}

static void cross(struct view *c, double h, double v, const uint8_t col[3])
{
	const double x = px(c, h), y = py(c, v);

	line(c, x - 4, y, x + 4, y, 1, col);
	line(c, x, y - 4, x, y + 4, 1, col);
}

/* A file's angle pair as evaluated: traffic mirrored, open ends at the view's edges. */
static void resolve(const struct view *c, enum hl_traffic traffic, const double p[2], double ret[2])
{
	double h = p[0];

	if (traffic == HL_TRAFFIC_LEFT)
		h = h == HL_REG_OPEN_LEFT  ? HL_REG_OPEN_RIGHT :
		    h == HL_REG_OPEN_RIGHT ? HL_REG_OPEN_LEFT :
					     -h;
	ret[0] = h == HL_REG_OPEN_LEFT ? c->h0 : h == HL_REG_OPEN_RIGHT ? c->h1 : h;
	ret[1] = p[1] == HL_REG_OPEN_DOWN ? c->v0 : p[1] == HL_REG_OPEN_UP ? c->v1 : p[1];
}

static void fmt_cd(double x, char *buf, size_t size)
{
	if (isnan(x))
		snprintf(buf, size, "-");
	else if (x >= 10000)
		snprintf(buf, size, "%.1fK", x / 1000);
	else
		snprintf(buf, size, "%.0f", x);
}

/* "ID 212/<=350" beside the deciding position. */
static void label(struct view *c, const struct hl_requirement *r, const struct hl_req_result *res,
		  double h, double v)
{
	char val[32], lim[32], buf[160];

	fmt_cd(res->value_cd, val, sizeof(val));
	if (res->pass) {
		snprintf(buf, sizeof(buf), "%s", r->id);
	} else {
		const bool min_fails = !isnan(res->min_cd) && !(res->value_cd >= res->min_cd);

		fmt_cd(min_fails ? res->min_cd : res->max_cd, lim, sizeof(lim));
		snprintf(buf, sizeof(buf), "%s %s%s%s", r->id, val, min_fails ? "<" : ">", lim);
	}
	hl_font_draw(c->rgb, c->w, c->h, (int)lround(px(c, h)) + 5, (int)lround(py(c, v)) - 9, 1,
		     buf, res->pass ? pass_rgb : fail_rgb);
}

static void bounds(const struct hl_lid_grid *g, const struct hl_regulation *reg,
		   const struct hl_verdict_options *o, struct view *c)
{
	double lo[2] = { -10.0, -5.0 }, hi[2] = { 10.0, 5.0 };

	for (int i = 0; i < reg->n_requirements; i++)
		for (int k = 0; k < reg->req[i].n_pts; k++)
			for (int a = 0; a < 2; a++) {
				double x = reg->req[i].pts[k][a];

				if (fabs(x) > 1e8)
					continue;
				if (a == 0 && o->traffic == HL_TRAFFIC_LEFT)
					x = -x;
				lo[a] = fmin(lo[a], x - PAD_DEG);
				hi[a] = fmax(hi[a], x + PAD_DEG);
			}
	c->h0 = fmax(lo[0], g->h_first_deg + o->aim_h_deg);
	c->h1 = fmin(hi[0], g->h_last_deg + o->aim_h_deg);
	c->v0 = fmax(lo[1], g->v_first_deg + o->aim_v_deg);
	c->v1 = fmin(hi[1], g->v_last_deg + o->aim_v_deg);
	c->scale = fmin(MAX_SCALE, MAX_PLOT_W / (c->h1 - c->h0));
	c->pw = (int)lround((c->h1 - c->h0) * c->scale);
	c->ph = (int)lround((c->v1 - c->v0) * c->scale);
}

static void draw_requirement(struct view *c, const struct hl_verdict_options *o,
			     const struct hl_requirement *r, const struct hl_req_result *res)
{
	const uint8_t *col = res->pass ? pass_rgb : fail_rgb;
	double a[2], b[2];

	switch (r->kind) {
	case HL_REQ_POINT:
	case HL_REQ_SUM:
		for (int k = 0; k < r->n_pts; k++) {
			resolve(c, o->traffic, r->pts[k], a);
			cross(c, a[0], a[1], col);
		}
		resolve(c, o->traffic, r->pts[0], a);
		label(c, r, res, a[0], a[1]);
		return;
	case HL_REQ_SEGMENT:
	case HL_REQ_ZONE: {
		const int n = r->kind == HL_REQ_SEGMENT ? 1 : r->n_pts;

		for (int k = 0; k < n; k++) {
			resolve(c, o->traffic, r->pts[k], a);
			resolve(c, o->traffic, r->pts[(k + 1) % r->n_pts], b);
			line(c, px(c, a[0]), py(c, a[1]), px(c, b[0]), py(c, b[1]),
			     r->kind == HL_REQ_SEGMENT ? 3 : 1, col);
		}
		break;
	}
	case HL_REQ_IMAX:
		break;
	}
	if (!isnan(res->at_h_deg)) {
		cross(c, res->at_h_deg, res->at_v_deg, col);
		label(c, r, res, res->at_h_deg, res->at_v_deg);
	}
}

int hl_plot_verdict_png(const struct hl_lid_grid *grid, const float *dense,
			const struct hl_regulation *reg, const struct hl_verdict_options *opts,
			const struct hl_req_result *results, const char *title, const char *path)
{
	struct view c = { .left = 50, .top = 34 };
	float *val;
	double peak = 0.0, hi, lo;
	int legend_y, n_fail = 0, rc;
	char buf[512];

	bounds(grid, reg, opts, &c);
	c.w = c.left + c.pw + 150;
	c.h = c.top + c.ph + 44 + 12 * (reg->n_requirements / 4 + 2);
	c.rgb = malloc((size_t)c.w * c.h * 3);
	val = malloc(sizeof(float) * (size_t)c.pw * c.ph);
	if (!c.rgb || !val) {
		free(c.rgb);
		free(val);
		return -ENOMEM;
	}
	memset(c.rgb, 24, (size_t)c.w * c.h * 3);
	/* the distribution as evaluated: value(h, v) = I(h - aim_h, v - aim_v), mirrored for
	 * left-hand traffic */
	for (int y = 0; y < c.ph; y++)
		for (int x = 0; x < c.pw; x++) {
			double h = c.h0 + (x + 0.5) / c.scale, v = c.v1 - (y + 0.5) / c.scale;

			if (opts->traffic == HL_TRAFFIC_LEFT)
				h = -h;
			val[(size_t)y * c.pw + x] =
				hl_lid_grid_lookup(grid, dense, (float)(h - opts->aim_h_deg),
						   (float)(v - opts->aim_v_deg));
			peak = fmax(peak, val[(size_t)y * c.pw + x]);
		}
	hi = peak > 0.0 ? pow(10.0, ceil(log10(peak))) : 1.0;
	lo = hi / pow(10.0, DECADES);
	for (int y = 0; y < c.ph; y++)
		for (int x = 0; x < c.pw; x++) {
			const double v = val[(size_t)y * c.pw + x];
			uint8_t *p = c.rgb + 3 * ((size_t)(c.top + y) * c.w + c.left + x);

			if (v < lo) {
				memset(p, 0, 3);
				continue;
			}
			hl_plot_colour((float)(log10(v / lo) / DECADES), p);
			for (int i = 0; i < 3; i++)
				p[i] = (uint8_t)(p[i] * 0.45);
		}
	/* isocandela lines: pixels at or above a level with a neighbour below it */
	for (size_t l = 0; l < N_LEVELS; l++) {
		uint8_t col[3];

		hl_plot_colour((float)fmax(0.0, log10(levels[l] / lo) / DECADES), col);
		for (int y = 0; y + 1 < c.ph; y++)
			for (int x = 0; x + 1 < c.pw; x++) {
				const float a = val[(size_t)y * c.pw + x];
				const float r = val[(size_t)y * c.pw + x + 1];
				const float d = val[(size_t)(y + 1) * c.pw + x];

				if ((a >= levels[l]) != (r >= levels[l]) ||
				    (a >= levels[l]) != (d >= levels[l]))
					put(&c, c.left + x, c.top + y, col);
			}
	}
	/* H and V lines, every 5° */
	for (int a = (int)ceil(c.h0); a <= c.h1; a++) {
		static const uint8_t grey[3] = { 110, 110, 110 };

		if (a % 5)
			continue;
		line(&c, px(&c, a), c.top, px(&c, a), c.top + c.ph - 1, a == 0 ? 1 : 0, grey);
		snprintf(buf, sizeof(buf), "%d%s", abs(a), a < 0 ? "L" : a > 0 ? "R" : "");
		hl_font_draw(c.rgb, c.w, c.h, (int)px(&c, a) - hl_font_width(buf, 1) / 2,
			     c.top + c.ph + 4, 1, buf, text_rgb);
	}
	for (int a = (int)ceil(c.v0); a <= c.v1; a++) {
		static const uint8_t grey[3] = { 110, 110, 110 };

		line(&c, c.left, py(&c, a), c.left + c.pw - 1, py(&c, a), a == 0 ? 1 : 0, grey);
		snprintf(buf, sizeof(buf), "%d%s", abs(a), a < 0 ? "D" : a > 0 ? "U" : "");
		hl_font_draw(c.rgb, c.w, c.h, c.left - 6 - hl_font_width(buf, 1),
			     (int)py(&c, a) - 3, 1, buf, text_rgb);
	}
	for (int i = 0; i < reg->n_requirements; i++) {
		draw_requirement(&c, opts, &reg->req[i], &results[i]);
		n_fail += !results[i].pass;
	}
	snprintf(buf, sizeof(buf), "%s  %s  %s  %d OF %d FAIL  AIM H %.2f V %.2f",
		 title ? title : "", reg->id, n_fail ? "FAIL" : "PASS", n_fail, reg->n_requirements,
		 opts->aim_h_deg, opts->aim_v_deg);
	hl_font_draw(c.rgb, c.w, c.h, c.left, 10, 1, buf, n_fail ? fail_rgb : pass_rgb);
	/* legend: the isocandela levels */
	legend_y = c.top;
	hl_font_draw(c.rgb, c.w, c.h, c.left + c.pw + 14, legend_y, 1, "ISOCANDELA", text_rgb);
	for (size_t l = 0; l < N_LEVELS; l++) {
		uint8_t col[3];

		hl_plot_colour((float)fmax(0.0, log10(levels[l] / lo) / DECADES), col);
		fmt_cd(levels[l], buf, sizeof(buf));
		strncat(buf, " CD", sizeof(buf) - strlen(buf) - 1);
		line(&c, c.left + c.pw + 14, legend_y + 16 + 12 * (int)l, c.left + c.pw + 30,
		     legend_y + 16 + 12 * (int)l, 1, col);
		hl_font_draw(c.rgb, c.w, c.h, c.left + c.pw + 36, legend_y + 13 + 12 * (int)l, 1,
			     buf, text_rgb);
	}
	/* the failing requirements, listed under the diagram */
	{
		int row = 0, col = 0;

		for (int i = 0; i < reg->n_requirements; i++) {
			char val[32], lim[32];
			const struct hl_req_result *r = &results[i];
			const bool min_fails = !isnan(r->min_cd) && !(r->value_cd >= r->min_cd);

			if (r->pass)
				continue;
			fmt_cd(r->value_cd, val, sizeof(val));
			fmt_cd(min_fails ? r->min_cd : r->max_cd, lim, sizeof(lim));
			snprintf(buf, sizeof(buf), "%s %s %s %s", reg->req[i].id, val,
				 min_fails ? "<" : ">", lim);
			hl_font_draw(c.rgb, c.w, c.h, c.left + col * (c.pw / 4),
				     c.top + c.ph + 20 + 12 * row, 1, buf, fail_rgb);
			if (++col == 4) {
				col = 0;
				row++;
			}
		}
	}
	rc = hl_png_write_rgb(path, c.rgb, c.w, c.h);
	free(val);
	free(c.rgb);
	return rc;
}
