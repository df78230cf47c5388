/* SPDX-License-Identifier: MIT */
#include "render/renderer.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "render/combine.h"
#include "render/gl_combine.h"
#include "render/gl_headlight.h"
#include "render/headlight.h"

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

/*
 * Measured on the project's 2-core llvmpipe machines (DESIGN.md §7, README "Rendering"): the
 * CPU combine (sparse, incremental) beats GLES box quads by an order of magnitude, and the
 * precomputed CPU headlight pass beats the llvmpipe shader. A real GPU turns both around.
 */
static enum hl_backend pick(enum hl_backend want, const struct hl_egl *egl)
{
	if (want != HL_BACKEND_AUTO)
		return want;
	if (egl && strcmp(hl_egl_platform(egl), "device") == 0)
		return HL_BACKEND_GLES;
	return HL_BACKEND_CPU;
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
	r->combine = pick(cfg->combine, cfg->egl);
	r->headlight = pick(cfg->headlight, cfg->egl);
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
		if (r->combine == HL_BACKEND_GLES)
			rc = hl_gl_combiner_new(lid, HL_GL_COMBINE_BOXES, 0, &r->gl_comb[k], NULL,
						0);
		else
			rc = hl_combiner_new(lid, 0, &r->cpu_comb[k]);
		if (rc < 0)
			goto err_free;
	}
	if (r->headlight == HL_BACKEND_GLES)
		rc = hl_gl_headlight_new(gb, r->n_lamps, lamps, &r->gl_light, NULL, 0);
	else
		rc = hl_headlight_new(gb, r->n_lamps, lamps, &r->cpu_light);
	if (rc < 0)
		goto err_free;
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

int hl_renderer_frame(struct hl_renderer *r, float *ret_lux)
{
	if (r->cpu_light) {
		const float *dense[2] = { NULL, NULL };

		for (int k = 0; k < r->n_lamps; k++) {
			dense[k] = cpu_dense(r, k);
			if (!dense[k])
				return -EIO;
		}
		hl_headlight_run(r->cpu_light, dense, ret_lux);
		return 0;
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
	return hl_gl_headlight_read(r->gl_light, ret_lux);
}

const float *hl_renderer_distribution(struct hl_renderer *r, int k)
{
	return cpu_dense(r, k);
}

const struct hl_lid_grid *hl_renderer_grid(const struct hl_renderer *r, int k)
{
	return hl_lid_grid(r->lids[k]);
}
