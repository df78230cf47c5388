/* SPDX-License-Identifier: MIT */
/*
 * The headlight pass against the physics (docs/design.md §1, §4): the papers' sphere validation for
 * type A and type B lamps, a single source lighting exactly its region, the wall at 25 m at
 * (0,0), B50L and 75R, and the GLES pass against the CPU pass.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "lamp/angles.h"
#include "lamp/combine.h"
#include "render/egl.h"
#include "render/gl_headlight.h"
#include "render/headlight.h"
#include "render/scene.h"
#include "lamp/model.h"

#define DEG (M_PI / 180.0)

#include "egl_fixture.h"

/* The GLES pass in one mode over gb, lamps reading dense[k]. */
static void gl_pass(const struct hl_gbuffer *gb, int n, const struct hl_headlight_lamp *lamps,
		    const float *const *dense, enum hl_gl_headlight_mode mode, float *out)
{
	struct hl_gl_headlight *gl;
	char log[1024] = "";

	assert_int_equal(hl_gl_headlight_new(gb, n, lamps, mode, &gl, log, sizeof(log)), 0);
	for (int k = 0; k < n; k++)
		assert_int_equal(hl_gl_headlight_upload(gl, k, dense[k]), 0);
	hl_gl_headlight_run(gl);
	assert_int_equal(hl_gl_headlight_read(gl, out), 0);
	hl_gl_headlight_free(gl);
}

/* Two smooth test sources, steep enough in V that a wrong angle system is off by > 1 %. */
static double source_cd(int k, double h_deg, double v_deg)
{
	if (k == 0)
		return 20000.0 * exp(-(h_deg - 2.0) * (h_deg - 2.0) / (2 * 8.0 * 8.0)) *
		       exp(-(v_deg + 1.0) * (v_deg + 1.0) / (2 * 3.0 * 3.0));
	return 8000.0 * exp(-(h_deg + 10.0) * (h_deg + 10.0) / (2 * 12.0 * 12.0)) *
	       exp(-(v_deg - 2.0) * (v_deg - 2.0) / (2 * 4.0 * 4.0));
}

static const float currents[2] = { 0.5f, 0.25f };

static struct hl_lid *test_lamp(enum hl_angles system)
{
	struct hl_lid_grid g;
	struct hl_lid *lid;
	float *dense;

	hl_model_default_grid(&g);
	g.angles = system;
	assert_int_equal(hl_lid_new(2, &g, false, &lid), 0);
	dense = malloc(sizeof(float) * g.width * g.height);
	assert_non_null(dense);
	for (int k = 0; k < 2; k++) {
		for (int y = 0; y < g.height; y++)
			for (int x = 0; x < g.width; x++)
				dense[y * g.width + x] = (float)source_cd(
					k, hl_lid_grid_h_deg(&g, x), hl_lid_grid_v_deg(&g, y));
		assert_int_equal(hl_lid_set_source(lid, k, dense), 0);
	}
	free(dense);
	return lid;
}

struct sphere_run {
	struct hl_scene scene;
	struct hl_camera cam;
	struct hl_gbuffer *gb;
	float *lux_cpu, *lux_gl, *lux_glp; /* CPU, GLES direct, GLES precomputed */
};

/* Renders the sphere scene lit by the left lamp only, on the CPU and in GLES. */
static void render_sphere(const struct hl_lid *lid, enum hl_angles label, int w, int h,
			  double fov_deg, struct sphere_run *run)
{
	struct hl_lamp_pose poses[2];
	struct hl_headlight_lamp lamp;
	struct hl_headlight *cpu;
	const struct hl_lid_grid *g = hl_lid_grid(lid);
	float *dense = malloc(sizeof(float) * g->width * g->height);
	const float *d[1] = { dense };

	assert_non_null(dense);
	hl_combine_sparse(lid, currents, dense);
	hl_lamp_pose_default(0, &poses[0]);
	hl_lamp_pose_default(1, &poses[1]);
	hl_scene_init(&run->scene, HL_SCENE_SPHERE, poses);
	hl_scene_default_camera(&run->scene, w, h, &run->cam);
	run->cam.fov_y_deg = fov_deg;
	assert_int_equal(hl_gbuffer_new(w, h, &run->gb), 0);
	assert_int_equal(hl_scene_render(&run->scene, &run->cam, run->gb), 0);
	lamp.pose = poses[0];
	lamp.grid = *g;
	lamp.grid.angles = label;
	run->lux_cpu = malloc(sizeof(float) * w * h);
	run->lux_gl = malloc(sizeof(float) * w * h);
	run->lux_glp = malloc(sizeof(float) * w * h);
	assert_non_null(run->lux_glp);
	assert_non_null(run->lux_cpu);
	assert_non_null(run->lux_gl);
	assert_int_equal(hl_headlight_new(run->gb, 1, &lamp, &cpu), 0);
	hl_headlight_run(cpu, d, run->lux_cpu);
	hl_headlight_free(cpu);
	gl_pass(run->gb, 1, &lamp, d, HL_GL_HEADLIGHT_DIRECT, run->lux_gl);
	gl_pass(run->gb, 1, &lamp, d, HL_GL_HEADLIGHT_PRECOMPUTED, run->lux_glp);
	free(dense);
}

