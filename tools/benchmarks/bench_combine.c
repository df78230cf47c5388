/* SPDX-License-Identifier: MIT */
/*
 * hdlamp-bench-combine: what hdlamp-bench-render does not measure, as one JSON object
 * (tools/bench runs both and puts them side by side).
 *   combine   per lamp (HD84, 95 sources, 900 x 250), all in this run: the papers' method
 *             (K full-image additive passes into R32F, GLES), GLES box quads (full redraw),
 *             CPU sparse (full), CPU incremental with exactly 1, 10 and 95 sources changed,
 *             a dense CPU combine (every source's full grid, like the papers but in C) and the
 *             memory floor of that dense combine: the time to read its K full grids once,
 *             at the read bandwidth measured here on the same data
 *   floor     the GLES headlight pass (1280 x 720, two lamps, road, precomputed terms) and
 *             llvmpipe's floor: a pass-through shader that only reads the two G-buffer texels
 *             of each pixel and writes one float; interleaved, so both see the same load
 *   scaling   pixel lamps (hl_model_pixel, the lamps of 'hdlamp model --sources N') with
 *             K = 95, 256, 1024, 4096 sources each: CPU sparse and incremental combine, GLES
 *             box quads, and whole CPU frames (two combines + headlight pass, 1280 x 720)
 *             with 10 % and with all sources changed per cycle
 * GL timings end with glFinish: work done, not work queued.
 */
#include <errno.h>
#include <getopt.h>
#include <stdint.h>
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
#include "render/gl_util.h"
#include "render/headlight.h"
#include "render/renderer.h"
#include "render/scene.h"
#include "render/shader.h"
#include "render/shaders.h"
#include "tools/benchmarks/bench_stats.h"
#include "lamp/model.h"

#define MAX_RUNS 100000
#define MAX_SCALING 8

struct opts {
	int runs; /* per CPU measurement */
	int gl_runs; /* per GLES measurement (llvmpipe is slow) */
	int papers_runs;
	int w, h;
	int scaling[MAX_SCALING];
	int n_scaling;
};

static void put_stats(FILE *f, const char *indent, const char *name, struct stats s,
		      const char *extra, bool last)
{
	fprintf(f,
		"%s\"%s\": {\"median_ms\": %.5f, \"min_ms\": %.5f, \"max_ms\": %.5f, \"n\": %d%s}%s\n",
		indent, name, s.median, s.min, s.max, s.n, extra ? extra : "", last ? "" : ",");
}

/* Exactly m distinct sources of i take a new value (different from the old one). */
static void change_sources(float *i, int n, int m, unsigned *seed, int *perm)
{
	for (int j = 0; j < n; j++)
		perm[j] = j;
	for (int j = 0; j < m; j++) {
		const int r = j + (int)(rand_r(seed) % (unsigned)(n - j));
		const int k = perm[r];
		const int old = (int)(i[k] * 63.0f + 0.5f);

		perm[r] = perm[j];
		perm[j] = k;
		i[k] = (float)((old + 1 + (int)(rand_r(seed) % 63)) % 64) / 63.0f;
	}
}

/* The papers' method (FULL_IMAGE) or the box quads redrawn in full (full_every 1). */
static struct stats bench_gl_combine(const struct hl_lid *lid, enum hl_gl_combine_mode mode,
				     int runs, double *t)
{
	const int n = hl_lid_n_sources(lid);
	float *i = calloc(n, sizeof(float));
	int *perm = malloc(sizeof(int) * n);
	struct hl_gl_combiner *gc = NULL;
	unsigned seed = 1;
	int done = 0;

	if (!i || !perm || hl_gl_combiner_new(lid, mode, 1, &gc, NULL, 0) < 0)
		goto out;
	change_sources(i, n, n, &seed, perm);
	hl_gl_combiner_update(gc, i); /* first draw: shader JIT */
	glFinish();
	for (; done < runs; done++) {
		double t0;

		change_sources(i, n, n / 10 > 0 ? n / 10 : 1, &seed, perm);
		t0 = hl_bench_now_ms();
		hl_gl_combiner_update(gc, i);
		glFinish();
		t[done] = hl_bench_now_ms() - t0;
	}
out:
	hl_gl_combiner_free(gc);
	free(i);
	free(perm);
	return hl_bench_summarise(t, done);
}

