/* SPDX-License-Identifier: MIT */
/*
 * Sensor-based lighting (render/hemicube.c, render/sensor.c, render/gi.c): the hemicube's
 * projected solid angles against brute-force quadrature, the sensor's normalisation (uniform
 * sky: E = pi L), grazing light the paper's 135° sensor misses, the energy check of the bounce
 * scene against a brute-force integral over the lit floor computed here, adaptive placement
 * against one sensor per pixel on the road, and the surface-restricted composition filter.
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

#include <cmocka.h>

#include "lamp/combine.h"
#include "render/egl.h"
#include "render/gi.h"
#include "render/gl_sensor.h"
#include "render/headlight.h"
#include "render/hemicube.h"
#include "render/scene.h"
#include "render/sensor.h"
#include "lamp/model.h"
#include "lamp/preset.h"

#define DEG (M_PI / 180.0)

#ifdef HL_TEST_GI_GLES
/* tests/unit/render/test_gi_gles.c: the placement tests with GLES sensors (render/gl_sensor.h). */
#include "egl_fixture.h"

#define BACKEND "gles"
#define GLES_BATCH 64

static int gi_run(const struct hl_gi_config *cfg, const struct hl_sensor_scene *field,
		  const struct hl_gbuffer *gb, float *out, struct hl_gi_stats *st)
{
	struct hl_gl_sensor_config gcfg;
	struct hl_gi_config c = *cfg;
	struct hl_scene_mesh *mesh;
	struct hl_gl_sensor *s;
	struct hl_gi_sensors sensors = { .batch = hl_gl_sensor_gi_batch };
	char log[1024] = "";
	int rc;

	assert_int_equal(hl_scene_mesh_new(field->scene, &mesh), 0);
	hl_gl_sensor_config_for(egl, cfg->sensor_size, cfg->aa_samples, GLES_BATCH, &gcfg);
	gcfg.sky_cd_m2 = field->sky_cd_m2;
	rc = hl_gl_sensor_new(egl, mesh, field->n_lamps, field->lamps, &gcfg, &s, log, sizeof(log));
	if (rc < 0)
		fprintf(stderr, "gl_sensor: %s\n", log);
	assert_int_equal(rc, 0);
	for (int k = 0; k < field->n_lamps; k++)
		assert_int_equal(hl_gl_sensor_upload(s, k, field->dense[k]), 0);
	sensors.userdata = s;
	c.batch = GLES_BATCH;
	rc = hl_gi_run_sensors(&c, &sensors, gb, out, st);
	hl_gl_sensor_free(s);
	hl_scene_mesh_free(mesh);
	return rc;
}
#else
#define BACKEND "cpu"

static int gi_run(const struct hl_gi_config *cfg, const struct hl_sensor_scene *field,
		  const struct hl_gbuffer *gb, float *out, struct hl_gi_stats *st)
{
	return hl_gi_run(cfg, hl_sensor_scene_radiance, field, gb, out, st);
}
#endif

#ifndef HL_TEST_GI_GLES
/* Midpoint quadrature of the projected solid angle of a front-face rectangle. */
static double front_brute(double x0, double x1, double y0, double y1, int n)
{
	double s = 0.0;

	for (int j = 0; j < n; j++)
		for (int i = 0; i < n; i++) {
			const double x = x0 + (i + 0.5) * (x1 - x0) / n;
			const double y = y0 + (j + 0.5) * (y1 - y0) / n;
			const double r2 = 1.0 + x * x + y * y;

			s += 1.0 / (r2 * r2);
		}
	return s * (x1 - x0) * (y1 - y0) / ((double)n * n);
}

static double side_brute(double y0, double y1, double z0, double z1, int n)
{
	double s = 0.0;

	for (int j = 0; j < n; j++)
		for (int i = 0; i < n; i++) {
			const double y = y0 + (i + 0.5) * (y1 - y0) / n;
			const double z = z0 + (j + 0.5) * (z1 - z0) / n;
			const double r2 = 1.0 + y * y + z * z;

			s += z / (r2 * r2);
		}
	return s * (y1 - y0) * (z1 - z0) / ((double)n * n);
}

