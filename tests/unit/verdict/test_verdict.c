/* SPDX-License-Identifier: MIT */
/*
 * verdict/verdict.c on hand-built distributions whose value at each requirement is known exactly:
 * constant patches, boxes and ramps (a bilinear grid reproduces a linear function exactly, and
 * a symmetric receiver's mean of a linear function is its value at the centre).
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "lamp/angles.h"
#include "verdict/verdict.h"

/* H -20..+20, V -10..+10 at 0.2°: 201 x 101, type A. */
static const struct hl_lid_grid grid = {
	.width = 201,
	.height = 101,
	.angles = HL_ANGLES_A,
	.h_first_deg = -20.0f,
	.h_last_deg = 20.0f,
	.v_first_deg = -10.0f,
	.v_last_deg = 10.0f,
};

typedef double (*field_fn)(double h, double v);

static float *make(const struct hl_lid_grid *g, field_fn f)
{
	float *d = malloc(sizeof(float) * g->width * g->height);

	assert_non_null(d);
	for (int y = 0; y < g->height; y++)
		for (int x = 0; x < g->width; x++)
			d[y * g->width + x] =
				(float)f(hl_lid_grid_h_deg(g, x), hl_lid_grid_v_deg(g, y));
	return d;
}

static struct hl_regulation *parse(const char *fmt, ...)
{
	char text[8192];
	struct hl_regulation *reg = NULL;
	struct hl_regulation_error err;
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(text, sizeof(text), fmt, ap);
	va_end(ap);
	if (hl_regulation_parse(text, "test.json", &reg, &err) < 0)
		fail_msg("%s", err.msg);
	return reg;
}

/* A set of the given requirements (JSON text), square receiver of size_deg, angles A. */
#define SET(applies, shape, size, reqs)                                                       \
	"{\"id\": \"t\", \"title\": \"t\", \"source\": \"test\", \"applies_to\": \"" applies  \
	"\", \"angles\": \"A\", \"receiver\": {\"shape\": \"" shape "\", \"size_deg\": " size \
	", \"source\": \"test\"}, \"requirements\": [" reqs "]}"

static struct hl_req_result *run(const struct hl_regulation *reg, const struct hl_lid_grid *g,
				 enum hl_traffic traffic, const float *a, const float *b,
				 bool *ret_pass)
{
	const struct hl_verdict_options o = { .traffic = traffic };
	struct hl_verdict *v;
	struct hl_req_result *r = calloc(reg->n_requirements, sizeof(*r));
	bool pass;

	assert_int_equal(hl_verdict_new(reg, g, &o, &v), 0);
	pass = hl_verdict_eval(v, a, b, r);
	if (ret_pass)
		*ret_pass = pass;
	hl_verdict_free(v);
	return r;
}

static double constant(double h, double v)
{
	(void)h;
	(void)v;
	return 1000.0;
}

static double ramp(double h, double v)
{
	return 500.0 + 10.0 * h + 20.0 * v;
}

static void verdict_point_on_constant_and_ramp(void **state)
{
	(void)state;
	struct hl_regulation *reg = parse(SET("each_lamp", "square", "0.149",
					      "{\"id\": \"B50L\", \"kind\": \"point\", \"at\": "
					      "[\"3.43L\", \"0.57U\"], \"max_cd\": 350, "
					      "\"source\": \"s\"}"));
	float *c = make(&grid, constant), *r = make(&grid, ramp);
	struct hl_req_result *res;
	bool pass;

	res = run(reg, &grid, HL_TRAFFIC_RIGHT, c, NULL, &pass);
	assert_float_equal(res[0].value_cd, 1000.0, 1e-3);
	assert_true(isnan(res[0].min_cd));
	assert_float_equal(res[0].max_cd, 350.0, 0);
	assert_float_equal(res[0].margin, (350.0 - 1000.0) / 350.0, 1e-6);
	assert_false(res[0].pass);
	assert_false(pass);
	assert_float_equal(res[0].at_h_deg, -3.43, 1e-6);
	assert_float_equal(res[0].at_v_deg, 0.57, 1e-6);
	free(res);

	/* 500 - 34.3 + 11.4 = 477.1 */
	res = run(reg, &grid, HL_TRAFFIC_RIGHT, r, NULL, &pass);
	assert_float_equal(res[0].value_cd, 477.1, 1e-3);
	assert_false(pass);
	free(res);
	/* left-hand traffic mirrors H: 3.43R, 500 + 34.3 + 11.4 */
	res = run(reg, &grid, HL_TRAFFIC_LEFT, r, NULL, NULL);
	assert_float_equal(res[0].value_cd, 545.7, 1e-3);
	assert_float_equal(res[0].at_h_deg, 3.43, 1e-6);
	free(res);
	free(c);
	free(r);
	hl_regulation_free(reg);
}

