/* SPDX-License-Identifier: MIT */
/*
 * The headlight pass in GLES (Mesa llvmpipe via EGL surfaceless) against the CPU pass on small
 * G-buffers: both modes on the road scene with two lamps, row 0 at the top and exact zeros
 * where no lamp reaches, a distribution read from another texture, changed rows uploaded equal
 * to a fresh pass over the new G-buffer, and the refusals with their -errno.
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "lamp/model.h"
#include "render/gl_headlight.h"
#include "render/gl_util.h"
#include "render/headlight.h"
#include "render/scene.h"

#include "egl_fixture.h"

#define W 40
#define H 24
static const enum hl_gl_headlight_mode modes[2] = { HL_GL_HEADLIGHT_DIRECT,
						    HL_GL_HEADLIGHT_PRECOMPUTED };

/* A smooth made-up distribution on the default grid, different per lamp. */
static float *distribution(const struct hl_lid_grid *g, int k)
{
	float *d = malloc(sizeof(float) * g->width * g->height);

	assert_non_null(d);
	for (int y = 0; y < g->height; y++)
		for (int x = 0; x < g->width; x++) {
			const double h = hl_lid_grid_h_deg(g, x) - (k ? -4.0 : 3.0);
			const double v = hl_lid_grid_v_deg(g, y) + 1.5;

			d[y * g->width + x] =
				(float)(30000.0 * exp(-h * h / 200.0 - v * v / 8.0) + 50.0);
		}
	return d;
}

struct setup {
	struct hl_headlight_lamp lamps[2];
	struct hl_lamp_pose poses[2];
	struct hl_scene scene;
	struct hl_gbuffer *gb;
	float *dense[2];
};

static void make(struct setup *s, enum hl_scene_kind kind)
{
	struct hl_camera cam;

	for (int k = 0; k < 2; k++) {
		hl_lamp_pose_default(k, &s->poses[k]);
		s->lamps[k].pose = s->poses[k];
		hl_model_default_grid(&s->lamps[k].grid);
		s->dense[k] = distribution(&s->lamps[k].grid, k);
	}
	hl_scene_init(&s->scene, kind, s->poses);
	hl_scene_default_camera(&s->scene, W, H, &cam);
	assert_int_equal(hl_gbuffer_new(W, H, &s->gb), 0);
	assert_int_equal(hl_scene_render(&s->scene, &cam, s->gb), 0);
}

static void unmake(struct setup *s)
{
	hl_gbuffer_free(s->gb);
	free(s->dense[0]);
	free(s->dense[1]);
}

static void cpu_pass(const struct setup *s, const struct hl_gbuffer *gb, float *lux)
{
	struct hl_headlight *h;

	assert_int_equal(hl_headlight_new(gb, 2, s->lamps, &h), 0);
	hl_headlight_run(h, (const float *const *)s->dense, lux);
	hl_headlight_free(h);
}

static void gl_pass(const struct setup *s, const struct hl_gbuffer *gb,
		    enum hl_gl_headlight_mode mode, float *lux)
{
	struct hl_gl_headlight *h;
	char log[1024] = "";

	if (hl_gl_headlight_new(gb, 2, s->lamps, mode, &h, log, sizeof(log)) != 0)
		fail_msg("%s", log);
	for (int k = 0; k < 2; k++)
		assert_int_equal(hl_gl_headlight_upload(h, k, s->dense[k]), 0);
	hl_gl_headlight_run(h);
	assert_int_equal(hl_gl_headlight_read(h, lux), 0);
	hl_gl_headlight_free(h);
}

/* Pixel by pixel within 1e-3 of the larger (GLSL float against the CPU's mix), zero exactly. */
static void expect_same(const float *cpu, const float *gl, int n)
{
	double peak = 0.0;

	for (int i = 0; i < n; i++)
		peak = fmax(peak, cpu[i]);
	assert_true(peak > 1.0);
	for (int i = 0; i < n; i++) {
		if (cpu[i] == 0.0f && gl[i] != 0.0f)
			fail_msg("pixel %d: CPU 0, GLES %g", i, (double)gl[i]);
		if (fabs(cpu[i] - gl[i]) > 1e-3 * fmax(cpu[i], 1e-3 * peak))
			fail_msg("pixel %d (row %d): CPU %.6g, GLES %.6g", i, i / W, (double)cpu[i],
				 (double)gl[i]);
	}
}