static void free_run(struct sphere_run *run)
{
	hl_gbuffer_free(run->gb);
	free(run->lux_cpu);
	free(run->lux_gl);
	free(run->lux_glp);
}

/*
 * Largest relative error of lux against I(H, V) / r^2 of the analytic combined distribution,
 * over pixels where I > 1 % of the peak; *ret_n counts them.
 */
static double sphere_error(const struct sphere_run *run, const float *lux, enum hl_angles system,
			   int *ret_n)
{
	const struct hl_camera *cam = &run->cam;
	const struct hl_lamp_pose *lamp = &run->scene.lamps[0];
	const double r = run->scene.sphere_radius_m;
	double peak = 0.0, worst = 0.0;
	double *ref = malloc(sizeof(double) * cam->width * cam->height);

	assert_non_null(ref);
	for (int pass = 0; pass < 2; pass++)
		for (int row = 0; row < cam->height; row++)
			for (int col = 0; col < cam->width; col++) {
				const int i = row * cam->width + col;
				double d[3], p[3], l[3], hh, vv, e;

				if (pass == 1) {
					if (ref[i] * r * r <= 0.01 * peak)
						continue;
					e = fabs(lux[i] - ref[i]) / ref[i];
					worst = e > worst ? e : worst;
					++*ret_n;
					continue;
				}
				hl_camera_ray(cam, col + 0.5, row + 0.5, d);
				for (int j = 0; j < 3; j++)
					p[j] = cam->pos_m[j] + d[j];
				hl_lamp_to_lamp_space(lamp, p, l);
				hl_angles_from_dir(system, l, &hh, &vv);
				hh /= DEG;
				vv /= DEG;
				ref[i] = (currents[0] * source_cd(0, hh, vv) +
					  currents[1] * source_cd(1, hh, vv)) /
					 (r * r);
				if (ref[i] * r * r > peak)
					peak = ref[i] * r * r;
			}
	free(ref);
	return worst;
}

static void sphere_validation(enum hl_angles system)
{
	struct hl_lid *lid = test_lamp(system);
	struct sphere_run run;
	int n = 0;
	double err_cpu, err_gl, err_glp, err_wrong;

	render_sphere(lid, system, 160, 120, 70.0, &run);
	err_cpu = sphere_error(&run, run.lux_cpu, system, &n);
	assert_true(n > 160 * 120 / 10);
	n = 0;
	err_gl = sphere_error(&run, run.lux_gl, system, &n);
	n = 0;
	err_glp = sphere_error(&run, run.lux_glp, system, &n);
	/* The same pixels judged in the other angle system must fail: the test can tell A from B. */
	err_wrong = sphere_error(&run, run.lux_cpu,
				 system == HL_ANGLES_A ? HL_ANGLES_B : HL_ANGLES_A, &n);
	printf("sphere type %c: max error CPU %.4f %%, GLES %.4f %%, GLES precomputed %.4f %%, "
	       "wrong system %.2f %% (%d px)\n",
	       system == HL_ANGLES_A ? 'A' : 'B', 100 * err_cpu, 100 * err_gl, 100 * err_glp,
	       100 * err_wrong, n);
	assert_true(err_cpu < 0.01);
	assert_true(err_gl < 0.01);
	assert_true(err_glp < 0.01);
	assert_true(err_wrong > 0.01);
	free_run(&run);
	hl_lid_free(lid);
}

static void headlight_sphere_type_a_within_1_percent(void **state)
{
	(void)state;
	sphere_validation(HL_ANGLES_A);
}

