/* SPDX-License-Identifier: MIT */
/*
 * A suite variant's plot as a standalone SVG 1.1 document: illuminance against range on a log
 * axis with the limits as a step line and the stretches over them marked, or the IIHS bird's-eye.
 * The geometry is verdict/suite_plot.h's. Every number written is finite: coordinates are
 * clamped, values that are not are left out or named in words.
 */
#include "verdict/suite_plot.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "base/xml_write.h"
#include "verdict/suite_result.h"

#define W (HL_SUITE_PLOT_RIGHT - HL_SUITE_PLOT_LEFT)
#define H (HL_SUITE_PLOT_BOTTOM - HL_SUITE_PLOT_TOP)
#define LEGEND_X (HL_SUITE_PLOT_RIGHT + 24.0) /* px */
#define PX_LIMIT 1e5 /* px: a coordinate is clamped to +-this, so none is ever inf */
#define RED "#d62728"

/* Colours told apart by eye and from the red of the marking (as many as HL_SUITE_MAX_SERIES). */
static const char *const palette[HL_SUITE_MAX_SERIES] = {
	"#1f77b4", "#2ca02c", "#9467bd", "#8c564b", "#17becf", "#bcbd22", "#e377c2", "#7f7f7f",
};

struct axes {
	double x_lo, x_hi; /* m */
	double top_lx;
};

static double clamp_px(double v)
{
	if (isnan(v))
		return 0.0;
	return fmin(fmax(v, -PX_LIMIT), PX_LIMIT);
}

/* The smallest of 1, 2, 5 x 10^k at or above x (x > 0). */
static double nice_at_least(double x)
{
	const double p = pow(10.0, floor(log10(x)));

	if (x <= p)
		return p;
	if (x <= 2.0 * p)
		return 2.0 * p;
	if (x <= 5.0 * p)
		return 5.0 * p;
	return 10.0 * p;
}

/* The largest of 1, 2, 5 x 10^k at or below x (x > 0). */
static double nice_at_most(double x)
{
	const double p = pow(10.0, floor(log10(x)));

	if (x >= 5.0 * p)
		return 5.0 * p;
	if (x >= 2.0 * p)
		return 2.0 * p;
	return p;
}

static double x_step(const struct axes *a)
{
	return nice_at_least((a->x_hi - a->x_lo) / HL_SUITE_PLOT_X_STEPS);
}

static double map_x(const struct axes *a, double r)
{
	return clamp_px(HL_SUITE_PLOT_LEFT + (r - a->x_lo) / (a->x_hi - a->x_lo) * W);
}

static double map_y(const struct axes *a, double lx)
{
	if (!(lx > HL_SUITE_PLOT_LX_MIN)) /* NaN, zero and negative too */
		return HL_SUITE_PLOT_BOTTOM;
	if (lx >= a->top_lx)
		return HL_SUITE_PLOT_TOP;
	return HL_SUITE_PLOT_BOTTOM -
	       log10(lx / HL_SUITE_PLOT_LX_MIN) / log10(a->top_lx / HL_SUITE_PLOT_LX_MIN) * H;
}

static bool on_axis(const struct axes *a, double r)
{
	return isfinite(r) && r >= a->x_lo && r <= a->x_hi;
}

/* A number for a label: finite as %g, or a word. */
static void put_num(FILE *f, const char *fmt, double v)
{
	if (isfinite(v))
		fprintf(f, fmt, v);
	else
		fputs("n/a", f);
}

static void axes_for(const struct hl_suite_result *r, const struct hl_suite_variant *v,
		     struct axes *ret)
{
	double lo = fmin(v->range_m[0], v->range_m[1]), hi = fmax(v->range_m[0], v->range_m[1]);
	double max_lx = 0.0, step;

