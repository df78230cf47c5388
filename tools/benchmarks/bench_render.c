/* SPDX-License-Identifier: MIT */
/*
 * hdlamp-bench-render: the render path's costs on this machine, as one JSON object.
 *   combine   per lamp (HD84, 95 sources, 900 x 250): the papers' method (K full-image additive
 *             passes into R32F, GLES), GLES box quads (full and incremental), the CPU sparse
 *             combiner (full and incremental), and CPU + texture upload, all in the same run
 *   headlight 1280 x 720, two lamps, road scene: CPU with precomputed per-pixel terms, GLES
 *             direct (everything per frame) and GLES with precomputed terms
 *   frame     the whole frame through hl_renderer for each backend pair: two combines (ten
 *             sources changed per lamp, like an ECU cycle), the headlight pass and the
 *             illuminance image in caller-owned host memory (GLES: glReadPixels of R32F; CPU:
 *             written there directly); with_display_tonemap adds the sRGB8 display view
 * GL timings end with glFinish, so they measure work done, not work queued.
 */
#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <GLES3/gl31.h>

#include "lamp/combine.h"
#include "render/egl.h"
#include "render/gl_combine.h"
#include "render/gl_headlight.h"
#include "render/headlight.h"
#include "render/renderer.h"
#include "render/scene.h"
#include "render/view.h"
#include "render/workers.h"
#include "tools/benchmarks/bench_stats.h"
#include "lamp/model.h"

#define CHANGED_PER_CYCLE 10 /* sources an ECU cycle typically changes per lamp */

static void print_stats(FILE *f, const char *name, struct stats s, bool last)
{
	fprintf(f,
		"    \"%s\": {\"median_ms\": %.4f, \"min_ms\": %.4f, \"max_ms\": %.4f, \"n\": %d}%s\n",
		name, s.median, s.min, s.max, s.n, last ? "" : ",");
}

#define IDLE_MS 15 /* the render thread's idle time between frames at 50 Hz, roughly */

struct bands {
	const struct hl_headlight *h;
	const float *const *dense;
	float *lux;
};

static void light_band(void *userdata, size_t c)
{
	const struct bands *b = userdata;

	hl_headlight_run_chunk(b->h, b->dense, c, b->lux);
}

/*
 * The headlight pass in bands on threads threads (as the daemon runs it), back to back or
 * after IDLE_MS of sleep before each frame, as at 50 Hz: then the other jobs on the machine
 * have had the caches, and the pass reads its terms from memory.
 */
static struct stats bench_bands(const struct hl_headlight *h, const float *const *dense, float *lux,
				int threads, bool idle, double *t, int runs)
{
	struct bands b = { h, dense, lux };
	struct hl_workers *w;
	struct stats s = { 0 };

	if (hl_workers_new(threads, &w) < 0)
		return s;
	hl_workers_run(w, hl_headlight_chunks(h), light_band, &b);
	for (int r = 0; r < runs; r++) {
		double t0;

		if (idle) {
			const struct timespec ts = { 0, IDLE_MS * 1000000L };

			nanosleep(&ts, NULL);
		}
		t0 = hl_bench_now_ms();
		hl_workers_run(w, hl_headlight_chunks(h), light_band, &b);
		t[r] = hl_bench_now_ms() - t0;
	}
	hl_workers_free(w);
	return hl_bench_summarise(t, runs);
}

/* The next ECU cycle: CHANGED_PER_CYCLE sources of i take new values. */
static void next_cycle(float *i, int n, unsigned *seed)
{
	for (int j = 0; j < CHANGED_PER_CYCLE; j++)
		i[rand_r(seed) % n] = (float)(rand_r(seed) % 64) / 63.0f;
}

struct ctx {
	struct hl_lid *lamps[2];
	float base[2][HL_HD84_SOURCES]; /* high beam */
	int runs;
};

