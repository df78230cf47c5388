/* SPDX-License-Identifier: MIT */
/*
 * verdict/suite_judge.c: the bin rule at every edge of the shipped FMVSS table (14.99, 15.0,
 * 29.9, 29.95, 30.0, ..., 220.0, 220.01), the rounding (half to even as ASTM E29, half up),
 * a variant's cases from samples (the bin maximum, where it occurred, the rounded value
 * against the limit, the margin, a bin never reached, samples outside the measured range
 * ignored), and the R149 rows' cases from glare results.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "verdict/suite_judge.h"
#include "suite_util.h"

/* The bin's bounds as the table writes them, or -1, -1 for none. */
static void bin_is(const struct hl_suite *s, enum hl_actor_role role, double range, double from,
		   double to)
{
	const int b = hl_suite_bin_of(s, role, range);

	if (from < 0) {
		if (b != -1)
			fail_msg("%.2f m: in bin %.1f-%.1f, expected none", range, s->bin[b].from_m,
				 s->bin[b].to_m);
		return;
	}
	if (b < 0 || s->bin[b].from_m != from || s->bin[b].to_m != to)
		fail_msg("%.2f m: bin %d, expected %.1f-%.1f", range, b, from, to);
}

static void judge_bin_edges(void **state)
{
	(void)state;
	struct hl_suite *s = read_shipped("fmvss108-adb");
	const enum hl_actor_role on = HL_ROLE_ONCOMING, pre = HL_ROLE_PRECEDING;

	bin_is(s, on, 14.99, -1, -1);
	bin_is(s, on, 15.0, 15.0, 29.9);
	bin_is(s, on, 29.9, 15.0, 29.9);
	bin_is(s, on, 29.95, 15.0, 29.9);
	bin_is(s, on, 30.0, 30.0, 59.9);
	bin_is(s, on, 59.9, 30.0, 59.9);
	bin_is(s, on, 59.95, 30.0, 59.9);
	bin_is(s, on, 60.0, 60.0, 119.9);
	bin_is(s, on, 119.9, 60.0, 119.9);
	bin_is(s, on, 119.95, 60.0, 119.9);
	bin_is(s, on, 120.0, 120.0, 220.0);
	bin_is(s, on, 219.99, 120.0, 220.0);
	bin_is(s, on, 220.0, 120.0, 220.0);
	bin_is(s, on, 220.01, -1, -1);
	bin_is(s, on, NAN, -1, -1);
	bin_is(s, pre, 14.99, -1, -1);
	bin_is(s, pre, 15.0, 15.0, 29.9);
	bin_is(s, pre, 29.95, 15.0, 29.9);
	bin_is(s, pre, 30.0, 30.0, 59.9);
	bin_is(s, pre, 60.0, 60.0, 119.9);
	bin_is(s, pre, 119.95, 60.0, 119.9);
	/* the preceding table has no limit beyond 119.9 m: a bin that is reported only */
	{
		const int b = hl_suite_bin_of(s, pre, 150.0);

		assert_true(b < 0 || isnan(s->bin[b].max_lx));
	}
	hl_suite_free(s);
}

static void judge_rounding(void **state)
{
	(void)state;
	struct hl_suite s = { .has_rounding = true, .decimals = 1, .rounding = HL_SUITE_HALF_EVEN };

	assert_true(hl_suite_round(&s, 0.25) == 0.2); /* a tie: to the even digit */
	assert_true(hl_suite_round(&s, 0.35) == 0.4); /* 0.35 is 0.34999... in binary: a tie */
	assert_true(hl_suite_round(&s, 3.05) == 3.0);
	assert_true(hl_suite_round(&s, 3.15) == 3.2);
	assert_true(hl_suite_round(&s, 3.149) == 3.1);
	assert_true(hl_suite_round(&s, 3.151) == 3.2);
	assert_true(hl_suite_round(&s, 0.3) == 0.3);
	assert_true(hl_suite_round(&s, 0.0) == 0.0);
	assert_true(hl_suite_round(&s, -0.25) == -0.2);
	assert_true(isnan(hl_suite_round(&s, NAN)));
	s.rounding = HL_SUITE_HALF_UP;
	assert_true(hl_suite_round(&s, 0.25) == 0.3);
	assert_true(hl_suite_round(&s, 3.05) == 3.1);
	assert_true(hl_suite_round(&s, 3.04) == 3.0);
	s.decimals = 2;
	assert_true(hl_suite_round(&s, 0.305) == 0.31);
	s.has_rounding = false;
	assert_true(hl_suite_round(&s, 0.3049) == 0.3049);
}