/* CPU: sparse full combine (changed < 0) or incremental with exactly `changed` sources. */
static struct stats bench_cpu_combine(const struct hl_lid *lid, int changed, int runs, double *t)
{
	const struct hl_lid_grid *g = hl_lid_grid(lid);
	const int n = hl_lid_n_sources(lid);
	float *out = malloc(sizeof(float) * g->width * g->height);
	float *i = calloc(n, sizeof(float));
	int *perm = malloc(sizeof(int) * n);
	struct hl_combiner *comb = NULL;
	unsigned seed = 3;
	int done = 0;

	/* the default full_every: the daemon's combiner, periodic full recompute included */
	if (!out || !i || !perm || hl_combiner_new(lid, 0, &comb) < 0)
		goto out;
	change_sources(i, n, n, &seed, perm);
	hl_combiner_update(comb, i);
	for (; done < runs; done++) {
		double t0;

		change_sources(i, n, changed < 0 ? n / 10 + 1 : changed, &seed, perm);
		t0 = hl_bench_now_ms();
		if (changed < 0)
			hl_combine_sparse(lid, i, out);
		else
			hl_combiner_update(comb, i);
		t[done] = hl_bench_now_ms() - t0;
	}
out:
	hl_combiner_free(comb);
	free(out);
	free(i);
	free(perm);
	return hl_bench_summarise(t, done);
}

/* out = sum_k i_k * src_k over full grids (the papers' arithmetic on the CPU). */
static void dense_combine(float *const *src, int k_n, const float *i, size_t n, float *restrict out)
{
	memset(out, 0, sizeof(float) * n);
	for (int k = 0; k < k_n; k++) {
		const float *restrict s = src[k];
		const float w = i[k];

		for (size_t j = 0; j < n; j++)
			out[j] += w * s[j];
	}
}

typedef float v4f __attribute__((vector_size(16)));

/* Reads every byte of the K grids once (four independent vector sums): the read floor. */
static float read_all(float *const *src, int k_n, size_t n)
{
	v4f a = { 0 }, b = { 0 }, c = { 0 }, d = { 0 };
	float s;

	for (int k = 0; k < k_n; k++) {
		const float *p = src[k];
		size_t j = 0;

		for (; j + 16 <= n; j += 16) {
			v4f x, y, z, w;

			memcpy(&x, p + j, 16);
			memcpy(&y, p + j + 4, 16);
			memcpy(&z, p + j + 8, 16);
			memcpy(&w, p + j + 12, 16);
			a += x;
			b += y;
			c += z;
			d += w;
		}
		for (; j < n; j++)
			a[0] += p[j];
	}
	a += b + c + d;
	s = a[0] + a[1] + a[2] + a[3];
	return s;
}

struct dense_result {
	struct stats combine, read;
	double bytes, gb_per_s;
};

static int bench_dense(const struct hl_lid *lid, int runs, double *t, double *t2,
		       struct dense_result *ret)
{
	const struct hl_lid_grid *g = hl_lid_grid(lid);
	const int k_n = hl_lid_n_sources(lid);
	const size_t n = (size_t)g->width * g->height;
	float **src = calloc(k_n, sizeof(float *));
	float *out = malloc(sizeof(float) * n), *i = malloc(sizeof(float) * k_n);
	volatile float sink = 0;
	int rc = -ENOMEM;

