/* SPDX-License-Identifier: MIT */
/*
 * GLES sensors (render/gl_sensor.c) against the CPU sensors (render/sensor.c): the
 * normalisation (a uniform sky through an empty scene gives E = pi L, for every sensor of a
 * batch, with and without multisampling and supersampling), and the irradiance at the same
 * points of the bounce and road scenes, both lamps lit by their combined distributions.
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#include "lamp/combine.h"
#include "render/egl.h"
#include "render/gl_sensor.h"
#include "render/hemicube.h"
#include "render/scene.h"
#include "render/scene_mesh.h"
#include "render/sensor.h"
#include "lamp/model.h"
#include "lamp/preset.h"

#include "egl_fixture.h"

static double now_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

/* A lamp that is never lit: the sky test needs the lamp uniforms, not their light. */
static void dark_lamp(struct hl_headlight_lamp *lamp, float **dense)
{
	hl_lamp_pose_default(0, &lamp->pose);
	hl_model_default_grid(&lamp->grid);
	*dense = calloc((size_t)lamp->grid.width * lamp->grid.height, sizeof(float));
	assert_non_null(*dense);
}

static void gl_sensor_uniform_sky_gives_pi_l(void **state)
{
	static const double normals[][3] = {
		{ 0, 0, 1 }, { 0, 0, -1 }, { 1, 0, 0 }, { 0.48, -0.6, 0.64 }, { -0.36, 0.48, 0.8 }
	};
	static const struct {
		int size, ss, msaa, batch;
	} cases[] = { { 2, 1, 1, 1 },  { 8, 1, 4, 3 },	{ 32, 1, 1, 7 }, { 64, 1, 1, 1 },
		      { 16, 2, 1, 1 }, { 32, 2, 1, 1 }, { 32, 1, 4, 5 }, { 32, 2, 4, 5 } };
	const size_t n = sizeof(normals) / sizeof(normals[0]);
	struct hl_headlight_lamp lamp;
	struct hl_scene_mesh *mesh;
	double p[3 * 5], nn[3 * 5], e[5];
	float *dense;
	char log[1024] = "";

	(void)state;
	dark_lamp(&lamp, &dense);
	assert_int_equal(hl_scene_mesh_new_empty(&mesh), 0);
	for (size_t i = 0; i < n; i++)
		for (int j = 0; j < 3; j++) {
			p[3 * i + j] = 10.0 * i + j;
			nn[3 * i + j] = normals[i][j];
		}
	for (size_t c = 0; c < sizeof(cases) / sizeof(cases[0]); c++) {
		const struct hl_gl_sensor_config cfg = { cases[c].size, cases[c].ss, cases[c].msaa,
							 cases[c].batch, 2.5 };
		struct hl_gl_sensor *s;

		assert_int_equal(hl_gl_sensor_new(egl, mesh, 1, &lamp, &cfg, &s, log, sizeof(log)),
				 0);
		assert_int_equal(hl_gl_sensor_upload(s, 0, dense), 0);
		assert_int_equal(hl_gl_sensor_run(s, n, p, nn, e), 0);
		for (size_t i = 0; i < n; i++) {
			printf("size %d ss %d msaa %d batch %d: E %.7f, pi L %.7f\n", cfg.size,
			       cfg.supersample, cfg.msaa, cfg.batch, e[i], M_PI * 2.5);
			assert_true(fabs(e[i] - M_PI * 2.5) < 1e-5 * M_PI * 2.5);
		}
		hl_gl_sensor_free(s);
	}
	hl_scene_mesh_free(mesh);
	free(dense);
}

/* The HD84 lamps' combined distributions for a preset: the road field of the CPU sensors. */
static void hd84_field(const char *preset_name, struct hl_lid *lids[2], float *dense[2],
		       struct hl_headlight_lamp lamps[2])
{
	struct hl_preset *preset;
	float *cur;

	assert_int_equal(hl_preset_new(HL_HD84_SOURCES, &preset), 0);
	for (int k = 0; k < 2; k++) {
		assert_int_equal(hl_model_hd84(k, &lids[k]), 0);
		hl_lamp_pose_default(k, &lamps[k].pose);
	}
	assert_int_equal(hl_model_hd84_preset(preset_name, lids, preset), 0);
	cur = malloc(sizeof(float) * HL_HD84_SOURCES);
	assert_non_null(cur);
	for (int k = 0; k < 2; k++) {
		const struct hl_lid_grid *g = hl_lid_grid(lids[k]);

		dense[k] = malloc(sizeof(float) * g->width * g->height);
		assert_non_null(dense[k]);
		hl_preset_intensities(preset, k, cur);
		hl_combine_sparse(lids[k], cur, dense[k]);
		lamps[k].grid = *g;
	}
	free(cur);
	hl_preset_free(preset);
}