static void hemicube_weights_are_projected_solid_angles(void **state)
{
	static const int sizes[] = { 2, 8, 32, 256 };
	struct hl_hemicube *h;

	(void)state;
	/* The closed forms against quadrature, on patches of each face. */
	assert_true(fabs(hl_hemicube_front_patch(-1, 1, -1, 1) - front_brute(-1, 1, -1, 1, 2000)) <
		    1e-6);
	assert_true(fabs(hl_hemicube_front_patch(0.25, 0.5, -0.75, 0.125) -
			 front_brute(0.25, 0.5, -0.75, 0.125, 400)) < 1e-7);
	assert_true(fabs(hl_hemicube_side_patch(-1, 1, 0, 1) - side_brute(-1, 1, 0, 1, 2000)) <
		    1e-6);
	assert_true(fabs(hl_hemicube_side_patch(0.5, 0.75, 0.0, 0.0625) -
			 side_brute(0.5, 0.75, 0.0, 0.0625, 400)) < 1e-7);
	/* Nusselt: the front face carries 55.4 % of the hemisphere's projected solid angle. */
	assert_true(fabs(hl_hemicube_front_patch(-1, 1, -1, 1) / M_PI - 0.5541) < 1e-4);
	for (size_t k = 0; k < sizeof(sizes) / sizeof(sizes[0]); k++) {
		const double *w;
		const float *d;
		double sum = 0.0;

		assert_int_equal(hl_hemicube_new(sizes[k], &h), 0);
		assert_int_equal(hl_hemicube_texels(h), 3 * (size_t)sizes[k] * sizes[k]);
		w = hl_hemicube_weights(h);
		d = hl_hemicube_dirs(h);
		for (size_t i = 0; i < hl_hemicube_texels(h); i++) {
			assert_true(w[i] > 0.0);
			assert_true(d[3 * i + 2] > 0.0); /* every texel above the tangent plane */
			sum += w[i];
		}
		assert_true(fabs(sum - M_PI) < 1e-12);
		hl_hemicube_free(h);
	}
	assert_int_equal(hl_hemicube_new(3, &h), -EINVAL);
	assert_int_equal(hl_hemicube_new(0, &h), -EINVAL);
	hl_hemicube_free(NULL);
}

struct sky {
	double n[3]; /* the sensor's normal, for fields defined relative to it */
	double l_cd_m2;
	double band_deg; /* grazing band: bright only below this elevation over the tangent plane */
};

static double uniform_sky(const void *field, const double o[3], const double d[3])
{
	(void)o;
	(void)d;
	return ((const struct sky *)field)->l_cd_m2;
}

static double cosine_sky(const void *field, const double o[3], const double d[3])
{
	const struct sky *s = field;

	(void)o;
	return s->l_cd_m2 * (d[0] * s->n[0] + d[1] * s->n[1] + d[2] * s->n[2]);
}

static double grazing_sky(const void *field, const double o[3], const double d[3])
{
	const struct sky *s = field;
	const double c = d[0] * s->n[0] + d[1] * s->n[1] + d[2] * s->n[2];

	(void)o;
	return c < sin(s->band_deg * DEG) ? s->l_cd_m2 : 0.0;
}

static double one_sensor(int size, hl_radiance_fn fn, const struct sky *sky)
{
	struct hl_hemicube *h;
	const double p[3] = { 1.0, 2.0, 3.0 };
	float *scratch;
	double e;

	assert_int_equal(hl_hemicube_new(size, &h), 0);
	scratch = malloc(sizeof(float) * hl_sensor_scratch_floats(h));
	assert_non_null(scratch);
	hl_sensor_batch(h, fn, sky, NULL, sky->n, 1, p, scratch, &e);
	free(scratch);
	hl_hemicube_free(h);
	return e;
}

static void sensor_uniform_sky_gives_pi_l(void **state)
{
	static const double normals[][3] = {
		{ 0, 0, 1 }, { 0, 0, -1 }, { 1, 0, 0 }, { 0.48, -0.6, 0.64 }
	};

	(void)state;
	for (size_t k = 0; k < sizeof(normals) / sizeof(normals[0]); k++) {
		struct sky sky = { .l_cd_m2 = 2.5 };

		memcpy(sky.n, normals[k], sizeof(sky.n));
		for (int size = 2; size <= 64; size *= 4) {
			const double e = one_sensor(size, uniform_sky, &sky);

			assert_true(fabs(e - M_PI * 2.5) < 1e-9);
		}
	}
}