	if (!isfinite(lo) || !isfinite(hi) || lo >= hi) { /* the series' extent instead */
		lo = INFINITY;
		hi = -INFINITY;
		for (int s = 0; s < v->n_series && s < HL_SUITE_MAX_SERIES; s++)
			for (int i = 0; i < v->series[s].n; i++) {
				const double x = v->series[s].range_m[i];

				if (isfinite(x)) {
					lo = fmin(lo, x);
					hi = fmax(hi, x);
				}
			}
		if (!(lo < hi)) {
			lo = isfinite(lo) ? lo : 0.0;
			hi = lo + 100.0;
		}
	}
	step = nice_at_least((hi - lo) / HL_SUITE_PLOT_X_STEPS);
	ret->x_lo = floor(lo / step) * step;
	ret->x_hi = ceil(hi / step) * step;
	if (!(ret->x_lo < ret->x_hi) || !isfinite(ret->x_hi - ret->x_lo)) { /* beyond doubles */
		ret->x_lo = 0.0;
		ret->x_hi = 100.0;
	}

	for (int s = 0; s < v->n_series && s < HL_SUITE_MAX_SERIES; s++)
		for (int i = 0; i < v->series[s].n; i++)
			if (isfinite(v->series[s].lx[i]))
				max_lx = fmax(max_lx, v->series[s].lx[i]);
	for (int b = 0; r->suite && b < r->suite->n_bins && b < HL_SUITE_MAX_BINS; b++)
		if (isfinite(r->suite->bin[b].max_lx))
			max_lx = fmax(max_lx, r->suite->bin[b].max_lx);
	ret->top_lx = HL_SUITE_PLOT_LX_TOP_MIN;
	if (max_lx > HL_SUITE_PLOT_LX_TOP_MIN)
		ret->top_lx = fmin(pow(10.0, ceil(log10(max_lx))), HL_SUITE_PLOT_LX_TOP_MAX);
}

/* The value as the suite judges it: rounded by its rule. */
static double as_judged(const struct hl_suite *suite, double lx)
{
	double scale, x;

	if (!suite || !suite->has_rounding || !isfinite(lx))
		return lx;
	scale = pow(10.0, suite->decimals);
	x = lx * scale;
	if (suite->rounding == HL_SUITE_HALF_UP)
		x = floor(x + 0.5);
	else
		x = nearbyint(x); /* the default rounding mode: to nearest, ties to even */
	return x / scale;
}

/* The bin of role holding range r (to 0.1 m, as the tables write it), or NULL. */
static const struct hl_suite_bin *bin_at(const struct hl_suite *suite, enum hl_actor_role role,
					 double r)
{
	const double r1 = floor(r * 10.0 + 0.5) / 10.0;

	for (int b = 0; suite && b < suite->n_bins && b < HL_SUITE_MAX_BINS; b++) {
		const struct hl_suite_bin *bin = &suite->bin[b];

		if (bin->role == role && r1 >= bin->from_m - 1e-9 && r1 <= bin->to_m + 1e-9)
			return bin;
	}
	return NULL;
}

static bool over_limit(const struct hl_suite *suite, const struct hl_suite_series *s, int i,
		       const struct hl_suite_bin **ret_bin)
{
	const struct hl_suite_bin *bin;

	if (!isfinite(s->range_m[i]) || isnan(s->lx[i]))
		return false;
	bin = bin_at(suite, s->role, s->range_m[i]);
	if (!bin || !isfinite(bin->max_lx) || !(as_judged(suite, s->lx[i]) > bin->max_lx))
		return false;
	*ret_bin = bin;
	return true;
}

static bool drawable(const struct axes *a, const struct hl_suite_series *s, int i)
{
	return on_axis(a, s->range_m[i]) && !isnan(s->lx[i]);
}

