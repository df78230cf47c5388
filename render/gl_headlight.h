/* SPDX-License-Identifier: MIT */
/*
 * The headlight pass in GLES: the G-buffer as two RGBA32F textures, one fragment per pixel,
 * into an R32F illuminance target (shaders/headlight.frag.glsl).
 *   DIRECT       every frame computes lamp space, type A/B angles, the bilinear lookup and
 *                E = I cos(eps) / r^2 for each lamp: the straight deferred pass of the papers,
 *                and an independent check of the CPU path (render/headlight.h)
 *   PRECOMPUTED  lamp poses are fixed and the G-buffer changes seldom: a first pass writes
 *                each lamp's sample coordinates and cos(eps) / r^2 per pixel into an RGBA32F
 *                texture once; a frame is then only the lookups and the sum
 * In a moving scene the rows of the G-buffer that changed are uploaded again (and their terms
 * redrawn, scissored to those rows): hl_gl_headlight_update_rows().
 *
 * Thread-safety: the thread that owns the current GL context.
 */
#ifndef HL_RENDER_GL_HEADLIGHT_H
#define HL_RENDER_GL_HEADLIGHT_H

#include <GLES3/gl31.h>

#include "render/headlight.h"

struct hl_gl_headlight;

enum hl_gl_headlight_mode {
	HL_GL_HEADLIGHT_DIRECT,
	HL_GL_HEADLIGHT_PRECOMPUTED,
};

/* Uploads the G-buffer. 0, -EINVAL, -ENOTSUP (no float targets), -ENOMEM, -EIO. */
int hl_gl_headlight_new(const struct hl_gbuffer *gb, int n_lamps,
			const struct hl_headlight_lamp *lamps, enum hl_gl_headlight_mode mode,
			struct hl_gl_headlight **ret, char *log, size_t log_size);
void hl_gl_headlight_free(struct hl_gl_headlight *h);

/* Lamp k reads its distribution from tex (R32F, grid layout), e.g. a GL combiner's target. */
void hl_gl_headlight_use_texture(struct hl_gl_headlight *h, int k, GLuint tex);
/* Lamp k reads dense (grid layout, cd), uploaded into the object's own texture. 0 or -EIO. */
int hl_gl_headlight_upload(struct hl_gl_headlight *h, int k, const float *dense);
/*
 * Rows y0 .. y0 + n_rows - 1 of the G-buffer changed: uploads them from gb (the size given to
 * _new) into the G-buffer textures with glTexSubImage2D and, PRECOMPUTED, redraws the terms of
 * those rows. 0, -EINVAL (another size, rows outside the image), -EIO.
 */
int hl_gl_headlight_update_rows(struct hl_gl_headlight *h, const struct hl_gbuffer *gb, int y0,
				int n_rows);
/* Draws the pass. */
void hl_gl_headlight_run(struct hl_gl_headlight *h);
/* Reads the illuminance (width * height floats, lux, row 0 at the top). 0 or -EIO. */
int hl_gl_headlight_read(struct hl_gl_headlight *h, float *ret_lux);

#endif
