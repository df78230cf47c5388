/* SPDX-License-Identifier: MIT */
/* The GLES combiner against the CPU reference: full, incremental, and the papers' method. */
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

#include "lamp/combine.h"
#include "render/egl.h"
#include "render/gl_combine.h"
#include "lamp/model.h"

static struct hl_egl *egl;
static struct hl_lid *lamp;

static int setup(void **state)
{
	struct hl_egl_error err;

	(void)state;
	if (hl_egl_new(&egl, &err) < 0 || hl_model_hd84(HL_SIDE_LEFT, &lamp) < 0)
		return -1;
	return 0;
}

static int teardown(void **state)
{
	(void)state;
	hl_lid_free(lamp);
	hl_egl_free(egl);
	return 0;
}

/* Largest |a - b| relative to max(|b|, 1e-6 of the peak of b). */
static double rel_diff(const float *a, const float *b, size_t n)
{
	double peak = 0.0, worst = 0.0;

	for (size_t i = 0; i < n; i++)
		peak = b[i] > peak ? b[i] : peak;
	for (size_t i = 0; i < n; i++) {
		const double floor_cd = 1e-6 * peak,
			     ref = fabs(b[i]) > floor_cd ? fabs(b[i]) : floor_cd;
		const double e = fabs((double)a[i] - b[i]) / ref;

		worst = e > worst ? e : worst;
	}
	return worst;
}

static void check_mode(enum hl_gl_combine_mode mode, int updates)
{
	const struct hl_lid_grid *g = hl_lid_grid(lamp);
	const size_t n = (size_t)g->width * g->height;
	float *gl = malloc(sizeof(float) * n), *ref = malloc(sizeof(float) * n);
	float i[HL_HD84_SOURCES];
	struct hl_gl_combiner *c;
	struct hl_preset *p;
	struct hl_lid *pair[2] = { lamp, lamp };
	double worst = 0.0, peak = 0.0;
	char log[512] = "";

	assert_non_null(gl);
	assert_non_null(ref);
	assert_int_equal(hl_gl_combiner_new(lamp, mode, 0, &c, log, sizeof(log)), 0);
	assert_int_equal(hl_preset_new(HL_HD84_SOURCES, &p), 0);
	assert_int_equal(hl_model_hd84_preset("high", pair, p), 0);
	hl_preset_intensities(p, HL_SIDE_LEFT, i);
	srand(5);
	for (int u = 0; u < updates; u++) {
		double e;

		if (u > 0) /* about ten sources change per ECU cycle */
			for (int j = 0; j < 10; j++)
				i[rand() % HL_HD84_SOURCES] = (float)(rand() % 64) / 63.0f;
		assert_true(hl_gl_combiner_update(c, i) >= 0);
		assert_int_equal(hl_gl_combiner_read(c, gl), 0);
		hl_combine_sparse(lamp, i, ref);
		e = rel_diff(gl, ref, n);
		worst = e > worst ? e : worst;
		if (u == 0) /* the high beam as it is */
			for (size_t j = 0; j < n; j++)
				peak = gl[j] > peak ? gl[j] : peak;
	}
	printf("%s, %d updates: high-beam peak %.0f cd, max relative difference %.2e\n",
	       mode == HL_GL_COMBINE_BOXES ? "boxes, incremental" : "full image (papers)", updates,
	       peak, worst);
	/* The high beam peaks above R16F's largest value (65,504): 32-bit accumulation holds it. */
	assert_true(peak > 65504.0);
	assert_true(worst <= 1e-5);
	i[3] = 1.5f;
	assert_int_equal(hl_gl_combiner_update(c, i), -EINVAL);
	hl_preset_free(p);
	hl_gl_combiner_free(c);
	free(gl);
	free(ref);
}

static void gl_combine_boxes_incremental_equals_cpu_reference(void **state)
{
	(void)state;
	check_mode(HL_GL_COMBINE_BOXES, 150);
}

static void gl_combine_full_image_equals_cpu_reference(void **state)
{
	(void)state;
	check_mode(HL_GL_COMBINE_FULL_IMAGE, 3);
}

static void gl_combine_rejects_combined_lid(void **state)
{
	struct hl_lid *combined;
	struct hl_gl_combiner *c = NULL;

	(void)state;
	assert_int_equal(hl_lid_new(1, hl_lid_grid(lamp), true, &combined), 0);
	assert_int_equal(hl_gl_combiner_new(combined, HL_GL_COMBINE_BOXES, 0, &c, NULL, 0),
			 -EINVAL);
	assert_null(c);
	hl_lid_free(combined);
	hl_gl_combiner_free(NULL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(gl_combine_boxes_incremental_equals_cpu_reference),
		cmocka_unit_test(gl_combine_full_image_equals_cpu_reference),
		cmocka_unit_test(gl_combine_rejects_combined_lid),
	};

	return cmocka_run_group_tests(tests, setup, teardown);
}