static void head(FILE *f, const struct hl_suite_variant *v)
{
	fputs("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n", f);
	fprintf(f,
		"<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"%d\" "
		"height=\"%d\" viewBox=\"0 0 %d %d\" font-family=\"sans-serif\" font-size=\"12\">\n",
		HL_SUITE_PLOT_WIDTH, HL_SUITE_PLOT_HEIGHT, HL_SUITE_PLOT_WIDTH,
		HL_SUITE_PLOT_HEIGHT);
	fputs("<title>", f);
	hl_xml_write_text(f, v->title);
	fputs("</title>\n", f);
	fprintf(f, "<rect x=\"0\" y=\"0\" width=\"%d\" height=\"%d\" fill=\"white\"/>\n",
		HL_SUITE_PLOT_WIDTH, HL_SUITE_PLOT_HEIGHT);
	fprintf(f,
		"<text class=\"title\" x=\"%.1f\" y=\"28\" font-size=\"16\" font-weight=\"bold\">",
		HL_SUITE_PLOT_LEFT);
	hl_xml_write_text(f, v->title);
	fputs("</text>\n", f);
	fprintf(f, "<text class=\"subtitle\" x=\"%.1f\" y=\"48\" fill=\"#555\">",
		HL_SUITE_PLOT_LEFT);
	hl_xml_write_text(f, v->id);
	if (isfinite(v->speed_mph)) {
		fputs(", ", f);
		put_num(f, "%.0f mph", v->speed_mph);
	}
	if (isfinite(v->radius_m) && v->radius_m > 0.0)
		fprintf(f, ", radius %.0f m", v->radius_m);
	fputs("</text>\n", f);
}

static void frame(FILE *f)
{
	fprintf(f,
		"<rect class=\"frame\" x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" "
		"fill=\"none\" stroke=\"#333\"/>\n",
		HL_SUITE_PLOT_LEFT, HL_SUITE_PLOT_TOP, W, H);
}

static void axes_draw(FILE *f, const struct axes *a)
{
	const double step = x_step(a);
	const int n_x = (int)lround((a->x_hi - a->x_lo) / step);
	const int top_dec = (int)lround(log10(a->top_lx));

	fputs("<g class=\"grid\" stroke=\"#ddd\" stroke-width=\"1\">\n", f);
	for (int i = 0; i <= n_x; i++) {
		const double x = map_x(a, a->x_lo + i * step);

		fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n", x,
			HL_SUITE_PLOT_TOP, x, HL_SUITE_PLOT_BOTTOM);
	}
	for (int d = -2; d <= top_dec; d++) {
		const double y = map_y(a, pow(10.0, d));

		fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n",
			HL_SUITE_PLOT_LEFT, y, HL_SUITE_PLOT_RIGHT, y);
	}
	fputs("</g>\n<g class=\"minor\" stroke=\"#999\" stroke-width=\"1\">\n", f);
	for (int d = -2; d < top_dec; d++)
		for (int m = 2; m <= 9; m++) {
			const double y = map_y(a, m * pow(10.0, d));

			fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n",
				HL_SUITE_PLOT_LEFT, y, HL_SUITE_PLOT_LEFT + 5.0, y);
		}
	fputs("</g>\n", f);
	frame(f);

	fputs("<g class=\"ticks\" fill=\"#333\">\n", f);
	for (int i = 0; i <= n_x; i++)
		fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%g</text>\n",
			map_x(a, a->x_lo + i * step), HL_SUITE_PLOT_BOTTOM + 18.0,
			a->x_lo + i * step);
	for (int d = -2; d <= top_dec; d++) {
		fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">",
			HL_SUITE_PLOT_LEFT - 6.0, map_y(a, pow(10.0, d)) + 4.0);
		if (d < 5)
			fprintf(f, "%g", pow(10.0, d));
		else
			fprintf(f, "1e%d", d);
		fputs("</text>\n", f);
	}
	fputs("</g>\n", f);
	fprintf(f,
		"<text class=\"xlabel\" x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">range (m)</text>\n",
		HL_SUITE_PLOT_LEFT + W / 2.0, HL_SUITE_PLOT_BOTTOM + 42.0);
	fprintf(f,
		"<text class=\"ylabel\" x=\"0\" y=\"0\" text-anchor=\"middle\" "
		"transform=\"translate(22 %.1f) rotate(-90)\">illuminance (lx)</text>\n",
		HL_SUITE_PLOT_TOP + H / 2.0);
}

/* Whether any of the variant's series has role. */
static bool role_drawn(const struct hl_suite_variant *v, enum hl_actor_role role)
{
	for (int s = 0; s < v->n_series && s < HL_SUITE_MAX_SERIES; s++)
		if (v->series[s].role == role)
			return true;
	return false;
}

