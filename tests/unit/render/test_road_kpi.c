/* SPDX-License-Identifier: MIT */
/*
 * The road KPIs against distributions whose answer is known in closed form: a uniform lamp
 * (E = I h / (d^2 + h^2)^(3/2) on the road, d the horizontal distance), and a uniform lamp cut
 * off hard above a V, whose range is where the bilinear ramp meets the level (found here by
 * bisection on an independent lamp-space formula). Two lamps add, a NULL distribution is dark,
 * the ends of the lines, and the -EINVAL cases.
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

#include "render/road_kpi.h"

#define DEG (M_PI / 180.0)
#define H_M 0.65 /* mounting height of the test lamps */
#define CENTRE_Y_M (-1.75)
#define EDGE_Y_M (-3.5)

/*
 * Linear interpolation of a smooth E between samples s apart puts the crossing off by at most
 * about s^2 / 8 * |E''| / |E'| there. For the uniform lamp, E ~ (d^2 + c)^(-3/2) along a line,
 * |E''/E'| < 4 / x along the range lines (x > 20 m here: 0.2 /m) and < 0.05 /m across the
 * width line at 25 m near its ends (|y| ~ 20 m), so at the default step of 0.05 m the error is
 * below 0.07 mm: 0.1 mm is the tolerance.
 */
#define SMOOTH_TOL_M 0.0001

/* A type A grid: H -60..60 every 1 deg, V -60..30 every 1 deg. */
static struct hl_lid_grid wide_grid(void)
{
	return (struct hl_lid_grid){ .width = 121,
				     .height = 91,
				     .angles = HL_ANGLES_A,
				     .h_first_deg = -60.0f,
				     .h_last_deg = 60.0f,
				     .v_first_deg = -60.0f,
				     .v_last_deg = 30.0f };
}

static float *uniform(const struct hl_lid_grid *g, float cd)
{
	float *d = malloc(sizeof(float) * g->width * g->height);

	assert_non_null(d);
	for (int i = 0; i < g->width * g->height; i++)
		d[i] = cd;
	return d;
}

static struct hl_headlight_lamp lamp_at(double y_m, double pitch_deg, struct hl_lid_grid g)
{
	return (struct hl_headlight_lamp){
		.pose = { .pos_m = { 0.0, y_m, H_M }, .yaw_deg = 0.0, .pitch_deg = pitch_deg },
		.grid = g,
	};
}

static void run(int n, const struct hl_headlight_lamp *lamps, const struct hl_road_kpi_options *o,
		const float *const *dense, struct hl_road_kpi *ret)
{
	struct hl_road_kpi_plan *p;

	assert_int_equal(hl_road_kpi_new(n, lamps, o, &p), 0);
	hl_road_kpi_run(p, dense, ret);
	hl_road_kpi_free(p);
}

/* Horizontal distance at which a uniform I gives E = level at lateral offset dy (0 if never). */
static double uniform_reach(double i_cd, double level, double dy)
{
	const double d2 = pow(i_cd * H_M / level, 2.0 / 3.0) - H_M * H_M - dy * dy;

	return d2 > 0.0 ? sqrt(d2) : 0.0;
}

