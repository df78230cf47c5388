/* SPDX-License-Identifier: MIT */
/* The render path: every backend pair gives the same frame; AUTO picks a real backend. */
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

#include "lamp/combine.h"
#include "render/headlight.h"
#include "render/renderer.h"
#include "lamp/model.h"

#define W 96
#define H 54

static struct hl_egl *egl;
static struct hl_lid *lamps[2];
static struct hl_gbuffer *gb;
static struct hl_preset *low, *high;

static int setup(void **state)
{
	struct hl_egl_error err;
	struct hl_lamp_pose p[2];
	struct hl_scene s;
	struct hl_camera cam;

	(void)state;
	if (hl_egl_new(&egl, &err) < 0 || hl_model_hd84(0, &lamps[0]) < 0 ||
	    hl_model_hd84(1, &lamps[1]) < 0 || hl_preset_new(HL_HD84_SOURCES, &low) < 0 ||
	    hl_preset_new(HL_HD84_SOURCES, &high) < 0 ||
	    hl_model_hd84_preset("low", lamps, low) < 0 ||
	    hl_model_hd84_preset("high", lamps, high) < 0)
		return -1;
	hl_lamp_pose_default(0, &p[0]);
	hl_lamp_pose_default(1, &p[1]);
	hl_scene_init(&s, HL_SCENE_ROAD, p);
	hl_scene_default_camera(&s, W, H, &cam);
	if (hl_gbuffer_new(W, H, &gb) < 0 || hl_scene_render(&s, &cam, gb) < 0)
		return -1;
	return 0;
}

static int teardown(void **state)
{
	(void)state;
	hl_gbuffer_free(gb);
	hl_preset_free(low);
	hl_preset_free(high);
	hl_lid_free(lamps[0]);
	hl_lid_free(lamps[1]);
	hl_egl_free(egl);
	return 0;
}

static void config(struct hl_renderer_config *cfg, enum hl_backend comb, enum hl_backend light)
{
	*cfg = (struct hl_renderer_config){
		.n_lamps = 2, .combine = comb, .headlight = light, .egl = egl
	};
	for (int k = 0; k < 2; k++) {
		cfg->lids[k] = lamps[k];
		hl_lamp_pose_default(k, &cfg->poses[k]);
	}
}

/* Two frames: low beam, then high beam as an incremental update. */
static void frames(struct hl_renderer *r, float *lux_low, float *lux_high)
{
	float i[HL_HD84_SOURCES];

	for (int k = 0; k < 2; k++) {
		hl_preset_intensities(low, k, i);
		assert_true(hl_renderer_set_currents(r, k, i) > 0);
	}
	assert_int_equal(hl_renderer_frame(r, lux_low), 0);
	for (int k = 0; k < 2; k++) {
		hl_preset_intensities(high, k, i);
		assert_true(hl_renderer_set_currents(r, k, i) > 0);
		assert_int_equal(hl_renderer_set_currents(r, k, i), 0);
	}
	assert_int_equal(hl_renderer_frame(r, lux_high), 0);
}

