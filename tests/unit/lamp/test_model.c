/* SPDX-License-Identifier: MIT */
/* The HD84 model's physical properties (docs/design.md §1), asserted on the files it writes. */
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
	struct hl_lid *lamps[2]; /* read back from the files */
	struct hl_preset *presets[5]; /* read back from the files */
	size_t n;
	float *a, *b; /* scratch distributions */
};

static int preset_index(const char *name)
{
	for (int i = 0; hl_model_preset_names[i]; i++)
		if (strcmp(hl_model_preset_names[i], name) == 0)
			return i;
	return -1;
}

static int setup(void **state)
{
	struct fixture *f = calloc(1, sizeof(*f));
	struct hl_lid *built[2] = { NULL, NULL };
	struct hl_preset *p = NULL;
	struct hl_lid_error err;
	struct hl_preset_error perr;
	char path[512];

	if (!f)
		return -1;
	for (int s = 0; s < 2; s++) {
		char name[64];

		snprintf(name, sizeof(name), "hd84_%s.lid.exr", hl_side_name(s));
		if (hl_model_hd84(s, &built[s]) < 0 ||
		    hl_lid_write(built[s], test_path(path, sizeof(path), name), &err) < 0 ||
		    hl_lid_read(path, &f->lamps[s], &err) < 0)
			return -1;
		unlink(path);
	}
	if (hl_preset_new(HL_HD84_SOURCES, &p) < 0)
		return -1;
	for (int i = 0; hl_model_preset_names[i]; i++) {
		char name[64];

		snprintf(name, sizeof(name), "%s.json", hl_model_preset_names[i]);
		if (hl_model_hd84_preset(hl_model_preset_names[i], built, p) < 0 ||
		    hl_preset_write(p, test_path(path, sizeof(path), name)) < 0 ||
		    hl_preset_read(path, &f->presets[i], &perr) < 0)
			return -1;
		unlink(path);
	}
	hl_preset_free(p);
	hl_lid_free(built[0]);
	hl_lid_free(built[1]);
	f->n = (size_t)hl_lid_grid(f->lamps[0])->width * hl_lid_grid(f->lamps[0])->height;
	f->a = malloc(sizeof(float) * f->n);
	f->b = malloc(sizeof(float) * f->n);
	*state = f;
	return f->a && f->b ? 0 : -1;
}

static int teardown(void **state)
{
	struct fixture *f = *state;

	for (int s = 0; s < 2; s++)
		hl_lid_free(f->lamps[s]);
	for (int i = 0; i < 5; i++)
		hl_preset_free(f->presets[i]);
	free(f->a);
	free(f->b);
	free(f);
	return 0;
}

static void combine(struct fixture *f, const char *preset, int side, float *out)
{
	float i[HL_HD84_SOURCES];

	hl_preset_intensities(f->presets[preset_index(preset)], side, i);
	hl_combine_sparse(f->lamps[side], i, out);
}

static float peak(const struct hl_lid_grid *g, const float *d, float *ret_h, float *ret_v)
{
	size_t best = 0, n = (size_t)g->width * g->height;

	for (size_t s = 1; s < n; s++)
		if (d[s] > d[best])
			best = s;
	*ret_h = hl_lid_grid_h_deg(g, (int)(best % g->width));
	*ret_v = hl_lid_grid_v_deg(g, (int)(best / g->width));
	return d[best];
}

/* Mean of d over H in [h0, h1], V in [v0, v1], degrees. */
static double mean_over(const struct hl_lid_grid *g, const float *d, float h0, float h1, float v0,
			float v1)
{
	double sum = 0.0;
	int n = 0;

	for (int y = 0; y < g->height; y++)
		for (int x = 0; x < g->width; x++) {
			const float h = hl_lid_grid_h_deg(g, x), v = hl_lid_grid_v_deg(g, y);

			if (h >= h0 && h <= h1 && v >= v0 && v <= v1) {
				sum += d[(size_t)y * g->width + x];
				n++;
			}
		}
	return n ? sum / n : 0.0;
}

