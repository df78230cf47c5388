/* SPDX-License-Identifier: MIT */
/*
 * The headlight pass in GLES: the G-buffer as two RGBA32F textures, one fragment per pixel
 * computing lamp space, type A/B angles, the bilinear lookup and E = I cos(eps) / r^2 for
 * each lamp, into an R32F illuminance target. Nothing is precomputed: this is the straight
 * deferred pass of the papers, and an independent check of the CPU path (render/headlight.h).
 *
 * Thread-safety: the thread that owns the current GL context.
 */
#ifndef HL_RENDER_GL_HEADLIGHT_H
#define HL_RENDER_GL_HEADLIGHT_H

#include <GLES3/gl31.h>

#include "render/headlight.h"

struct hl_gl_headlight;

/* Uploads the G-buffer. 0, -EINVAL, -ENOTSUP (no float targets), -ENOMEM, -EIO. */
int hl_gl_headlight_new(const struct hl_gbuffer *gb, int n_lamps,
			const struct hl_headlight_lamp *lamps, struct hl_gl_headlight **ret,
			char *log, size_t log_size);
void hl_gl_headlight_free(struct hl_gl_headlight *h);

/* Lamp k reads its distribution from tex (R32F, grid layout), e.g. a GL combiner's target. */
void hl_gl_headlight_use_texture(struct hl_gl_headlight *h, int k, GLuint tex);
/* Lamp k reads dense (grid layout, cd), uploaded into the object's own texture. 0 or -EIO. */
int hl_gl_headlight_upload(struct hl_gl_headlight *h, int k, const float *dense);
/* Draws the pass. */
void hl_gl_headlight_run(struct hl_gl_headlight *h);
/* Reads the illuminance (width * height floats, lux, row 0 at the top). 0 or -EIO. */
int hl_gl_headlight_read(struct hl_gl_headlight *h, float *ret_lux);

#endif
