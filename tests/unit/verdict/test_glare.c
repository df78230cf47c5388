/* SPDX-License-Identifier: MIT */
/*
 * verdict/glare.c against the test's own computation: still road users on a straight, the ego's
 * lamps yawed and pitched, the eye's direction in lamp space from the test's own basis, its own
 * angle formulas (A and B), a closed-form distribution (linear in H and V, which a bilinear grid
 * reproduces) and the HD84 low and high beams looked up with the test's own bilinear
 * interpolation; E = sum I / r^2 within 1 %. The limit rule on the shipped ADB glare set: the
 * largest tabulated distance not beyond the road user's, below and above the table, the
 * segment holding the eye's H, oncoming against preceding. Nothing allocated per frame.
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

#include "alloc_count.h"
#include "lamp/combine.h"
#include "lamp/model.h"
#include "lamp/preset.h"
#include "verdict/glare.h"

#define RAD (M_PI / 180.0)

/* The ego's lamps as the scenario below writes them (vehicle frame; the ego stands at x 0). */
static const double lamp_pos[2][3] = { { 0.0, 0.7, 0.65 }, { 0.0, -0.7, 0.65 } };
static const double lamp_yaw[2] = { 2.0, -1.5 }, lamp_pitch[2] = { -0.573, -1.0 };
#define EGO_Y (-1.75) /* lane 1 of two 3.5 m lanes */
#define EYE_X 1.8 /* behind the front of an oncoming car facing -x */
#define EYE_Y 0.37
#define EYE_Z 1.1

/* Oncoming cars whose eyes are 50, 100 and 200 m ahead of the lamps; a preceding car at 78.2. */
static const char scenario_json[] =
	"{\"version\": 1, \"title\": \"still\", \"duration_s\": 1,\n"
	" \"road\": {\"segments\": [{\"kind\": \"straight\", \"length_m\": 400}],\n"
	"          \"lanes\": {\"count\": 2, \"width_m\": 3.5}},\n"
	" \"ego\": {\"start_s_m\": 0, \"lane\": 1, \"speed_mps\": 0, \"lamps\": [\n"
	"   {\"pos_m\": [0, 0.7, 0.65], \"yaw_deg\": 2, \"pitch_deg\": -0.573},\n"
	"   {\"pos_m\": [0, -0.7, 0.65], \"yaw_deg\": -1.5, \"pitch_deg\": -1}]},\n"
	" \"actors\": [\n"
	"  {\"id\": \"at50\", \"kind\": \"car\", \"role\": \"oncoming\", \"eye_m\": [-1.8, 0.37, 1.1],\n"
	"   \"path\": {\"lane\": 2, \"start_s_m\": 48.2, \"speed_mps\": 0}},\n"
	"  {\"id\": \"at100\", \"kind\": \"car\", \"role\": \"oncoming\", \"eye_m\": [-1.8, 0.37, 1.1],\n"
	"   \"path\": {\"lane\": 2, \"start_s_m\": 98.2, \"speed_mps\": 0}},\n"
	"  {\"id\": \"at200\", \"kind\": \"car\", \"role\": \"oncoming\", \"eye_m\": [-1.8, 0.37, 1.1],\n"
	"   \"path\": {\"lane\": 2, \"start_s_m\": 198.2, \"speed_mps\": 0}},\n"
	"  {\"id\": \"ahead\", \"kind\": \"car\", \"role\": \"preceding\", \"eye_m\": [-1.8, 0.37, 1.1],\n"
	"   \"path\": {\"lane\": 1, \"start_s_m\": 80, \"speed_mps\": 0}}]}\n";

/* Where the test puts each eye (world = vehicle frame of the standing ego). */
static void eye(int i, double ret[3])
{
	static const double s[4] = { 48.2, 98.2, 198.2, 80.0 };

	if (i < 3) { /* facing -x in lane 2 (d +1.75): its left is -y */
		ret[0] = s[i] + EYE_X;
		ret[1] = 1.75 - EYE_Y;
	} else {
		ret[0] = s[i] - EYE_X;
		ret[1] = EGO_Y + EYE_Y;
	}
	ret[2] = EYE_Z;
}