	if (!src || !out || !i)
		goto out;
	for (int k = 0; k < k_n; k++) {
		src[k] = malloc(sizeof(float) * n);
		if (!src[k])
			goto out;
		hl_lid_source_dense(lid, k, src[k]);
		i[k] = (float)(k % 64) / 63.0f;
	}
	dense_combine(src, k_n, i, n, out);
	sink = read_all(src, k_n, n);
	/* interleaved, so the combine and its floor see the same load */
	for (int r = 0; r < runs; r++) {
		double t0 = hl_bench_now_ms();

		dense_combine(src, k_n, i, n, out);
		t[r] = hl_bench_now_ms() - t0;
		t0 = hl_bench_now_ms();
		sink += read_all(src, k_n, n);
		t2[r] = hl_bench_now_ms() - t0;
	}
	(void)sink;
	ret->combine = hl_bench_summarise(t, runs);
	ret->read = hl_bench_summarise(t2, runs);
	ret->bytes = (double)k_n * n * sizeof(float);
	ret->gb_per_s = ret->bytes / (ret->read.min * 1e-3) / 1e9;
	rc = 0;
out:
	if (src)
		for (int k = 0; k < k_n; k++)
			free(src[k]);
	free(src);
	free(out);
	free(i);
	return rc;
}

struct floor_result {
	struct stats passthrough, headlight_gles, headlight_cpu;
	size_t pairs;
};

/* The GLES headlight pass, its pass-through floor and the CPU pass, interleaved. */
static int bench_floor(struct hl_lid *const lamps[2], const float *const base[2],
		       const struct opts *o, double *t, struct floor_result *ret)
{
	struct hl_lamp_pose poses[2];
	struct hl_scene scene;
	struct hl_camera cam;
	struct hl_gbuffer *gb = NULL;
	struct hl_headlight_lamp hl[2];
	struct hl_headlight *hcpu = NULL;
	struct hl_gl_headlight *hg = NULL;
	float *dense[2] = { NULL, NULL }, *lux = NULL;
	double *t1 = t + o->gl_runs, *t2 = t + 2 * o->gl_runs;
	GLuint pos = 0, nrm = 0, target = 0, fbo = 0, prog = 0;
	char log[2048];
	int rc = -ENOMEM;

	for (int k = 0; k < 2; k++)
		hl_lamp_pose_default(k, &poses[k]);
	hl_scene_init(&scene, HL_SCENE_ROAD, poses);
	hl_scene_default_camera(&scene, o->w, o->h, &cam);
	if (hl_gbuffer_new(o->w, o->h, &gb) < 0 || hl_scene_render(&scene, &cam, gb) < 0)
		goto out;
	lux = malloc(sizeof(float) * o->w * o->h);
	if (!lux)
		goto out;
	for (int k = 0; k < 2; k++) {
		const struct hl_lid_grid *g = hl_lid_grid(lamps[k]);

		dense[k] = malloc(sizeof(float) * g->width * g->height);
		if (!dense[k])
			goto out;
		hl_combine_sparse(lamps[k], base[k], dense[k]);
		hl[k] = (struct hl_headlight_lamp){ poses[k], *g };
	}
	rc = -EIO;
	if (hl_headlight_new(gb, 2, hl, &hcpu) < 0 ||
	    hl_gl_headlight_new(gb, 2, hl, HL_GL_HEADLIGHT_PRECOMPUTED, &hg, log, sizeof(log)) < 0)
		goto out;
	hl_gl_headlight_upload(hg, 0, dense[0]);
	hl_gl_headlight_upload(hg, 1, dense[1]);
	pos = hl_gl_texture_float(o->w, o->h, true, gb->pos);
	nrm = hl_gl_texture_float(o->w, o->h, true, gb->nrm);
	target = hl_gl_texture_float(o->w, o->h, false, NULL);
	fbo = target ? hl_gl_framebuffer(target) : 0;
	if (!pos || !nrm || !fbo ||
	    hl_shader_build(hl_shader_quad_vert, hl_shader_passthrough_frag, &prog, log,
			    sizeof(log)) < 0) {
		fprintf(stderr, "hdlamp-bench-combine: pass-through shader: %s\n", log);
		goto out;
	}
	glUseProgram(prog);
	glUniform1i(glGetUniformLocation(prog, "u_pos"), 0);
	glUniform1i(glGetUniformLocation(prog, "u_nrm"), 1);
	for (int r = -1; r < o->gl_runs; r++) { /* run -1: shader JIT, first touches */
		double t0 = hl_bench_now_ms();

		glBindFramebuffer(GL_FRAMEBUFFER, fbo);
		glViewport(0, 0, o->w, o->h);
		glUseProgram(prog);
		glActiveTexture(GL_TEXTURE0);
		glBindTexture(GL_TEXTURE_2D, pos);
		glActiveTexture(GL_TEXTURE1);
		glBindTexture(GL_TEXTURE_2D, nrm);
		glActiveTexture(GL_TEXTURE0);
		glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
		glFinish();
		if (r >= 0)
			t[r] = hl_bench_now_ms() - t0;
		t0 = hl_bench_now_ms();
		hl_gl_headlight_run(hg);
		glFinish();
		if (r >= 0)
			t1[r] = hl_bench_now_ms() - t0;
		t0 = hl_bench_now_ms();
		hl_headlight_run(hcpu, (const float *const *)dense, lux);
		if (r >= 0)
			t2[r] = hl_bench_now_ms() - t0;
	}
	glBindFramebuffer(GL_FRAMEBUFFER, 0);
	rc = glGetError() == GL_NO_ERROR ? 0 : -EIO;
	ret->passthrough = hl_bench_summarise(t, o->gl_runs);
	ret->headlight_gles = hl_bench_summarise(t1, o->gl_runs);
	ret->headlight_cpu = hl_bench_summarise(t2, o->gl_runs);
	ret->pairs = hl_headlight_work(hcpu);
out:
	if (prog)
		glDeleteProgram(prog);
	if (fbo)
		glDeleteFramebuffers(1, &fbo);
	if (target)
		glDeleteTextures(1, &target);
	if (pos)
		glDeleteTextures(1, &pos);
	if (nrm)
		glDeleteTextures(1, &nrm);
	hl_gl_headlight_free(hg);
	hl_headlight_free(hcpu);
	hl_gbuffer_free(gb);
	free(dense[0]);
	free(dense[1]);
	free(lux);
	return rc;
}