static void road_kpi_uniform_lamp_closed_form(void **state)
{
	const struct hl_lid_grid g = wide_grid();
	const struct hl_headlight_lamp lamp = lamp_at(CENTRE_Y_M, 0.0, g);
	const double i_cd = 50000.0;
	float *d = uniform(&g, (float)i_cd);
	const float *dense[1] = { d };
	struct hl_road_kpi_options o;
	struct hl_road_kpi k;

	(void)state;
	hl_road_kpi_defaults(&o);
	run(1, &lamp, &o, dense, &k);
	for (int j = 0; j < HL_ROAD_KPI_LEVELS; j++) {
		/* the lamp is above the centre line: the edge is 1.75 m to the side */
		assert_float_equal(k.centre_range_m[j], uniform_reach(i_cd, o.levels_lx[j], 0.0),
				   SMOOTH_TOL_M);
		assert_float_equal(k.edge_range_m[j],
				   uniform_reach(i_cd, o.levels_lx[j], EDGE_Y_M - CENTRE_Y_M),
				   SMOOTH_TOL_M);
	}
	/* 1 lx: centre 31.90590 m, edge 31.85787 m; 3 lx: 22.11736 m, 22.04802 m */
	assert_float_equal(k.centre_range_m[0], 31.90590, SMOOTH_TOL_M);
	assert_float_equal(k.edge_range_m[0], 31.85787, SMOOTH_TOL_M);
	assert_float_equal(k.centre_range_m[1], 22.11736, SMOOTH_TOL_M);
	assert_float_equal(k.edge_range_m[1], 22.04802, SMOOTH_TOL_M);
	/* At 25 m: E = 1 lx where (dy^2 + 25^2 + h^2)^(3/2) = I h, symmetric about the lamp. */
	assert_float_equal(k.width_m[0], 2 * uniform_reach(i_cd, 1.0, 25.0), 2 * SMOOTH_TOL_M);
	assert_float_equal(k.width_m[0], 39.64778, 2 * SMOOTH_TOL_M);
	assert_float_equal(k.width_m[1], 0.0, 0.0); /* 1 lx never reaches 50 m */
	free(d);
}

/* A level lamp of I0 below V = -1.00 deg, zero from -0.99 deg up (rows 0.01 deg apart). */
#define CUT_I0_CD 1.0e6
#define CUT_TOP_DEG (-0.99) /* highest V still lit (the ramp's upper end) */
#define CUT_STEP_DEG 0.01

static struct hl_lid_grid cut_grid(void)
{
	/* H -45..45 every 0.5 deg; V -5..1 every 0.01 deg: row j at V = 1 - j / 100 */
	return (struct hl_lid_grid){ .width = 181,
				     .height = 601,
				     .angles = HL_ANGLES_A,
				     .h_first_deg = -45.0f,
				     .h_last_deg = 45.0f,
				     .v_first_deg = -5.0f,
				     .v_last_deg = 1.0f };
}

static float *cut_dense(const struct hl_lid_grid *g)
{
	float *d = uniform(g, 0.0f);

	for (int j = 200; j < g->height; j++) /* V <= -1.00 */
		for (int i = 0; i < g->width; i++)
			d[j * g->width + i] = (float)CUT_I0_CD;
	return d;
}

/*
 * E of the cut lamp (at y = lamp_y, pitched) at road point (x, y), from the lamp-space formula
 * of docs/design.md §4 written out here: lamp z = (cos p, 0, sin p), y (up) = (-sin p, 0, cos p),
 * x (right) = (0, -1, 0); type A V = atan2(d.y, hypot(d.x, d.z)); I = I0 * the bilinear ramp.
 */
static double cut_e(double lamp_y, double pitch_deg, double x, double y)
{
	const double p = pitch_deg * DEG, w[3] = { x, y - lamp_y, -H_M };
	const double lx = -w[1], ly = -sin(p) * w[0] + cos(p) * w[2];
	const double lz = cos(p) * w[0] + sin(p) * w[2];
	const double v_deg = atan2(ly, hypot(lx, lz)) / DEG;
	const double r2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
	double f = (CUT_TOP_DEG - v_deg) / CUT_STEP_DEG;

	f = f < 0.0 ? 0.0 : f > 1.0 ? 1.0 : f;
	return CUT_I0_CD * f * (H_M / sqrt(r2)) / r2;
}

/* The farthest x (between lo, lit above level, and hi, dark) where cut_e falls to level. */
static double cut_range(double lamp_y, double pitch_deg, double y, double level, double lo,
			double hi)
{
	assert_true(cut_e(lamp_y, pitch_deg, lo, y) > level);
	assert_true(cut_e(lamp_y, pitch_deg, hi, y) < level);
	for (int i = 0; i < 100; i++) {
		const double mid = (lo + hi) / 2;

		if (cut_e(lamp_y, pitch_deg, mid, y) >= level)
			lo = mid;
		else
			hi = mid;
	}
	return lo;
}

