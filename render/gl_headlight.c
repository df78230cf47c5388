/* SPDX-License-Identifier: MIT */
#include "render/gl_headlight.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/gl_util.h"
#include "render/shader.h"
#include "render/shaders.h"

struct hl_gl_headlight {
	int width, height, n_lamps;
	enum hl_gl_headlight_mode mode;
	struct hl_headlight_lamp lamps[HL_HEADLIGHT_MAX_LAMPS];
	GLuint program, pos, nrm, target, fbo;
	GLuint terms[HL_HEADLIGHT_MAX_LAMPS]; /* PRECOMPUTED: per lamp (x, y, factor) */
	GLuint terms_fbo[HL_HEADLIGHT_MAX_LAMPS], terms_program; /* PRECOMPUTED: the terms pass */
	GLuint own[HL_HEADLIGHT_MAX_LAMPS]; /* textures for uploaded distributions */
	GLuint lid[HL_HEADLIGHT_MAX_LAMPS]; /* what each lamp reads */
	float *scratch;
};

/* The shader with "#define HL_PASS pass" and the lamp lookup after its #version line. */
static int build(int pass, GLuint *ret, char *log, size_t log_size)
{
	char define[32], *src;
	int rc;

	snprintf(define, sizeof(define), "#define HL_PASS %d", pass);
	src = hl_shader_compose(hl_shader_headlight_frag, define, hl_shader_lamp_lookup);
	if (!src)
		return -ENOMEM;
	rc = hl_shader_build(hl_shader_quad_vert, src, ret, log, log_size);
	free(src);
	return rc;
}

static void set_uniforms(struct hl_gl_headlight *h, GLuint program)
{
	glUseProgram(program);
	glUniform1i(glGetUniformLocation(program, "u_pos"), 0);
	glUniform1i(glGetUniformLocation(program, "u_nrm"), 1);
	glUniform1i(glGetUniformLocation(program, "u_lid0"), 2);
	glUniform1i(glGetUniformLocation(program, "u_lid1"), 3);
	glUniform1i(glGetUniformLocation(program, "u_terms0"), 4);
	glUniform1i(glGetUniformLocation(program, "u_terms1"), 5);
	hl_gl_lamp_uniforms(program, h->n_lamps, h->lamps);
}

/* PRECOMPUTED: the terms of rows y0 .. y0 + n_rows - 1, each lamp into its RGBA32F texture. */
static void draw_terms(struct hl_gl_headlight *h, int y0, int n_rows)
{
	glDisable(GL_BLEND);
	glUseProgram(h->terms_program);
	glActiveTexture(GL_TEXTURE0);
	glBindTexture(GL_TEXTURE_2D, h->pos);
	glActiveTexture(GL_TEXTURE1);
	glBindTexture(GL_TEXTURE_2D, h->nrm);
	glActiveTexture(GL_TEXTURE0);
	glEnable(GL_SCISSOR_TEST);
	glScissor(0, y0, h->width, n_rows);
	for (int k = 0; k < h->n_lamps; k++) {
		glBindFramebuffer(GL_FRAMEBUFFER, h->terms_fbo[k]);
		glViewport(0, 0, h->width, h->height);
		glUniform1i(glGetUniformLocation(h->terms_program, "u_k"), k);
		glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
	}
	glDisable(GL_SCISSOR_TEST);
	glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

/*
 * PRECOMPUTED: the terms pass, its program and a target per lamp, kept for a moving scene's
 * changed rows (hl_gl_headlight_update_rows), then drawn over the whole G-buffer.
 */
static int make_terms(struct hl_gl_headlight *h, char *log, size_t log_size)
{
	int rc = build(1, &h->terms_program, log, log_size);

	if (rc < 0)
		return rc;
	set_uniforms(h, h->terms_program);
	for (int k = 0; k < h->n_lamps && rc == 0; k++) {
		/* Made before the G-buffer is bound: making a texture binds it to the active unit. */
		h->terms[k] = hl_gl_texture_float(h->width, h->height, true, NULL);
		h->terms_fbo[k] = h->terms[k] ? hl_gl_framebuffer(h->terms[k]) : 0;
		if (!h->terms_fbo[k])
			rc = -EIO;
	}
	if (rc == 0) {
		draw_terms(h, 0, h->height);
		if (glGetError() != GL_NO_ERROR)
			rc = -EIO;
	}
	if (rc < 0 && log && log_size)
		snprintf(log, log_size, "cannot make the RGBA32F terms textures");
	return rc;
}

int hl_gl_headlight_new(const struct hl_gbuffer *gb, int n_lamps,
			const struct hl_headlight_lamp *lamps, enum hl_gl_headlight_mode mode,
			struct hl_gl_headlight **ret, char *log, size_t log_size)
{
	struct hl_gl_headlight *h;
	int rc;

	if (n_lamps < 1 || n_lamps > HL_HEADLIGHT_MAX_LAMPS)
		return -EINVAL;
	for (int k = 0; k < n_lamps; k++)
		if (hl_lid_grid_check(&lamps[k].grid) < 0)
			return -EINVAL;
	h = calloc(1, sizeof(*h));
	if (!h)
		return -ENOMEM;
	h->width = gb->width;
	h->height = gb->height;
	h->n_lamps = n_lamps;
	h->mode = mode;
	memcpy(h->lamps, lamps, sizeof(*lamps) * n_lamps);
	h->scratch = malloc(sizeof(float) * 4 * (size_t)gb->width * gb->height);
	if (!h->scratch) {
		rc = -ENOMEM;
		goto err_free;
	}
	rc = build(mode == HL_GL_HEADLIGHT_PRECOMPUTED ? 2 : 0, &h->program, log, log_size);
	if (rc < 0)
		goto err_free;
	h->pos = hl_gl_texture_float(gb->width, gb->height, true, gb->pos);
	h->nrm = hl_gl_texture_float(gb->width, gb->height, true, gb->nrm);
	h->target = hl_gl_texture_float(gb->width, gb->height, false, NULL);
	for (int k = 0; k < n_lamps; k++) {
		h->own[k] =
			hl_gl_texture_float(lamps[k].grid.width, lamps[k].grid.height, false, NULL);
		h->lid[k] = h->own[k];
	}
	h->fbo = h->pos && h->nrm && h->target ? hl_gl_framebuffer(h->target) : 0;
	if (!h->fbo || !h->own[0] || (n_lamps > 1 && !h->own[1])) {
		if (log && log_size)
			snprintf(log, log_size, "cannot make the G-buffer textures or R32F target");
		rc = -EIO;
		goto err_free;
	}
	if (mode == HL_GL_HEADLIGHT_PRECOMPUTED) {
		rc = make_terms(h, log, log_size);
		if (rc < 0)
			goto err_free;
	}
	set_uniforms(h, h->program);
	*ret = h;
	return 0;

err_free:
	hl_gl_headlight_free(h);
	return rc;
}

void hl_gl_headlight_free(struct hl_gl_headlight *h)
{
	GLuint tex[] = { 0, 0, 0, 0, 0, 0, 0 };

	if (!h)
		return;
	tex[0] = h->pos;
	tex[1] = h->nrm;
	tex[2] = h->target;
	tex[3] = h->own[0];
	tex[4] = h->own[1];
	tex[5] = h->terms[0];
	tex[6] = h->terms[1];
	for (size_t i = 0; i < sizeof(tex) / sizeof(tex[0]); i++)
		if (tex[i])
			glDeleteTextures(1, &tex[i]);
	if (h->fbo)
		glDeleteFramebuffers(1, &h->fbo);
	for (int k = 0; k < HL_HEADLIGHT_MAX_LAMPS; k++)
		if (h->terms_fbo[k])
			glDeleteFramebuffers(1, &h->terms_fbo[k]);
	if (h->program)
		glDeleteProgram(h->program);
	if (h->terms_program)
		glDeleteProgram(h->terms_program);
	free(h->scratch);
	free(h);
}

void hl_gl_headlight_use_texture(struct hl_gl_headlight *h, int k, GLuint tex)
{
	h->lid[k] = tex;
}

int hl_gl_headlight_upload(struct hl_gl_headlight *h, int k, const float *dense)
{
	const struct hl_lid_grid *g = &h->lamps[k].grid;

	h->lid[k] = h->own[k];
	glBindTexture(GL_TEXTURE_2D, h->own[k]);
	glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
	glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, g->width, g->height, GL_RED, GL_FLOAT, dense);
	return glGetError() == GL_NO_ERROR ? 0 : -EIO;
}