static void sensor_cosine_sky_and_grazing_band(void **state)
{
	struct sky sky = { .n = { 0.48, -0.6, 0.64 }, .l_cd_m2 = 3.0, .band_deg = 20.0 };
	double e, ref, e16;

	(void)state;
	/* L = L0 cos(theta): E = integral L0 cos^2 d(omega) = 2 pi L0 / 3. */
	e = one_sensor(32, cosine_sky, &sky);
	ref = 2.0 * M_PI * 3.0 / 3.0;
	printf("cosine sky: E %.5f, exact %.5f (%+.4f %%)\n", e, ref, 100 * (e - ref) / ref);
	assert_true(fabs(e - ref) < 1e-3 * ref);
	/*
	 * Bright only within 20° of the tangent plane, i.e. beyond 70° from the normal: a 135°
	 * sensor (67.5° half angle) sees none of it. E = pi L (1 - sin^2 70°) = pi L cos^2 70°.
	 */
	ref = M_PI * 3.0 * cos(70 * DEG) * cos(70 * DEG);
	e = one_sensor(64, grazing_sky, &sky);
	e16 = one_sensor(16, grazing_sky, &sky);
	printf("grazing band: E %.5f (64) %.5f (16), exact %.5f (%+.2f %%)\n", e, e16, ref,
	       100 * (e - ref) / ref);
	assert_true(fabs(e - ref) < 0.02 * ref);
	assert_true(fabs(e16 - ref) < 0.08 * ref);
}

/* Luminance 1 on the road's posts, 0 elsewhere. */
static double posts_only(const void *field, const double o[3], const double d[3])
{
	float p[4], n[4];

	return hl_scene_cast(field, o, d, p, n) == HL_SURF_POST ? 1.0 : 0.0;
}

static void sensor_supersampling_removes_post_aliasing(void **state)
{
	struct hl_lamp_pose poses[2];
	struct hl_scene scene;
	struct hl_capsule thin[HL_SCENE_MAX_THIN];
	struct hl_hemicube *h32, *h512;
	const double n[3] = { 0, 0, 1 };
	float *scratch;
	double worst_aa = 0.0, worst_plain = 0.0, worst_512 = 0.0;
	struct hl_sensor_aa aa = { thin, 0, 8 };
	double d[3];

	(void)state;
	hl_lamp_pose_default(0, &poses[0]);
	hl_lamp_pose_default(1, &poses[1]);
	hl_scene_init(&scene, HL_SCENE_ROAD, poses);
	aa.n_thin = hl_scene_thin_objects(&scene, thin, HL_SCENE_MAX_THIN);
	assert_int_equal(aa.n_thin, 28);
	assert_int_equal(hl_hemicube_new(32, &h32), 0);
	assert_int_equal(hl_hemicube_new(512, &h512), 0);
	/* Sub-sample 0 of a 1 x 1 grid is the texel's centre direction. */
	for (size_t i = 0; i < hl_hemicube_texels(h32); i += 97) {
		const float *c = hl_hemicube_dirs(h32) + 3 * i;
		double len;

		hl_hemicube_subdir(h32, i, 0, 0, 1, d);
		len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
		for (int j = 0; j < 3; j++)
			assert_true(fabs(d[j] / len - c[j]) < 1e-6);
	}
	scratch = malloc(sizeof(float) * hl_sensor_scratch_floats(h512));
	assert_non_null(scratch);
	/* Points on the road 2 m from the posts' line, moving along it. */
	for (int k = 0; k < 8; k++) {
		const double p[3] = { 3.0 + 0.13 * k, 2.2, 0.0 };
		double ref, e_plain, e_aa;

		struct hl_sensor_aa fine = aa;
		double e_512;

		/* The reference: 32 x 32 rays per texel near the posts (a 1024-texel hemicube). */
		fine.samples = 32;
		hl_sensor_batch(h32, posts_only, &scene, &fine, n, 1, p, scratch, &ref);
		hl_sensor_batch(h32, posts_only, &scene, NULL, n, 1, p, scratch, &e_plain);
		hl_sensor_batch(h32, posts_only, &scene, &aa, n, 1, p, scratch, &e_aa);
		hl_sensor_batch(h512, posts_only, &scene, NULL, n, 1, p, scratch, &e_512);
		printf("x %.2f: E %.6f lx (reference), 32 plain %.6f, 32 aa 8 %.6f, 512 plain %.6f\n",
		       p[0], ref, e_plain, e_aa, e_512);
		worst_512 = fmax(worst_512, fabs(e_512 - ref) / ref);
		worst_plain = fmax(worst_plain, fabs(e_plain - ref) / ref);
		worst_aa = fmax(worst_aa, fabs(e_aa - ref) / ref);
	}
	printf("posts seen from the road, 32x32 hemicube: point sampled %.1f %%, supersampled 8x8 "
	       "near posts %.1f %%; 512x512 point sampled %.1f %%\n",
	       100 * worst_plain, 100 * worst_aa, 100 * worst_512);
	/* 32 x 32 texels with 8 x 8 near posts beat a point-sampled 512 x 512 hemicube. */
	assert_true(worst_aa < 0.15);
	assert_true(worst_512 < 0.25); /* the reference is what a fine hemicube converges to */
	assert_true(worst_plain > 3 * worst_aa);
	free(scratch);
	hl_hemicube_free(h32);
	hl_hemicube_free(h512);
}

