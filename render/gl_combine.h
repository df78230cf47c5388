/* SPDX-License-Identifier: MIT */
/*
 * The combiner in GLES: the lamp's distribution is an R32F texture; each source is an R32F
 * texture over its non-zero box, drawn as one quad over that box with additive blending
 * (EXT_color_buffer_float + EXT_float_blend: 32-bit accumulation, no R16F overflow above
 * 65,504 cd). Updates are incremental, like the CPU reference: only changed sources are drawn,
 * weighted by i_new - i_old, with a full redraw every full_every-th update to bound drift.
 *
 * HL_GL_COMBINE_FULL_IMAGE is the papers' method, kept for the benchmark: every source is a
 * full-grid texture and every update draws all K sources over the whole image.
 *
 * Thread-safety: the thread that owns the current GL context; the lid must outlive the object.
 */
#ifndef HL_RENDER_GL_COMBINE_H
#define HL_RENDER_GL_COMBINE_H

#include <GLES3/gl31.h>

#include "lamp/lid.h"

enum hl_gl_combine_mode {
	HL_GL_COMBINE_BOXES, /* one quad per source over its box, incremental */
	HL_GL_COMBINE_FULL_IMAGE, /* the papers': K full-image additive passes, every update */
};

struct hl_gl_combiner;

/*
 * Uploads the sources. full_every 0 means HL_COMBINE_FULL_EVERY. 0, -ENOTSUP (no float
 * render targets or float blending), -EINVAL (combined lid), -ENOMEM, -EIO (GL error).
 */
int hl_gl_combiner_new(const struct hl_lid *lid, enum hl_gl_combine_mode mode, unsigned full_every,
		       struct hl_gl_combiner **ret, char *log, size_t log_size);
void hl_gl_combiner_free(struct hl_gl_combiner *c);

/* As hl_combiner_update(): the number of changed sources or -EINVAL. Draws; does not wait. */
int hl_gl_combiner_update(struct hl_gl_combiner *c, const float *i);
/* The distribution texture (R32F, grid layout: texel (x, y) is column x, row y). */
GLuint hl_gl_combiner_texture(const struct hl_gl_combiner *c);
/* Reads the distribution into out (width * height floats, cd). Waits for the GPU. 0 or -EIO. */
int hl_gl_combiner_read(struct hl_gl_combiner *c, float *out);

#endif