int hl_gl_headlight_update_rows(struct hl_gl_headlight *h, const struct hl_gbuffer *gb, int y0,
				int n_rows)
{
	const size_t first = (size_t)y0 * h->width;

	if (gb->width != h->width || gb->height != h->height || y0 < 0 || n_rows < 0 ||
	    y0 + n_rows > h->height)
		return -EINVAL;
	if (n_rows == 0)
		return 0;
	glActiveTexture(GL_TEXTURE0);
	glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
	glBindTexture(GL_TEXTURE_2D, h->pos);
	glTexSubImage2D(GL_TEXTURE_2D, 0, 0, y0, h->width, n_rows, GL_RGBA, GL_FLOAT,
			gb->pos + 4 * first);
	glBindTexture(GL_TEXTURE_2D, h->nrm);
	glTexSubImage2D(GL_TEXTURE_2D, 0, 0, y0, h->width, n_rows, GL_RGBA, GL_FLOAT,
			gb->nrm + 4 * first);
	if (h->mode == HL_GL_HEADLIGHT_PRECOMPUTED)
		draw_terms(h, y0, n_rows);
	return glGetError() == GL_NO_ERROR ? 0 : -EIO;
}

void hl_gl_headlight_run(struct hl_gl_headlight *h)
{
	glBindFramebuffer(GL_FRAMEBUFFER, h->fbo);
	glViewport(0, 0, h->width, h->height);
	glDisable(GL_BLEND);
	glUseProgram(h->program);
	glActiveTexture(GL_TEXTURE0);
	glBindTexture(GL_TEXTURE_2D, h->pos);
	glActiveTexture(GL_TEXTURE1);
	glBindTexture(GL_TEXTURE_2D, h->nrm);
	glActiveTexture(GL_TEXTURE2);
	glBindTexture(GL_TEXTURE_2D, h->lid[0]);
	glActiveTexture(GL_TEXTURE3);
	glBindTexture(GL_TEXTURE_2D, h->n_lamps > 1 ? h->lid[1] : h->lid[0]);
	if (h->mode == HL_GL_HEADLIGHT_PRECOMPUTED) {
		glActiveTexture(GL_TEXTURE4);
		glBindTexture(GL_TEXTURE_2D, h->terms[0]);
		glActiveTexture(GL_TEXTURE5);
		glBindTexture(GL_TEXTURE_2D, h->n_lamps > 1 ? h->terms[1] : h->terms[0]);
	}
	glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
	glActiveTexture(GL_TEXTURE0);
}

int hl_gl_headlight_read(struct hl_gl_headlight *h, float *ret_lux)
{
	glBindFramebuffer(GL_FRAMEBUFFER, h->fbo);
	return hl_gl_read_red_float(h->width, h->height, ret_lux, h->scratch);
}
