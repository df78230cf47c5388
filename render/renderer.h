/* SPDX-License-Identifier: MIT */
/*
 * The render path of one scene view: per lamp the combiner (L = sum_k i_k L_k, 32-bit), then
 * the headlight pass over the scene's G-buffer, giving illuminance per pixel. Each stage runs on
 * the CPU or in GLES; HL_BACKEND_AUTO times both when the renderer is made (a few updates of
 * the combiner, one headlight frame) and keeps the faster on this machine. On a software
 * rasteriser (llvmpipe: GLES runs on the same cores) AUTO is the CPU without timing: there the
 * GLES stages are 7-60x slower (tools/bench), and building them only to time them would double
 * the daemon's memory at start-up.
 *
 * The CPU headlight pass and the per-pixel views after it are split into bands of pixels that
 * the renderer's threads (config threads: the calling thread and threads - 1 helpers) take in
 * turn.
 *
 * A still scene keeps the G-buffer given to hl_renderer_new(): its per-pixel lamp terms are
 * computed once. A moving scene hands the renderer a new G-buffer before a frame
 * (hl_renderer_set_gbuffer); the frame then recomputes what depends on the geometry only for
 * the pixels whose position, normal or hit/miss changed (render/gbuffer_diff.h): on the CPU
 * the lamp terms of those pixels, band by band on the renderer's threads; in GLES the rows
 * holding them are uploaded again and their terms redrawn. Albedo and surface ids are not the
 * pass's business: the views read them from the caller's G-buffer.
 *
 * Thread-safety: one thread (the render thread, which owns the EGL context when GLES is used);
 * a frame's pixels callback runs on that thread and on the helpers at once.
 */
#ifndef HL_RENDER_RENDERER_H
#define HL_RENDER_RENDERER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "world/camera.h"
#include "render/egl.h"
#include "lamp/lid.h"
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
	int threads; /* threads lighting a frame, the caller included; 0 = 1 */
	/*
	 * The G-buffer will change (hl_renderer_set_gbuffer): make room for it now, with the
	 * G-buffer given to hl_renderer_new() as the one the first new G-buffer is compared
	 * against. Costs 33 bytes per pixel, and on the CPU the terms of every pixel
	 * (n_lamps x 12 bytes) instead of those of lit pixels.
	 */
	bool moving;
	/*
	 * With moving: new G-buffers come only through hl_renderer_set_gbuffer_fill(), which says
	 * itself what changed, so no comparison copy is filled (32 bytes a pixel less in memory:
	 * 29 MB at 1280 x 720). The first frame recomputes every pixel; a plain
	 * hl_renderer_set_gbuffer() still works (its first frame, too, recomputes every pixel).
	 */
	bool fill_only;
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

/*
 * The next frame lights gb (the size given to hl_renderer_new(): -EINVAL otherwise), which
 * must stay valid and unchanged until that frame has returned; gb may be the same object as
 * before with new contents. Without config moving the first call makes room for moving scenes
 * (allocates, -ENOMEM) and its frame recomputes every pixel; after that, and with moving,
 * neither this nor a frame allocates, and a frame recomputes only the pixels that changed.
 * A frame without a call before it lights the G-buffer it lit last, at the cost of a still
 * scene. 0, -EINVAL, -ENOMEM.
 */
int hl_renderer_set_gbuffer(struct hl_renderer *r, const struct hl_gbuffer *gb);

/*
 * Writes pixels first .. first + count - 1 of gb (row-major), as a ray cast of the moving
 * scene does (render/world_scene.h), and sets changed[i] of each of them: 1 when the pixel's
 * position, normal or hit/miss differ from what gb held there before (the rule of
 * render/gbuffer_diff.h, bit for bit), else 0. Runs on the renderer's threads, several disjoint
 * ranges at once.
 */
typedef void (*hl_renderer_fill_fn)(void *userdata, struct hl_gbuffer *gb, size_t first,
				    size_t count, uint8_t *changed);
/*
 * As hl_renderer_set_gbuffer(), but the next frame fills gb itself, band by band, just before
 * it lights each band (fill with userdata): the ray cast runs on all of the renderer's threads,
 * the fill says which pixels changed (no comparison with a copy) and each band is lit while it
 * is still in the cache. When gb is not the G-buffer the renderer lit last (or nothing is known
 * yet) every pixel counts as changed. Every pixel is filled exactly once per frame. 0,
 * -EINVAL, -ENOMEM.
 */
int hl_renderer_set_gbuffer_fill(struct hl_renderer *r, struct hl_gbuffer *gb,
				 hl_renderer_fill_fn fill, void *userdata);

/* One frame: combines what changed and lights the G-buffer into ret_lux (w * h floats). */
int hl_renderer_frame(struct hl_renderer *r, float *ret_lux);

/*
 * Called once the illuminance of pixels first .. first + count - 1 is final, for every pixel
 * once per frame, from any of the renderer's threads, bands in no particular order; writes
 * only what those pixels own.
 */
typedef void (*hl_renderer_pixels_fn)(void *userdata, const float *lux, size_t first, size_t count);

/*
 * hl_renderer_frame(), and pixels() over each run of pixels while it is still in the cache. On
 * the CPU only the pixels some lamp can reach are written and passed to pixels(): the others
 * must be zero in ret_lux, and whatever pixels() fills must hold their value already (buffers
 * zeroed once and only ever used for this). In a moving scene "can reach" means: in this
 * frame's G-buffer or in any G-buffer lit since hl_renderer_new() (a pixel that goes dark is
 * written as zero, and passed, in every later frame), so that any number of buffers stay
 * right. GLES writes and passes every pixel.
 */
int hl_renderer_frame_pixels(struct hl_renderer *r, float *ret_lux, hl_renderer_pixels_fn pixels,
			     void *userdata);

/* The current combined distribution of lamp k (grid layout, cd), valid until the next frame. */
const float *hl_renderer_distribution(struct hl_renderer *r, int k);
const struct hl_lid_grid *hl_renderer_grid(const struct hl_renderer *r, int k);

#endif