static struct stats bench_gl_combine(struct ctx *c, enum hl_gl_combine_mode mode, bool incremental,
				     int runs)
{
	struct hl_gl_combiner *gc;
	float i[HL_HD84_SOURCES], zero[HL_HD84_SOURCES] = { 0 };
	double *t = malloc(sizeof(double) * runs);
	unsigned seed = 1;
	struct stats s = { 0 };

	if (!t || hl_gl_combiner_new(c->lamps[0], mode, 1000000, &gc, NULL, 0) < 0) {
		free(t);
		return s;
	}
	memcpy(i, c->base[0], sizeof(i));
	hl_gl_combiner_update(gc, i);
	glFinish();
	for (int r = 0; r < runs; r++) {
		double t0;

		next_cycle(i, HL_HD84_SOURCES, &seed);
		if (!incremental && mode == HL_GL_COMBINE_BOXES) {
			/* A full recompute: from zero to everything. */
			hl_gl_combiner_free(gc);
			hl_gl_combiner_new(c->lamps[0], mode, 1, &gc, NULL, 0);
			hl_gl_combiner_update(gc, zero);
			glFinish();
		}
		t0 = hl_bench_now_ms();
		hl_gl_combiner_update(gc, i);
		glFinish();
		t[r] = hl_bench_now_ms() - t0;
	}
	s = hl_bench_summarise(t, runs);
	hl_gl_combiner_free(gc);
	free(t);
	return s;
}

static struct stats bench_cpu_combine(struct ctx *c, bool incremental, bool upload, int runs)
{
	const struct hl_lid_grid *g = hl_lid_grid(c->lamps[0]);
	float *out = malloc(sizeof(float) * g->width * g->height);
	float i[HL_HD84_SOURCES];
	double *t = malloc(sizeof(double) * runs);
	struct hl_combiner *comb = NULL;
	unsigned seed = 1;
	GLuint tex = 0;
	struct stats s = { 0 };

	if (!out || !t || hl_combiner_new(c->lamps[0], 0, &comb) < 0)
		goto out;
	memcpy(i, c->base[0], sizeof(i));
	hl_combiner_update(comb, i);
	if (upload) {
		glGenTextures(1, &tex);
		glBindTexture(GL_TEXTURE_2D, tex);
		glTexStorage2D(GL_TEXTURE_2D, 1, GL_R32F, g->width, g->height);
	}
	for (int r = 0; r < runs; r++) {
		double t0;

		next_cycle(i, HL_HD84_SOURCES, &seed);
		t0 = hl_bench_now_ms();
		if (incremental)
			hl_combiner_update(comb, i);
		else
			hl_combine_sparse(c->lamps[0], i, out);
		if (upload) {
			glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, g->width, g->height, GL_RED,
					GL_FLOAT, incremental ? hl_combiner_result(comb) : out);
			glFinish();
		}
		t[r] = hl_bench_now_ms() - t0;
	}
	s = hl_bench_summarise(t, runs);
out:
	if (tex)
		glDeleteTextures(1, &tex);
	hl_combiner_free(comb);
	free(out);
	free(t);
	return s;
}

/* Whole frames through hl_renderer; also returns the set-up time (precompute, uploads). */
static struct stats bench_frame(struct ctx *c, struct hl_egl *egl, const struct hl_gbuffer *gb,
				enum hl_backend comb, enum hl_backend light, int runs,
				double *ret_setup_ms, struct stats *ret_display)
{
	struct hl_renderer_config cfg = {
		.n_lamps = 2, .combine = comb, .headlight = light, .egl = egl
	};
	const size_t n = (size_t)gb->width * gb->height;
	float *lux = malloc(sizeof(float) * n);
	uint8_t *rgb = malloc(3 * n);
	double *t = malloc(sizeof(double) * runs), *td = malloc(sizeof(double) * runs), t0;
	float i[2][HL_HD84_SOURCES];
	struct hl_renderer *r = NULL;
	unsigned seed = 7;
	struct stats s = { 0 };

	for (int k = 0; k < 2; k++) {
		cfg.lids[k] = c->lamps[k];
		hl_lamp_pose_default(k, &cfg.poses[k]);
		memcpy(i[k], c->base[k], sizeof(i[k]));
	}
	t0 = hl_bench_now_ms();
	if (!lux || !rgb || !t || !td || hl_renderer_new(&cfg, gb, &r) < 0)
		goto out;
	for (int k = 0; k < 2; k++)
		hl_renderer_set_currents(r, k, i[k]);
	hl_renderer_frame(r, lux); /* first frame: shader JIT, first uploads */
	*ret_setup_ms = hl_bench_now_ms() - t0;
	for (int f = 0; f < runs; f++) {
		for (int k = 0; k < 2; k++)
			next_cycle(i[k], HL_HD84_SOURCES, &seed);
		t0 = hl_bench_now_ms();
		for (int k = 0; k < 2; k++)
			hl_renderer_set_currents(r, k, i[k]);
		hl_renderer_frame(r, lux);
		t[f] = hl_bench_now_ms() - t0;
		hl_view_display(gb, lux, 0.0, rgb);
		td[f] = hl_bench_now_ms() - t0;
	}
	s = hl_bench_summarise(t, runs);
	*ret_display = hl_bench_summarise(td, runs);
out:
	hl_renderer_free(r);
	free(lux);
	free(rgb);
	free(t);
	free(td);
	return s;
}