static void gl_headlight_both_modes_equal_the_cpu_pass_on_the_road(void **state)
{
	struct setup s;
	float cpu[W * H], gl[W * H];
	int lit = 0, dark = 0;
	(void)state;

	make(&s, HL_SCENE_ROAD);
	cpu_pass(&s, s.gb, cpu);
	for (int i = 0; i < W * H; i++) {
		lit += cpu[i] > 0.0f;
		dark += s.gb->nrm[4 * i + 3] == HL_SURF_NONE;
	}
	assert_true(lit > W * H / 4);
	assert_true(dark > 0); /* sky in the top rows */
	for (int m = 0; m < 2; m++) {
		memset(gl, 0x7f, sizeof(gl));
		gl_pass(&s, s.gb, modes[m], gl);
		expect_same(cpu, gl, W * H);
		/* the sky is row 0 (the top): nothing lights it */
		for (int i = 0; i < W; i++)
			assert_true(gl[i] == 0.0f);
	}
	unmake(&s);
}

/* A G-buffer that is sky but for one wall point in row 1: only that pixel is lit. */
static void gl_headlight_rows_top_down_and_zero_where_nothing_is(void **state)
{
	struct setup s;
	struct hl_gbuffer *gb;
	float cpu[W * H], gl[W * H];
	const int at = 1 * W + 7;
	(void)state;

	make(&s, HL_SCENE_ROAD);
	assert_int_equal(hl_gbuffer_new(W, H, &gb), 0);
	memset(gb->pos, 0, sizeof(float) * 4 * W * H);
	memset(gb->nrm, 0, sizeof(float) * 4 * W * H);
	/* 20 m ahead, 1 m left, 0.5 m up, facing the lamps, albedo 0.5 */
	gb->pos[4 * at + 0] = 20.0f;
	gb->pos[4 * at + 1] = 1.0f;
	gb->pos[4 * at + 2] = 0.5f;
	gb->pos[4 * at + 3] = 0.5f;
	gb->nrm[4 * at + 0] = -1.0f;
	gb->nrm[4 * at + 3] = HL_SURF_WALL;
	cpu_pass(&s, gb, cpu);
	assert_true(cpu[at] > 1.0f);
	for (int m = 0; m < 2; m++) {
		gl_pass(&s, gb, modes[m], gl);
		for (int i = 0; i < W * H; i++)
			if (i != at && gl[i] != 0.0f)
				fail_msg("mode %d: pixel %d lit (%g)", m, i, (double)gl[i]);
		assert_float_equal(gl[at], cpu[at], 1e-3 * cpu[at]);
	}
	hl_gbuffer_free(gb);
	unmake(&s);
}

/* Lamp 1 reads a texture of the caller's (a GL combiner's target): the same as uploading it. */
static void gl_headlight_reads_a_distribution_from_a_texture(void **state)
{
	struct setup s;
	struct hl_gl_headlight *h;
	float cpu[W * H], gl[W * H];
	GLuint tex[2];
	char log[1024] = "";
	(void)state;

	make(&s, HL_SCENE_WALL);
	cpu_pass(&s, s.gb, cpu);
	for (int k = 0; k < 2; k++) {
		tex[k] = hl_gl_texture_float(s.lamps[k].grid.width, s.lamps[k].grid.height, false,
					     s.dense[k]);
		assert_int_not_equal(tex[k], 0);
	}
	for (int m = 0; m < 2; m++) {
		if (hl_gl_headlight_new(s.gb, 2, s.lamps, modes[m], &h, log, sizeof(log)) != 0)
			fail_msg("%s", log);
		hl_gl_headlight_use_texture(h, 0, tex[0]);
		hl_gl_headlight_use_texture(h, 1, tex[1]);
		hl_gl_headlight_run(h);
		assert_int_equal(hl_gl_headlight_read(h, gl), 0);
		expect_same(cpu, gl, W * H);
		/* an upload after use_texture: the object's own texture again (here dark) */
		{
			float *zero = calloc((size_t)s.lamps[0].grid.width * s.lamps[0].grid.height,
					     sizeof(float));

			assert_non_null(zero);
			assert_int_equal(hl_gl_headlight_upload(h, 0, zero), 0);
			assert_int_equal(hl_gl_headlight_upload(h, 1, zero), 0);
			hl_gl_headlight_run(h);
			assert_int_equal(hl_gl_headlight_read(h, gl), 0);
			for (int i = 0; i < W * H; i++)
				assert_true(gl[i] == 0.0f);
			free(zero);
		}
		hl_gl_headlight_free(h);
	}
	glDeleteTextures(2, tex);
	unmake(&s);
}