/* The limit of each role a series has: a step line over the suite's bins. */
static void limits_draw(FILE *f, const struct hl_suite *suite, const struct hl_suite_variant *v,
			const struct axes *a)
{
	const struct hl_suite_bin *prev = NULL;

	fputs("<g class=\"limits\" stroke=\"#000\" stroke-width=\"2\" fill=\"#000\">\n", f);
	for (int b = 0; suite && b < suite->n_bins && b < HL_SUITE_MAX_BINS; b++) {
		const struct hl_suite_bin *bin = &suite->bin[b];
		const double from = fmax(bin->from_m, a->x_lo), to = fmin(bin->to_m, a->x_hi);
		const double y = map_y(a, bin->max_lx);

		if (!role_drawn(v, bin->role) || !isfinite(bin->max_lx) || !(from < to)) {
			prev = NULL;
			continue;
		}
		if (prev && prev->role == bin->role && bin->from_m - prev->to_m >= 0.0 &&
		    bin->from_m - prev->to_m <= 0.5)
			fprintf(f,
				"<line class=\"limit-riser\" x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" "
				"y2=\"%.1f\"/>\n",
				map_x(a, bin->from_m), map_y(a, prev->max_lx),
				map_x(a, bin->from_m), y);
		fprintf(f,
			"<line class=\"limit\" x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n",
			map_x(a, from), y, map_x(a, to), y);
		fprintf(f,
			"<text stroke=\"#fff\" stroke-width=\"3\" paint-order=\"stroke\" font-size=\"10\" "
			"x=\"%.1f\" y=\"%.1f\">%.3g lx</text>\n",
			map_x(a, from) + 3.0, y - 4.0, bin->max_lx);
		prev = bin;
	}
	fputs("</g>\n", f);
}

/* The series' samples first to last, one polyline per run on the axis. */
static void series_draw(FILE *f, const struct hl_suite_variant *v, const struct axes *a)
{
	for (int s = 0; s < v->n_series && s < HL_SUITE_MAX_SERIES; s++) {
		const struct hl_suite_series *ser = &v->series[s];
		bool open = false;

		for (int i = 0; i < ser->n; i++) {
			if (!drawable(a, ser, i)) {
				if (open)
					fputs("\"/>\n", f);
				open = false;
				continue;
			}
			if (!open)
				fprintf(f,
					"<polyline class=\"series\" data-series=\"%d\" fill=\"none\" "
					"stroke=\"%s\" stroke-width=\"1.5\" points=\"",
					s, palette[s]);
			fprintf(f, "%s%.1f,%.1f", open ? " " : "", map_x(a, ser->range_m[i]),
				map_y(a, ser->lx[i]));
			open = true;
		}
		if (open)
			fputs("\"/>\n", f);
	}
}

/* A stretch over the limit: its band behind everything, or its red line over the series. */
static void over_run(FILE *f, const struct hl_suite_series *ser, int i0, int i1,
		     const struct axes *a, bool band)
{
	double x_min = INFINITY, x_max = -INFINITY;

	for (int i = i0; i < i1; i++) {
		x_min = fmin(x_min, map_x(a, ser->range_m[i]));
		x_max = fmax(x_max, map_x(a, ser->range_m[i]));
	}
	if (band) {
		fprintf(f,
			"<rect class=\"over-band\" x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" "
			"fill=\"" RED "\" fill-opacity=\"0.12\" stroke=\"none\"/>\n",
			x_min - 2.0, HL_SUITE_PLOT_TOP, x_max - x_min + 4.0, H);
		return;
	}
	if (i1 - i0 == 1) {
		fprintf(f,
			"<circle class=\"over\" cx=\"%.1f\" cy=\"%.1f\" r=\"4\" fill=\"" RED
			"\"/>\n",
			map_x(a, ser->range_m[i0]), map_y(a, ser->lx[i0]));
		return;
	}
	fputs("<polyline class=\"over\" fill=\"none\" stroke=\"" RED "\" stroke-width=\"5\" "
	      "stroke-opacity=\"0.8\" stroke-linecap=\"round\" points=\"",
	      f);
	for (int i = i0; i < i1; i++)
		fprintf(f, "%s%.1f,%.1f", i > i0 ? " " : "", map_x(a, ser->range_m[i]),
			map_y(a, ser->lx[i]));
	fputs("\"/>\n", f);
}

