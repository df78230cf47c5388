/* SPDX-License-Identifier: MIT */
/*
 * The distribution's peak for the Imax requirements (verdict/verdict.h, hl_verdict_peak and
 * hl_verdict_copy_peak): vectorised lanes over blocks that stay in L1. Compiled aligned like
 * verdict.c (verdict/CMakeLists.txt).
 */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "lamp/angles.h"
#include "verdict/verdict.h"

#define MAX_LANES 8
static float max_of(const float *a, size_t n)
{
	float lane[MAX_LANES] = { 0.0f };
	size_t i = 0;

	for (; i + MAX_LANES <= n; i += MAX_LANES)
		for (int k = 0; k < MAX_LANES; k++)
			lane[k] = a[i + k] > lane[k] ? a[i + k] : lane[k];
	for (; i < n; i++)
		lane[0] = a[i] > lane[0] ? a[i] : lane[0];
	for (int k = 1; k < MAX_LANES; k++)
		lane[0] = lane[k] > lane[0] ? lane[k] : lane[0];
	return lane[0];
}

static float max_sum(const float *a, const float *b, size_t n)
{
	float lane[MAX_LANES] = { 0.0f };
	size_t i = 0;

	for (; i + MAX_LANES <= n; i += MAX_LANES)
		for (int k = 0; k < MAX_LANES; k++) {
			const float x = a[i + k] + b[i + k];

			lane[k] = x > lane[k] ? x : lane[k];
		}
	for (; i < n; i++) {
		const float x = a[i] + b[i];

		lane[0] = x > lane[0] ? x : lane[0];
	}
	for (int k = 1; k < MAX_LANES; k++)
		lane[0] = lane[k] > lane[0] ? lane[k] : lane[0];
	return lane[0];
}

/* The highest sample, and where; two passes so that the first vectorises. */
#define PEAK_BLOCK 4096 /* samples: a block stays in L1 between its copy and its scan */

/* The block holding the largest value of x (or x + y), and that value; blocks of PEAK_BLOCK. */
static void peak_in_blocks(const float *x, const float *y, size_t n, float *ret_m,
			   size_t *ret_index)
{
	float m = -1.0f;
	size_t best = 0, at;

	for (size_t b0 = 0; b0 < n; b0 += PEAK_BLOCK) {
		const size_t len = n - b0 < PEAK_BLOCK ? n - b0 : PEAK_BLOCK;
		const float bm = y ? max_sum(x + b0, y + b0, len) : max_of(x + b0, len);

		if (bm > m) {
			m = bm;
			best = b0;
		}
	}
	/* the first sample of the best block that holds it */
	for (at = best; at < n && (y ? x[at] + y[at] : x[at]) != m; at++)
		;
	*ret_m = m < 0.0f ? 0.0f : m;
	*ret_index = at == n ? 0 : at;
}

void hl_verdict_peak(size_t n, const float *a, const float *b, struct hl_verdict_peak *ret)
{
	float m;

	peak_in_blocks(a, b, n, &m, &ret->index);
	ret->value_cd = b ? 0.5f * m : m;
}

void hl_verdict_copy_peak(float *restrict dst, const float *restrict src, size_t n,
			  struct hl_verdict_peak *ret)
{
	float m = -1.0f;
	size_t best = 0, at;

	for (size_t b0 = 0; b0 < n; b0 += PEAK_BLOCK) {
		const size_t len = n - b0 < PEAK_BLOCK ? n - b0 : PEAK_BLOCK;
		float bm;

		memcpy(dst + b0, src + b0, len * sizeof(float));
		bm = max_of(dst + b0, len); /* still in L1 */
		if (bm > m) {
			m = bm;
			best = b0;
		}
	}
	for (at = best; at < n && dst[at] != m; at++)
		;
	ret->value_cd = m < 0.0f ? 0.0f : m;
	ret->index = at == n ? 0 : at;
}