static void headlight_sphere_type_b_within_1_percent(void **state)
{
	(void)state;
	sphere_validation(HL_ANGLES_B);
}

/* One flat source over a box of samples lights exactly the pixels whose direction is inside. */
static void headlight_single_source_lights_exactly_its_region(void **state)
{
	const int x0 = 455, x1 = 475, y0 = 95, y1 = 106; /* H 1.1..5.1, V -1.1..0.9 */
	struct hl_lid_grid g;
	struct hl_lid *lid;
	struct sphere_run run;
	float *dense;
	int lit = 0, full = 0;

	(void)state;
	hl_model_default_grid(&g);
	assert_int_equal(hl_lid_new(1, &g, false, &lid), 0);
	dense = calloc(g.width * g.height, sizeof(float));
	assert_non_null(dense);
	for (int y = y0; y < y1; y++)
		for (int x = x0; x < x1; x++)
			dense[y * g.width + x] = 1000.0f;
	assert_int_equal(hl_lid_set_source(lid, 0, dense), 0);
	{
		/* render_sphere combines with currents[0] = 0.5: 500 cd, 5 lx at 10 m. */
		render_sphere(lid, HL_ANGLES_A, 200, 150, 12.0, &run);
	}
	for (int row = 0; row < run.cam.height; row++)
		for (int col = 0; col < run.cam.width; col++) {
			const int i = row * run.cam.width + col;
			double d[3], p[3], l[3], hh, vv, fx, fy;
			bool inside, core, edge;

			hl_camera_ray(&run.cam, col + 0.5, row + 0.5, d);
			for (int j = 0; j < 3; j++)
				p[j] = run.cam.pos_m[j] + d[j];
			hl_lamp_to_lamp_space(&run.scene.lamps[0], p, l);
			hl_angles_from_dir(HL_ANGLES_A, l, &hh, &vv);
			fx = (hh / DEG - g.h_first_deg) / 0.2;
			fy = (g.v_last_deg - vv / DEG) / 0.2;
			/* Bilinear: non-zero strictly between the neighbours outside the box. */
			inside = fx > x0 - 1 && fx < x1 && fy > y0 - 1 && fy < y1;
			core = fx >= x0 && fx <= x1 - 1 && fy >= y0 && fy <= y1 - 1;
			edge = fabs(fx - (x0 - 1)) < 1e-3 || fabs(fx - x1) < 1e-3 ||
			       fabs(fy - (y0 - 1)) < 1e-3 || fabs(fy - y1) < 1e-3;
			if (edge)
				continue;
			assert_int_equal(run.lux_cpu[i] > 0.0f, inside);
			assert_int_equal(run.lux_gl[i] > 0.0f, inside);
			assert_int_equal(run.lux_glp[i] > 0.0f, inside);
			lit += inside;
			if (core) {
				assert_float_equal(run.lux_cpu[i], 5.0, 5e-4);
				assert_float_equal(run.lux_gl[i], 5.0, 5e-4);
				assert_float_equal(run.lux_glp[i], 5.0, 5e-4);
				full++;
			}
		}
	printf("single source: %d pixels lit, %d at full 5 lx\n", lit, full);
	assert_true(full > 100);
	free_run(&run);
	free(dense);
	hl_lid_free(lid);
}

/*
 * Wall at 25 m, HD84 left lamp, low beam: the pixel whose ray is the lamp's direction (H, V)
 * (camera at the lamp, odd image, centre pixel) against I(H, V) cos(eps) / r^2.
 */