/* The eye in lamp l's space (x right, y up, z the optical axis) from the test's own basis. */
static void lamp_space(int l, const double p[3], double ret[3])
{
	const double y = lamp_yaw[l] * RAD, t = lamp_pitch[l] * RAD;
	const double ax[3] = { sin(y), -cos(y), 0.0 };
	const double az[3] = { cos(t) * cos(y), cos(t) * sin(y), sin(t) };
	const double ay[3] = { -sin(t) * cos(y), -sin(t) * sin(y), cos(t) };
	const double d[3] = { p[0] - lamp_pos[l][0], p[1] - (EGO_Y + lamp_pos[l][1]),
			      p[2] - lamp_pos[l][2] };

	ret[0] = d[0] * ax[0] + d[1] * ax[1] + d[2] * ax[2];
	ret[1] = d[0] * ay[0] + d[1] * ay[1] + d[2] * ay[2];
	ret[2] = d[0] * az[0] + d[1] * az[1] + d[2] * az[2];
}

static void angles(enum hl_angles sys, const double d[3], double *h_deg, double *v_deg)
{
	if (sys == HL_ANGLES_A) {
		*h_deg = atan2(d[0], d[2]) / RAD;
		*v_deg = atan2(d[1], hypot(d[0], d[2])) / RAD;
	} else {
		*v_deg = atan2(d[1], d[2]) / RAD;
		*h_deg = atan2(d[0], hypot(d[1], d[2])) / RAD;
	}
}

/* The test's own bilinear lookup: samples at texel centres, row 0 the highest V, 0 outside. */
static double bilinear(const struct hl_lid_grid *g, const float *d, double h, double v)
{
	const double dh = (g->h_last_deg - g->h_first_deg) / (g->width - 1);
	const double dv = (g->v_last_deg - g->v_first_deg) / (g->height - 1);
	const double x = (h - g->h_first_deg) / dh, yu = (v - g->v_first_deg) / dv;
	int x0, y0;
	double fx, fy, r0, r1;

	if (x < 0 || yu < 0 || x > g->width - 1 || yu > g->height - 1)
		return 0.0;
	x0 = (int)fmin(floor(x), g->width - 2);
	y0 = (int)fmin(floor(yu), g->height - 2);
	fx = x - x0;
	fy = yu - y0;
	/* row for V index y from the bottom: height - 1 - y */
	r0 = (1 - fx) * d[(g->height - 1 - y0) * g->width + x0] +
	     fx * d[(g->height - 1 - y0) * g->width + x0 + 1];
	r1 = (1 - fx) * d[(g->height - 2 - y0) * g->width + x0] +
	     fx * d[(g->height - 2 - y0) * g->width + x0 + 1];
	return (1 - fy) * r0 + fy * r1;
}

static struct hl_scenario *scenario(void)
{
	struct hl_scenario *sc = NULL;
	struct hl_json_error err;

	if (hl_scenario_parse(scenario_json, "still.json", &sc, &err) < 0)
		fail_msg("%s", err.msg);
	return sc;
}

static struct hl_regulation *adb_glare(void)
{
	char path[4096];
	struct hl_regulation *reg = NULL;
	struct hl_regulation_error err;

	snprintf(path, sizeof(path), "%s/regulations/unece-r149-01-adb-glare.json",
		 getenv("HL_SOURCE_DIR") ? getenv("HL_SOURCE_DIR") : ".");
	if (hl_regulation_read(path, &reg, &err) < 0)
		fail_msg("%s", err.msg);
	return reg;
}

/* Compares glare's result for road user i with the test's own computation; returns E. */
static double check_user(const struct hl_glare_result *r, int i,
			 const struct hl_lid_grid *const g[2], const float *const d[2],
			 double (*closed)(double h, double v))
{
	double p[3], e = 0.0, sum = 0.0;

	eye(i, p);
	for (int k = 0; k < 3; k++)
		assert_true(fabs(r->eye_m[k] - p[k]) < 1e-6);
	for (int l = 0; l < 2; l++) {
		double q[3], h, v, dist, cd;

		lamp_space(l, p, q);
		dist = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
		angles(g[l]->angles, q, &h, &v);
		cd = closed ? closed(h, v) : bilinear(g[l], d[l], h, v);
		assert_true(cd > 0.0);
		assert_true(fabs(r->r_m[l] - dist) < 1e-6 * dist);
		assert_true(fabs(r->h_deg[l] - h) < 1e-6 && fabs(r->v_deg[l] - v) < 1e-6);
		if (fabs(r->intensity_cd[l] - cd) > 0.01 * cd)
			fail_msg("user %d lamp %d: %.3f cd, expected %.3f", i, l,
				 r->intensity_cd[l], cd);
		e += cd / (dist * dist);
		sum += cd;
	}
	assert_true(fabs(r->pair_half_cd - 0.5 * sum) <= 0.01 * 0.5 * sum);
	if (fabs(r->illuminance_lx - e) > 0.01 * e)
		fail_msg("user %d: %.6f lx, expected %.6f", i, r->illuminance_lx, e);
	return e;
}