#endif

/* The energy check's lamp: one smooth source, wide enough to light the floor near the lamp. */
#define BOUNCE_PEAK_CD 20000.0
#define BOUNCE_PITCH_DEG (-10.0)
#define BOUNCE_LAMP_Z_M 0.65

static double bounce_cd(double h_deg, double v_deg)
{
	return BOUNCE_PEAK_CD * exp(-h_deg * h_deg / (2 * 20.0 * 20.0)) *
	       exp(-(v_deg + 8.0) * (v_deg + 8.0) / (2 * 5.0 * 5.0));
}

/*
 * Luminance of the floor at (x, y), computed here from the analytic source: lamp at
 * (0, 0, 0.65) pitched down, type A angles, E = I cos(eps) / r^2, L = rho E / pi.
 */
static double floor_luminance(double x, double y)
{
	const double s = sin(BOUNCE_PITCH_DEG * DEG), c = cos(BOUNCE_PITCH_DEG * DEG);
	const double w[3] = { x, y, -BOUNCE_LAMP_Z_M };
	/* Lamp axes: x right (-y), y up, z along the axis. */
	const double lx = -w[1], ly = -s * w[0] + c * w[2], lz = c * w[0] + s * w[2];
	const double h = atan2(lx, lz) / DEG, v = atan2(ly, hypot(lx, lz)) / DEG;
	const double r2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];

	if (fabs(h) > 89.9 || v < -29.9 || v > 19.9) /* outside the measured grid: dark */
		return 0.0;
	return HL_BOUNCE_FLOOR_ALBEDO * (bounce_cd(h, v) * BOUNCE_LAMP_Z_M / sqrt(r2) / r2) *
	       M_1_PI;
}

/*
 * Irradiance at wall point p (normal +x) from the floor: the integral over the floor of
 * L cos(theta_p) cos(theta_q) / r^2 dA, midpoint rule with x - x_wall = e^u and
 * y - p_y = z tan(phi), so that the cells shrink where the kernel is steep.
 */
static double wall_reference(const double p[3])
{
	const int nu = 1500, nphi = 1500;
	const double u0 = log(1e-4), u1 = log(HL_BOUNCE_FLOOR_END_M - HL_BOUNCE_WALL_X_M);
	const double zs = p[2];
	const double f0 = atan((-HL_BOUNCE_FLOOR_HALF_M - p[1]) / zs);
	const double f1 = atan((HL_BOUNCE_FLOOR_HALF_M - p[1]) / zs);
	const double du = (u1 - u0) / nu, df = (f1 - f0) / nphi;
	double e = 0.0;

	for (int i = 0; i < nu; i++) {
		const double a = exp(u0 + (i + 0.5) * du); /* x - x_wall */
		const double x = HL_BOUNCE_WALL_X_M + a;

		for (int j = 0; j < nphi; j++) {
			const double t = tan(f0 + (j + 0.5) * df);
			const double y = p[1] + zs * t;
			const double dx = x - p[0], dy = y - p[1], dz = -p[2];
			const double r2 = dx * dx + dy * dy + dz * dz;
			const double jac = a * du * zs * (1 + t * t) * df;

			e += floor_luminance(x, y) * (dx * p[2]) / (r2 * r2) * jac;
		}
	}
	return e;
}