/* Whole CPU frames of a pixel lamp pair with `changed` sources per lamp changed per cycle. */
static struct stats bench_frame(const struct hl_lid *lid, const struct hl_gbuffer *gb, int changed,
				int runs, double *t)
{
	struct hl_renderer_config cfg = { .n_lamps = 2,
					  .combine = HL_BACKEND_CPU,
					  .headlight = HL_BACKEND_CPU };
	const int n = hl_lid_n_sources(lid);
	float *lux = malloc(sizeof(float) * gb->width * gb->height);
	float *i[2] = { calloc(n, sizeof(float)), calloc(n, sizeof(float)) };
	int *perm = malloc(sizeof(int) * n);
	struct hl_renderer *r = NULL;
	unsigned seed = 11;
	int done = 0;

	for (int k = 0; k < 2; k++) {
		cfg.lids[k] = lid;
		hl_lamp_pose_default(k, &cfg.poses[k]);
	}
	if (!lux || !i[0] || !i[1] || !perm || hl_renderer_new(&cfg, gb, &r) < 0)
		goto out;
	for (int k = 0; k < 2; k++) {
		change_sources(i[k], n, n, &seed, perm);
		hl_renderer_set_currents(r, k, i[k]);
	}
	hl_renderer_frame(r, lux);
	for (; done < runs; done++) {
		double t0;

		for (int k = 0; k < 2; k++)
			change_sources(i[k], n, changed, &seed, perm);
		t0 = hl_bench_now_ms();
		for (int k = 0; k < 2; k++)
			hl_renderer_set_currents(r, k, i[k]);
		hl_renderer_frame(r, lux);
		t[done] = hl_bench_now_ms() - t0;
	}
out:
	hl_renderer_free(r);
	free(lux);
	free(i[0]);
	free(i[1]);
	free(perm);
	return hl_bench_summarise(t, done);
}

struct scaling_result {
	int k;
	struct stats sparse, incremental, gles_boxes, frame_tenth, frame_all;
	double model_ms;
};