/* The runs of samples, in one bin, whose value as judged exceeds its limit. */
static int overs_draw(FILE *f, const struct hl_suite *suite, const struct hl_suite_variant *v,
		      const struct axes *a, bool band)
{
	int n_runs = 0;

	for (int s = 0; s < v->n_series && s < HL_SUITE_MAX_SERIES; s++) {
		const struct hl_suite_series *ser = &v->series[s];
		const struct hl_suite_bin *run_bin = NULL, *bin = NULL;
		int i0 = 0;

		for (int i = 0; i <= ser->n; i++) {
			const bool over = i < ser->n && drawable(a, ser, i) &&
					  over_limit(suite, ser, i, &bin);

			if (run_bin && (!over || bin != run_bin)) {
				over_run(f, ser, i0, i, a, band);
				n_runs++;
				run_bin = NULL;
			}
			if (over && !run_bin) {
				run_bin = bin;
				i0 = i;
			}
		}
	}
	return n_runs;
}

static void legend_line(FILE *f, double y, const char *colour, double width)
{
	fprintf(f,
		"<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\" "
		"stroke-width=\"%.1f\"/>\n",
		LEGEND_X, y - 4.0, LEGEND_X + 24.0, y - 4.0, colour, width);
}

static void legend_text(FILE *f, double y, const char *text, const char *suffix)
{
	fprintf(f, "<text x=\"%.1f\" y=\"%.1f\">", LEGEND_X + 30.0, y);
	hl_xml_write_text(f, text);
	hl_xml_write_text(f, suffix);
	fputs("</text>\n", f);
}

static void legend(FILE *f, const struct hl_suite_variant *v, bool any_limit, int n_over)
{
	double y = HL_SUITE_PLOT_TOP + 12.0;

	fputs("<g class=\"legend\">\n", f);
	for (int s = 0; s < v->n_series && s < HL_SUITE_MAX_SERIES; s++, y += 18.0) {
		legend_line(f, y, palette[s], 2.0);
		legend_text(f, y, v->series[s].label, v->series[s].n ? "" : " (no samples)");
	}
	if (any_limit) {
		legend_line(f, y, "#000", 2.0);
		legend_text(f, y, "limit", "");
		y += 18.0;
	}
	legend_line(f, y, RED, 5.0);
	legend_text(f, y, n_over ? "over the limit" : "over the limit: none", "");
	fputs("</g>\n", f);
	if (v->n_series == 0)
		fprintf(f,
			"<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\" fill=\"#888\">"
			"no series</text>\n",
			HL_SUITE_PLOT_LEFT + W / 2.0, HL_SUITE_PLOT_TOP + H / 2.0);
}

static void range_plot(FILE *f, const struct hl_suite_result *r, const struct hl_suite_variant *v)
{
	struct axes a;
	bool any_limit = false;
	int n_over;

	axes_for(r, v, &a);
	axes_draw(f, &a);
	for (int b = 0; r->suite && b < r->suite->n_bins && b < HL_SUITE_MAX_BINS; b++)
		any_limit |= role_drawn(v, r->suite->bin[b].role) &&
			     isfinite(r->suite->bin[b].max_lx);
	n_over = overs_draw(f, r->suite, v, &a, true);
	limits_draw(f, r->suite, v, &a);
	series_draw(f, v, &a);
	overs_draw(f, r->suite, v, &a, false); /* on top, so the marking shows */
	legend(f, v, any_limit, n_over);
}

/* Bird's-eye: world metres to the plot box, one scale, y up. */
struct view {
	double cx, cy; /* m, the box's centre */
	double s; /* px per m */
};

static bool finite2(const double p[2])
{
	return isfinite(p[0]) && isfinite(p[1]);
}

static void grow_box(double box[4], const double p[2])
{
	if (!finite2(p))
		return;
	box[0] = fmin(box[0], p[0]);
	box[1] = fmin(box[1], p[1]);
	box[2] = fmax(box[2], p[0]);
	box[3] = fmax(box[3], p[1]);
}

