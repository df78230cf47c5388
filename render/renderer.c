/* SPDX-License-Identifier: MIT */
#include "render/renderer.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <GLES3/gl31.h>

#include "lamp/combine.h"
#include "render/gbuffer_diff.h"
#include "render/gl_combine.h"
#include "render/gl_headlight.h"
#include "render/headlight.h"
#include "render/workers.h"

#define GLES_BAND_PIXELS 16384 /* bands of a read-back GLES frame handed to pixels() */

struct hl_renderer {
	int n_lamps;
	int width, height;
	enum hl_backend combine, headlight;
	const struct hl_lid *lids[2];
	struct hl_combiner *cpu_comb[2];
	struct hl_gl_combiner *gl_comb[2];
	struct hl_headlight *cpu_light;
	struct hl_gl_headlight *gl_light;
	float *dense[2]; /* combined distributions on the CPU (or a combined lid's copy) */
	bool dense_stale[2]; /* GL combine ran since dense was read back */
	bool dirty[2]; /* currents changed since the last frame */
	struct hl_workers *workers;
	/* A moving scene (hl_renderer_set_gbuffer): the geometry as last lit, the next G-buffer. */
	struct hl_gbuffer_diff *diff;
	const struct hl_gbuffer *next_gb;
	struct hl_gbuffer *fill_gb; /* next_gb, to be filled band by band by fill */
	hl_renderer_fill_fn fill;
	void *fill_userdata;
	uint8_t *fill_changed; /* per pixel, as the fill said */
	bool fill_all; /* the fill's frame recomputes every pixel */
	const struct hl_gbuffer *lit_gb; /* the G-buffer of the last frame */
	bool diff_stale; /* a fill's frame went by: diff's copy is not the G-buffer lit last */
	bool diff_all; /* the next frame recomputes every pixel: diff knows no G-buffer yet */
};

static const char *const backend_names[] = { "auto", "cpu", "gles" };

int hl_backend_from_name(const char *name)
{
	for (int i = 0; i < 3; i++)
		if (strcmp(name, backend_names[i]) == 0)
			return i;
	return -EINVAL;
}

const char *hl_backend_name(enum hl_backend b)
{
	return backend_names[b];
}

static double now_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

#define PICK_RUNS 5 /* timed updates per candidate */

/*
 * AUTO for the combiner: times the CPU reference and the GLES box quads on this lamp (a full
 * combine, then incremental updates of ten sources, as an ECU cycle) and returns the faster.
 * On llvmpipe the CPU wins by about 40x; on a real GPU the upload-free GLES path may.
 */
static enum hl_backend pick_combine(const struct hl_lid *lid)
{
	const int n = hl_lid_n_sources(lid);
	struct hl_combiner *cpu = NULL;
	struct hl_gl_combiner *gl = NULL;
	float *i = calloc(n, sizeof(float));
	double t_cpu = 0.0, t_gl = 0.0;
	enum hl_backend best = HL_BACKEND_CPU;

	if (!i || hl_combiner_new(lid, 0, &cpu) < 0 ||
	    hl_gl_combiner_new(lid, HL_GL_COMBINE_BOXES, 0, &gl, NULL, 0) < 0)
		goto out;
	for (int r = 0; r <= PICK_RUNS; r++) {
		double t0;

		for (int j = 0; j < n; j++)
			i[j] = r == 0 ? 1.0f :
					(j % PICK_RUNS == r - 1 ? 0.5f * r / PICK_RUNS : i[j]);
		t0 = now_ms();
		hl_combiner_update(cpu, i);
		t_cpu += now_ms() - t0;
		t0 = now_ms();
		hl_gl_combiner_update(gl, i);
		glFinish();
		t_gl += now_ms() - t0;
	}
	best = t_gl < t_cpu ? HL_BACKEND_GLES : HL_BACKEND_CPU;
out:
	hl_combiner_free(cpu);
	hl_gl_combiner_free(gl);
	free(i);
	return best;
}