static int bench_scaling(const struct opts *o, double *t, struct scaling_result *res)
{
	struct hl_lamp_pose poses[2];
	struct hl_scene scene;
	struct hl_camera cam;
	struct hl_gbuffer *gb = NULL;

	for (int k = 0; k < 2; k++)
		hl_lamp_pose_default(k, &poses[k]);
	hl_scene_init(&scene, HL_SCENE_ROAD, poses);
	hl_scene_default_camera(&scene, o->w, o->h, &cam);
	if (hl_gbuffer_new(o->w, o->h, &gb) < 0 || hl_scene_render(&scene, &cam, gb) < 0) {
		hl_gbuffer_free(gb);
		return -ENOMEM;
	}
	for (int s = 0; s < o->n_scaling; s++) {
		struct scaling_result *r = &res[s];
		struct hl_lid *lid = NULL;
		double t0 = hl_bench_now_ms();
		int rc = hl_model_pixel(o->scaling[s], &lid);

		if (rc < 0) {
			hl_gbuffer_free(gb);
			return rc;
		}
		r->k = o->scaling[s];
		r->model_ms = hl_bench_now_ms() - t0;
		fprintf(stderr, "scaling: K = %d\n", r->k);
		r->sparse = bench_cpu_combine(lid, -1, o->runs, t);
		r->incremental = bench_cpu_combine(lid, r->k / 10 > 0 ? r->k / 10 : 1, o->runs, t);
		r->gles_boxes = bench_gl_combine(lid, HL_GL_COMBINE_BOXES, o->gl_runs, t);
		r->frame_tenth = bench_frame(lid, gb, r->k / 10 > 0 ? r->k / 10 : 1, o->runs, t);
		r->frame_all = bench_frame(lid, gb, r->k, o->runs, t);
		hl_lid_free(lid);
	}
	hl_gbuffer_free(gb);
	return 0;
}

static void usage(FILE *f)
{
	fprintf(f,
		"usage: hdlamp-bench-combine [--runs N] [--gl-runs N] [--papers-runs N]\n"
		"                            [--scaling K1,K2,..] [--size WxH] [--out FILE.json]\n"
		"Times, in one run: the combiners against the papers' method and the dense memory\n"
		"floor (HD84, 95 sources), the GLES headlight pass against llvmpipe's pass-through\n"
		"floor, and pixel lamps of K sources (default 95,256,1024,4096). Prints JSON.\n");
}

static int parse_scaling(const char *s, struct opts *o)
{
	char *end;

	o->n_scaling = 0;
	while (*s && o->n_scaling < MAX_SCALING) {
		long k = strtol(s, &end, 10);

		if (end == s || k < 1 || k > 4096 || (*end && *end != ','))
			return -EINVAL;
		o->scaling[o->n_scaling++] = (int)k;
		s = *end ? end + 1 : end;
	}
	return *s ? -EINVAL : 0;
}

