/* SPDX-License-Identifier: MIT */
/* Judging a suite's measurements: see verdict/suite_judge.h. */
#include "verdict/suite_judge.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define BIN_STEP_M 0.1 /* the tables' resolution */
#define EPS 1e-9

int hl_suite_bin_of(const struct hl_suite *s, enum hl_actor_role role, double range_m)
{
	if (!isfinite(range_m))
		return -1;
	for (int i = 0; i < s->n_bins; i++) {
		const struct hl_suite_bin *b = &s->bin[i];
		double next = INFINITY;

		if (b->role != role || range_m < b->from_m - EPS)
			continue;
		/* the lowest bound above this bin's of the same role */
		for (int j = 0; j < s->n_bins; j++)
			if (s->bin[j].role == role && s->bin[j].from_m > b->from_m + EPS)
				next = fmin(next, s->bin[j].from_m);
		if (isfinite(next) && next - b->to_m <= BIN_STEP_M + EPS) {
			if (range_m < next - EPS)
				return i;
		} else if (range_m <= b->to_m + EPS) {
			return i;
		}
	}
	return -1;
}

double hl_suite_round(const struct hl_suite *s, double v)
{
	double p, x, f, diff, r;

	if (!s->has_rounding || !isfinite(v))
		return v;
	p = pow(10.0, s->decimals);
	x = fabs(v) * p;
	f = floor(x);
	diff = x - f - 0.5;
	if (fabs(diff) <= EPS * fmax(1.0, x))
		r = s->rounding == HL_SUITE_HALF_UP || fmod(f, 2.0) != 0.0 ? f + 1.0 : f;
	else
		r = diff < 0.0 ? f : f + 1.0;
	return copysign(r / p, v);
}

struct hl_suite_case *hl_suite_case_add(struct hl_suite_variant *v)
{
	struct hl_suite_case *c = realloc(v->cases, sizeof(*c) * (size_t)(v->n_cases + 1));

	if (!c)
		return NULL;
	v->cases = c;
	c = &v->cases[v->n_cases++];
	memset(c, 0, sizeof(*c));
	c->max_raw = c->value = c->at_range_m = c->at_t_s = c->margin = c->limit = NAN;
	c->from_m = c->to_m = NAN;
	c->bin_index = c->photometer_index = -1;
	c->worst_margin = INFINITY;
	return c;
}

int hl_suite_fmvss_cases(const struct hl_suite *s, enum hl_actor_role role,
			 struct hl_suite_variant *v)
{
	for (int b = 0; b < s->n_bins; b++) {
		const struct hl_suite_bin *bin = &s->bin[b];

		/* a bin that meets the measured range in one point only is not judged */
		if (bin->role != role || bin->from_m >= v->range_m[1] - EPS ||
		    bin->to_m < v->range_m[0] - BIN_STEP_M)
			continue;
		for (int p = 0; p < s->n_photometers; p++) {
			struct hl_suite_case *c;

			if (s->photometer[p].role != role)
				continue;
			c = hl_suite_case_add(v);
			if (!c)
				return -ENOMEM;
			snprintf(c->name, sizeof(c->name), "%s %.1f-%.1f m, photometer %s",
				 hl_actor_role_name(role), bin->from_m, bin->to_m,
				 s->photometer[p].id);
			snprintf(c->photometer, sizeof(c->photometer), "%s", s->photometer[p].id);
			c->from_m = bin->from_m;
			c->to_m = bin->to_m;
			c->unit = "lx";
			c->limit = bin->max_lx;
			snprintf(c->source, sizeof(c->source), "%s", bin->source);
			c->bin_index = b;
			c->photometer_index = p;
		}
	}
	return 0;
}

void hl_suite_fmvss_sample(const struct hl_suite *s, struct hl_suite_variant *v, int pm,
			   double range_m, double lx, double t_s)
{
	int b;

	if (range_m < v->range_m[0] - EPS || range_m > v->range_m[1] + EPS)
		return;
	b = hl_suite_bin_of(s, s->photometer[pm].role, range_m);
	if (b < 0)
		return;
	for (int i = 0; i < v->n_cases; i++) {
		struct hl_suite_case *c = &v->cases[i];

		if (c->bin_index != b || c->photometer_index != pm)
			continue;
		c->n_samples++;
		if (isnan(c->max_raw) || lx > c->max_raw) {
			c->max_raw = lx;
			c->at_range_m = range_m;
			c->at_t_s = t_s;
		}
		return;
	}
}

