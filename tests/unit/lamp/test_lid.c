/* SPDX-License-Identifier: MIT */
/* The LID grid: sample positions, bilinear lookup, zero outside, source validation. */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "lamp/angles.h"
#include "lamp/lid.h"

static const struct hl_lid_grid grid = { 4, 3, HL_ANGLES_A, -1.0f, 2.0f, -1.0f, 1.0f };
/* rows: V = 1, 0, -1; columns H = -1, 0, 1, 2 */
static const float dense[12] = { 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12 };

static void lid_grid_samples_at_texel_centres(void **state)
{
	(void)state;
	assert_true(hl_lid_grid_h_deg(&grid, 0) == -1.0f);
	assert_true(hl_lid_grid_h_deg(&grid, 3) == 2.0f);
	assert_true(hl_lid_grid_v_deg(&grid, 0) == 1.0f);
	assert_true(hl_lid_grid_v_deg(&grid, 2) == -1.0f);
	assert_true(hl_lid_grid_lookup(&grid, dense, -1.0f, 1.0f) == 1.0f);
	assert_true(hl_lid_grid_lookup(&grid, dense, 2.0f, -1.0f) == 12.0f);
	assert_true(hl_lid_grid_lookup(&grid, dense, 0.0f, 0.0f) == 6.0f);
}

static void lid_grid_lookup_is_bilinear(void **state)
{
	(void)state;
	assert_float_equal(hl_lid_grid_lookup(&grid, dense, -0.5f, 1.0f), 1.5f, 1e-6);
	assert_float_equal(hl_lid_grid_lookup(&grid, dense, -1.0f, 0.5f), 3.0f, 1e-6);
	assert_float_equal(hl_lid_grid_lookup(&grid, dense, 0.5f, -0.5f), 8.5f, 1e-6);
	/* the samples are 1 + x + 4 y, linear, so bilinear is exact: x = 2.75, y = 0.75 */
	assert_float_equal(hl_lid_grid_lookup(&grid, dense, 1.75f, 0.25f), 1.0f + 2.75f + 3.0f,
			   1e-5);
}

/* Equal grids sample the same directions: every field counts. */
static void lid_grid_equal_compares_every_field(void **state)
{
	struct hl_lid_grid g = grid;

	(void)state;
	assert_true(hl_lid_grid_equal(&grid, &g));
	for (int field = 0; field < 7; field++) {
		g = grid;
		switch (field) {
		case 0:
			g.width++;
			break;
		case 1:
			g.height++;
			break;
		case 2:
			g.angles = HL_ANGLES_B;
			break;
		case 3:
			g.h_first_deg -= 0.5f;
			break;
		case 4:
			g.h_last_deg += 0.5f;
			break;
		case 5:
			g.v_first_deg -= 0.5f;
			break;
		default:
			g.v_last_deg += 0.5f;
			break;
		}
		assert_false(hl_lid_grid_equal(&grid, &g));
		assert_false(hl_lid_grid_equal(&g, &grid));
	}
}

static void lid_grid_lookup_is_zero_outside(void **state)
{
	(void)state;
	assert_true(hl_lid_grid_lookup(&grid, dense, -1.001f, 0.0f) == 0.0f);
	assert_true(hl_lid_grid_lookup(&grid, dense, 2.001f, 0.0f) == 0.0f);
	assert_true(hl_lid_grid_lookup(&grid, dense, 0.0f, 1.001f) == 0.0f);
	assert_true(hl_lid_grid_lookup(&grid, dense, 0.0f, -1.001f) == 0.0f);
	assert_true(hl_lid_grid_lookup(&grid, dense, NAN, 0.0f) == 0.0f);
}

static void lid_rejects_bad_grids_and_values(void **state)
{
	struct hl_lid_grid g = grid;
	struct hl_lid *lid = NULL;
	float bad[12] = { 0 };
	(void)state;

	g.width = 1;
	assert_int_equal(hl_lid_new(1, &g, false, &lid), -EINVAL);
	g = grid;
	g.h_first_deg = 3.0f;
	assert_int_equal(hl_lid_new(1, &g, false, &lid), -EINVAL);
	g = grid;
	g.v_last_deg = 91.0f;
	assert_int_equal(hl_lid_new(1, &g, false, &lid), -EINVAL);
	assert_int_equal(hl_lid_new(0, &grid, false, &lid), -EINVAL);
	assert_int_equal(hl_lid_new(HL_LID_MAX_SOURCES + 1, &grid, false, &lid), -EINVAL);
	assert_int_equal(hl_lid_new(2, &grid, true, &lid), -EINVAL);
	assert_null(lid);

	assert_int_equal(hl_lid_new(2, &grid, false, &lid), 0);
	bad[5] = -1.0f;
	assert_int_equal(hl_lid_set_source(lid, 0, bad), -EINVAL);
	bad[5] = INFINITY;
	assert_int_equal(hl_lid_set_source(lid, 0, bad), -EINVAL);
	assert_int_equal(hl_lid_set_source(lid, 2, dense), -EINVAL);
	assert_int_equal(hl_lid_set_name(lid, 0, "two\nlines"), -EINVAL);
	assert_int_equal(hl_lid_set_source(lid, 1, dense), 0);
	assert_true(hl_lid_peak_cd(lid, 1) == 12.0f);
	hl_lid_free(lid);
	hl_lid_free(NULL);
}

static void angles_type_a_and_b_differ_as_design_says(void **state)
{
	const double deg = M_PI / 180.0;
	double d[3], h, v;
	(void)state;

	/* The same direction: type A (20°, 5°) is not type B (20°, 5°); ~0.3° apart in V. */
	hl_angles_to_dir(HL_ANGLES_A, 20 * deg, 5 * deg, d);
	hl_angles_from_dir(HL_ANGLES_B, d, &h, &v);
	assert_true(fabs(v / deg - 5.0) > 0.25 && fabs(v / deg - 5.0) < 0.35);
	/* Both round-trip exactly (to double rounding). */
	for (int s = 0; s < 2; s++) {
		hl_angles_to_dir(s, -37 * deg, 12 * deg, d);
		hl_angles_from_dir(s, d, &h, &v);
		assert_float_equal(h, -37 * deg, 1e-12);
		assert_float_equal(v, 12 * deg, 1e-12);
	}
	/* The axes: +z forward, +x right (H > 0), +y up (V > 0). */
	d[0] = 1;
	d[1] = 0;
	d[2] = 1;
	hl_angles_from_dir(HL_ANGLES_A, d, &h, &v);
	assert_float_equal(h, 45 * deg, 1e-12);
	assert_float_equal(v, 0, 1e-12);
	d[0] = 0;
	d[1] = 1;
	hl_angles_from_dir(HL_ANGLES_B, d, &h, &v);
	assert_float_equal(h, 0, 1e-12);
	assert_float_equal(v, 45 * deg, 1e-12);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(lid_grid_samples_at_texel_centres),
		cmocka_unit_test(lid_grid_lookup_is_bilinear),
		cmocka_unit_test(lid_grid_lookup_is_zero_outside),
		cmocka_unit_test(lid_grid_equal_compares_every_field),
		cmocka_unit_test(lid_rejects_bad_grids_and_values),
		cmocka_unit_test(angles_type_a_and_b_differ_as_design_says),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