/* The road's rows 10..15 replaced by the wall scene's: equal to a fresh pass over the mix. */
static void gl_headlight_changed_rows_equal_a_fresh_pass(void **state)
{
	struct setup road, wall;
	struct hl_gl_headlight *h;
	float fresh[W * H], gl[W * H];
	char log[1024] = "";
	const size_t first = 10 * W, n = 6 * W;
	(void)state;

	make(&road, HL_SCENE_ROAD);
	make(&wall, HL_SCENE_WALL);
	for (int m = 0; m < 2; m++) {
		struct hl_gbuffer *gb;

		assert_int_equal(hl_gbuffer_new(W, H, &gb), 0);
		memcpy(gb->pos, road.gb->pos, sizeof(float) * 4 * W * H);
		memcpy(gb->nrm, road.gb->nrm, sizeof(float) * 4 * W * H);
		if (hl_gl_headlight_new(gb, 2, road.lamps, modes[m], &h, log, sizeof(log)) != 0)
			fail_msg("%s", log);
		for (int k = 0; k < 2; k++)
			assert_int_equal(hl_gl_headlight_upload(h, k, road.dense[k]), 0);
		memcpy(gb->pos + 4 * first, wall.gb->pos + 4 * first, sizeof(float) * 4 * n);
		memcpy(gb->nrm + 4 * first, wall.gb->nrm + 4 * first, sizeof(float) * 4 * n);
		assert_int_equal(hl_gl_headlight_update_rows(h, gb, 10, 6), 0);
		assert_int_equal(hl_gl_headlight_update_rows(h, gb, 0, 0), 0); /* nothing */
		hl_gl_headlight_run(h);
		assert_int_equal(hl_gl_headlight_read(h, gl), 0);
		hl_gl_headlight_free(h);
		gl_pass(&road, gb, modes[m], fresh);
		assert_memory_equal(gl, fresh, sizeof(gl));
		/* and the rows really changed: not the road's any more */
		cpu_pass(&road, gb, fresh);
		expect_same(fresh, gl, W * H);
		hl_gbuffer_free(gb);
	}
	unmake(&road);
	unmake(&wall);
}

static void gl_headlight_refusals_and_their_errno(void **state)
{
	struct setup s;
	struct hl_gl_headlight *h = NULL;
	struct hl_headlight_lamp bad[2];
	struct hl_gbuffer *other;
	char log[1024] = "";
	(void)state;

	make(&s, HL_SCENE_ROAD);
	assert_int_equal(hl_gl_headlight_new(s.gb, 0, s.lamps, HL_GL_HEADLIGHT_DIRECT, &h, log,
					     sizeof(log)),
			 -EINVAL);
	assert_int_equal(hl_gl_headlight_new(s.gb, 3, s.lamps, HL_GL_HEADLIGHT_DIRECT, &h, log,
					     sizeof(log)),
			 -EINVAL);
	memcpy(bad, s.lamps, sizeof(bad));
	bad[1].grid.width = 1; /* a grid needs 2 samples a side */
	assert_int_equal(hl_gl_headlight_new(s.gb, 2, bad, HL_GL_HEADLIGHT_PRECOMPUTED, &h, log,
					     sizeof(log)),
			 -EINVAL);
	memcpy(bad, s.lamps, sizeof(bad));
	bad[0].grid.h_last_deg = bad[0].grid.h_first_deg;
	assert_int_equal(hl_gl_headlight_new(s.gb, 1, bad, HL_GL_HEADLIGHT_DIRECT, &h, log,
					     sizeof(log)),
			 -EINVAL);
	assert_null(h);

	if (hl_gl_headlight_new(s.gb, 2, s.lamps, HL_GL_HEADLIGHT_PRECOMPUTED, &h, log,
				sizeof(log)) != 0)
		fail_msg("%s", log);
	assert_int_equal(hl_gbuffer_new(W, H + 1, &other), 0);
	assert_int_equal(hl_gl_headlight_update_rows(h, other, 0, 1), -EINVAL);
	assert_int_equal(hl_gl_headlight_update_rows(h, s.gb, -1, 2), -EINVAL);
	assert_int_equal(hl_gl_headlight_update_rows(h, s.gb, 0, -1), -EINVAL);
	assert_int_equal(hl_gl_headlight_update_rows(h, s.gb, H - 2, 3), -EINVAL);
	assert_int_equal(hl_gl_headlight_update_rows(h, s.gb, H - 2, 2), 0);
	assert_int_equal(glGetError(), GL_NO_ERROR);
	hl_gbuffer_free(other);
	hl_gl_headlight_free(h);
	hl_gl_headlight_free(NULL);
	unmake(&s);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(gl_headlight_both_modes_equal_the_cpu_pass_on_the_road),
		cmocka_unit_test(gl_headlight_rows_top_down_and_zero_where_nothing_is),
		cmocka_unit_test(gl_headlight_reads_a_distribution_from_a_texture),
		cmocka_unit_test(gl_headlight_changed_rows_equal_a_fresh_pass),
		cmocka_unit_test(gl_headlight_refusals_and_their_errno),
	};

	return cmocka_run_group_tests(tests, egl_setup, egl_teardown);
}