static void verdict_segment_deciding_extremes(void **state)
{
	(void)state;
	struct hl_regulation *reg = parse(SET(
		"each_lamp", "square", "0.149",
		"{\"id\": \"Segment BLL\", \"kind\": \"segment\", \"from\": [\"8L\", \"0.57U\"], "
		"\"to\": [\"20L\", \"0.57U\"], \"max_cd\": 625, \"source\": \"s\"},"
		"{\"id\": \"Segment 25\", \"kind\": \"segment\", \"from\": [\"9L\", \"1.72D\"], "
		"\"to\": [\"9R\", \"1.72D\"], \"min_cd\": 400, \"source\": \"s\"},"
		"{\"id\": \"V line\", \"kind\": \"segment\", \"from\": [\"V\", \"2D\"], "
		"\"to\": [\"V\", \"1U\"], \"min_cd\": 100, \"max_cd\": 530, \"source\": \"s\"}"));
	float *r = make(&grid, ramp);
	struct hl_req_result *res = run(reg, &grid, HL_TRAFFIC_RIGHT, r, NULL, NULL);

	/* max of 500 + 10 h + 11.4 over h in [-20, -8]: at 8L, 431.4 */
	assert_float_equal(res[0].value_cd, 431.4, 1e-3);
	assert_float_equal(res[0].at_h_deg, -8.0, 1e-6);
	assert_float_equal(res[0].at_v_deg, 0.57, 1e-6);
	assert_true(res[0].pass);
	assert_float_equal(res[0].margin, (625.0 - 431.4) / 625.0, 1e-5);
	/* min of 500 + 10 h - 34.4 over h in [-9, 9]: at 9L, 375.6 < 400 */
	assert_float_equal(res[1].value_cd, 375.6, 1e-3);
	assert_float_equal(res[1].at_h_deg, -9.0, 1e-6);
	assert_false(res[1].pass);
	/* both limits: 460..520 along V; the max 520 is nearer its limit (530) than 460 to 100 */
	assert_float_equal(res[2].value_cd, 520.0, 1e-3);
	assert_float_equal(res[2].at_v_deg, 1.0, 1e-6);
	assert_float_equal(res[2].margin, 10.0 / 530.0, 1e-5);
	free(res);
	free(r);
	hl_regulation_free(reg);
}

static double box(double h, double v)
{
	/* 2000 cd over H 1..3, V 1..2 (edges included), 100 elsewhere */
	return (h >= 0.99 && h <= 3.01 && v >= 0.99 && v <= 2.01) ? 2000.0 : 100.0;
}

