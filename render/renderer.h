/* SPDX-License-Identifier: MIT */
/*
 * The render path of one scene view: per lamp the combiner (L = sum_k i_k L_k, 32-bit), then
 * the headlight pass over a static G-buffer, giving illuminance per pixel. Each stage runs on
 * the CPU or in GLES; HL_BACKEND_AUTO times both when the renderer is made (a few updates of
 * the combiner, one headlight frame) and keeps the faster on this machine.
 *
 * Thread-safety: one thread (the render thread, which owns the EGL context when GLES is used).
 */
#ifndef HL_RENDER_RENDERER_H
#define HL_RENDER_RENDERER_H

#include <stdbool.h>

#include "render/camera.h"
#include "render/egl.h"
#include "render/lid.h"
#include "render/scene.h"

enum hl_backend {
	HL_BACKEND_AUTO,
	HL_BACKEND_CPU,
	HL_BACKEND_GLES,
};

struct hl_renderer_config {
	int n_lamps; /* 1 (left only) or 2 */
	const struct hl_lid *lids[2]; /* source files or combined distributions; must outlive */
	struct hl_lamp_pose poses[2];
	enum hl_backend combine; /* AUTO: measured */
	enum hl_backend headlight; /* AUTO: measured */
	struct hl_egl *egl; /* needed for GLES stages; NULL for CPU only */
};

struct hl_renderer;

/* "auto", "cpu", "gles" to a backend; -EINVAL otherwise. */
int hl_backend_from_name(const char *name);
const char *hl_backend_name(enum hl_backend b);

/*
 * Builds both stages for gb (precomputing the per-pixel lamp terms; GL objects when GLES).
 * 0, -EINVAL, -ENOMEM, -ENODEV (a GLES stage without egl), -ENOTSUP (the context lacks float
 * render targets or float blending), -EIO (a GL failure).
 */
int hl_renderer_new(const struct hl_renderer_config *cfg, const struct hl_gbuffer *gb,
		    struct hl_renderer **ret);
void hl_renderer_free(struct hl_renderer *r);

/* The stages in use (never AUTO). */
enum hl_backend hl_renderer_combine_backend(const struct hl_renderer *r);
enum hl_backend hl_renderer_headlight_backend(const struct hl_renderer *r);

/*
 * Relative currents of lamp k (n_sources values in [0, 1]; ignored for a combined lid).
 * Returns how many changed, or -EINVAL.
 */
int hl_renderer_set_currents(struct hl_renderer *r, int k, const float *i);

/* One frame: combines what changed and lights the G-buffer into ret_lux (w * h floats). */
int hl_renderer_frame(struct hl_renderer *r, float *ret_lux);

/* The current combined distribution of lamp k (grid layout, cd), valid until the next frame. */
const float *hl_renderer_distribution(struct hl_renderer *r, int k);
const struct hl_lid_grid *hl_renderer_grid(const struct hl_renderer *r, int k);

#endif
