/* SPDX-License-Identifier: MIT */
/* Small GL helpers shared by the GLES stages of render/ (current context's thread only). */
#ifndef HL_RENDER_GL_UTIL_H
#define HL_RENDER_GL_UTIL_H

#include <stdbool.h>

#include <GLES3/gl31.h>

#include "render/headlight.h"

/* An R32F (or RGBA32F when rgba) texture, nearest, clamped; data may be NULL. 0 on failure. */
GLuint hl_gl_texture_float(int width, int height, bool rgba, const float *data);
/* A framebuffer with tex as colour attachment 0; 0 when incomplete. */
GLuint hl_gl_framebuffer(GLuint tex);
/*
 * Reads an R32F colour attachment of the bound read framebuffer (width x height) into out.
 * scratch (4 * width * height floats) is used when the driver only offers RGBA. 0 or -EIO.
 */
int hl_gl_read_red_float(int width, int height, float *out, float *scratch);
/*
 * The lamp uniforms of render/shaders/lamp_lookup.glsl in the program in use: u_n_lamps and
 * per lamp its position, vehicle-to-lamp rotation, angle system and grid. (The samplers
 * u_lid0/u_lid1 are the caller's: their texture units differ between programs.)
 */
void hl_gl_lamp_uniforms(GLuint program, int n_lamps, const struct hl_headlight_lamp *lamps);

#endif
