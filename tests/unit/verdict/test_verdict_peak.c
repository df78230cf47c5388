/* SPDX-License-Identifier: MIT */
/*
 * verdict/verdict_peak.c: a distribution's highest sample and its index, of one lamp and of half
 * the pair's sum, across the L1 blocks and the vector lanes' tails; the copy that finds the peak
 * on the way; the first of equal peaks; a dark grid.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "verdict/verdict.h"

#define N 10007 /* three 4096-sample blocks and a tail that is no multiple of the lanes */

static float *ramp(float scale)
{
	float *x = malloc(sizeof(float) * N);

	assert_non_null(x);
	for (size_t i = 0; i < N; i++)
		x[i] = scale * (float)(i % 97);
	return x;
}

static void verdict_peak_of_one_lamp_and_of_half_the_pair(void **state)
{
	float *a = ramp(1.0f), *b = ramp(0.5f);
	struct hl_verdict_peak p;
	(void)state;

	a[9001] = 5000.0f; /* in the third block */
	hl_verdict_peak(N, a, NULL, &p);
	assert_true(p.value_cd == 5000.0f);
	assert_int_equal(p.index, 9001);
	/* half the pair's sum: b's peak in the last sample outweighs a's */
	b[N - 1] = 20000.0f;
	hl_verdict_peak(N, a, b, &p);
	assert_int_equal(p.index, N - 1);
	assert_true(p.value_cd == 0.5f * (a[N - 1] + 20000.0f));
	free(a);
	free(b);
}

static void verdict_peak_first_of_equal_peaks_and_a_dark_grid(void **state)
{
	float *a = calloc(N, sizeof(float));
	struct hl_verdict_peak p;
	(void)state;

	assert_non_null(a);
	hl_verdict_peak(N, a, NULL, &p);
	assert_true(p.value_cd == 0.0f);
	assert_int_equal(p.index, 0);
	a[4095] = 7.0f; /* the last of the first block */
	a[4096] = 7.0f; /* the first of the second */
	a[9999] = 7.0f;
	hl_verdict_peak(N, a, NULL, &p);
	assert_true(p.value_cd == 7.0f);
	assert_int_equal(p.index, 4095);
	free(a);
}

static void verdict_copy_peak_copies_and_finds_the_same(void **state)
{
	float *src = ramp(2.0f), *dst = malloc(sizeof(float) * N);
	struct hl_verdict_peak p, q;
	(void)state;

	assert_non_null(dst);
	src[4097] = 1e6f;
	hl_verdict_copy_peak(dst, src, N, &p);
	assert_memory_equal(dst, src, sizeof(float) * N);
	hl_verdict_peak(N, src, NULL, &q);
	assert_true(p.value_cd == 1e6f && q.value_cd == 1e6f);
	assert_int_equal(p.index, 4097);
	assert_int_equal(q.index, 4097);
	free(src);
	free(dst);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(verdict_peak_of_one_lamp_and_of_half_the_pair),
		cmocka_unit_test(verdict_peak_first_of_equal_peaks_and_a_dark_grid),
		cmocka_unit_test(verdict_copy_peak_copies_and_finds_the_same),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