static double linear_field(double h, double v)
{
	return 5000.0 + 100.0 * h + 200.0 * v;
}

/* Left lamp on a type A grid, right on a type B grid, both I = 5000 + 100 H + 200 V. */
static void still_oncoming_on_closed_form_grids(void **state)
{
	(void)state;
	const struct hl_lid_grid ga = { 201, 101, HL_ANGLES_A, -20.0f, 20.0f, -10.0f, 10.0f };
	const struct hl_lid_grid gb = { 201, 101, HL_ANGLES_B, -20.0f, 20.0f, -10.0f, 10.0f };
	const struct hl_lid_grid *const g[2] = { &ga, &gb };
	float *d0 = malloc(sizeof(float) * 201 * 101), *d1 = malloc(sizeof(float) * 201 * 101);
	const float *const d[2] = { d0, d1 };
	struct hl_scenario *sc = scenario();
	struct hl_regulation *reg = adb_glare();
	struct hl_glare *gl = NULL;
	struct hl_glare_result res[4];

	assert_non_null(d0);
	assert_non_null(d1);
	for (int y = 0; y < 101; y++)
		for (int x = 0; x < 201; x++)
			d0[y * 201 + x] = d1[y * 201 + x] = (float)linear_field(
				hl_lid_grid_h_deg(&ga, x), hl_lid_grid_v_deg(&ga, y));
	assert_int_equal(hl_glare_new(sc, reg, g, &gl), 0);
	allocs = 0;
	hl_glare_eval(gl, 0.5, d, res);
	if (HL_COUNT_ALLOCS)
		assert_int_equal(allocs, 0);
	allocs = -1;
	for (int i = 0; i < 3; i++) {
		const double e = check_user(&res[i], i, g, d, linear_field);

		/* E within a few % of the on-axis 2 x 5000 cd / D^2: the test's numbers are sane */
		assert_true(fabs(e - 2 * 5000.0 / pow(50.0 * (1 << i), 2)) < 0.1 * e);
		assert_string_equal(sc->actor[res[i].actor].id, i == 0 ? "at50" :
								i == 1 ? "at100" :
									 "at200");
	}
	check_user(&res[3], 3, g, d, linear_field);
	hl_glare_free(gl);
	hl_regulation_free(reg);
	hl_scenario_free(sc);
	free(d0);
	free(d1);
}

/* The HD84 pair under a preset, looked up with the test's own bilinear interpolation. */
static void hd84_at(const char *preset, struct hl_glare_result res[4], double ret_e[3])
{
	struct hl_lid *lamp[2] = { NULL, NULL };
	struct hl_preset *p = NULL;
	float *dense[2];
	struct hl_scenario *sc = scenario();
	struct hl_regulation *reg = adb_glare();
	struct hl_glare *gl = NULL;
	const struct hl_lid_grid *g[2];

	for (int l = 0; l < 2; l++)
		assert_int_equal(hl_model_hd84(l, &lamp[l]), 0);
	assert_int_equal(hl_preset_new(HL_HD84_SOURCES, &p), 0);
	assert_int_equal(hl_model_hd84_preset(preset, lamp, p), 0);
	for (int l = 0; l < 2; l++) {
		float cur[HL_HD84_SOURCES];

		g[l] = hl_lid_grid(lamp[l]);
		dense[l] = malloc(sizeof(float) * g[l]->width * g[l]->height);
		assert_non_null(dense[l]);
		hl_preset_intensities(p, l, cur);
		hl_combine_sparse(lamp[l], cur, dense[l]);
	}
	assert_int_equal(hl_glare_new(sc, reg, g, &gl), 0);
	hl_glare_eval(gl, 0.0, (const float *const *)dense, res);
	for (int i = 0; i < 3; i++)
		ret_e[i] = check_user(&res[i], i, g, (const float *const *)dense, NULL);
	check_user(&res[3], 3, g, (const float *const *)dense, NULL);
	print_message("%s: E at 50/100/200 m = %.4f / %.4f / %.4f lx, pair half %.1f / %.1f / "
		      "%.1f cd, limits %.0f / %.0f / %.0f\n",
		      preset, ret_e[0], ret_e[1], ret_e[2], res[0].pair_half_cd,
		      res[1].pair_half_cd, res[2].pair_half_cd, res[0].limit.max_cd,
		      res[1].limit.max_cd, res[2].limit.max_cd);
	hl_glare_free(gl);
	hl_regulation_free(reg);
	hl_scenario_free(sc);
	hl_preset_free(p);
	for (int l = 0; l < 2; l++) {
		free(dense[l]);
		hl_lid_free(lamp[l]);
	}
}