int hl_suite_r149_cases(const struct hl_regulation *reg, enum hl_actor_role role,
			struct hl_suite_variant *v)
{
	double d[HL_GLARE_MAX_ROWS], lim[HL_GLARE_MAX_ROWS];
	int n = 0;

	/* the tabulated distances of role, each once, with the strictest limit at each */
	for (int i = 0; i < reg->n_requirements; i++) {
		enum hl_actor_role r;
		double x;
		int k;

		if (hl_glare_row_id(reg->req[i].id, &r, &x) < 0 || r != role)
			continue;
		for (k = 0; k < n && d[k] != x; k++)
			;
		if (k == n) {
			if (n == HL_GLARE_MAX_ROWS)
				continue;
			d[n] = x;
			lim[n++] = INFINITY;
		}
		if (reg->req[i].max.set)
			lim[k] = fmin(lim[k], reg->req[i].max.cd);
	}
	for (int i = 0; i < n; i++) /* ascending */
		for (int j = i + 1; j < n; j++)
			if (d[j] < d[i]) {
				const double td = d[i], tl = lim[i];

				d[i] = d[j], lim[i] = lim[j];
				d[j] = td, lim[j] = tl;
			}
	for (int i = 0; i < n; i++) {
		const double hi = i + 1 < n ? d[i + 1] : INFINITY;
		struct hl_suite_case *c;

		if (d[i] > v->range_m[1] + EPS || hi < v->range_m[0])
			continue;
		c = hl_suite_case_add(v);
		if (!c)
			return -ENOMEM;
		snprintf(c->name, sizeof(c->name), "%s %g m (half the pair's intensity)",
			 role == HL_ROLE_ONCOMING ? "Oncoming" : "Preceding", d[i]);
		c->from_m = d[i];
		c->to_m = isfinite(hi) ? hi - BIN_STEP_M : v->range_m[1];
		c->unit = "cd";
		/* the strictest row at this distance until a frame says which */
		c->limit = isinf(lim[i]) ? NAN : lim[i];
		snprintf(c->source, sizeof(c->source), "%s: %s", reg->id, reg->source);
	}
	return 0;
}

void hl_suite_r149_sample(struct hl_suite_variant *v, const struct hl_glare_result *r)
{
	if (r->distance_m < v->range_m[0] - EPS || r->distance_m > v->range_m[1] + EPS ||
	    isnan(r->limit.max_cd))
		return;
	for (int i = 0; i < v->n_cases; i++) {
		struct hl_suite_case *c = &v->cases[i];
		double m;

		if (r->limit.table_distance_m != c->from_m)
			continue;
		c->n_samples++;
		m = r->limit.max_cd - r->pair_half_cd;
		if (m < c->worst_margin) { /* the worst frame: its value and its limit */
			c->worst_margin = m;
			c->max_raw = r->pair_half_cd;
			c->limit = r->limit.max_cd;
			c->at_range_m = r->distance_m;
			c->at_t_s = r->t_s;
		}
		return;
	}
}

void hl_suite_judge_finish(const struct hl_suite *s, struct hl_suite_variant *v)
{
	for (int i = 0; i < v->n_cases; i++) {
		struct hl_suite_case *c = &v->cases[i];

		c->value = !strcmp(c->unit ? c->unit : "", "lx") ? hl_suite_round(s, c->max_raw) :
								   c->max_raw;
		c->no_samples = !isnan(c->limit) && c->n_samples == 0;
		c->judged = !isnan(c->limit) && c->n_samples > 0;
		if (!c->judged) {
			c->pass = !c->no_samples;
			c->margin = NAN;
			continue;
		}
		c->margin = c->limit_is_min ? c->value - c->limit : c->limit - c->value;
		c->pass = c->margin >= 0.0;
	}
}
