/* SPDX-License-Identifier: MIT */
/* render/gbuffer_diff.c: which pixels changed for the headlight pass, exactly. */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "render/gbuffer_diff.h"

#define W 8
#define H 4
#define N (W * H)

/* Every pixel on the ground (z = 0, normal up) at its own x, id road, albedo 0.1. */
static void ground(struct hl_gbuffer *gb)
{
	for (int i = 0; i < N; i++) {
		const float p[4] = { 5.0f + i, -1.0f, 0.0f, 0.1f },
			    n[4] = { 0, 0, 1, HL_SURF_ROAD };

		memcpy(gb->pos + 4 * i, p, sizeof(p));
		memcpy(gb->nrm + 4 * i, n, sizeof(n));
		gb->albedo[i] = 0.1f;
	}
}

static size_t flagged(const struct hl_gbuffer_diff *d)
{
	size_t n = 0;

	for (int i = 0; i < N; i++)
		n += hl_gbuffer_diff_flags(d)[i];
	return n;
}

static void gbuffer_diff_counts_geometry_not_albedo_or_id(void **state)
{
	struct hl_gbuffer *gb = NULL;
	struct hl_gbuffer_diff *d = NULL;

	(void)state;
	assert_int_equal(hl_gbuffer_new(W, H, &gb), 0);
	ground(gb);
	assert_int_equal(hl_gbuffer_diff_new(W, H, gb, &d), 0);
	assert_int_equal(flagged(d), 0);
	assert_int_equal(hl_gbuffer_diff_band(d, gb, 0, N, false), 0);

	/* markings slide under the car: albedo and surface id change, the geometry does not */
	for (int i = 0; i < N; i += 3) {
		gb->pos[4 * i + 3] = 0.6f;
		gb->albedo[i] = 0.6f;
		gb->nrm[4 * i + 3] = HL_SURF_MARKING;
	}
	assert_int_equal(hl_gbuffer_diff_band(d, gb, 0, N, false), 0);
	assert_int_equal(flagged(d), 0);

	/* position (one ulp), normal, -0 for +0: changed, bit for bit */
	gb->pos[4 * 5 + 0] = nextafterf(gb->pos[4 * 5 + 0], 100.0f);
	gb->nrm[4 * 9 + 1] = 0.1f;
	gb->pos[4 * 17 + 2] = -0.0f;
	assert_int_equal(hl_gbuffer_diff_band(d, gb, 0, N, false), 3);
	assert_int_equal(flagged(d), 3);
	assert_int_equal(hl_gbuffer_diff_flags(d)[5], 1);
	assert_int_equal(hl_gbuffer_diff_flags(d)[9], 1);
	assert_int_equal(hl_gbuffer_diff_flags(d)[17], 1);
	/* taken into the copy: the same G-buffer again is no change */
	assert_int_equal(hl_gbuffer_diff_band(d, gb, 0, N, false), 0);
	assert_int_equal(flagged(d), 0);

	/* hit -> nothing, then nothing -> nothing at another position, then nothing -> hit */
	gb->nrm[4 * 20 + 3] = HL_SURF_NONE;
	assert_int_equal(hl_gbuffer_diff_band(d, gb, 0, N, false), 1);
	assert_int_equal(hl_gbuffer_diff_flags(d)[20], 1);
	gb->pos[4 * 20 + 0] = 1e6f;
	gb->nrm[4 * 20 + 2] = -1.0f;
	assert_int_equal(hl_gbuffer_diff_band(d, gb, 0, N, false), 0);
	gb->nrm[4 * 20 + 3] = HL_SURF_POST;
	assert_int_equal(hl_gbuffer_diff_band(d, gb, 0, N, false), 1);
	assert_int_equal(hl_gbuffer_diff_flags(d)[20], 1);

	hl_gbuffer_diff_free(d);
	hl_gbuffer_free(gb);
}

static void gbuffer_diff_compares_its_band_only(void **state)
{
	struct hl_gbuffer *gb = NULL;
	struct hl_gbuffer_diff *d = NULL;

	(void)state;
	assert_int_equal(hl_gbuffer_new(W, H, &gb), 0);
	ground(gb);
	assert_int_equal(hl_gbuffer_diff_new(W, H, gb, &d), 0);
	gb->pos[4 * 3 + 2] = 1.0f;
	gb->pos[4 * 30 + 2] = 1.0f;
	/* pixels 0 .. 15: pixel 3 only; pixel 30 waits for its band */
	assert_int_equal(hl_gbuffer_diff_band(d, gb, 0, 16, false), 1);
	assert_int_equal(hl_gbuffer_diff_flags(d)[3], 1);
	assert_int_equal(hl_gbuffer_diff_flags(d)[30], 0);
	assert_int_equal(hl_gbuffer_diff_band(d, gb, 16, 16, false), 1);
	assert_int_equal(hl_gbuffer_diff_flags(d)[30], 1);
	assert_int_equal(hl_gbuffer_diff_flags(d)[3], 1); /* not its band: kept */
	/* all: every pixel of the band, whatever it holds */
	assert_int_equal(hl_gbuffer_diff_band(d, gb, 8, 10, true), 10);
	assert_int_equal(hl_gbuffer_diff_band(d, gb, 0, N, false), 0);
	hl_gbuffer_diff_free(d);

	/* without a G-buffer to start from, the first comparison takes everything */
	assert_int_equal(hl_gbuffer_diff_new(W, H, NULL, &d), 0);
	assert_int_equal(hl_gbuffer_diff_band(d, gb, 0, N, true), N);
	assert_int_equal(hl_gbuffer_diff_band(d, gb, 0, N, false), 0);
	hl_gbuffer_diff_free(d);
	hl_gbuffer_diff_free(NULL);
	hl_gbuffer_free(gb);
}

static void gbuffer_diff_refuses_other_sizes(void **state)
{
	struct hl_gbuffer *gb = NULL;
	struct hl_gbuffer_diff *d = NULL;

	(void)state;
	assert_int_equal(hl_gbuffer_new(W, H, &gb), 0);
	assert_int_equal(hl_gbuffer_diff_new(W + 1, H, gb, &d), -EINVAL);
	assert_int_equal(hl_gbuffer_diff_new(W, 0, NULL, &d), -EINVAL);
	assert_int_equal(hl_gbuffer_diff_new(-1, H, NULL, &d), -EINVAL);
	assert_null(d);
	hl_gbuffer_free(gb);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(gbuffer_diff_counts_geometry_not_albedo_or_id),
		cmocka_unit_test(gbuffer_diff_compares_its_band_only),
		cmocka_unit_test(gbuffer_diff_refuses_other_sizes),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