static void headlight_wall_25m_test_points(void **state)
{
	static const struct {
		const char *name;
		double h_deg, v_deg;
	} points[] = { { "(0,0)", 0.0, 0.0 }, { "B50L", -3.43, 0.57 }, { "75R", 1.15, -0.57 } };
	struct hl_lid *lamps[2];
	struct hl_preset *p;
	float *i, *dense;
	const float *dd[1];
	struct hl_lamp_pose poses[2];
	const struct hl_lid_grid *g;

	(void)state;
	assert_int_equal(hl_model_hd84(HL_SIDE_LEFT, &lamps[0]), 0);
	assert_int_equal(hl_model_hd84(HL_SIDE_RIGHT, &lamps[1]), 0);
	assert_int_equal(hl_preset_new(HL_HD84_SOURCES, &p), 0);
	assert_int_equal(hl_model_hd84_preset("low", lamps, p), 0);
	g = hl_lid_grid(lamps[0]);
	i = malloc(sizeof(float) * HL_HD84_SOURCES);
	dense = malloc(sizeof(float) * g->width * g->height);
	assert_non_null(i);
	assert_non_null(dense);
	hl_preset_intensities(p, HL_SIDE_LEFT, i);
	hl_combine_sparse(lamps[0], i, dense);
	dd[0] = dense;
	hl_lamp_pose_default(0, &poses[0]);
	hl_lamp_pose_default(1, &poses[1]);

	for (size_t t = 0; t < sizeof(points) / sizeof(points[0]); t++) {
		const int w = 33, h = 33, c = (h / 2) * w + w / 2;
		struct hl_headlight_lamp lamp = { poses[0], *g };
		struct hl_scene scene;
		struct hl_camera cam = { .width = w, .height = h, .fov_y_deg = 2.0 };
		struct hl_gbuffer *gb;
		struct hl_headlight *cpu;
		double ax[3], ay[3], az[3], l[3], d[3], tt, r2, cos_eps, ref, intensity;
		float lux[33 * 33], lux_gl[33 * 33], lux_glp[33 * 33];

		hl_scene_init(&scene, HL_SCENE_WALL, poses);
		scene.wall_distance_m = 25.0;
		hl_lamp_basis(&poses[0], ax, ay, az);
		hl_angles_to_dir(HL_ANGLES_A, points[t].h_deg * DEG, points[t].v_deg * DEG, l);
		for (int j = 0; j < 3; j++) {
			d[j] = l[0] * ax[j] + l[1] * ay[j] + l[2] * az[j];
			cam.pos_m[j] = poses[0].pos_m[j];
			cam.dir[j] = d[j];
		}
		cam.up[2] = 1.0;
		assert_int_equal(hl_gbuffer_new(w, h, &gb), 0);
		assert_int_equal(hl_scene_render(&scene, &cam, gb), 0);
		assert_true(gb->nrm[4 * c + 3] == HL_SURF_WALL ||
			    gb->nrm[4 * c + 3] == HL_SURF_WALL_LINE);
		assert_int_equal(hl_headlight_new(gb, 1, &lamp, &cpu), 0);
		hl_headlight_run(cpu, dd, lux);
		hl_headlight_free(cpu);
		gl_pass(gb, 1, &lamp, dd, HL_GL_HEADLIGHT_DIRECT, lux_gl);
		gl_pass(gb, 1, &lamp, dd, HL_GL_HEADLIGHT_PRECOMPUTED, lux_glp);

		/* The ray meets the screen x = 25 m; its normal is -x, so cos(eps) = d.x / |d|. */
		tt = (25.0 - poses[0].pos_m[0]) / d[0];
		r2 = tt * tt * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
		cos_eps = d[0] / sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
		intensity = hl_lid_grid_lookup(g, dense, (float)points[t].h_deg,
					       (float)points[t].v_deg);
		ref = intensity * cos_eps / r2;
		printf("wall 25 m %-5s: I %.1f cd, reference %.4f lx, CPU %.4f lx (%+.4f %%), "
		       "GLES %.4f lx (%+.4f %%), GLES precomputed %.4f lx (%+.4f %%)\n",
		       points[t].name, intensity, ref, lux[c], 100 * (lux[c] - ref) / ref,
		       lux_gl[c], 100 * (lux_gl[c] - ref) / ref, lux_glp[c],
		       100 * (lux_glp[c] - ref) / ref);
		assert_true(intensity > 1.0);
		assert_true(fabs(lux[c] - ref) <= 0.01 * ref);
		assert_true(fabs(lux_gl[c] - ref) <= 0.01 * ref);
		assert_true(fabs(lux_glp[c] - ref) <= 0.01 * ref);
		hl_gbuffer_free(gb);
	}
	free(i);
	free(dense);
	hl_preset_free(p);
	hl_lid_free(lamps[0]);
	hl_lid_free(lamps[1]);
}