static double view_x(const struct view *w, double x)
{
	return clamp_px(HL_SUITE_PLOT_LEFT + W / 2.0 + (x - w->cx) * w->s);
}

static double view_y(const struct view *w, double y)
{
	return clamp_px(HL_SUITE_PLOT_TOP + H / 2.0 - (y - w->cy) * w->s);
}

static void view_for(const struct hl_suite_birdseye *be, struct view *ret)
{
	double box[4] = { INFINITY, INFINITY, -INFINITY, -INFINITY }, dx, dy;

	for (int i = 0; i < be->n; i++) {
		if (be->left)
			grow_box(box, be->left[i]);
		if (be->right)
			grow_box(box, be->right[i]);
	}
	grow_box(box, be->ego);
	for (int e = 0; e < 2; e++)
		if (isfinite(be->vis_m[e]))
			grow_box(box, be->vis_at[e]);
	if (!(box[0] <= box[2])) { /* nothing finite: 100 m around the origin */
		box[0] = box[1] = -50.0;
		box[2] = box[3] = 50.0;
	}
	dx = fmax(box[2] - box[0], 10.0);
	dy = fmax(box[3] - box[1], 10.0);
	ret->cx = box[0] / 2.0 + box[2] / 2.0;
	ret->cy = box[1] / 2.0 + box[3] / 2.0;
	ret->s = fmin(W / (dx * (1.0 + 2.0 * HL_SUITE_PLOT_PAD)),
		      H / (dy * (1.0 + 2.0 * HL_SUITE_PLOT_PAD)));
	if (!isfinite(ret->s) || !(ret->s > 0.0) || !isfinite(ret->cx) || !isfinite(ret->cy)) {
		ret->cx = ret->cy = 0.0;
		ret->s = 1.0;
	}
}

static void edge_draw(FILE *f, const struct view *w, const double (*p)[2], int n, const char *side)
{
	bool open = false;

	for (int i = 0; p && i < n; i++) {
		if (!finite2(p[i])) {
			if (open)
				fputs("\"/>\n", f);
			open = false;
			continue;
		}
		if (!open)
			fprintf(f,
				"<polyline class=\"edge\" data-edge=\"%s\" fill=\"none\" "
				"stroke=\"#444\" stroke-width=\"2\" points=\"",
				side);
		fprintf(f, "%s%.1f,%.1f", open ? " " : "", view_x(w, p[i][0]), view_y(w, p[i][1]));
		open = true;
	}
	if (open)
		fputs("\"/>\n", f);
}

static void vis_label(FILE *f, const char *side, double vis_m)
{
	fprintf(f, "%s edge: ", side);
	if (isfinite(vis_m))
		fprintf(f, "%.1f m", vis_m);
	else
		fputs("not reached", f);
}