/* AUTO for the headlight pass: one timed frame of each (after the shader's first run). */
static enum hl_backend pick_headlight(struct hl_renderer *r, const struct hl_gbuffer *gb,
				      const struct hl_headlight_lamp *lamps, float *lux)
{
	const float *dense[2] = { r->dense[0], r->dense[1] };
	double t_cpu, t_gl, t0;

	if (hl_headlight_new(gb, r->n_lamps, lamps, &r->cpu_light) < 0)
		return HL_BACKEND_CPU;
	if (hl_gl_headlight_new(gb, r->n_lamps, lamps, HL_GL_HEADLIGHT_PRECOMPUTED, &r->gl_light,
				NULL, 0) < 0)
		return HL_BACKEND_CPU;
	for (int k = 0; k < r->n_lamps; k++)
		hl_gl_headlight_upload(r->gl_light, k, r->dense[k]);
	hl_gl_headlight_run(r->gl_light);
	glFinish();
	t0 = now_ms();
	hl_gl_headlight_run(r->gl_light);
	hl_gl_headlight_read(r->gl_light, lux);
	t_gl = now_ms() - t0;
	t0 = now_ms();
	hl_headlight_run(r->cpu_light, dense, lux);
	t_cpu = now_ms() - t0;
	return t_gl < t_cpu ? HL_BACKEND_GLES : HL_BACKEND_CPU;
}

/*
 * Ready for new G-buffers: the copy of the geometry to compare against (gb's, or none: the
 * next frame then recomputes every pixel) and the CPU pass's moving layout.
 */
static int make_moving(struct hl_renderer *r, const struct hl_gbuffer *gb)
{
	int rc = hl_gbuffer_diff_new(r->width, r->height, gb, &r->diff);

	if (rc < 0)
		return rc;
	r->diff_all = !gb;
	return r->cpu_light ? hl_headlight_make_moving(r->cpu_light) : 0;
}

int hl_renderer_new(const struct hl_renderer_config *cfg, const struct hl_gbuffer *gb,
		    struct hl_renderer **ret)
{
	struct hl_headlight_lamp lamps[2];
	struct hl_renderer *r;
	int rc = 0;