static void model_files_have_95_sources_on_the_default_grid(void **state)
{
	struct fixture *f = *state;

	for (int s = 0; s < 2; s++) {
		const struct hl_lid_grid *g = hl_lid_grid(f->lamps[s]);

		assert_int_equal(hl_lid_n_sources(f->lamps[s]), 95);
		assert_int_equal(g->width, 900);
		assert_int_equal(g->height, 250);
		assert_int_equal(g->angles, HL_ANGLES_A);
		assert_float_equal(g->h_first_deg, -89.9, 1e-5);
		assert_float_equal(g->h_last_deg, 89.9, 1e-5);
		assert_float_equal(g->v_first_deg, -29.9, 1e-5);
		assert_float_equal(g->v_last_deg, 19.9, 1e-5);
		assert_float_equal((g->h_last_deg - g->h_first_deg) / (g->width - 1), 0.2, 1e-6);
		assert_float_equal((g->v_last_deg - g->v_first_deg) / (g->height - 1), 0.2, 1e-6);
		assert_string_equal(hl_lid_name(f->lamps[s], 0), "row1_led01");
		assert_string_equal(hl_lid_name(f->lamps[s], 44), "row2_led17");
		assert_string_equal(hl_lid_name(f->lamps[s], HL_HD84_HB_SPOT - 1), "hb_spot");
		for (int k = 0; k < 95; k++)
			assert_true(hl_lid_peak_cd(f->lamps[s], k) > 0.0f);
	}
}

/* Three rows of 28 windows of a few degrees, row 1 lowest, mostly zero, small overlaps. */
static void model_matrix_leds_are_small_overlapping_windows(void **state)
{
	struct fixture *f = *state;
	const struct hl_lid_grid *g = hl_lid_grid(f->lamps[0]);
	float row_top[3];

	for (int r = 0; r < 3; r++) {
		struct hl_lid_box b;

		row_top[r] = -90.0f;
		for (int j = 0; j < 28; j++) {
			const int k = r * 28 + j;
			float width_deg, height_deg;

			hl_lid_source(f->lamps[0], k, &b);
			width_deg = (b.x1 - b.x0) * 0.2f;
			height_deg = (b.y1 - b.y0) * 0.2f;
			assert_true(width_deg > 1.0f && width_deg < 4.0f);
			assert_true(height_deg > 3.0f && height_deg < 9.0f);
			/* "most of each grid is zero" */
			assert_true((double)(b.x1 - b.x0) * (b.y1 - b.y0) <
				    0.005 * g->width * g->height);
			row_top[r] = fmaxf(row_top[r], hl_lid_grid_v_deg(g, b.y0));
			if (j > 0) {
				struct hl_lid_box prev;

				hl_lid_source(f->lamps[0], k - 1, &prev);
				/* numbered by increasing H; neighbours overlap, by less than half */
				assert_true(b.x0 > prev.x0);
				assert_true(b.x0 < prev.x1);
				assert_true(prev.x1 - b.x0 < (b.x1 - b.x0) / 2);
			}
		}
	}
	assert_true(row_top[0] < row_top[1] && row_top[1] < row_top[2]);
}

static void model_low_beam_peak_and_cutoff_step_at_h0(void **state)
{
	struct fixture *f = *state;
	const struct hl_lid_grid *g = hl_lid_grid(f->lamps[0]);

	for (int s = 0; s < 2; s++) {
		float h, v, p;
		double right, left;

		combine(f, "low", s, f->a);
		p = peak(g, f->a, &h, &v);
		print_message("low %s: peak %.0f cd at H %.1f V %.1f\n", hl_side_name(s), p, h, v);
		assert_true(p >= 15000.0f && p <= 35000.0f);
		assert_true(v < 0.0f); /* a low beam peaks below the horizon */
		/* Above the horizon: light at H > 0 (the rising cut-off), hardly any at H < 0. */
		right = mean_over(g, f->a, 1.0f, 6.0f, 0.2f, 0.8f);
		left = mean_over(g, f->a, -6.0f, -1.0f, 0.2f, 0.8f);
		print_message("low %s: above horizon right %.0f cd, left %.0f cd\n",
			      hl_side_name(s), right, left);
		assert_true(right > 1000.0);
		assert_true(right > 10.0 * left);
		/* The step sits at H = 0: just left of it dark, just right of it lit. */
		assert_true(mean_over(g, f->a, -0.8f, -0.4f, 0.2f, 0.6f) <
			    0.1 * mean_over(g, f->a, 0.4f, 0.8f, 0.2f, 0.6f));
	}
}