struct agreement {
	double mean_rel; /* sum |gles - cpu| / sum cpu */
	double bias_rel; /* sum (gles - cpu) / sum cpu */
	double worst_rel; /* over points with cpu > 1 % of the mean */
	double p90_rel; /* 90th percentile of the same */
	size_t n;
};

/*
 * CPU and GLES sensors at every step-th surface pixel of the scene's default view (w x h):
 * the CPU with aa x aa rays near the scene's thin objects, GLES with cfg.
 */
static int cmp_double(const void *a, const void *b)
{
	const double x = *(const double *)a, y = *(const double *)b;

	return (x > y) - (x < y);
}

static struct agreement compare(enum hl_scene_kind kind, const char *preset, int w, int h, int step,
				int aa, const struct hl_gl_sensor_config *cfg)
{
	struct hl_lid *lids[2];
	float *dense[2];
	struct hl_headlight_lamp lamps[2];
	struct hl_lamp_pose poses[2];
	struct hl_scene scene;
	struct hl_camera cam;
	struct hl_gbuffer *gb;
	struct hl_scene_mesh *mesh;
	struct hl_gl_sensor *s;
	struct hl_hemicube *cube;
	struct hl_capsule thin[HL_SCENE_MAX_THIN];
	struct hl_sensor_aa sa = { thin, 0, aa };
	struct hl_sensor_scene field;
	struct agreement a = { 0 };
	double *p, *n, *e_gl, *e_cpu, sum_abs = 0.0, sum = 0.0, t_gl, t_cpu;
	float *scratch;
	char log[1024] = "";
	size_t m = 0, n_rel = 0;

	hd84_field(preset, lids, dense, lamps);
	poses[0] = lamps[0].pose;
	poses[1] = lamps[1].pose;
	hl_scene_init(&scene, kind, poses);
	hl_scene_default_camera(&scene, w, h, &cam);
	assert_int_equal(hl_gbuffer_new(w, h, &gb), 0);
	assert_int_equal(hl_scene_render(&scene, &cam, gb), 0);
	sa.n_thin = hl_scene_thin_objects(&scene, thin, HL_SCENE_MAX_THIN);
	field = (struct hl_sensor_scene){ .scene = &scene, .n_lamps = 2 };
	for (int k = 0; k < 2; k++) {
		field.lamps[k] = lamps[k];
		field.dense[k] = dense[k];
	}
	p = malloc(sizeof(double) * 3 * w * h);
	n = malloc(sizeof(double) * 3 * w * h);
	e_gl = malloc(sizeof(double) * w * h);
	e_cpu = malloc(sizeof(double) * w * h);
	assert_true(p && n && e_gl && e_cpu);
	for (size_t i = 0; i < (size_t)w * h; i += step) {
		if (gb->nrm[4 * i + 3] == (float)HL_SURF_NONE)
			continue;
		for (int j = 0; j < 3; j++) {
			p[3 * m + j] = gb->pos[4 * i + j];
			n[3 * m + j] = gb->nrm[4 * i + j];
		}
		m++;
	}
	assert_int_equal(hl_scene_mesh_new(&scene, &mesh), 0);
	assert_int_equal(hl_gl_sensor_new(egl, mesh, 2, lamps, cfg, &s, log, sizeof(log)), 0);
	for (int k = 0; k < 2; k++)
		assert_int_equal(hl_gl_sensor_upload(s, k, dense[k]), 0);
	assert_int_equal(hl_gl_sensor_run(s, 1, p, n, e_gl), 0); /* shader compilation */
	t_gl = now_ms();
	assert_int_equal(hl_gl_sensor_run(s, m, p, n, e_gl), 0);
	t_gl = now_ms() - t_gl;
	assert_int_equal(hl_hemicube_new(cfg->size, &cube), 0);
	scratch = malloc(sizeof(float) * hl_sensor_scratch_floats(cube));
	assert_non_null(scratch);
	t_cpu = now_ms();
	for (size_t i = 0; i < m; i++)
		hl_sensor_batch(cube, hl_sensor_scene_radiance, &field, &sa, n + 3 * i, 1,
				p + 3 * i, scratch, &e_cpu[i]);
	t_cpu = now_ms() - t_cpu;
	for (size_t i = 0; i < m; i++) {
		sum_abs += fabs(e_gl[i] - e_cpu[i]);
		a.bias_rel += e_gl[i] - e_cpu[i];
		sum += e_cpu[i];
	}
	for (size_t i = 0; i < m; i++)
		if (e_cpu[i] > 0.01 * sum / m) {
			const double r = fabs(e_gl[i] - e_cpu[i]) / e_cpu[i];

			e_cpu[n_rel++] = r; /* done with it: reused for the percentile */

			if (r > a.worst_rel) {
				a.worst_rel = r;
				if (r > 0.05)
					printf("  (%.3f, %.3f, %.3f) n (%.2f, %.2f, %.2f): cpu %.5f, "
					       "gles %.5f lx\n",
					       p[3 * i], p[3 * i + 1], p[3 * i + 2], n[3 * i],
					       n[3 * i + 1], n[3 * i + 2], e_cpu[i], e_gl[i]);
			}
		}
	qsort(e_cpu, n_rel, sizeof(double), cmp_double);
	a.p90_rel = n_rel ? e_cpu[n_rel * 9 / 10] : 0.0;
	a.mean_rel = sum_abs / sum;
	a.bias_rel /= sum;
	a.n = m;
	printf("%s %s: %zu sensors %dx%d (gles ss %d msaa %d batch %d, cpu aa %d): mean E %.4f lx, "
	       "sum |gles - cpu| / sum cpu %.3f %% (bias %+.3f %%), per point: 90 %% within %.2f %%, worst %.2f %%; "
	       "gles %.3f ms, cpu %.3f ms per sensor\n",
	       hl_scene_name(kind), preset, m, cfg->size, cfg->size, cfg->supersample, cfg->msaa,
	       cfg->batch, aa, sum / m, 100 * a.mean_rel, 100 * a.bias_rel, 100 * a.p90_rel,
	       100 * a.worst_rel, t_gl / m, t_cpu / m);
	free(scratch);
	hl_hemicube_free(cube);
	hl_gl_sensor_free(s);
	hl_scene_mesh_free(mesh);
	hl_gbuffer_free(gb);
	free(p);
	free(n);
	free(e_gl);
	free(e_cpu);
	for (int k = 0; k < 2; k++) {
		hl_lid_free(lids[k]);
		free(dense[k]);
	}
	return a;
}