static void gi_energy_check_bounce_wall(void **state)
{
	const int w = 64, h = 36;
	struct hl_lamp_pose poses[2];
	struct hl_sensor_scene field = { 0 };
	struct hl_gi_config cfg;
	struct hl_gi_stats st;
	struct hl_scene scene;
	struct hl_camera cam;
	struct hl_gbuffer *gb;
	struct hl_lid_grid g;
	float *dense, *ind;
	double x[3], y[3], z[3], worst = 0.0, sum_e = 0.0;
	int n = 0;

	(void)state;
	hl_model_default_grid(&g);
	dense = malloc(sizeof(float) * g.width * g.height);
	ind = malloc(sizeof(float) * w * h);
	assert_non_null(dense);
	assert_non_null(ind);
	for (int row = 0; row < g.height; row++)
		for (int col = 0; col < g.width; col++)
			dense[row * g.width + col] = (float)bounce_cd(hl_lid_grid_h_deg(&g, col),
								      hl_lid_grid_v_deg(&g, row));
	hl_lamp_pose_default(0, &poses[0]);
	hl_lamp_pose_default(1, &poses[1]);
	poses[0].pos_m[1] = 0.0;
	poses[0].pos_m[2] = BOUNCE_LAMP_Z_M;
	poses[0].pitch_deg = BOUNCE_PITCH_DEG;
	/* The reference's lamp axes are the renderer's. */
	hl_lamp_basis(&poses[0], x, y, z);
	assert_true(fabs(x[1] + 1) < 1e-12 && fabs(y[0] + sin(BOUNCE_PITCH_DEG * DEG)) < 1e-12);
	assert_true(fabs(z[0] - cos(BOUNCE_PITCH_DEG * DEG)) < 1e-12 &&
		    fabs(z[2] - sin(BOUNCE_PITCH_DEG * DEG)) < 1e-12);
	hl_scene_init(&scene, HL_SCENE_BOUNCE, poses);
	hl_scene_default_camera(&scene, w, h, &cam);
	assert_int_equal(hl_gbuffer_new(w, h, &gb), 0);
	assert_int_equal(hl_scene_render(&scene, &cam, gb), 0);

	field.scene = &scene;
	field.n_lamps = 1;
	field.lamps[0] = (struct hl_headlight_lamp){ poses[0], g };
	field.dense[0] = dense;
	hl_gi_config_default(&cfg);
	cfg.sensor_size = 64;
	cfg.tile = 4;
	cfg.dradiance = 0.1;
	cfg.sigma_px = 0.0;
	assert_int_equal(gi_run(&cfg, &field, gb, ind, &st), 0);
	printf(BACKEND ": bounce %dx%d: %zu sensors of %zu surface pixels, %.3f ms per sensor\n", w,
	       h, st.sensors, st.surface_pixels, st.sensor_ms / st.sensors);
	/* Wall pixels on a coarse grid, away from its edges. */
	for (int row = 2; row < h; row += 5)
		for (int col = 3; col < w; col += 9) {
			const size_t i = (size_t)row * w + col;
			double p[3], ref, err;

			if (gb->nrm[4 * i + 3] != (float)HL_SURF_WALL || gb->pos[4 * i + 2] < 0.2)
				continue;
			for (int k = 0; k < 3; k++)
				p[k] = gb->pos[4 * i + k];
			ref = wall_reference(p);
			err = (ind[i] - ref) / ref;
			printf("wall (%.2f, %.2f, %.2f): indirect %.5f lx, brute force %.5f lx, "
			       "%+.2f %%\n",
			       p[0], p[1], p[2], ind[i], ref, 100 * err);
			worst = fabs(err) > worst ? fabs(err) : worst;
			sum_e += ref;
			n++;
		}
	printf(BACKEND ": energy check: %d wall points, worst error %.2f %%\n", n, 100 * worst);
	assert_true(n >= 6);
	assert_true(sum_e / n > 0.01); /* the wall is lit by the bounce, clearly */
	assert_true(worst < 0.05);
	/* The lamp does not reach the wall directly. */
	for (size_t i = 0; i < (size_t)w * h; i++)
		if (gb->nrm[4 * i + 3] == (float)HL_SURF_WALL) {
			const double p[3] = { gb->pos[4 * i], gb->pos[4 * i + 1],
					      gb->pos[4 * i + 2] };
			const double nn[3] = { 1, 0, 0 };

			assert_true(hl_headlight_point(&field.lamps[0], dense, p, nn) == 0.0);
		}
	hl_gbuffer_free(gb);
	free(dense);
	free(ind);
}