static void verdict_zone_finds_the_box(void **state)
{
	(void)state;
	struct hl_regulation *reg = parse(
		SET("each_lamp", "square", "0.149",
		    "{\"id\": \"Zone III\", \"kind\": \"zone\", \"polygon\": [[\"8L\", \"1U\"], "
		    "[\"8L\", \"4U\"], [\"8R\", \"4U\"], [\"8R\", \"2U\"], [\"6R\", \"1.5U\"], "
		    "[\"1.5R\", \"1.5U\"], [\"V\", \"H\"], [\"4L\", \"H\"]], \"max_cd\": 625, "
		    "\"source\": \"s\"},"
		    "{\"id\": \"Zone min\", \"kind\": \"zone\", \"polygon\": [[\"8L\", \"1U\"], "
		    "[\"8L\", \"4U\"], [\"8R\", \"4U\"], [\"8R\", \"1U\"]], \"min_cd\": 50, "
		    "\"source\": \"s\"},"
		    "{\"id\": \"Far zone\", \"kind\": \"zone\", \"polygon\": [[\"5R\", \"5U\"], "
		    "[\"5R\", \"7U\"], [\"7R\", \"7U\"]], \"max_cd\": 625, \"source\": \"s\"}"));
	float *b = make(&grid, box);
	struct hl_req_result *res = run(reg, &grid, HL_TRAFFIC_RIGHT, b, NULL, NULL);

	/* The box reaches inside Zone III above 1.5U: a receiver wholly inside it reads 2000. */
	assert_float_equal(res[0].value_cd, 2000.0, 1e-2);
	assert_true(res[0].at_h_deg >= 1.0 && res[0].at_h_deg <= 3.0);
	assert_true(res[0].at_v_deg >= 1.0 && res[0].at_v_deg <= 2.0);
	assert_false(res[0].pass);
	assert_int_equal(res[0].n_outside, 0);
	/* the lowest value over the rectangle is the background */
	assert_float_equal(res[1].value_cd, 100.0, 1e-3);
	assert_true(res[1].pass);
	/* a zone the box does not reach sees only the background */
	assert_float_equal(res[2].value_cd, 100.0, 1e-3);
	assert_true(res[2].pass);
	free(res);
	free(b);
	hl_regulation_free(reg);
}

static void verdict_sum_imax_and_relative(void **state)
{
	(void)state;
	struct hl_regulation *reg = parse(SET(
		"each_lamp", "square", "0.149",
		"{\"id\": \"4U\", \"kind\": \"sum\", \"points\": [[\"8L\", \"4U\"], [\"V\", \"4U\"], "
		"[\"8R\", \"4U\"]], \"min_cd\": 190, \"source\": \"s\"},"
		"{\"id\": \"Imax\", \"kind\": \"imax\", \"min_cd\": 40000, \"max_cd\": 215000, "
		"\"source\": \"s\"},"
		"{\"id\": \"H-V\", \"kind\": \"point\", \"at\": [\"V\", \"H\"], "
		"\"min_cd\": {\"of\": \"Imax\", \"factor\": 0.8}, \"source\": \"s\"},"
		"{\"id\": \"50R\", \"kind\": \"point\", \"at\": [\"1.72R\", \"0.86D\"], "
		"\"min_cd\": 100, \"source\": \"s\"},"
		"{\"id\": \"50V\", \"kind\": \"point\", \"at\": [\"V\", \"0.86D\"], "
		"\"max_cd\": {\"of\": \"50R\", \"factor\": 0.5}, \"source\": \"s\"}"));
	float *r = make(&grid, ramp);
	struct hl_req_result *res;

	/* a peak of 50,000 cd on one sample at H 2, V 1 (column 110, row 45) */
	r[45 * grid.width + 110] = 50000.0f;
	res = run(reg, &grid, HL_TRAFFIC_RIGHT, r, NULL, NULL);
	/* (500 - 80 + 80) + (500 + 80) + (500 + 80 + 80) = 1740 */
	assert_float_equal(res[0].value_cd, 1740.0, 1e-2);
	assert_true(res[0].pass);
	assert_float_equal(res[1].value_cd, 50000.0, 0);
	assert_float_equal(res[1].at_h_deg, 2.0, 1e-5);
	assert_float_equal(res[1].at_v_deg, 1.0, 1e-5);
	assert_true(res[1].pass);
	/* the smaller of (50000 - 40000) / 40000 and (215000 - 50000) / 215000 */
	assert_float_equal(res[1].margin, 0.25, 1e-9);
	assert_float_equal(res[2].min_cd, 40000.0, 1e-6);
	assert_float_equal(res[2].value_cd, 500.0, 1e-3);
	assert_float_equal(res[2].margin, (500.0 - 40000.0) / 40000.0, 1e-6);
	assert_false(res[2].pass);
	/* 50R = 500 + 17.2 - 17.2 = 500; 50V = 482.8 <= 0.5 * 500? no */
	assert_float_equal(res[3].value_cd, 500.0, 1e-3);
	assert_float_equal(res[4].max_cd, 250.0, 1e-3);
	assert_float_equal(res[4].value_cd, 482.8, 1e-3);
	assert_false(res[4].pass);
	free(res);
	free(r);
	hl_regulation_free(reg);
}

