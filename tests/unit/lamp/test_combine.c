/* SPDX-License-Identifier: MIT */
/* The reference combiner against a naive double-precision sum, sparse and incremental. */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "lamp/combine.h"
#include "lamp/model.h"
#include "testutil.h"

struct fixture {
	struct hl_lid *lid;
	float *dense; /* all sources, dense, for the naive sum */
	double *naive;
	size_t n_samples;
};

static int setup(void **state)
{
	struct fixture *f = calloc(1, sizeof(*f));
	const struct hl_lid_grid *g;
	int k;

	if (!f || hl_model_hd84(HL_SIDE_LEFT, &f->lid) < 0)
		return -1;
	g = hl_lid_grid(f->lid);
	f->n_samples = (size_t)g->width * g->height;
	f->dense = malloc(sizeof(float) * f->n_samples * HL_HD84_SOURCES);
	f->naive = malloc(sizeof(double) * f->n_samples);
	if (!f->dense || !f->naive)
		return -1;
	for (k = 0; k < HL_HD84_SOURCES; k++)
		hl_lid_source_dense(f->lid, k, f->dense + f->n_samples * k);
	*state = f;
	return 0;
}

static int teardown(void **state)
{
	struct fixture *f = *state;

	hl_lid_free(f->lid);
	free(f->dense);
	free(f->naive);
	free(f);
	return 0;
}

static void naive_sum(struct fixture *f, const float *i)
{
	for (size_t s = 0; s < f->n_samples; s++) {
		double sum = 0.0;

		for (int k = 0; k < HL_HD84_SOURCES; k++)
			sum += (double)i[k] * (double)f->dense[f->n_samples * k + s];
		f->naive[s] = sum;
	}
}

/* The ECU's values: v / 63. */
static void random_intensities(unsigned long long *rng, float *i)
{
	for (int k = 0; k < HL_HD84_SOURCES; k++)
		i[k] = (float)(test_rand(rng) % 64) / 63.0f;
}

static void combine_sparse_matches_naive_double_per_sample(void **state)
{
	struct fixture *f = *state;
	unsigned long long rng = 42;
	float i[HL_HD84_SOURCES], *out = malloc(sizeof(float) * f->n_samples);
	double worst = 0.0;

	assert_non_null(out);
	for (int trial = 0; trial < 5; trial++) {
		random_intensities(&rng, i);
		hl_combine_sparse(f->lid, i, out);
		naive_sum(f, i);
		for (size_t s = 0; s < f->n_samples; s++) {
			if (f->naive[s] == 0.0) {
				assert_true(out[s] == 0.0f);
				continue;
			}
			worst = fmax(worst, fabs(out[s] - f->naive[s]) / f->naive[s]);
		}
	}
	print_message("sparse: worst per-sample relative error %.3g\n", worst);
	assert_true(worst <= 1e-5);
	free(out);
}

/*
 * 100,000 incremental updates of 1..12 random sources each. Relative error is measured
 * against the distribution's peak (‖a − b‖∞ / ‖b‖∞): a sample that drops from the peak to
 * near zero by subtraction keeps an absolute error of a few float ulps of the peak.
 */
static void combine_incremental_stays_within_1e5_after_100k_updates(void **state)
{
	struct fixture *f = *state;
	struct hl_combiner *c;
	unsigned long long rng = 7;
	float i[HL_HD84_SOURCES] = { 0 };
	double worst = 0.0;

	assert_int_equal(hl_combiner_new(f->lid, 0, &c), 0);
	for (int u = 1; u <= 100000; u++) {
		const int n = 1 + (int)(test_rand(&rng) % 12);

		for (int j = 0; j < n; j++)
			i[test_rand(&rng) % HL_HD84_SOURCES] =
				(float)(test_rand(&rng) % 64) / 63.0f;
		assert_true(hl_combiner_update(c, i) >= 0);
		if (u % 25000 == 0 || u == 99999) {
			const float *out = hl_combiner_result(c);
			double peak = 0.0, err = 0.0;

			naive_sum(f, i);
			for (size_t s = 0; s < f->n_samples; s++) {
				peak = fmax(peak, f->naive[s]);
				err = fmax(err, fabs(out[s] - f->naive[s]));
			}
			worst = fmax(worst, err / peak);
		}
	}
	print_message("incremental: worst relative error %.3g after 100000 updates\n", worst);
	assert_true(worst <= 1e-5);
	hl_combiner_free(c);
}

static void combiner_counts_changed_sources_and_rejects_bad_values(void **state)
{
	struct fixture *f = *state;
	struct hl_combiner *c;
	float i[HL_HD84_SOURCES] = { 0 };

	assert_int_equal(hl_combiner_new(f->lid, 0, &c), 0);
	assert_int_equal(hl_combiner_update(c, i), 0);
	i[3] = 0.5f;
	i[90] = 1.0f;
	assert_int_equal(hl_combiner_update(c, i), 2);
	assert_int_equal(hl_combiner_update(c, i), 0);
	i[3] = 1.5f;
	assert_int_equal(hl_combiner_update(c, i), -EINVAL);
	i[3] = NAN;
	assert_int_equal(hl_combiner_update(c, i), -EINVAL);
	assert_true(hl_combiner_intensities(c)[3] == 0.5f);
	assert_true(hl_combiner_intensities(c)[90] == 1.0f);
	hl_combiner_free(c);
	hl_combiner_free(NULL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(combine_sparse_matches_naive_double_per_sample),
		cmocka_unit_test(combine_incremental_stays_within_1e5_after_100k_updates),
		cmocka_unit_test(combiner_counts_changed_sources_and_rejects_bad_values),
	};

	return cmocka_run_group_tests(tests, setup, teardown);
}