/*
 * Inside a diffuse sphere every point sees every surface element dA with the same form factor
 * dA / (4 pi R^2), so one bounce gives the same irradiance everywhere:
 * E = rho Phi / (4 pi R^2), Phi the lamp's flux (integral of I over the solid angle; type A:
 * d(omega) = cos V dH dV), computed here from the analytic source.
 */
static void gi_sphere_interior_is_uniform(void **state)
{
	const int w = 48, h = 27;
	struct hl_lamp_pose poses[2];
	struct hl_sensor_scene field = { 0 };
	struct hl_gi_config cfg;
	struct hl_gi_stats st;
	struct hl_scene scene;
	struct hl_camera cam;
	struct hl_gbuffer *gb;
	struct hl_lid_grid g;
	float *dense, *ind;
	double phi = 0.0, expect, lo = INFINITY, hi = 0.0, sum = 0.0;
	const int nh = 3600, nv = 1000;
	int n = 0;

	(void)state;
	hl_model_default_grid(&g);
	/* The flux, midpoint rule over the measured range (the source is ~0 at its edges). */
	for (int j = 0; j < nv; j++)
		for (int i = 0; i < nh; i++) {
			const double hd =
				g.h_first_deg + (i + 0.5) * (g.h_last_deg - g.h_first_deg) / nh;
			const double vd =
				g.v_first_deg + (j + 0.5) * (g.v_last_deg - g.v_first_deg) / nv;

			phi += bounce_cd(hd, vd) * cos(vd * DEG);
		}
	phi *= (g.h_last_deg - g.h_first_deg) * DEG / nh * (g.v_last_deg - g.v_first_deg) * DEG /
	       nv;
	dense = malloc(sizeof(float) * g.width * g.height);
	ind = malloc(sizeof(float) * w * h);
	assert_non_null(dense);
	assert_non_null(ind);
	for (int row = 0; row < g.height; row++)
		for (int col = 0; col < g.width; col++)
			dense[row * g.width + col] = (float)bounce_cd(hl_lid_grid_h_deg(&g, col),
								      hl_lid_grid_v_deg(&g, row));
	hl_lamp_pose_default(0, &poses[0]);
	hl_lamp_pose_default(1, &poses[1]);
	hl_scene_init(&scene, HL_SCENE_SPHERE, poses);
	hl_scene_default_camera(&scene, w, h, &cam);
	assert_int_equal(hl_gbuffer_new(w, h, &gb), 0);
	assert_int_equal(hl_scene_render(&scene, &cam, gb), 0);
	field.scene = &scene;
	field.n_lamps = 1;
	field.lamps[0] = (struct hl_headlight_lamp){ poses[0], g };
	field.dense[0] = dense;
	hl_gi_config_default(&cfg);
	cfg.tile = 4;
	cfg.sigma_px = 0.0;
	assert_int_equal(gi_run(&cfg, &field, gb, ind, &st), 0);
	expect = gb->albedo[0] * phi / (4 * M_PI * scene.sphere_radius_m * scene.sphere_radius_m);
	for (int i = 0; i < w * h; i++) {
		lo = fmin(lo, ind[i]);
		hi = fmax(hi, ind[i]);
		sum += ind[i];
		n++;
	}
	printf(BACKEND
	       ": sphere interior: flux %.1f lm, expected %.5f lx everywhere; %zu sensors: mean "
	       "%.5f (%+.2f %%), min %+.2f %%, max %+.2f %%\n",
	       phi, expect, st.sensors, sum / n, 100 * (sum / n - expect) / expect,
	       100 * (lo - expect) / expect, 100 * (hi - expect) / expect);
	assert_true(fabs(sum / n - expect) < 0.02 * expect);
	assert_true(lo > 0.95 * expect && hi < 1.05 * expect);
	hl_gbuffer_free(gb);
	free(dense);
	free(ind);
}