	if (cfg->n_lamps < 1 || cfg->n_lamps > 2)
		return -EINVAL;
	r = calloc(1, sizeof(*r));
	if (!r)
		return -ENOMEM;
	r->n_lamps = cfg->n_lamps;
	r->width = gb->width;
	r->height = gb->height;
	r->lit_gb = gb;
	r->combine = cfg->combine;
	r->headlight = cfg->headlight;
	if (!cfg->egl || hl_egl_software(cfg->egl)) {
		r->combine = r->combine == HL_BACKEND_AUTO ? HL_BACKEND_CPU : r->combine;
		r->headlight = r->headlight == HL_BACKEND_AUTO ? HL_BACKEND_CPU : r->headlight;
	}
	rc = hl_workers_new(cfg->threads > 0 ? cfg->threads : 1, &r->workers);
	if (rc < 0)
		goto err_free;
	if ((r->combine == HL_BACKEND_GLES || r->headlight == HL_BACKEND_GLES) && !cfg->egl) {
		rc = -ENODEV;
		goto err_free;
	}
	for (int k = 0; k < r->n_lamps; k++) {
		const struct hl_lid *lid = cfg->lids[k];
		const struct hl_lid_grid *g = hl_lid_grid(lid);

		r->lids[k] = lid;
		lamps[k] = (struct hl_headlight_lamp){ cfg->poses[k], *g };
		r->dense[k] = calloc((size_t)g->width * g->height, sizeof(float));
		if (!r->dense[k]) {
			rc = -ENOMEM;
			goto err_free;
		}
		r->dirty[k] = true;
		if (hl_lid_is_combined(lid)) {
			hl_lid_source_dense(lid, 0, r->dense[k]);
			continue;
		}
		if (r->combine == HL_BACKEND_AUTO)
			r->combine = pick_combine(lid);
		if (r->combine == HL_BACKEND_GLES)
			rc = hl_gl_combiner_new(lid, HL_GL_COMBINE_BOXES, 0, &r->gl_comb[k], NULL,
						0);
		else
			rc = hl_combiner_new(lid, 0, &r->cpu_comb[k]);
		if (rc < 0)
			goto err_free;
	}
	if (r->combine == HL_BACKEND_AUTO) /* only combined distributions: nothing to combine */
		r->combine = HL_BACKEND_CPU;
	if (r->headlight == HL_BACKEND_AUTO) {
		float *lux = malloc(sizeof(float) * (size_t)gb->width * gb->height);

		if (!lux) {
			rc = -ENOMEM;
			goto err_free;
		}
		r->headlight = pick_headlight(r, gb, lamps, lux);
		free(lux);
		/* Keep the winner only. */
		if (r->headlight == HL_BACKEND_GLES) {
			hl_headlight_free(r->cpu_light);
			r->cpu_light = NULL;
		} else {
			hl_gl_headlight_free(r->gl_light);
			r->gl_light = NULL;
		}
	}
	if (r->headlight == HL_BACKEND_GLES && !r->gl_light)
		rc = hl_gl_headlight_new(gb, r->n_lamps, lamps, HL_GL_HEADLIGHT_PRECOMPUTED,
					 &r->gl_light, NULL, 0);
	else if (r->headlight == HL_BACKEND_CPU && !r->cpu_light)
		rc = hl_headlight_new(gb, r->n_lamps, lamps, &r->cpu_light);
	if (rc < 0)
		goto err_free;
	for (int k = 0; r->gl_light && k < r->n_lamps; k++)
		r->dirty[k] = true;
	if (cfg->moving) {
		/* fill_only: no copy, so the first frame relights every pixel (diff_all) */
		rc = make_moving(r, cfg->fill_only ? NULL : gb);
		if (rc < 0)
			goto err_free;
	}
	*ret = r;
	return 0;

err_free:
	hl_renderer_free(r);
	return rc;
}

void hl_renderer_free(struct hl_renderer *r)
{
	if (!r)
		return;
	for (int k = 0; k < 2; k++) {
		hl_combiner_free(r->cpu_comb[k]);
		hl_gl_combiner_free(r->gl_comb[k]);
		free(r->dense[k]);
	}
	hl_headlight_free(r->cpu_light);
	hl_gl_headlight_free(r->gl_light);
	hl_workers_free(r->workers);
	hl_gbuffer_diff_free(r->diff);
	free(r->fill_changed);
	free(r);
}

enum hl_backend hl_renderer_combine_backend(const struct hl_renderer *r)
{
	return r->combine;
}

enum hl_backend hl_renderer_headlight_backend(const struct hl_renderer *r)
{
	return r->headlight;
}

int hl_renderer_set_currents(struct hl_renderer *r, int k, const float *i)
{
	int changed;

	if (k < 0 || k >= r->n_lamps)
		return -EINVAL;
	if (hl_lid_is_combined(r->lids[k]))
		return 0;
	if (r->gl_comb[k]) {
		changed = hl_gl_combiner_update(r->gl_comb[k], i);
		r->dense_stale[k] |= changed > 0;
	} else {
		changed = hl_combiner_update(r->cpu_comb[k], i);
	}
	if (changed > 0)
		r->dirty[k] = true;
	return changed;
}

/* What both ways of handing over a new G-buffer check and make room for. */
static int take_gbuffer(struct hl_renderer *r, const struct hl_gbuffer *gb)
{
	if (!gb || gb->width != r->width || gb->height != r->height)
		return -EINVAL;
	if (!r->diff) {
		const int rc = make_moving(r, NULL);

		if (rc < 0) {
			hl_gbuffer_diff_free(r->diff);
			r->diff = NULL;
			return rc;
		}
	}
	r->next_gb = gb;
	r->fill = NULL;
	return 0;
}