static void road_kpi_hard_cut_off_range(void **state)
{
	const struct hl_lid_grid g = cut_grid();
	const double pitch = -atan(0.01) / DEG; /* aimed 1 % down, as mounted by default */
	const struct hl_headlight_lamp lamp = lamp_at(CENTRE_Y_M, pitch, g);
	float *d = cut_dense(&g);
	const float *dense[1] = { d };
	struct hl_road_kpi_options o;
	struct hl_road_kpi k;

	(void)state;
	hl_road_kpi_defaults(&o);
	/*
	 * The ramp from I0 to 0 is only 0.15 m long on the road, so E falls from ~50 lx to 0 within
	 * three default steps of 0.05 m: sample at 1 cm instead. The interpolated crossing lies
	 * between the last sample at or above the level and the first below it: one step is the
	 * tolerance.
	 */
	o.step_m = 0.01;
	o.max_range_m = 60.0;
	run(1, &lamp, &o, dense, &k);
	for (int j = 0; j < HL_ROAD_KPI_LEVELS; j++) {
		const double lv = o.levels_lx[j];
		/* V = -1.00 deg in lamp space: tan(1.00 deg - 0.573 deg) ... on the road: 23.7 m */
		const double centre = cut_range(CENTRE_Y_M, pitch, CENTRE_Y_M, lv, 23.0, 24.5);
		const double edge = cut_range(CENTRE_Y_M, pitch, EDGE_Y_M, lv, 23.0, 24.5);

		assert_float_equal(k.centre_range_m[j], centre, o.step_m);
		assert_float_equal(k.edge_range_m[j], edge, o.step_m);
		assert_true(centre > 23.6 && centre < 23.9);
	}
	/* Nothing of the cut lamp reaches 25 m or 50 m: both widths are 0. */
	assert_float_equal(k.width_m[0], 0.0, 0.0);
	assert_float_equal(k.width_m[1], 0.0, 0.0);
	free(d);
}

static void road_kpi_lamps_add_and_null_is_dark(void **state)
{
	const struct hl_lid_grid g = wide_grid();
	const struct hl_headlight_lamp one = lamp_at(CENTRE_Y_M, 0.0, g);
	const struct hl_headlight_lamp two[2] = { one, one };
	float *full = uniform(&g, 50000.0f), *half = uniform(&g, 25000.0f);
	const float *d_one[1] = { full }, *d_two[2] = { half, half }, *d_dark[2] = { half, NULL };
	const float *d_half[1] = { half };
	struct hl_road_kpi_options o;
	struct hl_road_kpi a, b, c, e;

	(void)state;
	hl_road_kpi_defaults(&o);
	run(1, &one, &o, d_one, &a);
	run(2, two, &o, d_two, &b);
	run(2, two, &o, d_dark, &c);
	run(1, &one, &o, d_half, &e);
	for (int j = 0; j < HL_ROAD_KPI_LEVELS; j++) {
		assert_float_equal(b.centre_range_m[j], a.centre_range_m[j], 1e-9);
		assert_float_equal(b.edge_range_m[j], a.edge_range_m[j], 1e-9);
		assert_float_equal(c.centre_range_m[j], e.centre_range_m[j], 0.0);
		assert_float_equal(c.edge_range_m[j], e.edge_range_m[j], 0.0);
	}
	assert_float_equal(b.width_m[0], a.width_m[0], 1e-9);
	assert_float_equal(c.width_m[0], e.width_m[0], 0.0);
	assert_true(e.centre_range_m[0] < a.centre_range_m[0] - 1.0);
	free(full);
	free(half);
}