static double vee(double h, double v)
{
	(void)v;
	return 100.0 * fabs(h);
}

static void verdict_receiver_averages(void **state)
{
	(void)state;
	/* 100 |h| has its kink on the sample at h = 0: the point value there is 0, the receiver's
	 * mean is 100 times the mean of |h| over it. Square of side s: s / 4 exactly (the 4 x 4
	 * midpoint rule is exact for |h| on either half). Circle of diameter d: 4 (d/2) / (3 pi),
	 * which the 8 x 8 lattice meets within 2 %. */
	struct hl_regulation *sq = parse(SET("each_lamp", "square", "0.149",
					     "{\"id\": \"HV\", \"kind\": \"point\", \"at\": "
					     "[\"V\", \"H\"], \"max_cd\": 10, \"source\": \"s\"}"));
	struct hl_regulation *ci = parse(SET("each_lamp", "circle", "0.516",
					     "{\"id\": \"HV\", \"kind\": \"point\", \"at\": "
					     "[\"V\", \"H\"], \"max_cd\": 10, \"source\": \"s\"}"));
	float *d = make(&grid, vee);
	struct hl_req_result *res;

	assert_float_equal(hl_lid_grid_lookup(&grid, d, 0.0f, 0.0f), 0.0, 0);
	res = run(sq, &grid, HL_TRAFFIC_RIGHT, d, NULL, NULL);
	assert_float_equal(res[0].value_cd, 100.0 * 0.149 / 4, 1e-4);
	free(res);
	res = run(ci, &grid, HL_TRAFFIC_RIGHT, d, NULL, NULL);
	assert_float_equal(res[0].value_cd, 100.0 * 4 * 0.258 / (3 * M_PI),
			   0.02 * 100.0 * 4 * 0.258 / (3 * M_PI));
	free(res);
	free(d);
	hl_regulation_free(sq);
	hl_regulation_free(ci);
}

static void verdict_pair_half_sum(void **state)
{
	(void)state;
	struct hl_regulation *reg = parse(SET("pair_half", "square", "0.149",
					      "{\"id\": \"Oncoming 50 m\", \"kind\": \"segment\", "
					      "\"from\": [\"4.8L\", \"0.57U\"], \"to\": [\"2L\", "
					      "\"0.57U\"], \"max_cd\": 625, \"source\": \"s\"},"
					      "{\"id\": \"Imax\", \"kind\": \"imax\", \"max_cd\": "
					      "1e6, \"source\": \"s\"}"));
	float *c = make(&grid, constant), *r = make(&grid, ramp);
	struct hl_req_result *res = run(reg, &grid, HL_TRAFFIC_RIGHT, c, r, NULL);

	/* max over h in [-4.8, -2] of (1000 + 500 + 10 h + 11.4) / 2: at 2L, 745.7 */
	assert_float_equal(res[0].value_cd, 745.7, 1e-3);
	assert_float_equal(res[0].at_h_deg, -2.0, 1e-6);
	assert_false(res[0].pass);
	/* the ramp's largest sample is at 20R 10U: (1000 + 900) / 2 */
	assert_float_equal(res[1].value_cd, 950.0, 1e-3);
	free(res);
	free(c);
	free(r);
	hl_regulation_free(reg);
}