static void renderer_backend_pairs_agree(void **state)
{
	static const enum hl_backend pairs[4][2] = {
		{ HL_BACKEND_CPU, HL_BACKEND_CPU },
		{ HL_BACKEND_GLES, HL_BACKEND_GLES },
		{ HL_BACKEND_CPU, HL_BACKEND_GLES },
		{ HL_BACKEND_GLES, HL_BACKEND_CPU },
	};
	static float ref_low[W * H], ref_high[W * H], low_lx[W * H], high_lx[W * H];
	double peak = 0.0, diff_presets = 0.0;

	(void)state;
	for (int j = 0; j < 4; j++) {
		struct hl_renderer_config cfg;
		struct hl_renderer *r;
		double worst = 0.0;

		config(&cfg, pairs[j][0], pairs[j][1]);
		assert_int_equal(hl_renderer_new(&cfg, gb, &r), 0);
		assert_int_equal(hl_renderer_combine_backend(r), pairs[j][0]);
		assert_int_equal(hl_renderer_headlight_backend(r), pairs[j][1]);
		frames(r, j ? low_lx : ref_low, j ? high_lx : ref_high);
		if (j == 0) {
			for (int i = 0; i < W * H; i++) {
				peak = ref_high[i] > peak ? ref_high[i] : peak;
				diff_presets += fabs(ref_high[i] - ref_low[i]);
			}
			assert_true(peak > 10.0);
			assert_true(diff_presets > 100.0); /* the frames differ */
		} else {
			for (int i = 0; i < W * H; i++) {
				double e =
					fabs(low_lx[i] - ref_low[i]) / (1e-3 * peak + ref_low[i]);

				worst = e > worst ? e : worst;
				e = fabs(high_lx[i] - ref_high[i]) / (1e-3 * peak + ref_high[i]);
				worst = e > worst ? e : worst;
			}
			printf("combine %s, headlight %s: max rel. difference to cpu/cpu %.2e\n",
			       hl_backend_name(pairs[j][0]), hl_backend_name(pairs[j][1]), worst);
			assert_true(worst < 5e-3);
		}
		/* The distribution the lid view reads is the CPU reference's. */
		{
			const struct hl_lid_grid *g = hl_renderer_grid(r, 1);
			float *ref = malloc(sizeof(float) * g->width * g->height);
			float i[HL_HD84_SOURCES];
			const float *d = hl_renderer_distribution(r, 1);

			hl_preset_intensities(high, 1, i);
			hl_combine_sparse(lamps[1], i, ref);
			for (int s = 0; s < g->width * g->height; s++)
				assert_true(fabs(d[s] - ref[s]) <= 1e-5 * (ref[s] + 1.0));
			free(ref);
		}
		hl_renderer_free(r);
	}
}

/* What frame_pixels() handed out: how often each pixel, and the display view it wrote. */
struct seen {
	int width;
	uint8_t *count;
	float *copy;
};

static void record_pixels(void *userdata, const float *lux, size_t first, size_t count)
{
	struct seen *s = userdata;

	/* bands are disjoint, so each thread writes only its own pixels here */
	for (size_t i = first; i < first + count; i++) {
		s->count[i]++;
		s->copy[i] = lux[i];
	}
}

/*
 * A frame lit on 1, 2 and 3 threads, band by band with the pixels callback, is the frame of
 * hl_renderer_frame() on one thread bit for bit; on the CPU the callback sees every lit pixel
 * once and nothing else (the others are zero in every frame), under GLES every pixel once.
 */