/* The point reference agrees with the fast pass pixel by pixel on the road (both lamps). */
static void headlight_road_cpu_equals_gles_and_point_reference(void **state)
{
	struct hl_lid *lamps[2];
	struct hl_preset *p;
	struct hl_lamp_pose poses[2];
	struct hl_headlight_lamp hl[2];
	struct hl_scene scene;
	struct hl_camera cam;
	struct hl_gbuffer *gb;
	struct hl_headlight *cpu;
	const int w = 160, h = 90;
	float *dense[2], *lux = malloc(sizeof(float) * w * h),
			 *lux_gl = malloc(sizeof(float) * w * h),
			 *lux_glp = malloc(sizeof(float) * w * h);
	float i[HL_HD84_SOURCES];
	double worst = 0.0, worst_p = 0.0, worst_ref = 0.0, peak = 0.0;

	(void)state;
	assert_int_equal(hl_model_hd84(HL_SIDE_LEFT, &lamps[0]), 0);
	assert_int_equal(hl_model_hd84(HL_SIDE_RIGHT, &lamps[1]), 0);
	assert_int_equal(hl_preset_new(HL_HD84_SOURCES, &p), 0);
	assert_int_equal(hl_model_hd84_preset("high", lamps, p), 0);
	for (int k = 0; k < 2; k++) {
		const struct hl_lid_grid *g = hl_lid_grid(lamps[k]);

		dense[k] = malloc(sizeof(float) * g->width * g->height);
		hl_preset_intensities(p, k, i);
		hl_combine_sparse(lamps[k], i, dense[k]);
		hl_lamp_pose_default(k, &poses[k]);
		hl[k] = (struct hl_headlight_lamp){ poses[k], *g };
	}
	hl_scene_init(&scene, HL_SCENE_ROAD, poses);
	hl_scene_default_camera(&scene, w, h, &cam);
	assert_int_equal(hl_gbuffer_new(w, h, &gb), 0);
	assert_int_equal(hl_scene_render(&scene, &cam, gb), 0);
	assert_int_equal(hl_headlight_new(gb, 2, hl, &cpu), 0);
	hl_headlight_run(cpu, (const float *const *)dense, lux);
	gl_pass(gb, 2, hl, (const float *const *)dense, HL_GL_HEADLIGHT_DIRECT, lux_gl);
	gl_pass(gb, 2, hl, (const float *const *)dense, HL_GL_HEADLIGHT_PRECOMPUTED, lux_glp);
	for (int j = 0; j < w * h; j++)
		peak = lux[j] > peak ? lux[j] : peak;
	for (int j = 0; j < w * h; j++) {
		const double pp[3] = { gb->pos[4 * j], gb->pos[4 * j + 1], gb->pos[4 * j + 2] };
		const double nn[3] = { gb->nrm[4 * j], gb->nrm[4 * j + 1], gb->nrm[4 * j + 2] };
		double ref = 0.0, e;

		if (gb->nrm[4 * j + 3] != HL_SURF_NONE)
			for (int k = 0; k < 2; k++)
				ref += hl_headlight_point(&hl[k], dense[k], pp, nn);
		e = fabs(lux[j] - lux_gl[j]) / (peak * 1e-3 + fabs(lux[j]));
		worst = e > worst ? e : worst;
		e = fabs(lux[j] - lux_glp[j]) / (peak * 1e-3 + fabs(lux[j]));
		worst_p = e > worst_p ? e : worst_p;
		e = fabs(lux[j] - ref) / (peak * 1e-3 + ref);
		worst_ref = e > worst_ref ? e : worst_ref;
	}
	printf("road, high beam: peak %.1f lx; CPU vs GLES max rel. diff %.2e (precomputed "
	       "%.2e), CPU vs point reference %.2e\n",
	       peak, worst, worst_p, worst_ref);
	assert_true(peak > 10.0);
	/* GLSL float atan at the steep lower grid edge: measured 1.3e-3 locally. */
	assert_true(worst < 5e-3);
	assert_true(worst_p < 5e-3);
	assert_true(worst_ref < 1e-4);
	hl_headlight_free(cpu);
	hl_gbuffer_free(gb);
	free(dense[0]);
	free(dense[1]);
	free(lux);
	free(lux_gl);
	free(lux_glp);
	hl_preset_free(p);
	hl_lid_free(lamps[0]);
	hl_lid_free(lamps[1]);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(headlight_sphere_type_a_within_1_percent),
		cmocka_unit_test(headlight_sphere_type_b_within_1_percent),
		cmocka_unit_test(headlight_single_source_lights_exactly_its_region),
		cmocka_unit_test(headlight_wall_25m_test_points),
		cmocka_unit_test(headlight_road_cpu_equals_gles_and_point_reference),
	};

	return cmocka_run_group_tests(tests, egl_setup, egl_teardown);
}
