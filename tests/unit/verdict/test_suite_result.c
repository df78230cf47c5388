/* SPDX-License-Identifier: MIT */
/*
 * verdict/suite_result.c on a result built by hand: the totals counted case by case, the overall
 * verdict (a failing case, an unfinished run, a bin with a limit never reached each fail it), a
 * series grown geometrically keeping every sample, a half-built result freed.
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "suite_fixture.h"

static void suite_totals_count_each_case(void **state)
{
	struct hl_suite *s = fixture_suite();
	struct hl_suite_result r;
	struct hl_suite_totals t;

	(void)state;
	fixture_result(&r, s, 2);
	hl_suite_result_totals(&r, &t);
	assert_int_equal(t.cases, 8);
	assert_int_equal(t.judged, 8);
	assert_int_equal(t.failed, 0);
	assert_int_equal(t.no_samples, 0);
	assert_int_equal(t.errors, 0);

	/* variant 0: bin 2 fails (2.46 rounds to 2.5 > 1.8), bin 3 never reached */
	r.v[0].cases[1] = fixture_case(1, 2.46, 42.0);
	r.v[0].cases[3] = fixture_case(3, NAN, NAN);
	/* variant 1: a case reported only (no limit), and its run did not finish */
	r.v[1].cases[0].limit = NAN;
	r.v[1].cases[0].judged = false;
	r.v[1].cases[0].pass = true;
	snprintf(r.v[1].error, sizeof(r.v[1].error), "the ECU stopped answering");
	r.v[1].exit_code = 1;
	hl_suite_result_totals(&r, &t);
	assert_int_equal(t.cases, 8);
	assert_int_equal(t.judged, 6);
	assert_int_equal(t.failed, 1);
	assert_int_equal(t.no_samples, 1);
	assert_int_equal(t.errors, 1);
	assert_false(hl_suite_result_passed(&r));
	hl_suite_result_free(&r);
	assert_null(r.v);
	assert_int_equal(r.n_variants, 0);
	free(s);
}

static void suite_passed_when_all_pass(void **state)
{
	struct hl_suite *s = fixture_suite();
	struct hl_suite_result r;

	(void)state;
	fixture_result(&r, s, 3);
	assert_true(hl_suite_result_passed(&r));
	hl_suite_result_free(&r);
	/* nothing run is nothing failed */
	assert_true(hl_suite_result_passed(&r));
	free(s);
}

static void suite_fails_on_one_failing_case(void **state)
{
	struct hl_suite *s = fixture_suite();
	struct hl_suite_result r;

	(void)state;
	fixture_result(&r, s, 3);
	r.v[2].cases[0] = fixture_case(0, 3.2, 20.0);
	assert_true(r.v[2].cases[0].judged);
	assert_false(r.v[2].cases[0].pass);
	assert_false(hl_suite_result_passed(&r));
	/* 3.14 as judged is 3.1: passes, as the case says */
	r.v[2].cases[0] = fixture_case(0, 3.14, 20.0);
	assert_true(hl_suite_result_passed(&r));
	hl_suite_result_free(&r);
	free(s);
}

static void suite_fails_on_unfinished_run(void **state)
{
	struct hl_suite *s = fixture_suite();
	struct hl_suite_result r;
	struct hl_suite_totals t;

	(void)state;
	fixture_result(&r, s, 2);
	snprintf(r.v[0].error, sizeof(r.v[0].error), "the FMU returned fmi2Error");
	assert_false(hl_suite_result_passed(&r));
	r.v[0].error[0] = '\0';
	assert_true(hl_suite_result_passed(&r));
	r.v[1].exit_code = 2; /* no message, still not finished */
	hl_suite_result_totals(&r, &t);
	assert_int_equal(t.errors, 1);
	assert_int_equal(t.failed, 0);
	assert_false(hl_suite_result_passed(&r));
	hl_suite_result_free(&r);
	free(s);
}

static void suite_fails_on_bin_never_reached(void **state)
{
	struct hl_suite *s = fixture_suite();
	struct hl_suite_result r;
	struct hl_suite_totals t;

	(void)state;
	fixture_result(&r, s, 1);
	r.v[0].cases[0] = fixture_case(0, NAN, NAN);
	assert_false(r.v[0].cases[0].judged);
	assert_true(r.v[0].cases[0].pass);
	hl_suite_result_totals(&r, &t);
	assert_int_equal(t.judged, 3);
	assert_int_equal(t.failed, 0);
	assert_int_equal(t.no_samples, 1);
	assert_false(hl_suite_result_passed(&r));
	hl_suite_result_free(&r);
	free(s);
}

static void suite_series_grows_keeping_samples(void **state)
{
	struct hl_suite_series ser = { 0 };
	int caps = 0, last_cap = 0;

	(void)state;
	for (int i = 0; i < 1000; i++) {
		assert_int_equal(hl_suite_series_add(&ser, 220.0 - 0.2 * i, 0.001 * i, 0.02 * i),
				 0);
		assert_int_equal(ser.n, i + 1);
		if (ser.cap != last_cap) {
			assert_int_equal(ser.cap, last_cap ? 2 * last_cap : 64);
			last_cap = ser.cap;
			caps++;
		}
	}
	assert_int_equal(ser.cap, 1024);
	assert_int_equal(caps, 5); /* 64 128 256 512 1024: geometric */
	for (int i = 0; i < 1000; i++) {
		assert_true(ser.range_m[i] == 220.0 - 0.2 * i);
		assert_true(ser.lx[i] == 0.001 * i);
		assert_true(ser.t_s[i] == 0.02 * i);
	}
	/* the series belongs to a variant; freeing the result frees it */
	{
		struct hl_suite_result r = { 0 };

		r.v = calloc(1, sizeof(*r.v));
		assert_non_null(r.v);
		r.n_variants = 1;
		r.v[0].series[0] = ser;
		r.v[0].n_series = 1;
		hl_suite_result_free(&r);
	}
}

static void suite_free_half_built(void **state)
{
	struct hl_suite_result r = { 0 };

	(void)state;
	hl_suite_result_free(NULL);
	hl_suite_result_free(&r); /* nothing allocated */
	r.v = calloc(2, sizeof(*r.v));
	assert_non_null(r.v);
	r.n_variants = 2;
	/* variant 0 got a series and bird's-eye edges, variant 1 nothing yet */
	assert_int_equal(hl_suite_series_add(&r.v[0].series[3], 10.0, 1.0, 0.0), 0);
	r.v[0].n_series = 1; /* not yet counting the series being filled */
	r.v[0].birdseye.left = malloc(4 * sizeof(*r.v[0].birdseye.left));
	assert_non_null(r.v[0].birdseye.left);
	r.v[0].birdseye.n = 4;
	hl_suite_result_free(&r); /* the leak checker of the sanitizer build sees the rest */
	assert_null(r.v);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(suite_totals_count_each_case),
		cmocka_unit_test(suite_passed_when_all_pass),
		cmocka_unit_test(suite_fails_on_one_failing_case),
		cmocka_unit_test(suite_fails_on_unfinished_run),
		cmocka_unit_test(suite_fails_on_bin_never_reached),
		cmocka_unit_test(suite_series_grows_keeping_samples),
		cmocka_unit_test(suite_free_half_built),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