int main(int argc, char **argv)
{
	static const struct option lopts[] = {
		{ "runs", required_argument, NULL, 'r' },
		{ "gl-runs", required_argument, NULL, 'g' },
		{ "papers-runs", required_argument, NULL, 'p' },
		{ "scaling", required_argument, NULL, 'k' },
		{ "size", required_argument, NULL, 's' },
		{ "out", required_argument, NULL, 'o' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	struct opts o = { .runs = 200,
			  .gl_runs = 30,
			  .papers_runs = 20,
			  .w = 1280,
			  .h = 720,
			  .scaling = { 95, 256, 1024, 4096 },
			  .n_scaling = 4 };
	static const int inc_changed[3] = { 1, 10, 95 };
	struct stats papers, boxes, sparse, inc[3];
	struct dense_result dense = { 0 };
	struct floor_result fl = { 0 };
	struct scaling_result sc[MAX_SCALING];
	struct hl_lid *lamps[2] = { NULL, NULL };
	struct hl_preset *p = NULL;
	struct hl_egl *egl = NULL;
	struct hl_egl_error eerr;
	float base[2][HL_HD84_SOURCES];
	const float *basep[2] = { base[0], base[1] };
	const char *out_path = NULL;
	double *t, *t2, load0[3], load1[3], t_start = hl_bench_now_ms();
	FILE *f;
	char tail;
	int c;

	while ((c = getopt_long(argc, argv, "h", lopts, NULL)) != -1) {
		switch (c) {
		case 'r':
		case 'g':
		case 'p': {
			const int v = atoi(optarg);

			if (v < 3 || v > MAX_RUNS) {
				fprintf(stderr, "hdlamp-bench-combine: runs: 3..%d\n", MAX_RUNS);
				return 2;
			}
			*(c == 'r' ? &o.runs : c == 'g' ? &o.gl_runs : &o.papers_runs) = v;
			break;
		}
		case 'k':
			if (parse_scaling(optarg, &o) < 0) {
				fprintf(stderr,
					"hdlamp-bench-combine: --scaling: K1,K2,.. each 1..4096\n");
				return 2;
			}
			break;
		case 's':
			if (sscanf(optarg, "%dx%d%c", &o.w, &o.h, &tail) != 2 || o.w < 16 ||
			    o.h < 16 || o.w > 8192 || o.h > 8192) {
				fprintf(stderr, "hdlamp-bench-combine: --size: WxH, 16..8192\n");
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
	if (getloadavg(load0, 3) < 0)
		load0[0] = load0[1] = load0[2] = -1.0;
	{
		int most = o.runs > o.gl_runs ? o.runs : o.gl_runs;

		most = most > o.papers_runs ? most : o.papers_runs;
		t = malloc(sizeof(double) * 3 * most);
	}
	t2 = malloc(sizeof(double) * o.runs);
	if (!t || !t2)
		return 1;
	if (hl_egl_new(&egl, &eerr) < 0) {
		fprintf(stderr, "hdlamp-bench-combine: no EGL: %s\n", eerr.msg);
		return 1;
	}
	if (hl_model_hd84(HL_SIDE_LEFT, &lamps[0]) < 0 ||
	    hl_model_hd84(HL_SIDE_RIGHT, &lamps[1]) < 0 || hl_preset_new(HL_HD84_SOURCES, &p) < 0 ||
	    hl_model_hd84_preset("high", lamps, p) < 0) {
		fprintf(stderr, "hdlamp-bench-combine: cannot build the HD84 lamps\n");
		return 1;
	}
	hl_preset_intensities(p, HL_SIDE_LEFT, base[0]);
	hl_preset_intensities(p, HL_SIDE_RIGHT, base[1]);

	fprintf(stderr, "combine (K = 95)...\n");
	papers = bench_gl_combine(lamps[0], HL_GL_COMBINE_FULL_IMAGE, o.papers_runs, t);
	boxes = bench_gl_combine(lamps[0], HL_GL_COMBINE_BOXES, o.gl_runs, t);
	sparse = bench_cpu_combine(lamps[0], -1, o.runs, t);
	for (int j = 0; j < 3; j++)
		inc[j] = bench_cpu_combine(lamps[0], inc_changed[j], o.runs, t);
	if (bench_dense(lamps[0], o.runs < 50 ? o.runs : 50, t, t2, &dense) < 0) {
		fprintf(stderr, "hdlamp-bench-combine: out of memory (dense combine)\n");
		return 1;
	}
	fprintf(stderr, "headlight pass vs pass-through floor...\n");
	if (bench_floor(lamps, basep, &o, t, &fl) < 0) {
		fprintf(stderr, "hdlamp-bench-combine: headlight floor failed\n");
		return 1;
	}
	if (bench_scaling(&o, t, sc) < 0) {
		fprintf(stderr, "hdlamp-bench-combine: scaling failed\n");
		return 1;
	}

	f = hl_bench_open_json("hdlamp-bench-combine", out_path);
	if (!f)
		return 1;
	if (getloadavg(load1, 3) < 0)
		load1[0] = load1[1] = load1[2] = -1.0;
	fprintf(f, "{\n");
	fprintf(f,
		"  \"machine\": {\"cpus_online\": %ld, \"egl_platform\": \"%s\", \"renderer\": \"%s\", "
		"\"gl_version\": \"%s\", \"loadavg_1_5_15_start\": [%.2f, %.2f, %.2f], "
		"\"loadavg_1_5_15_end\": [%.2f, %.2f, %.2f]},\n",
		sysconf(_SC_NPROCESSORS_ONLN), hl_egl_platform(egl), hl_egl_renderer(egl),
		hl_egl_version(egl), load0[0], load0[1], load0[2], load1[0], load1[1], load1[2]);
	fprintf(f, "  \"seconds\": %.1f,\n", (hl_bench_now_ms() - t_start) / 1e3);
	fprintf(f, "  \"combine_per_lamp\": {\n    \"sources\": %d, \"grid\": [%d, %d],\n",
		HL_HD84_SOURCES, hl_lid_grid(lamps[0])->width, hl_lid_grid(lamps[0])->height);
	put_stats(f, "    ", "papers_gles_full_image_passes_r32f", papers, NULL, false);
	put_stats(f, "    ", "gles_box_quads_full", boxes, NULL, false);
	put_stats(f, "    ", "cpu_sparse_full", sparse, NULL, false);
	for (int j = 0; j < 3; j++) {
		char name[64];

		snprintf(name, sizeof(name), "cpu_incremental_%d_changed", inc_changed[j]);
		put_stats(f, "    ", name, inc[j], NULL, false);
	}
	put_stats(f, "    ", "cpu_dense_full", dense.combine, NULL, false);
	{
		char extra[160];

		snprintf(extra, sizeof(extra),
			 ", \"bytes\": %.0f, \"read_gb_per_s_best\": %.2f, \"floor_ms\": %.4f",
			 dense.bytes, dense.gb_per_s, dense.read.min);
		put_stats(f, "    ", "dense_read_floor", dense.read, extra, false);
	}
	fprintf(f,
		"    \"speedup_vs_papers\": {\"gles_box_quads_full\": %.1f, \"cpu_sparse_full\": %.1f, "
		"\"cpu_incremental_1_changed\": %.1f, \"cpu_incremental_10_changed\": %.1f, "
		"\"cpu_incremental_95_changed\": %.1f, \"cpu_dense_full\": %.2f, "
		"\"dense_read_floor\": %.2f}\n",
		papers.median / boxes.median, papers.median / sparse.median,
		papers.median / inc[0].median, papers.median / inc[1].median,
		papers.median / inc[2].median, papers.median / dense.combine.median,
		papers.median / dense.read.median);
	fprintf(f, "  },\n");
	fprintf(f,
		"  \"headlight_floor\": {\n    \"size\": [%d, %d], \"lamps\": 2, \"scene\": \"road\", "
		"\"pixel_lamp_pairs\": %zu,\n",
		o.w, o.h, fl.pairs);
	put_stats(f, "    ", "gles_passthrough_floor", fl.passthrough, NULL, false);
	put_stats(f, "    ", "gles_precomputed", fl.headlight_gles, NULL, false);
	put_stats(f, "    ", "cpu_precomputed", fl.headlight_cpu, NULL, false);
	fprintf(f, "    \"gles_over_floor\": %.2f, \"cpu_over_gles_floor\": %.3f\n",
		fl.headlight_gles.median / fl.passthrough.median,
		fl.headlight_cpu.median / fl.passthrough.median);
	fprintf(f, "  },\n  \"scaling\": [\n");
	for (int s = 0; s < o.n_scaling; s++) {
		fprintf(f, "    {\"sources\": %d, \"model_ms\": %.1f,\n", sc[s].k, sc[s].model_ms);
		put_stats(f, "     ", "cpu_sparse_full", sc[s].sparse, NULL, false);
		put_stats(f, "     ", "cpu_incremental_tenth_changed", sc[s].incremental, NULL,
			  false);
		put_stats(f, "     ", "gles_box_quads_full", sc[s].gles_boxes, NULL, false);
		put_stats(f, "     ", "frame_cpu_tenth_changed", sc[s].frame_tenth, NULL, false);
		put_stats(f, "     ", "frame_cpu_all_changed", sc[s].frame_all, NULL, true);
		fprintf(f, "    }%s\n", s + 1 < o.n_scaling ? "," : "");
	}
	fprintf(f, "  ]\n}\n");
	if (f != stdout)
		fclose(f);

	hl_preset_free(p);
	hl_lid_free(lamps[0]);
	hl_lid_free(lamps[1]);
	hl_egl_free(egl);
	free(t);
	free(t2);
	return 0;
}