static void model_high_beam_3x_brighter_with_hot_spot_above_horizon(void **state)
{
	struct fixture *f = *state;
	const struct hl_lid_grid *g = hl_lid_grid(f->lamps[0]);

	for (int s = 0; s < 2; s++) {
		float h, v, low, high, symmetric_left, symmetric_right;

		combine(f, "low", s, f->a);
		low = peak(g, f->a, &h, &v);
		combine(f, "high", s, f->b);
		high = peak(g, f->b, &h, &v);
		print_message("high %s: peak %.0f cd at H %.1f V %.1f, %.2f x low\n",
			      hl_side_name(s), high, h, v, high / low);
		assert_true(high / low >= 2.5f && high / low <= 3.5f);
		assert_true(v > 0.0f && v <= 2.0f);
		assert_true(fabsf(h) <= 2.0f);
		/* symmetric: the field at ±5° H above the horizon within 20 % */
		symmetric_left = (float)mean_over(g, f->b, -6.0f, -4.0f, 0.5f, 1.5f);
		symmetric_right = (float)mean_over(g, f->b, 4.0f, 6.0f, 0.5f, 1.5f);
		assert_true(fabsf(symmetric_left - symmetric_right) < 0.2f * symmetric_right);
	}
}

static void model_presets_dim_led1_and_led45_as_specified(void **state)
{
	struct fixture *f = *state;
	const struct hl_preset *low = f->presets[preset_index("low")];
	const struct hl_preset *high = f->presets[preset_index("high")];

	for (int s = 0; s < 2; s++) {
		/* LED 1 at 3 %, LED 45 at 24 % (low) and 80 % (high), to a 6-bit step */
		assert_true(fabs(low->dim[s][0] / 63.0 - 0.03) < 0.5 / 63);
		assert_true(fabs(low->dim[s][44] / 63.0 - 0.24) < 0.5 / 63);
		assert_true(fabs(high->dim[s][44] / 63.0 - 0.80) < 0.5 / 63);
		for (int j = 0; j < 28; j++) {
			assert_true(low->dim[s][j] > 0); /* row 1 all on */
			assert_int_equal(low->dim[s][56 + j], 0); /* row 3 off */
			assert_true(high->dim[s][56 + j] > 0); /* high: all rows */
			if (j < 14)
				assert_int_equal(low->dim[s][28 + j], 0); /* row 2: left half off */
		}
		/* row 1: dimmed edges, full in the middle */
		assert_true(low->dim[s][0] < low->dim[s][1] && low->dim[s][1] < low->dim[s][13]);
		assert_int_equal(low->dim[s][13], 63);
	}
}

static void model_glarefree_keeps_the_oncoming_window_dark(void **state)
{
	struct fixture *f = *state;
	const struct hl_lid_grid *g = hl_lid_grid(f->lamps[0]);

	for (int s = 0; s < 2; s++) {
		double window, lit;

		combine(f, "glarefree", s, f->a);
		combine(f, "high", s, f->b);
		window = mean_over(g, f->a, HL_GLAREFREE_H_MIN, HL_GLAREFREE_H_MAX,
				   HL_GLAREFREE_V_MIN, HL_GLAREFREE_V_MAX);
		assert_true(window == 0.0);
		assert_true(mean_over(g, f->b, -6.0f, -2.0f, -0.3f, 2.0f) > 5000.0);
		/* the rest of the high beam stays: right of the window and far left */
		lit = mean_over(g, f->a, 3.0f, 8.0f, 0.0f, 2.0f);
		assert_true(lit > 0.3 * mean_over(g, f->b, 3.0f, 8.0f, 0.0f, 2.0f));
		assert_true(mean_over(g, f->a, -14.0f, -10.0f, 0.0f, 2.0f) > 1000.0);
	}
}