/* Road, HD84 lamps, low beam (hdlamp render's default): the combined distributions of both lamps. */
static void road_field(struct hl_lid *lids[2], float *dense[2], struct hl_sensor_scene *field,
		       struct hl_scene *scene)
{
	struct hl_lamp_pose poses[2];
	struct hl_preset *preset;
	float *cur;

	assert_int_equal(hl_preset_new(HL_HD84_SOURCES, &preset), 0);
	for (int k = 0; k < 2; k++) {
		assert_int_equal(hl_model_hd84(k, &lids[k]), 0);
		hl_lamp_pose_default(k, &poses[k]);
	}
	assert_int_equal(hl_model_hd84_preset("low", lids, preset), 0);
	cur = malloc(sizeof(float) * HL_HD84_SOURCES);
	assert_non_null(cur);
	hl_scene_init(scene, HL_SCENE_ROAD, poses);
	*field = (struct hl_sensor_scene){ .scene = scene, .n_lamps = 2 };
	for (int k = 0; k < 2; k++) {
		const struct hl_lid_grid *g = hl_lid_grid(lids[k]);

		dense[k] = malloc(sizeof(float) * g->width * g->height);
		assert_non_null(dense[k]);
		hl_preset_intensities(preset, k, cur);
		hl_combine_sparse(lids[k], cur, dense[k]);
		field->lamps[k] = (struct hl_headlight_lamp){ poses[k], *g };
		field->dense[k] = dense[k];
	}
	free(cur);
	hl_preset_free(preset);
}

static void gi_adaptive_road_matches_sensor_per_pixel(void **state)
{
	const int w = 160, h = 90;
	struct hl_lid *lids[2];
	float *dense[2];
	struct hl_sensor_scene field;
	struct hl_scene scene;
	struct hl_camera cam;
	struct hl_gbuffer *gb;
	struct hl_gi_config cfg;
	struct hl_gi_stats full, adapt;
	struct hl_capsule thin[HL_SCENE_MAX_THIN];
	float *ref = malloc(sizeof(float) * w * h), *ind = malloc(sizeof(float) * w * h);
	double sum_abs = 0.0, sum_ref = 0.0, post_ref = 0.0, road_far = 0.0;
	int n_post = 0, n_far = 0;

	(void)state;
	assert_non_null(ref);
	assert_non_null(ind);
	road_field(lids, dense, &field, &scene);
	hl_scene_default_camera(&scene, w, h, &cam);
	assert_int_equal(hl_gbuffer_new(w, h, &gb), 0);
	assert_int_equal(hl_scene_render(&scene, &cam, gb), 0);
	hl_gi_config_default(&cfg); /* 32 x 32 hemicube, aa 4, tile 8, dradiance 1 */
	cfg.n_thin = hl_scene_thin_objects(&scene, thin, HL_SCENE_MAX_THIN);
	cfg.thin = thin;
	cfg.tile = 1;
	assert_int_equal(gi_run(&cfg, &field, gb, ref, &full), 0);
	cfg.tile = 8;
	assert_int_equal(gi_run(&cfg, &field, gb, ind, &adapt), 0);
	assert_int_equal(full.sensors, full.surface_pixels);
	for (size_t i = 0; i < (size_t)w * h; i++) {
		const float id = gb->nrm[4 * i + 3];

		if (id == (float)HL_SURF_NONE) {
			assert_true(ref[i] == 0.0f && ind[i] == 0.0f);
			continue;
		}
		sum_abs += fabs(ind[i] - ref[i]);
		sum_ref += ref[i];
		if (id == (float)HL_SURF_POST) {
			post_ref += ref[i];
			n_post++;
		} else if (gb->pos[4 * i] > 60.0) {
			road_far += ref[i];
			n_far++;
		}
	}
	printf(BACKEND
	       ": road %dx%d, 32x32 hemicube: one per pixel %zu sensors (%.3f ms each), adaptive "
	       "%zu sensors (%.3f ms each, %d passes): %.1fx fewer, mean error %.3f %%\n",
	       w, h, full.sensors, full.sensor_ms / full.sensors, adapt.sensors,
	       adapt.sensor_ms / adapt.sensors, adapt.levels, (double)full.sensors / adapt.sensors,
	       100 * sum_abs / sum_ref);
	printf("mean indirect: posts %.4f lx (%d px), road beyond 60 m %.5f lx (%d px)\n",
	       post_ref / n_post, n_post, road_far / n_far, n_far);
	assert_true(full.sensors >= 5 * adapt.sensors);
	assert_true(sum_abs / sum_ref <= 0.02);
	/* Bounce light reaches the posts and the far road. */
	assert_true(post_ref / n_post > 0.0 && road_far / n_far > 0.0);
	hl_gbuffer_free(gb);
	for (int k = 0; k < 2; k++) {
		hl_lid_free(lids[k]);
		free(dense[k]);
	}
	free(ref);
	free(ind);
}