static void usage(FILE *f)
{
	fprintf(f,
		"usage: hdlamp-bench-render [--frames N] [--size WxH] [--out FILE.json]\n"
		"Times combine, headlight pass and whole frames on this machine; prints JSON.\n");
}

int main(int argc, char **argv)
{
	static const struct option opts[] = {
		{ "frames", required_argument, NULL, 'n' },
		{ "size", required_argument, NULL, 's' },
		{ "out", required_argument, NULL, 'o' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	int frames = 200, w = 1280, h = 720, c;
	const char *out_path = NULL;
	struct hl_egl *egl = NULL;
	struct hl_egl_error eerr;
	struct ctx ctx = { 0 };
	struct hl_gbuffer *gb = NULL;
	struct hl_scene scene;
	struct hl_camera cam;
	struct hl_lamp_pose poses[2];
	struct hl_preset *p = NULL;
	struct hl_headlight *hcpu = NULL;
	struct hl_headlight_lamp hl[2];
	struct stats s_papers, s_gl_full, s_gl_inc, s_cpu_full, s_cpu_inc, s_cpu_upload;
	struct stats s_light_cpu, s_light_gl[2], s_bands[4], fr[4], frd[4];
	double gl_setup_ms[2];
	double setup[4] = { 0 }, precompute_ms, *t, load[3];
	float *dense[2] = { NULL, NULL }, *lux;
	FILE *f;
	char tail;
	static const enum hl_backend pairs[4][2] = {
		{ HL_BACKEND_CPU, HL_BACKEND_CPU },
		{ HL_BACKEND_GLES, HL_BACKEND_GLES },
		{ HL_BACKEND_CPU, HL_BACKEND_GLES },
		{ HL_BACKEND_GLES, HL_BACKEND_CPU },
	};

	while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
		switch (c) {
		case 'n':
			frames = atoi(optarg);
			if (frames < 3 || frames > 100000) {
				fprintf(stderr, "hdlamp-bench-render: --frames: 3..100000\n");
				return 2;
			}
			break;
		case 's':
			if (sscanf(optarg, "%dx%d%c", &w, &h, &tail) != 2 || w < 2 || h < 2) {
				fprintf(stderr, "hdlamp-bench-render: --size: WxH\n");
				return 2;
			}
			break;
		case 'o':
			out_path = optarg;
			break;
		case 'h':
			usage(stdout);
			return 0;
		default:
			usage(stderr);
			return 2;
		}
	}
	if (hl_egl_new(&egl, &eerr) < 0) {
		fprintf(stderr, "hdlamp-bench-render: no EGL: %s\n", eerr.msg);
		return 1;
	}
	if (hl_model_hd84(HL_SIDE_LEFT, &ctx.lamps[0]) < 0 ||
	    hl_model_hd84(HL_SIDE_RIGHT, &ctx.lamps[1]) < 0 ||
	    hl_preset_new(HL_HD84_SOURCES, &p) < 0 ||
	    hl_model_hd84_preset("high", ctx.lamps, p) < 0) {
		fprintf(stderr, "hdlamp-bench-render: cannot build the HD84 lamps\n");
		return 1;
	}
	hl_preset_intensities(p, HL_SIDE_LEFT, ctx.base[0]);
	hl_preset_intensities(p, HL_SIDE_RIGHT, ctx.base[1]);

	fprintf(stderr, "combine...\n");
	s_papers = bench_gl_combine(&ctx, HL_GL_COMBINE_FULL_IMAGE, false, 20);
	s_gl_full = bench_gl_combine(&ctx, HL_GL_COMBINE_BOXES, false, 20);
	s_gl_inc = bench_gl_combine(&ctx, HL_GL_COMBINE_BOXES, true, frames);
	s_cpu_full = bench_cpu_combine(&ctx, false, false, frames);
	s_cpu_inc = bench_cpu_combine(&ctx, true, false, frames);
	s_cpu_upload = bench_cpu_combine(&ctx, true, true, frames);

	fprintf(stderr, "headlight...\n");
	for (int k = 0; k < 2; k++)
		hl_lamp_pose_default(k, &poses[k]);
	hl_scene_init(&scene, HL_SCENE_ROAD, poses);
	hl_scene_default_camera(&scene, w, h, &cam);
	if (hl_gbuffer_new(w, h, &gb) < 0 || hl_scene_render(&scene, &cam, gb) < 0)
		return 1;
	lux = malloc(sizeof(float) * w * h);
	t = malloc(sizeof(double) * frames);
	for (int k = 0; k < 2; k++) {
		const struct hl_lid_grid *g = hl_lid_grid(ctx.lamps[k]);

		dense[k] = malloc(sizeof(float) * g->width * g->height);
		if (!dense[k])
			return 1;
		hl_combine_sparse(ctx.lamps[k], ctx.base[k], dense[k]);
		hl[k] = (struct hl_headlight_lamp){ poses[k], *g };
	}
	if (!lux || !t)
		return 1;
	{
		double t0 = hl_bench_now_ms();

		if (hl_headlight_new(gb, 2, hl, &hcpu) < 0)
			return 1;
		precompute_ms = hl_bench_now_ms() - t0;
	}
	for (int r = 0; r < frames; r++) {
		double t0 = hl_bench_now_ms();

		hl_headlight_run(hcpu, (const float *const *)dense, lux);
		t[r] = hl_bench_now_ms() - t0;
	}
	s_light_cpu = hl_bench_summarise(t, frames);
	for (int k = 0; k < 4; k++)
		s_bands[k] = bench_bands(hcpu, (const float *const *)dense, lux, 1 + k % 2, k >= 2,
					 t, k >= 2 && frames > 40 ? 40 : frames);
	for (int m = 0; m < 2; m++) {
		struct hl_gl_headlight *hg;
		int runs = frames < 30 ? frames : 30;
		double t0 = hl_bench_now_ms();

		if (hl_gl_headlight_new(gb, 2, hl, m, &hg, NULL, 0) < 0)
			return 1;
		hl_gl_headlight_upload(hg, 0, dense[0]);
		hl_gl_headlight_upload(hg, 1, dense[1]);
		hl_gl_headlight_run(hg);
		glFinish();
		gl_setup_ms[m] = hl_bench_now_ms() - t0;
		for (int r = 0; r < runs; r++) {
			t0 = hl_bench_now_ms();
			hl_gl_headlight_run(hg);
			glFinish();
			t[r] = hl_bench_now_ms() - t0;
		}
		s_light_gl[m] = hl_bench_summarise(t, runs);
		hl_gl_headlight_free(hg);
	}

	fprintf(stderr, "frames...\n");
	for (int j = 0; j < 4; j++) {
		const bool gl_light = pairs[j][1] == HL_BACKEND_GLES;

		fr[j] = bench_frame(&ctx, egl, gb, pairs[j][0], pairs[j][1],
				    gl_light ? (frames < 30 ? frames : 30) : frames, &setup[j],
				    &frd[j]);
	}

	f = hl_bench_open_json("hdlamp-bench-render", out_path);
	if (!f)
		return 1;
	if (getloadavg(load, 3) < 0)
		load[0] = load[1] = load[2] = -1.0;
	fprintf(f, "{\n");
	fprintf(f,
		"  \"machine\": {\"cpus_online\": %ld, \"egl_platform\": \"%s\", \"renderer\": \"%s\", "
		"\"gl_version\": \"%s\", \"loadavg_1_5_15\": [%.2f, %.2f, %.2f]},\n",
		sysconf(_SC_NPROCESSORS_ONLN), hl_egl_platform(egl), hl_egl_renderer(egl),
		hl_egl_version(egl), load[0], load[1], load[2]);
	fprintf(f,
		"  \"lamp\": {\"sources\": %d, \"grid\": [%d, %d], \"changed_per_cycle\": %d},\n",
		HL_HD84_SOURCES, hl_lid_grid(ctx.lamps[0])->width,
		hl_lid_grid(ctx.lamps[0])->height, CHANGED_PER_CYCLE);
	fprintf(f, "  \"combine_per_lamp\": {\n");
	print_stats(f, "papers_gles_full_image_passes_r32f", s_papers, false);
	print_stats(f, "gles_box_quads_full", s_gl_full, false);
	print_stats(f, "gles_box_quads_incremental", s_gl_inc, false);
	print_stats(f, "cpu_sparse_full", s_cpu_full, false);
	print_stats(f, "cpu_incremental", s_cpu_inc, false);
	print_stats(f, "cpu_incremental_plus_texture_upload", s_cpu_upload, true);
	fprintf(f, "  },\n");
	fprintf(f,
		"  \"combine_speedup_vs_papers\": {\"cpu_incremental\": %.1f, "
		"\"cpu_sparse_full\": %.1f, \"gles_box_quads_incremental\": %.1f},\n",
		s_papers.median / s_cpu_inc.median, s_papers.median / s_cpu_full.median,
		s_papers.median / s_gl_inc.median);
	fprintf(f,
		"  \"headlight\": {\n    \"size\": [%d, %d], \"lamps\": 2, \"scene\": \"road\", "
		"\"pixel_lamp_pairs\": %zu, \"cpu_precompute_ms\": %.1f,\n",
		w, h, hl_headlight_work(hcpu), precompute_ms);
	print_stats(f, "cpu_precomputed", s_light_cpu, false);
	print_stats(f, "cpu_bands_1_thread", s_bands[0], false);
	print_stats(f, "cpu_bands_2_threads", s_bands[1], false);
	print_stats(f, "cpu_bands_1_thread_after_idle_15ms", s_bands[2], false);
	print_stats(f, "cpu_bands_2_threads_after_idle_15ms", s_bands[3], false);
	print_stats(f, "gles_direct", s_light_gl[HL_GL_HEADLIGHT_DIRECT], false);
	print_stats(f, "gles_precomputed", s_light_gl[HL_GL_HEADLIGHT_PRECOMPUTED], false);
	fprintf(f, "    \"gles_setup_ms\": {\"direct\": %.1f, \"precomputed\": %.1f}\n",
		gl_setup_ms[0], gl_setup_ms[1]);
	fprintf(f, "  },\n");
	fprintf(f, "  \"frame\": {\n");
	for (int j = 0; j < 4; j++) {
		char name[64];

		snprintf(name, sizeof(name), "combine_%s_headlight_%s",
			 hl_backend_name(pairs[j][0]), hl_backend_name(pairs[j][1]));
		fprintf(f,
			"    \"%s\": {\"median_ms\": %.3f, \"min_ms\": %.3f, \"max_ms\": %.3f, "
			"\"n\": %d, \"setup_ms\": %.1f,\n      \"with_display_tonemap\": "
			"{\"median_ms\": %.3f, \"min_ms\": %.3f, \"max_ms\": %.3f}}%s\n",
			name, fr[j].median, fr[j].min, fr[j].max, fr[j].n, setup[j], frd[j].median,
			frd[j].min, frd[j].max, j == 3 ? "" : ",");
	}
	fprintf(f, "  }\n}\n");
	if (f != stdout)
		fclose(f);

	hl_headlight_free(hcpu);
	hl_gbuffer_free(gb);
	free(dense[0]);
	free(dense[1]);
	free(lux);
	free(t);
	hl_preset_free(p);
	hl_lid_free(ctx.lamps[0]);
	hl_lid_free(ctx.lamps[1]);
	hl_egl_free(egl);
	return 0;
}