int hl_renderer_set_gbuffer(struct hl_renderer *r, const struct hl_gbuffer *gb)
{
	const int rc = take_gbuffer(r, gb);

	if (rc < 0)
		return rc;
	if (r->diff_stale) { /* the copy missed the fills' frames: compare nothing with it */
		r->diff_all = true;
		r->diff_stale = false;
	}
	return 0;
}

int hl_renderer_set_gbuffer_fill(struct hl_renderer *r, struct hl_gbuffer *gb,
				 hl_renderer_fill_fn fill, void *userdata)
{
	const int rc = fill ? take_gbuffer(r, gb) : -EINVAL;

	if (rc < 0)
		return rc;
	if (!r->fill_changed) {
		r->fill_changed = malloc((size_t)r->width * r->height);
		if (!r->fill_changed) {
			r->next_gb = NULL;
			return -ENOMEM;
		}
	}
	/* the fill compares with what gb holds: the frame lit last, unless gb is another one */
	r->fill_all = r->diff_all || gb != r->lit_gb;
	r->fill_gb = gb;
	r->fill = fill;
	r->fill_userdata = userdata;
	return 0;
}

/*
 * Band first .. + count - 1 of a frame's new G-buffer filled, with its changed flags; false
 * when the frame has no fill (then diff compares).
 */
static bool fill_band(const struct hl_renderer *r, size_t first, size_t count)
{
	if (!r->fill)
		return false;
	r->fill(r->fill_userdata, r->fill_gb, first, count, r->fill_changed);
	if (r->fill_all)
		memset(r->fill_changed + first, 1, count);
	return true;
}

/* The CPU copy of lamp k's distribution, read back from GL when it changed there. */
static const float *cpu_dense(struct hl_renderer *r, int k)
{
	if (r->cpu_comb[k])
		return hl_combiner_result(r->cpu_comb[k]);
	if (r->gl_comb[k] && r->dense_stale[k]) {
		if (hl_gl_combiner_read(r->gl_comb[k], r->dense[k]) < 0)
			return NULL;
		r->dense_stale[k] = false;
	}
	return r->dense[k];
}

struct frame_job {
	struct hl_renderer *r;
	const float *dense[2];
	float *lux;
	hl_renderer_pixels_fn pixels;
	void *userdata;
	const struct hl_gbuffer *gb; /* a new G-buffer to take first, or NULL */
};

/* CPU, a new G-buffer: the terms of band c's pixels whose geometry changed. */
static void update_band(const struct frame_job *j, size_t c)
{
	struct hl_renderer *r = j->r;
	size_t first, count;

	hl_headlight_chunk_pixels(r->cpu_light, c, &first, &count);
	if (fill_band(r, first, count)) {
		if (memchr(r->fill_changed + first, 1, count))
			hl_headlight_update_chunk(r->cpu_light, j->gb, c, r->fill_changed);
		return;
	}
	if (hl_gbuffer_diff_band(r->diff, j->gb, first, count, r->diff_all) > 0)
		hl_headlight_update_chunk(r->cpu_light, j->gb, c, hl_gbuffer_diff_flags(r->diff));
}

static void light_band(void *arg, size_t c)
{
	const struct frame_job *j = arg;

	if (j->gb)
		update_band(j, c);
	hl_headlight_run_chunk(j->r->cpu_light, j->dense, c, j->lux);
}

static void light_band_lit(void *arg, size_t c)
{
	const struct frame_job *j = arg;

	if (j->gb)
		update_band(j, c);
	hl_headlight_run_chunk_lit(j->r->cpu_light, j->dense, c, j->lux, j->pixels, j->userdata);
}

static void view_band(void *arg, size_t c)
{
	const struct frame_job *j = arg;
	const size_t n = (size_t)j->r->width * j->r->height, first = c * GLES_BAND_PIXELS;

	j->pixels(j->userdata, j->lux, first,
		  n - first < GLES_BAND_PIXELS ? n - first : GLES_BAND_PIXELS);
}