static void still_oncoming_hd84_low_and_high(void **state)
{
	(void)state;
	struct hl_glare_result lo[4], hi[4];
	double elo[3], ehi[3];

	hd84_at("low", lo, elo);
	hd84_at("high", hi, ehi);
	/* The high beam puts more light at every oncoming eye than the low beam. */
	for (int i = 0; i < 3; i++)
		assert_true(ehi[i] > elo[i]);
	/* At 50 m (625 cd on half the pair): the low beam under, the high beam over. */
	assert_true(lo[0].limit.max_cd == 625.0 && lo[0].pair_half_cd < 625.0 && lo[0].pass);
	assert_true(hi[0].pair_half_cd > 625.0 && !hi[0].pass);
}

/* The distance rule and the classes on the shipped set (its values read from the set). */
static void limit_follows_the_distance_rule(void **state)
{
	(void)state;
	struct hl_scenario *sc = scenario();
	struct hl_regulation *reg = adb_glare();
	const struct hl_lid_grid gr = { 3, 3, HL_ANGLES_A, -1.0f, 1.0f, -1.0f, 1.0f };
	const struct hl_lid_grid *const g[2] = { &gr, &gr };
	struct hl_glare *gl = NULL;
	struct hl_glare_limit lim;
	const int o50 = hl_regulation_find(reg, "Oncoming 50 m");
	const int o100 = hl_regulation_find(reg, "Oncoming 100 m");
	const int o200 = hl_regulation_find(reg, "Oncoming 200 m");
	const int p50 = hl_regulation_find(reg, "Preceding 50 m");
	const int p50b = hl_regulation_find(reg, "Preceding 50 m beyond");
	const int p200 = hl_regulation_find(reg, "Preceding 200 m");
	static const struct {
		enum hl_actor_role role;
		double d, h;
		int which; /* 0 o50, 1 o100, 2 o200, 3 p50, 4 p50b, 5 p200, -1 none */
		double table_d;
	} cases[] = {
		{ HL_ROLE_ONCOMING, 20.0, -4.0, 0, 50 }, /* below the table: its nearest row */
		{ HL_ROLE_ONCOMING, 50.0, -4.0, 0, 50 }, /* at */
		{ HL_ROLE_ONCOMING, 99.99, -2.0, 0, 50 }, /* between: not beyond */
		{ HL_ROLE_ONCOMING, 100.0, -2.0, 1, 100 },
		{ HL_ROLE_ONCOMING, 199.0, -1.0, 1, 100 },
		{ HL_ROLE_ONCOMING, 200.0, -1.0, 2, 200 },
		{ HL_ROLE_ONCOMING, 900.0, -0.2, 2, 200 }, /* above: the largest */
		{ HL_ROLE_PRECEDING, 60.0, 0.0, 3, 50 }, /* preceding class */
		{ HL_ROLE_PRECEDING, 60.0, 1.5, 4, 50 }, /* beyond 1.0R: its own row */
		{ HL_ROLE_PRECEDING, 60.0, 1.0, 3, 50 }, /* the shared end: the stricter */
		{ HL_ROLE_PRECEDING, 60.0, 5.0, 3, 50 }, /* no segment holds it: the stricter */
		{ HL_ROLE_PRECEDING, 250.0, 0.0, 5, 200 },
		{ HL_ROLE_CROSSING, 60.0, 0.0, -1, NAN },
		{ HL_ROLE_ROADSIDE, 60.0, 0.0, -1, NAN },
	};
	const int idx[6] = { o50, o100, o200, p50, p50b, p200 };

	for (int k = 0; k < 6; k++)
		assert_true(idx[k] >= 0);
	assert_int_equal(hl_glare_new(sc, reg, g, &gl), 0);
	for (size_t k = 0; k < sizeof(cases) / sizeof(cases[0]); k++) {
		hl_glare_limit(gl, cases[k].role, cases[k].d, cases[k].h, &lim);
		if (cases[k].which < 0) {
			assert_true(isnan(lim.max_cd) && isnan(lim.table_distance_m));
			assert_int_equal(lim.req, -1);
			continue;
		}
		assert_int_equal(lim.req, idx[cases[k].which]);
		assert_true(lim.max_cd == reg->req[idx[cases[k].which]].max.cd);
		assert_true(lim.table_distance_m == cases[k].table_d);
	}
	/* The values themselves, as regulations/unece-r149-01-adb-glare.json cites them. */
	hl_glare_limit(gl, HL_ROLE_ONCOMING, 50.0, -4.0, &lim);
	assert_true(lim.max_cd == 625.0);
	hl_glare_limit(gl, HL_ROLE_PRECEDING, 50.0, 0.0, &lim);
	assert_true(lim.max_cd == 1850.0);
	hl_glare_free(gl);
	hl_regulation_free(reg);
	hl_scenario_free(sc);
}