static void verdict_outside_the_grid_is_not_measured(void **state)
{
	(void)state;
	struct hl_regulation *reg = parse(SET(
		"each_lamp", "circle", "0.516",
		"{\"id\": \"10U-90U\", \"kind\": \"zone\", \"polygon\": [[\"L\", \"10U\"], "
		"[\"L\", \"90U\"], [\"R\", \"90U\"], [\"R\", \"10U\"]], \"max_cd\": 1e9, "
		"\"source\": \"s\"},"
		"{\"id\": \"1.5U-1R to R\", \"kind\": \"segment\", \"from\": [\"1R\", \"1.5U\"], "
		"\"to\": [\"R\", \"1.5U\"], \"max_cd\": 1e9, \"source\": \"s\"},"
		"{\"id\": \"12U\", \"kind\": \"point\", \"at\": [\"V\", \"12U\"], \"max_cd\": 1e9, "
		"\"source\": \"s\"}"));
	float *r = make(&grid, ramp);
	struct hl_req_result *res = run(reg, &grid, HL_TRAFFIC_RIGHT, r, NULL, NULL);

	/* The grid ends at 10U: the zone's bottom edge is measured (inset by the receiver's
	 * radius at the open ends), everything above is counted outside. */
	assert_true(res[0].n_outside > 1000);
	assert_false(isnan(res[0].value_cd));
	/* the open end R runs to the grid's edge less the receiver's radius */
	assert_float_equal(res[1].at_h_deg, 20.0 - 0.258, 1e-3);
	assert_float_equal(res[1].value_cd, 500.0 + 10.0 * (20.0 - 0.258) + 30.0, 1e-2);
	assert_int_equal(res[1].n_outside, 0);
	/* a point beyond the grid has no value and fails */
	assert_true(isnan(res[2].value_cd));
	assert_int_equal(res[2].n_outside, 1);
	assert_false(res[2].pass);
	free(res);
	free(r);
	hl_regulation_free(reg);
}

static void verdict_angle_systems_convert(void **state)
{
	(void)state;
	/* A type B set on a type A grid: the point (10R, 5U) in B is another direction in A. */
	struct hl_regulation *reg =
		parse(SET("each_lamp", "square", "0.001",
			  "{\"id\": \"P\", \"kind\": \"point\", \"at\": [\"10R\", "
			  "\"5U\"], \"max_cd\": 1e9, \"source\": \"s\"}"));
	float *r = make(&grid, ramp);
	struct hl_req_result *res;
	double d[3], h, v;

	reg->angles = HL_ANGLES_B;
	hl_angles_to_dir(HL_ANGLES_B, 10.0 * M_PI / 180, 5.0 * M_PI / 180, d);
	hl_angles_from_dir(HL_ANGLES_A, d, &h, &v);
	res = run(reg, &grid, HL_TRAFFIC_RIGHT, r, NULL, NULL);
	assert_float_equal(res[0].value_cd, ramp(h * 180 / M_PI, v * 180 / M_PI), 1e-2);
	assert_true(fabs(res[0].value_cd - ramp(10.0, 5.0)) > 0.5);
	free(res);
	free(r);
	hl_regulation_free(reg);
}

/* A fine grid for the cut-off scans: V -5..+3 at 0.05° so that the profile is resolved. */
static const struct hl_lid_grid fine = {
	.width = 41,
	.height = 161,
	.angles = HL_ANGLES_A,
	.h_first_deg = -5.0f,
	.h_last_deg = 5.0f,
	.v_first_deg = -5.0f,
	.v_last_deg = 3.0f,
};

static double cut_at;

static double cutoff(double h, double v)
{
	(void)h;
	return pow(10.0, 3.0 - 1.0 * tanh((v - cut_at) / 0.12));
}

#define AIM_SET(size)                                                                             \
	"{\"id\": \"t\", \"title\": \"t\", \"source\": \"test\", \"applies_to\": \"each_lamp\", " \
	"\"angles\": \"A\", \"receiver\": {\"shape\": \"square\", \"size_deg\": " size            \
	", \"source\": \"test\"}, \"aim\": {\"method\": \"cutoff\", \"scan_h\": \"2.5L\", "       \
	"\"cutoff_v\": \"0.57D\", \"linearity_h\": [\"1.5L\", \"3.5L\"], "                        \
	"\"linearity_max_deg\": 0.2, \"g_min\": 0.13, \"g_max\": 0.40, \"source\": \"t\"}, "      \
	"\"requirements\": [{\"id\": \"B\", \"kind\": \"point\", \"at\": [\"2.5L\", \"0.57D\"], " \
	"\"min_cd\": 1, \"source\": \"s\"}]}"