static void road_kpi_line_ends(void **state)
{
	const struct hl_lid_grid g = wide_grid();
	const struct hl_headlight_lamp lamp = lamp_at(CENTRE_Y_M, 0.0, g);
	float *bright = uniform(&g, 1.0e9f), *dark = uniform(&g, 0.0f);
	const float *d_bright[1] = { bright }, *d_dark[1] = { dark };
	struct hl_road_kpi_options o;
	struct hl_road_kpi k;

	(void)state;
	hl_road_kpi_defaults(&o);
	o.max_range_m = 50.0;
	/* Still above both levels at the end of the lines: the lines' lengths. */
	run(1, &lamp, &o, d_bright, &k);
	assert_float_equal(k.centre_range_m[0], 50.0, 0.0);
	assert_float_equal(k.edge_range_m[1], 50.0, 0.0);
	assert_float_equal(k.width_m[0], 2 * HL_ROAD_KPI_WIDTH_HALF_M, 0.0);
	assert_float_equal(k.width_m[1], 2 * HL_ROAD_KPI_WIDTH_HALF_M, 0.0);
	/* Never reached: zeros. */
	run(1, &lamp, &o, d_dark, &k);
	for (int j = 0; j < HL_ROAD_KPI_LEVELS; j++) {
		assert_float_equal(k.centre_range_m[j], 0.0, 0.0);
		assert_float_equal(k.edge_range_m[j], 0.0, 0.0);
		assert_float_equal(k.width_m[j], 0.0, 0.0);
	}
	free(bright);
	free(dark);
}

static void road_kpi_rejects_bad_input(void **state)
{
	const struct hl_lid_grid g = wide_grid();
	struct hl_headlight_lamp lamps[3] = { lamp_at(0.7, 0.0, g), lamp_at(-0.7, 0.0, g),
					      lamp_at(0.0, 0.0, g) };
	struct hl_road_kpi_plan *p = (struct hl_road_kpi_plan *)&p;
	struct hl_road_kpi_options ok, o;

	(void)state;
	hl_road_kpi_defaults(&ok);
	assert_int_equal(hl_road_kpi_new(0, lamps, &ok, &p), -EINVAL);
	assert_int_equal(hl_road_kpi_new(3, lamps, &ok, &p), -EINVAL);
	o = ok, o.levels_lx[1] = 0.0;
	assert_int_equal(hl_road_kpi_new(2, lamps, &o, &p), -EINVAL);
	o = ok, o.levels_lx[0] = NAN;
	assert_int_equal(hl_road_kpi_new(2, lamps, &o, &p), -EINVAL);
	o = ok, o.step_m = -0.25;
	assert_int_equal(hl_road_kpi_new(2, lamps, &o, &p), -EINVAL);
	o = ok, o.max_range_m = 0.01; /* shorter than a step */
	assert_int_equal(hl_road_kpi_new(2, lamps, &o, &p), -EINVAL);
	o = ok, o.step_m = 1e-5; /* 30 million samples */
	assert_int_equal(hl_road_kpi_new(2, lamps, &o, &p), -EINVAL);
	o = ok, o.width_at_m[1] = INFINITY;
	assert_int_equal(hl_road_kpi_new(2, lamps, &o, &p), -EINVAL);
	o = ok, o.edge_y_m = NAN;
	assert_int_equal(hl_road_kpi_new(2, lamps, &o, &p), -EINVAL);
	lamps[1].grid.width = 1;
	assert_int_equal(hl_road_kpi_new(2, lamps, &ok, &p), -EINVAL);
	/* *ret untouched on failure */
	assert_ptr_equal(p, (struct hl_road_kpi_plan *)&p);
	hl_road_kpi_free(NULL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(road_kpi_uniform_lamp_closed_form),
		cmocka_unit_test(road_kpi_hard_cut_off_range),
		cmocka_unit_test(road_kpi_lamps_add_and_null_is_dark),
		cmocka_unit_test(road_kpi_line_ends),
		cmocka_unit_test(road_kpi_rejects_bad_input),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