/* A preceding car is judged by the preceding rows, an oncoming one by the oncoming rows. */
static void preceding_car_uses_preceding_limit(void **state)
{
	(void)state;
	const struct hl_lid_grid ga = { 201, 101, HL_ANGLES_A, -20.0f, 20.0f, -10.0f, 10.0f };
	const struct hl_lid_grid *const g[2] = { &ga, &ga };
	float *d0 = calloc(201 * 101, sizeof(float));
	const float *const d[2] = { d0, d0 };
	struct hl_scenario *sc = scenario();
	struct hl_regulation *reg = adb_glare();
	struct hl_glare *gl = NULL;
	struct hl_glare_result res[4];

	assert_non_null(d0);
	for (int i = 0; i < 201 * 101; i++)
		d0[i] = 1000.0f; /* between the oncoming 50 m and the preceding 50 m limits */
	assert_int_equal(hl_glare_new(sc, reg, g, &gl), 0);
	assert_int_equal(hl_glare_eval(gl, 0.0, d, res), 1);
	assert_true(res[0].limit.max_cd == 625.0 && !res[0].pass); /* oncoming at 50 m */
	assert_true(res[3].limit.max_cd == 1850.0 && res[3].pass); /* preceding at 78.2 m */
	assert_int_equal(res[3].limit.req, hl_regulation_find(reg, "Preceding 50 m"));
	assert_true(fabs(res[3].distance_m - hypot(78.2, EYE_Y)) < 1e-6);
	assert_true(res[1].pass && res[2].pass);
	hl_glare_free(gl);
	hl_regulation_free(reg);
	hl_scenario_free(sc);
	free(d0);
}

/* A set on each lamp, not on the pair, cannot give glare limits. */
static void each_lamp_set_refused(void **state)
{
	(void)state;
	struct hl_scenario *sc = scenario();
	struct hl_regulation *reg = adb_glare();
	const struct hl_lid_grid gr = { 3, 3, HL_ANGLES_A, -1.0f, 1.0f, -1.0f, 1.0f };
	const struct hl_lid_grid *const g[2] = { &gr, &gr };
	struct hl_glare *gl = NULL;

	reg->applies = HL_REG_EACH_LAMP;
	assert_int_equal(hl_glare_new(sc, reg, g, &gl), -EINVAL);
	reg->applies = HL_REG_PAIR_HALF;
	for (int i = 0; i < reg->n_requirements; i++)
		snprintf(reg->req[i].id, sizeof(reg->req[i].id), "row %d", i);
	assert_int_equal(hl_glare_new(sc, reg, g, &gl), -EINVAL);
	assert_null(gl);
	hl_regulation_free(reg);
	hl_scenario_free(sc);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(still_oncoming_on_closed_form_grids),
		cmocka_unit_test(still_oncoming_hd84_low_and_high),
		cmocka_unit_test(limit_follows_the_distance_rule),
		cmocka_unit_test(preceding_car_uses_preceding_limit),
		cmocka_unit_test(each_lamp_set_refused),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