static void renderer_threads_and_pixel_runs_give_the_same_frame(void **state)
{
	const int w = 320, h = 180; /* several bands of the headlight pass */
	struct hl_gbuffer *big = NULL;
	struct hl_lamp_pose p[2];
	struct hl_scene scene;
	struct hl_camera cam;
	float *ref = calloc((size_t)w * h, sizeof(float));
	float *lux = calloc((size_t)w * h, sizeof(float));
	struct seen seen = { w, calloc((size_t)w * h, 1), calloc((size_t)w * h, sizeof(float)) };
	size_t lit = 0;

	(void)state;
	hl_lamp_pose_default(0, &p[0]);
	hl_lamp_pose_default(1, &p[1]);
	hl_scene_init(&scene, HL_SCENE_ROAD, p);
	hl_scene_default_camera(&scene, w, h, &cam);
	assert_int_equal(hl_gbuffer_new(w, h, &big), 0);
	assert_int_equal(hl_scene_render(&scene, &cam, big), 0);
	for (int light = HL_BACKEND_CPU; light <= HL_BACKEND_GLES; light++) {
		for (int threads = 1; threads <= 3; threads++) {
			struct hl_renderer_config cfg;
			struct hl_renderer *r = NULL;
			float i[HL_HD84_SOURCES];

			config(&cfg, HL_BACKEND_CPU, (enum hl_backend)light);
			cfg.threads = threads;
			assert_int_equal(hl_renderer_new(&cfg, big, &r), 0);
			for (int k = 0; k < 2; k++) {
				hl_preset_intensities(high, k, i);
				hl_renderer_set_currents(r, k, i);
			}
			if (threads == 1) {
				assert_int_equal(hl_renderer_frame(r, ref), 0);
				lit = 0;
				for (int j = 0; j < w * h; j++)
					lit += ref[j] > 0.0f;
				assert_true(lit > (size_t)w * h / 4);
			}
			/* twice into the same buffers, as the daemon's frame pool does */
			for (int rep = 0; rep < 2; rep++) {
				memset(seen.count, 0, (size_t)w * h);
				assert_int_equal(
					hl_renderer_frame_pixels(r, lux, record_pixels, &seen), 0);
				for (int j = 0; j < w * h; j++) {
					assert_true(lux[j] == ref[j]);
					if (light == HL_BACKEND_GLES)
						assert_int_equal(seen.count[j], 1);
					else if (ref[j] > 0.0f)
						assert_int_equal(seen.count[j], 1);
					if (seen.count[j])
						assert_true(seen.copy[j] == ref[j]);
				}
			}
			hl_renderer_free(r);
		}
	}
	printf("%zu of %d pixels lit; 1-3 threads give the same frame\n", lit, w * h);
	hl_gbuffer_free(big);
	free(ref);
	free(lux);
	free(seen.count);
	free(seen.copy);
}

static void renderer_auto_picks_a_backend_and_cpu_needs_no_egl(void **state)
{
	struct hl_renderer_config cfg;
	struct hl_renderer *r = NULL;
	static float lux[W * H];

	(void)state;
	config(&cfg, HL_BACKEND_AUTO, HL_BACKEND_AUTO);
	assert_int_equal(hl_renderer_new(&cfg, gb, &r), 0);
	printf("auto on %s: combine %s, headlight %s\n", hl_egl_renderer(egl),
	       hl_backend_name(hl_renderer_combine_backend(r)),
	       hl_backend_name(hl_renderer_headlight_backend(r)));
	assert_int_not_equal(hl_renderer_combine_backend(r), HL_BACKEND_AUTO);
	assert_int_not_equal(hl_renderer_headlight_backend(r), HL_BACKEND_AUTO);
	if (hl_egl_software(egl)) {
		/* GLES on the CPU's own cores: no timing, the CPU stages */
		assert_int_equal(hl_renderer_combine_backend(r), HL_BACKEND_CPU);
		assert_int_equal(hl_renderer_headlight_backend(r), HL_BACKEND_CPU);
	}
	hl_renderer_free(r);
	r = NULL;

	cfg.egl = NULL;
	cfg.combine = cfg.headlight = HL_BACKEND_AUTO;
	assert_int_equal(hl_renderer_new(&cfg, gb, &r), 0);
	assert_int_equal(hl_renderer_headlight_backend(r), HL_BACKEND_CPU);
	assert_int_equal(hl_renderer_frame(r, lux), 0);
	hl_renderer_free(r);
	r = NULL;
	cfg.headlight = HL_BACKEND_GLES;
	assert_int_equal(hl_renderer_new(&cfg, gb, &r), -ENODEV);
	assert_null(r);
	cfg.n_lamps = 3;
	assert_int_equal(hl_renderer_new(&cfg, gb, &r), -EINVAL);
	hl_renderer_free(NULL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(renderer_backend_pairs_agree),
		cmocka_unit_test(renderer_threads_and_pixel_runs_give_the_same_frame),
		cmocka_unit_test(renderer_auto_picks_a_backend_and_cpu_needs_no_egl),
	};

	return cmocka_run_group_tests(tests, setup, teardown);
}
