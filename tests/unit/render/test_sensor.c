/* SPDX-License-Identifier: MIT */
/*
 * Sensors: a uniform sky gives pi L at any normal; a vertical sensor under a sky that ends at
 * the horizon gives exactly half; the eye sits HL_SENSOR_OFFSET_M along the normal; thin-object
 * supersampling keeps the weights (pi L still) and only adds rays near the capsule; the scene's
 * radiance is the sky where nothing is hit and rho E / pi on a surface, E from both lamps.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "lamp/model.h"
#include "render/sensor.h"

#define assert_near(a, b, eps)                                                                   \
	do {                                                                                     \
		const double a_ = (a), b_ = (b);                                                 \
		if (!(fabs(a_ - b_) <= (eps)))                                                   \
			fail_msg("%s = %.17g, expected %.17g +- %g", #a, a_, b_, (double)(eps)); \
	} while (0)

struct field {
	double l;
	long calls;
};

static double uniform(const void *field, const double o[3], const double d[3])
{
	struct field *f = (struct field *)field;

	(void)o;
	(void)d;
	f->calls++;
	return f->l;
}

static double upper_half(const void *field, const double o[3], const double d[3])
{
	(void)o;
	return d[2] > 0.0 ? ((const struct field *)field)->l : 0.0;
}

/* The eye's height as luminance: shows where the sensor looks from. */
static double eye_height(const void *field, const double o[3], const double d[3])
{
	(void)field;
	(void)d;
	return o[2];
}

static struct hl_hemicube *cube(int size, float **scratch)
{
	struct hl_hemicube *h;

	assert_int_equal(hl_hemicube_new(size, &h), 0);
	assert_int_equal(hl_sensor_scratch_floats(h), 3 * hl_hemicube_texels(h));
	*scratch = malloc(sizeof(float) * hl_sensor_scratch_floats(h));
	assert_non_null(*scratch);
	return h;
}

static void sensor_uniform_sky_gives_pi_l_at_any_normal(void **state)
{
	static const double normals[4][3] = {
		{ 0, 0, 1 }, { 0, 0, -1 }, { 1, 0, 0 }, { 0.48, -0.6, 0.64 }
	};
	const double p[9] = { 0, 0, 0, 5, -3, 1, 100, 200, -7 };
	float *scratch;
	struct hl_hemicube *h = cube(8, &scratch);
	struct field f = { 2.5, 0 };
	double e[3];
	(void)state;

	for (int k = 0; k < 4; k++) {
		f.calls = 0;
		hl_sensor_batch(h, uniform, &f, NULL, normals[k], 3, p, scratch, e);
		assert_int_equal(f.calls, 3 * (long)hl_hemicube_texels(h)); /* one ray a texel */
		for (int s = 0; s < 3; s++)
			assert_near(e[s], M_PI * 2.5, 1e-12);
	}
	free(scratch);
	hl_hemicube_free(h);
}

static void sensor_vertical_under_a_horizon_sky_gets_exactly_half(void **state)
{
	const double n[3] = { 1, 0, 0 }, p[3] = { 0, 0, 1 };
	float *scratch;
	struct hl_hemicube *h = cube(16, &scratch);
	struct field f = { 4.0, 0 };
	double e;
	(void)state;

	hl_sensor_batch(h, upper_half, &f, NULL, n, 1, p, scratch, &e);
	assert_near(e, M_PI * 4.0 / 2, 1e-12);
	/* facing up it sees all of it, facing down none */
	hl_sensor_batch(h, upper_half, &f, NULL, (const double[3]){ 0, 0, 1 }, 1, p, scratch, &e);
	assert_near(e, M_PI * 4.0, 1e-12);
	hl_sensor_batch(h, upper_half, &f, NULL, (const double[3]){ 0, 0, -1 }, 1, p, scratch, &e);
	assert_near(e, 0.0, 0.0);
	free(scratch);
	hl_hemicube_free(h);
}

static void sensor_eye_is_offset_along_the_normal(void **state)
{
	const double p[6] = { 3, 4, 0, 3, 4, 2 };
	float *scratch;
	struct hl_hemicube *h = cube(4, &scratch);
	double e[2];
	(void)state;

	hl_sensor_batch(h, eye_height, NULL, NULL, (const double[3]){ 0, 0, 1 }, 2, p, scratch, e);
	assert_near(e[0], M_PI * HL_SENSOR_OFFSET_M, 1e-15);
	assert_near(e[1], M_PI * (2 + HL_SENSOR_OFFSET_M), 1e-12);
	hl_sensor_batch(h, eye_height, NULL, NULL, (const double[3]){ 0, 0, -1 }, 2, p, scratch, e);
	assert_near(e[0], -M_PI * HL_SENSOR_OFFSET_M, 1e-15);
	free(scratch);
	hl_hemicube_free(h);
}