static void verdict_cutoff_found_where_it_was_moved(void **state)
{
	(void)state;
	struct hl_regulation *reg = parse(AIM_SET("0.149"));
	const double at[] = { -0.57, 0.2, -1.37, 0.9 };
	struct hl_cutoff c;

	for (size_t k = 0; k < sizeof(at) / sizeof(at[0]); k++) {
		float *d;

		cut_at = at[k];
		d = make(&fine, cutoff);
		assert_int_equal(hl_verdict_find_cutoff(reg, &fine, d, HL_TRAFFIC_RIGHT, &c), 0);
		assert_float_equal(c.v_deg, at[k], 0.05);
		/* the profile is the same at every H: the three scans agree */
		assert_float_equal(c.linearity_deg, 0.0, 1e-6);
		assert_true(c.linear_ok);
		free(d);
	}
	hl_regulation_free(reg);
}

static double two_level(double h, double v)
{
	/* log10 I: 4 up to V 0, falling by 0.3 over the one 0.1° step to V 0.1, 3.7 above */
	(void)h;
	return v <= 0.001 ? 1e4 : v <= 0.051 ? pow(10.0, 3.85) : pow(10.0, 3.7);
}

static void verdict_cutoff_sharpness_exact(void **state)
{
	(void)state;
	/* With a point receiver, G at the steepest 0.1° is log10(1e4) - log10(10^3.7) = 0.3 and
	 * the inflection point is its middle, V 0.05. */
	struct hl_regulation *reg = parse(AIM_SET("0.0001"));
	float *d = make(&fine, two_level);
	struct hl_cutoff c;

	assert_int_equal(hl_verdict_find_cutoff(reg, &fine, d, HL_TRAFFIC_RIGHT, &c), 0);
	assert_float_equal(c.g, 0.3, 1e-4);
	assert_float_equal(c.v_deg, 0.05, 1e-3);
	assert_true(c.sharp_ok);
	free(d);
	hl_regulation_free(reg);
}

static void verdict_aim_shift_moves_the_beam(void **state)
{
	(void)state;
	/* aimed 0.5° down and 1° right: the value at (h, v) is the mounted value at (h - 1, v + 0.5) */
	struct hl_regulation *reg =
		parse(SET("each_lamp", "square", "0.149",
			  "{\"id\": \"P\", \"kind\": \"point\", \"at\": [\"2R\", "
			  "\"1U\"], \"max_cd\": 1e9, \"source\": \"s\"}"));
	const struct hl_verdict_options o = { .aim_h_deg = 1.0, .aim_v_deg = -0.5 };
	float *r = make(&grid, ramp);
	struct hl_verdict *v;
	struct hl_req_result res;

	assert_int_equal(hl_verdict_new(reg, &grid, &o, &v), 0);
	hl_verdict_eval(v, r, NULL, &res);
	assert_float_equal(res.value_cd, ramp(1.0, 1.5), 1e-3);
	hl_verdict_free(v);
	free(r);
	hl_regulation_free(reg);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(verdict_point_on_constant_and_ramp),
		cmocka_unit_test(verdict_segment_deciding_extremes),
		cmocka_unit_test(verdict_zone_finds_the_box),
		cmocka_unit_test(verdict_sum_imax_and_relative),
		cmocka_unit_test(verdict_receiver_averages),
		cmocka_unit_test(verdict_pair_half_sum),
		cmocka_unit_test(verdict_outside_the_grid_is_not_measured),
		cmocka_unit_test(verdict_angle_systems_convert),
		cmocka_unit_test(verdict_cutoff_found_where_it_was_moved),
		cmocka_unit_test(verdict_cutoff_sharpness_exact),
		cmocka_unit_test(verdict_aim_shift_moves_the_beam),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