/* GLES, a new G-buffer: which pixels of band c changed. */
static void diff_band(void *arg, size_t c)
{
	const struct frame_job *j = arg;
	const size_t n = (size_t)j->r->width * j->r->height, first = c * GLES_BAND_PIXELS;
	const size_t count = n - first < GLES_BAND_PIXELS ? n - first : GLES_BAND_PIXELS;

	if (!fill_band(j->r, first, count))
		hl_gbuffer_diff_band(j->r->diff, j->gb, first, count, j->r->diff_all);
}

/* GLES, a new G-buffer: each run of rows with a changed pixel uploaded again. */
static int update_gl(struct hl_renderer *r, struct frame_job *j)
{
	const size_t n = (size_t)r->width * r->height;
	const uint8_t *changed;
	int y0 = -1;

	hl_workers_run(r->workers, (n + GLES_BAND_PIXELS - 1) / GLES_BAND_PIXELS, diff_band, j);
	changed = r->fill ? r->fill_changed : hl_gbuffer_diff_flags(r->diff);
	for (int y = 0; y <= r->height; y++) {
		const bool row = y < r->height &&
				 memchr(changed + (size_t)y * r->width, 1, r->width) != NULL;

		if (row && y0 < 0)
			y0 = y;
		if (!row && y0 >= 0) {
			if (hl_gl_headlight_update_rows(r->gl_light, j->gb, y0, y - y0) < 0)
				return -EIO;
			y0 = -1;
		}
	}
	return 0;
}

/* A frame has lit its new G-buffer. */
static void took_gbuffer(struct hl_renderer *r)
{
	r->lit_gb = r->next_gb;
	r->diff_stale |= r->fill != NULL; /* the fill compared, not diff: its copy is old */
	r->next_gb = NULL;
	r->fill = NULL;
	r->diff_all = false;
}

int hl_renderer_frame_pixels(struct hl_renderer *r, float *ret_lux, hl_renderer_pixels_fn pixels,
			     void *userdata)
{
	struct frame_job j = {
		.r = r, .lux = ret_lux, .pixels = pixels, .userdata = userdata, .gb = r->next_gb
	};
	const size_t n = (size_t)r->width * r->height;
	int rc;

	if (r->cpu_light) {
		for (int k = 0; k < r->n_lamps; k++) {
			j.dense[k] = cpu_dense(r, k);
			if (!j.dense[k])
				return -EIO;
		}
		hl_workers_run(r->workers, hl_headlight_chunks(r->cpu_light),
			       pixels ? light_band_lit : light_band, &j);
		if (j.gb)
			took_gbuffer(r);
		return 0;
	}
	if (j.gb) {
		rc = update_gl(r, &j);
		if (rc < 0) {
			r->fill = NULL;
			r->diff_all = true; /* some rows may be missing: all again next time */
			return rc;
		}
		took_gbuffer(r);
	}
	for (int k = 0; k < r->n_lamps; k++) {
		if (r->gl_comb[k]) {
			hl_gl_headlight_use_texture(r->gl_light, k,
						    hl_gl_combiner_texture(r->gl_comb[k]));
		} else if (r->dirty[k]) {
			const float *d = r->cpu_comb[k] ? hl_combiner_result(r->cpu_comb[k]) :
							  r->dense[k];

			if (hl_gl_headlight_upload(r->gl_light, k, d) < 0)
				return -EIO;
		}
		r->dirty[k] = false;
	}
	hl_gl_headlight_run(r->gl_light);
	rc = hl_gl_headlight_read(r->gl_light, ret_lux);
	if (rc == 0 && pixels)
		hl_workers_run(r->workers, (n + GLES_BAND_PIXELS - 1) / GLES_BAND_PIXELS, view_band,
			       &j);
	return rc;
}

int hl_renderer_frame(struct hl_renderer *r, float *ret_lux)
{
	return hl_renderer_frame_pixels(r, ret_lux, NULL, NULL);
}

const float *hl_renderer_distribution(struct hl_renderer *r, int k)
{
	return cpu_dense(r, k);
}

const struct hl_lid_grid *hl_renderer_grid(const struct hl_renderer *r, int k)
{
	return hl_lid_grid(r->lids[k]);
}