static struct hl_suite_case *find(struct hl_suite_variant *v, double from, const char *pm)
{
	for (int i = 0; i < v->n_cases; i++)
		if (v->cases[i].from_m == from && !strcmp(v->cases[i].photometer, pm))
			return &v->cases[i];
	fail_msg("no case %.1f m at %s", from, pm);
	return NULL;
}

static void judge_fmvss_cases(void **state)
{
	(void)state;
	struct hl_suite *s = read_shipped("fmvss108-adb");
	struct hl_suite_variant v = { .range_m = { 15.0, 60.0 } };
	struct hl_suite_case *c;
	int pm = -1, n_on = 0;

	assert_non_null(s);
	for (int p = 0; p < s->n_photometers; p++)
		if (s->photometer[p].role == HL_ROLE_ONCOMING) {
			n_on++;
			if (pm < 0)
				pm = p;
		}
	assert_true(pm >= 0);
	/* 15-60 m: the bins 15.0-29.9 and 30.0-59.9; 60.0-119.9 meets it in one point only */
	assert_int_equal(hl_suite_fmvss_cases(s, HL_ROLE_ONCOMING, &v), 0);
	assert_int_equal(v.n_cases, 2 * n_on);
	hl_suite_fmvss_sample(s, &v, pm, 14.0, 99.0, 0.0); /* outside the measured range */
	hl_suite_fmvss_sample(s, &v, pm, 29.95, 3.12, 1.0); /* 3.1 as judged: passes 3.1 */
	hl_suite_fmvss_sample(s, &v, pm, 25.0, 2.0, 1.5);
	hl_suite_fmvss_sample(s, &v, pm, 45.0, 1.86, 0.5); /* 1.9 > 1.8: fails */
	hl_suite_fmvss_sample(s, &v, pm, 31.0, 1.7, 0.9);
	hl_suite_fmvss_sample(s, &v, pm, 60.0, 0.05, 0.2); /* a bin not judged here */
	hl_suite_fmvss_sample(s, &v, pm, 61.0, 5.0, 0.1); /* beyond 60 m: not measured */
	hl_suite_judge_finish(s, &v);

	c = find(&v, 15.0, s->photometer[pm].id);
	assert_int_equal(c->n_samples, 2);
	assert_true(c->max_raw == 3.12 && c->value == 3.1 && c->limit == 3.1);
	assert_true(c->judged && c->pass && c->margin == 0.0);
	assert_true(c->at_range_m == 29.95 && c->at_t_s == 1.0);
	assert_string_equal(c->unit, "lx");
	assert_true(strlen(c->source) > 0);
	c = find(&v, 30.0, s->photometer[pm].id);
	assert_int_equal(c->n_samples, 2);
	assert_true(c->max_raw == 1.86 && fabs(c->value - 1.9) < 1e-12 && c->limit == 1.8);
	assert_true(c->judged && !c->pass && fabs(c->margin + 0.1) < 1e-12);
	assert_true(c->at_range_m == 45.0);
	for (int i = 0; i < v.n_cases; i++)
		assert_true(v.cases[i].from_m != 60.0);
	/* another photometer of the oncoming car: limits, but never sampled */
	for (int p = 0; p < s->n_photometers; p++)
		if (p != pm && s->photometer[p].role == HL_ROLE_ONCOMING) {
			c = find(&v, 15.0, s->photometer[p].id);
			assert_true(c->no_samples && !c->judged && !c->pass);
		}
	free(v.cases);
	hl_suite_free(s);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(judge_bin_edges),
		cmocka_unit_test(judge_rounding),
		cmocka_unit_test(judge_fmvss_cases),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