static void birdseye_plot(FILE *f, const struct hl_suite_result *r,
			  const struct hl_suite_variant *v)
{
	static const char *const side[2] = { "left", "right" };
	static const char *const colour[2] = { "#2ca02c", "#9467bd" };
	const struct hl_suite_birdseye *be = &v->birdseye;
	struct view w;
	double bar_m, y;

	view_for(be, &w);
	frame(f);
	edge_draw(f, &w, be->left, be->n, "left");
	edge_draw(f, &w, be->right, be->n, "right");

	for (int e = 0; e < 2; e++) {
		if (!isfinite(be->vis_m[e]) || !finite2(be->vis_at[e]))
			continue;
		if (finite2(be->ego))
			fprintf(f,
				"<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\" "
				"stroke-dasharray=\"4 3\"/>\n",
				view_x(&w, be->ego[0]), view_y(&w, be->ego[1]),
				view_x(&w, be->vis_at[e][0]), view_y(&w, be->vis_at[e][1]),
				colour[e]);
		fprintf(f,
			"<circle class=\"vis\" data-edge=\"%s\" cx=\"%.1f\" cy=\"%.1f\" r=\"5\" "
			"fill=\"%s\"/>\n",
			side[e], view_x(&w, be->vis_at[e][0]), view_y(&w, be->vis_at[e][1]),
			colour[e]);
		fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" fill=\"%s\">",
			view_x(&w, be->vis_at[e][0]) + 8.0,
			view_y(&w, be->vis_at[e][1]) + (e == 0 ? -6.0 : 14.0), colour[e]);
		vis_label(f, side[e], be->vis_m[e]);
		fputs("</text>\n", f);
	}
	if (finite2(be->ego)) {
		const double h = isfinite(be->ego_heading_rad) ? be->ego_heading_rad : 0.0;
		const double x = view_x(&w, be->ego[0]), yy = view_y(&w, be->ego[1]);

		fprintf(f,
			"<g class=\"ego\"><line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" "
			"stroke=\"#1f77b4\" stroke-width=\"3\"/><circle cx=\"%.1f\" cy=\"%.1f\" r=\"6\" "
			"fill=\"#1f77b4\"/><text x=\"%.1f\" y=\"%.1f\" fill=\"#1f77b4\">ego</text></g>\n",
			x, yy, x + 28.0 * cos(h), yy - 28.0 * sin(h), x, yy, x + 8.0, yy + 18.0);
	}

	/* the scale bar: a round length near a quarter of the box */
	bar_m = nice_at_most(W / 4.0 / w.s);
	fprintf(f,
		"<g class=\"scale\" stroke=\"#000\" stroke-width=\"2\"><line x1=\"%.1f\" y1=\"%.1f\" "
		"x2=\"%.1f\" y2=\"%.1f\"/><text stroke=\"none\" x=\"%.1f\" y=\"%.1f\">%g m</text></g>\n",
		HL_SUITE_PLOT_LEFT + 12.0, HL_SUITE_PLOT_BOTTOM - 14.0,
		clamp_px(HL_SUITE_PLOT_LEFT + 12.0 + bar_m * w.s), HL_SUITE_PLOT_BOTTOM - 14.0,
		HL_SUITE_PLOT_LEFT + 12.0, HL_SUITE_PLOT_BOTTOM - 20.0, bar_m);
	fprintf(f,
		"<g class=\"north\"><line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" "
		"stroke=\"#000\" stroke-width=\"2\"/><path d=\"M %.1f %.1f l -5 9 l 10 0 z\"/>"
		"<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">N</text></g>\n",
		HL_SUITE_PLOT_RIGHT - 20.0, HL_SUITE_PLOT_TOP + 44.0, HL_SUITE_PLOT_RIGHT - 20.0,
		HL_SUITE_PLOT_TOP + 24.0, HL_SUITE_PLOT_RIGHT - 20.0, HL_SUITE_PLOT_TOP + 20.0,
		HL_SUITE_PLOT_RIGHT - 20.0, HL_SUITE_PLOT_TOP + 58.0);

	fputs("<g class=\"legend\">\n", f);
	y = HL_SUITE_PLOT_TOP + 12.0;
	if (r->suite && isfinite(r->suite->visibility_lx)) {
		fprintf(f, "<text x=\"%.1f\" y=\"%.1f\">visibility: ", LEGEND_X, y);
		put_num(f, "%g lx", r->suite->visibility_lx);
		fputs(" at ", f);
		put_num(f, "%g m", r->suite->visibility_height_m);
		fputs("</text>\n", f);
		y += 20.0;
	}
	for (int e = 0; e < 2; e++, y += 18.0) {
		fprintf(f, "<text class=\"vis-label\" x=\"%.1f\" y=\"%.1f\" fill=\"%s\">", LEGEND_X,
			y, colour[e]);
		vis_label(f, side[e], be->vis_m[e]);
		fputs("</text>\n", f);
	}
	fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" fill=\"#555\">world x, y (m), north up</text>\n",
		LEGEND_X, y + 8.0);
	fputs("</g>\n", f);
}

int hl_suite_plot_svg(const struct hl_suite_result *r, const struct hl_suite_variant *v, FILE *f)
{
	head(f, v);
	if (v->has_birdseye)
		birdseye_plot(f, r, v);
	else
		range_plot(f, r, v);
	fputs("</svg>\n", f);
	return ferror(f) ? -EIO : 0;
}