#ifndef HL_TEST_GI_GLES
static void gi_filter_keeps_surfaces_apart(void **state)
{
	struct hl_gbuffer *gb;
	float in[16], out[16];

	(void)state;
	/* 4x4: left half id POST (value 1), right half id ROAD (value 3), a sky pixel. */
	assert_int_equal(hl_gbuffer_new(4, 4, &gb), 0);
	for (int i = 0; i < 16; i++) {
		const bool left = i % 4 < 2;

		gb->nrm[4 * i + 3] = (float)(left ? HL_SURF_POST : HL_SURF_ROAD);
		in[i] = left ? 1.0f : 3.0f;
	}
	gb->nrm[4 * 15 + 3] = (float)HL_SURF_NONE;
	in[15] = 100.0f;
	assert_int_equal(hl_gi_filter(gb, in, 1.5, out), 0);
	for (int i = 0; i < 15; i++)
		assert_true(fabsf(out[i] - in[i]) < 1e-6f);
	assert_true(out[15] == 0.0f);
	/* A step inside one surface is smoothed. */
	in[0] = 5.0f;
	assert_int_equal(hl_gi_filter(gb, in, 1.0, out), 0);
	assert_true(out[0] < 5.0f && out[0] > 1.0f && out[1] > 1.0f);
	assert_int_equal(hl_gi_filter(gb, in, 0.0, out), -EINVAL);
	hl_gbuffer_free(gb);
}

static void gi_rejects_bad_config(void **state)
{
	struct sky sky = { .l_cd_m2 = 1.0 };
	struct hl_gbuffer *gb;
	struct hl_gi_config cfg;
	float out[4];

	(void)state;
	assert_int_equal(hl_gbuffer_new(2, 2, &gb), 0);
	hl_gi_config_default(&cfg);
	cfg.tile = 3;
	assert_int_equal(hl_gi_run(&cfg, uniform_sky, &sky, gb, out, NULL), -EINVAL);
	hl_gi_config_default(&cfg);
	cfg.sensor_size = 7;
	assert_int_equal(hl_gi_run(&cfg, uniform_sky, &sky, gb, out, NULL), -EINVAL);
	hl_gi_config_default(&cfg);
	cfg.dradiance = 0.0;
	assert_int_equal(hl_gi_run(&cfg, uniform_sky, &sky, gb, out, NULL), -EINVAL);
	hl_gbuffer_free(gb);
}

#endif

int main(void)
{
	const struct CMUnitTest tests[] = {
#ifndef HL_TEST_GI_GLES
		cmocka_unit_test(hemicube_weights_are_projected_solid_angles),
		cmocka_unit_test(sensor_uniform_sky_gives_pi_l),
		cmocka_unit_test(sensor_cosine_sky_and_grazing_band),
		cmocka_unit_test(sensor_supersampling_removes_post_aliasing),
		cmocka_unit_test(gi_filter_keeps_surfaces_apart),
		cmocka_unit_test(gi_rejects_bad_config),
#endif
		cmocka_unit_test(gi_energy_check_bounce_wall),
		cmocka_unit_test(gi_sphere_interior_is_uniform),
		cmocka_unit_test(gi_adaptive_road_matches_sensor_per_pixel),
	};

#ifdef HL_TEST_GI_GLES
	return cmocka_run_group_tests(tests, egl_setup, egl_teardown);
#else
	return cmocka_run_group_tests(tests, NULL, NULL);
#endif
}