/*
 * At the same points, GLES and CPU sensors converge to the same irradiance: 128 x 128 hemicubes
 * (CPU: 4 x 4 rays per texel near the posts; GLES: 4 samples per texel everywhere). At 32 x 32
 * a single point can differ by tens of per cent where a post or the grazing lit floor covers
 * less than a texel (both are sampling it, differently); the mean over many points agrees.
 */
static void gl_sensor_matches_cpu_bounce(void **state)
{
	const struct hl_gl_sensor_config fine = { 128, 1, 4, 64, 0.0 };
	const struct hl_gl_sensor_config coarse = { 32, 1, 4, 64, 0.0 };
	struct agreement a;

	(void)state;
	a = compare(HL_SCENE_BOUNCE, "high", 64, 36, 13, 4, &fine);
	assert_true(a.n > 100);
	assert_true(a.mean_rel < 0.005);
	assert_true(a.p90_rel < 0.01);
	assert_true(a.worst_rel < 0.05);
	a = compare(HL_SCENE_BOUNCE, "high", 64, 36, 7, 4, &coarse);
	assert_true(a.mean_rel < 0.02);
	assert_true(fabs(a.bias_rel) < 0.01);
}

static void gl_sensor_matches_cpu_road(void **state)
{
	const struct hl_gl_sensor_config fine = { 128, 1, 4, 64, 0.0 };
	const struct hl_gl_sensor_config coarse = { 32, 2, 4, 64, 0.0 };
	struct agreement a;

	(void)state;
	a = compare(HL_SCENE_ROAD, "low", 160, 90, 41, 4, &fine);
	assert_true(a.n > 100);
	assert_true(a.mean_rel < 0.015);
	assert_true(fabs(a.bias_rel) < 0.01);
	assert_true(a.p90_rel < 0.2);
	assert_true(a.worst_rel < 0.4);
	a = compare(HL_SCENE_ROAD, "low", 160, 90, 23, 4, &coarse);
	assert_true(a.mean_rel < 0.1);
	assert_true(fabs(a.bias_rel) < 0.03);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(gl_sensor_uniform_sky_gives_pi_l),
		cmocka_unit_test(gl_sensor_matches_cpu_bounce),
		cmocka_unit_test(gl_sensor_matches_cpu_road),
	};

	return cmocka_run_group_tests(tests, egl_setup, egl_teardown);
}