static void model_right_lamp_mirrors_outboard_sources_only(void **state)
{
	struct fixture *f = *state;
	const struct hl_lid_grid *g = hl_lid_grid(f->lamps[0]);
	static const int mirrored[][2] = {
		{ HL_HD84_APRON, HL_HD84_APRON },
		{ HL_HD84_CORNER, HL_HD84_CORNER },
		{ HL_HD84_BEND_LEFT, HL_HD84_BEND_RIGHT },
		{ HL_HD84_BEND_RIGHT, HL_HD84_BEND_LEFT },
	};

	/* Right lamp's source at H equals the left lamp's partner at -H. */
	for (size_t m = 0; m < sizeof(mirrored) / sizeof(mirrored[0]); m++) {
		hl_lid_source_dense(f->lamps[1], mirrored[m][0] - 1, f->a);
		hl_lid_source_dense(f->lamps[0], mirrored[m][1] - 1, f->b);
		for (int y = 0; y < g->height; y++)
			for (int x = 0; x < g->width; x++) {
				const float r = f->a[(size_t)y * g->width + x];
				const float l = f->b[(size_t)y * g->width + (g->width - 1 - x)];

				assert_true(fabsf(r - l) <= 1e-3f * fmaxf(l, 1.0f));
			}
	}
	/* The outboard corner light points outboard: left lamp left, right lamp right. */
	assert_true(mean_over(g, (hl_lid_source_dense(f->lamps[0], HL_HD84_CORNER - 1, f->a), f->a),
			      -70, -35, -10, -1) > 100.0);
	assert_true(mean_over(g, (hl_lid_source_dense(f->lamps[1], HL_HD84_CORNER - 1, f->a), f->a),
			      35, 70, -10, -1) > 100.0);
	/* Traffic-side asymmetry and the matrix are the same in both lamps. */
	for (int k = 0; k < HL_HD84_SOURCES; k++) {
		if (k == HL_HD84_APRON - 1 || k == HL_HD84_CORNER - 1 ||
		    k == HL_HD84_BEND_LEFT - 1 || k == HL_HD84_BEND_RIGHT - 1)
			continue;
		hl_lid_source_dense(f->lamps[0], k, f->a);
		hl_lid_source_dense(f->lamps[1], k, f->b);
		assert_memory_equal(f->a, f->b, sizeof(float) * f->n);
	}
}

static void model_bend_presets_light_their_side(void **state)
{
	struct fixture *f = *state;
	const struct hl_lid_grid *g = hl_lid_grid(f->lamps[0]);

	for (int s = 0; s < 2; s++) {
		double l_left, l_right, r_left, r_right;

		combine(f, "bend_left", s, f->a);
		l_left = mean_over(g, f->a, -35, -15, -4, -1);
		l_right = mean_over(g, f->a, 15, 35, -4, -1);
		combine(f, "bend_right", s, f->b);
		r_left = mean_over(g, f->b, -35, -15, -4, -1);
		r_right = mean_over(g, f->b, 15, 35, -4, -1);
		assert_true(l_left > 1.5 * l_right);
		assert_true(r_right > 1.5 * r_left);
	}
}

static void model_pixel_lamp_has_n_small_sources(void **state)
{
	struct hl_lid *lid;
	(void)state;

	assert_int_equal(hl_model_pixel(0, &lid), -EINVAL);
	assert_int_equal(hl_model_pixel(4097, &lid), -EINVAL);
	assert_int_equal(hl_model_pixel(256, &lid), 0);
	assert_int_equal(hl_lid_n_sources(lid), 256);
	for (int k = 0; k < 256; k++) {
		struct hl_lid_box b;

		assert_non_null(hl_lid_source(lid, k, &b));
		assert_true((b.x1 - b.x0) * (b.y1 - b.y0) < 900 * 250 / 100);
	}
	hl_lid_free(lid);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(model_files_have_95_sources_on_the_default_grid),
		cmocka_unit_test(model_matrix_leds_are_small_overlapping_windows),
		cmocka_unit_test(model_low_beam_peak_and_cutoff_step_at_h0),
		cmocka_unit_test(model_high_beam_3x_brighter_with_hot_spot_above_horizon),
		cmocka_unit_test(model_presets_dim_led1_and_led45_as_specified),
		cmocka_unit_test(model_glarefree_keeps_the_oncoming_window_dark),
		cmocka_unit_test(model_right_lamp_mirrors_outboard_sources_only),
		cmocka_unit_test(model_bend_presets_light_their_side),
		cmocka_unit_test(model_pixel_lamp_has_n_small_sources),
	};

	return cmocka_run_group_tests(tests, setup, teardown);
}
