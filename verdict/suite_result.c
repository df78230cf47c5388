/* SPDX-License-Identifier: MIT */
/* What a suite run found: totals, the overall verdict, freeing, series growth. */
#include "verdict/suite_result.h"

#include <errno.h>
#include <limits.h>
#include <stdlib.h>

#define SERIES_FIRST_CAP 64 /* samples; doubled when full */

/* A variant that did not finish: the runner says why, or its run exited non-zero. */
static bool variant_is_error(const struct hl_suite_variant *v)
{
	return v->error[0] != '\0' || v->exit_code != 0;
}

void hl_suite_variant_totals(const struct hl_suite_variant *v, struct hl_suite_totals *ret)
{
	struct hl_suite_totals t = { 0 };

	for (int c = 0; c < v->n_cases; c++) {
		const struct hl_suite_case *k = &v->cases[c];

		t.cases++;
		t.judged += k->judged;
		t.failed += k->judged && !k->pass;
		t.no_samples += k->no_samples;
	}
	t.errors = variant_is_error(v);
	*ret = t;
}

void hl_suite_result_totals(const struct hl_suite_result *r, struct hl_suite_totals *ret)
{
	struct hl_suite_totals t = { 0 };

	for (int i = 0; i < r->n_variants; i++) {
		struct hl_suite_totals one;

		hl_suite_variant_totals(&r->v[i], &one);
		t.cases += one.cases;
		t.judged += one.judged;
		t.failed += one.failed;
		t.no_samples += one.no_samples;
		t.errors += one.errors;
	}
	*ret = t;
}

bool hl_suite_result_passed(const struct hl_suite_result *r)
{
	struct hl_suite_totals t;

	hl_suite_result_totals(r, &t);
	return t.failed == 0 && t.no_samples == 0 && t.errors == 0;
}

static void series_free(struct hl_suite_series *s)
{
	free(s->range_m);
	free(s->lx);
	free(s->t_s);
	s->range_m = s->lx = s->t_s = NULL;
	s->n = s->cap = 0;
}

void hl_suite_result_free(struct hl_suite_result *r)
{
	if (!r)
		return;
	for (int i = 0; r->v && i < r->n_variants; i++) {
		struct hl_suite_variant *v = &r->v[i];

		free(v->cases);
		v->cases = NULL;
		v->n_cases = 0;
		/* all of them: a half-built variant may hold series past n_series */
		for (int s = 0; s < HL_SUITE_MAX_SERIES; s++)
			series_free(&v->series[s]);
		v->n_series = 0;
		free(v->birdseye.left);
		free(v->birdseye.right);
		v->birdseye.left = v->birdseye.right = NULL;
		v->birdseye.n = 0;
	}
	free(r->v);
	r->v = NULL;
	r->n_variants = 0;
}

/* *p grown to cap doubles; on failure *p is untouched. */
static int grow(double **p, int cap)
{
	double *q = realloc(*p, (size_t)cap * sizeof(**p));

	if (!q)
		return -ENOMEM;
	*p = q;
	return 0;
}

int hl_suite_series_add(struct hl_suite_series *s, double range_m, double lx, double t_s)
{
	if (s->n == s->cap) {
		int cap;

		if (s->cap > INT_MAX / 2)
			return -ENOMEM;
		cap = s->cap ? 2 * s->cap : SERIES_FIRST_CAP;
		/* an array grown before a later one fails stays valid: cap is raised only after */
		if (grow(&s->range_m, cap) < 0 || grow(&s->lx, cap) < 0 || grow(&s->t_s, cap) < 0)
			return -ENOMEM;
		s->cap = cap;
	}
	s->range_m[s->n] = range_m;
	s->lx[s->n] = lx;
	s->t_s[s->n] = t_s;
	s->n++;
	return 0;
}