static void sensor_supersampling_keeps_the_weights_and_adds_rays_near_thin_objects(void **state)
{
	/* a post 1 m in front of the sensor (above its tangent plane), and one 5 m under it */
	const struct hl_capsule near_post = { { 1, 0, 0 }, { 1, 0, 1 }, 0.06 };
	const struct hl_capsule buried = { { 0, 0, -6 }, { 0, 0, -5 }, 0.06 };
	const double n[3] = { 0, 0, 1 }, p[3] = { 0, 0, 0 };
	float *scratch;
	struct hl_hemicube *h = cube(16, &scratch);
	const long texels = (long)hl_hemicube_texels(h);
	struct field f = { 1.5, 0 };
	struct hl_sensor_aa aa = { &near_post, 1, 4 };
	double e;
	(void)state;

	hl_sensor_batch(h, uniform, &f, &aa, n, 1, p, scratch, &e);
	assert_near(e, M_PI * 1.5, 1e-12);
	/* the texels near the post take 16 rays instead of 1: calls = texels + 15 per fine texel */
	assert_true(f.calls > texels);
	assert_int_equal((f.calls - texels) % 15, 0);
	assert_true((f.calls - texels) / 15 < texels / 4);
	/* a thin object below the tangent plane, or samples 1, or no objects: one ray a texel */
	aa = (struct hl_sensor_aa){ &buried, 1, 4 };
	f.calls = 0;
	hl_sensor_batch(h, uniform, &f, &aa, n, 1, p, scratch, &e);
	assert_int_equal(f.calls, texels);
	aa = (struct hl_sensor_aa){ &near_post, 1, 1 };
	f.calls = 0;
	hl_sensor_batch(h, uniform, &f, &aa, n, 1, p, scratch, &e);
	assert_int_equal(f.calls, texels);
	aa = (struct hl_sensor_aa){ &near_post, 0, 4 };
	f.calls = 0;
	hl_sensor_batch(h, uniform, &f, &aa, n, 1, p, scratch, &e);
	assert_int_equal(f.calls, texels);
	free(scratch);
	hl_hemicube_free(h);
}

/* A smooth distribution on the default grid. */
static float *distribution(const struct hl_lid_grid *g)
{
	float *d = malloc(sizeof(float) * g->width * g->height);

	assert_non_null(d);
	for (int y = 0; y < g->height; y++)
		for (int x = 0; x < g->width; x++) {
			const double h = hl_lid_grid_h_deg(g, x), v = hl_lid_grid_v_deg(g, y) + 2;

			d[y * g->width + x] = (float)(20000.0 * exp(-h * h / 300.0 - v * v / 10.0));
		}
	return d;
}

static void sensor_scene_radiance_is_sky_or_rho_e_over_pi(void **state)
{
	struct hl_lamp_pose poses[2];
	struct hl_scene scene;
	struct hl_sensor_scene f;
	const double o[3] = { 0, 0, 1.2 };
	const double up[3] = { 0, 0, 1 }, down[3] = { 0.96, 0, -0.28 };
	float pos[4], nrm[4];
	double p[3], nn[3], e = 0.0;
	(void)state;

	hl_lamp_pose_default(0, &poses[0]);
	hl_lamp_pose_default(1, &poses[1]);
	hl_scene_init(&scene, HL_SCENE_ROAD, poses);
	memset(&f, 0, sizeof(f));
	f.scene = &scene;
	f.n_lamps = 2;
	for (int k = 0; k < 2; k++) {
		f.lamps[k].pose = poses[k];
		hl_model_default_grid(&f.lamps[k].grid);
		f.dense[k] = distribution(&f.lamps[k].grid);
	}
	f.sky_cd_m2 = 0.03;
	assert_near(hl_sensor_scene_radiance(&f, o, up), 0.03, 0.0);
	/* looking down the road: the surface hit, lit by both lamps */
	assert_int_not_equal(hl_scene_cast(&scene, o, down, pos, nrm), HL_SURF_NONE);
	for (int i = 0; i < 3; i++) {
		p[i] = pos[i];
		nn[i] = nrm[i];
	}
	for (int k = 0; k < 2; k++)
		e += hl_headlight_point(&f.lamps[k], f.dense[k], p, nn);
	assert_true(e > 0.0);
	assert_near(hl_sensor_scene_radiance(&f, o, down), pos[3] * e / M_PI, 1e-12 * e);
	/* lamp 1 without a distribution: dark */
	free((void *)f.dense[1]);
	f.dense[1] = NULL;
	assert_near(hl_sensor_scene_radiance(&f, o, down),
		    pos[3] * hl_headlight_point(&f.lamps[0], f.dense[0], p, nn) / M_PI, 1e-12 * e);
	free((void *)f.dense[0]);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(sensor_uniform_sky_gives_pi_l_at_any_normal),
		cmocka_unit_test(sensor_vertical_under_a_horizon_sky_gets_exactly_half),
		cmocka_unit_test(sensor_eye_is_offset_along_the_normal),
		cmocka_unit_test(
			sensor_supersampling_keeps_the_weights_and_adds_rays_near_thin_objects),
		cmocka_unit_test(sensor_scene_radiance_is_sky_or_rho_e_over_pi),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
