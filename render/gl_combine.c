/* SPDX-License-Identifier: MIT */
#include "render/gl_combine.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lamp/combine.h"
#include "render/gl_util.h"
#include "render/shader.h"
#include "render/shaders.h"

struct hl_gl_combiner {
	const struct hl_lid *lid;
	enum hl_gl_combine_mode mode;
	int width, height, n;
	GLuint program, target, fbo;
	GLint u_src, u_origin, u_weight;
	GLuint *src; /* per source: its texture (0 for an empty box) */
	struct hl_lid_box *boxes; /* where each texture goes (the full grid in FULL_IMAGE mode) */
	float *current;
	float *scratch; /* RGBA readback when the driver offers no RED/FLOAT */
	unsigned full_every, since_full;
	bool drawn; /* the target holds a valid sum */
};

static bool has_ext(const char *name)
{
	GLint n = 0;

	glGetIntegerv(GL_NUM_EXTENSIONS, &n);
	for (GLint i = 0; i < n; i++)
		if (strcmp((const char *)glGetStringi(GL_EXTENSIONS, i), name) == 0)
			return true;
	return false;
}

static int upload_sources(struct hl_gl_combiner *c, float *dense)
{
	for (int k = 0; k < c->n; k++) {
		struct hl_lid_box b;
		const float *data = hl_lid_source(c->lid, k, &b);

		if (!data)
			continue;
		if (c->mode == HL_GL_COMBINE_FULL_IMAGE) {
			hl_lid_source_dense(c->lid, k, dense);
			data = dense;
			b = (struct hl_lid_box){ 0, 0, c->width, c->height };
		}
		c->boxes[k] = b;
		c->src[k] = hl_gl_texture_float(b.x1 - b.x0, b.y1 - b.y0, false, data);
		if (!c->src[k])
			return -EIO;
	}
	return 0;
}

int hl_gl_combiner_new(const struct hl_lid *lid, enum hl_gl_combine_mode mode, unsigned full_every,
		       struct hl_gl_combiner **ret, char *log, size_t log_size)
{
	const struct hl_lid_grid *g = hl_lid_grid(lid);
	struct hl_gl_combiner *c;
	float *dense = NULL;
	int rc;

	if (hl_lid_is_combined(lid))
		return -EINVAL;
	if (!has_ext("GL_EXT_color_buffer_float") || !has_ext("GL_EXT_float_blend")) {
		if (log && log_size)
			snprintf(log, log_size, "no EXT_color_buffer_float / EXT_float_blend");
		return -ENOTSUP;
	}
	c = calloc(1, sizeof(*c));
	if (!c)
		return -ENOMEM;
	c->lid = lid;
	c->mode = mode;
	c->width = g->width;
	c->height = g->height;
	c->n = hl_lid_n_sources(lid);
	c->full_every = full_every ? full_every : HL_COMBINE_FULL_EVERY;
	c->src = calloc(c->n, sizeof(*c->src));
	c->boxes = calloc(c->n, sizeof(*c->boxes));
	c->current = calloc(c->n, sizeof(*c->current));
	c->scratch = malloc(sizeof(float) * 4 * (size_t)c->width * c->height);
	if (mode == HL_GL_COMBINE_FULL_IMAGE)
		dense = malloc(sizeof(float) * (size_t)c->width * c->height);
	if (!c->src || !c->boxes || !c->current || !c->scratch ||
	    (mode == HL_GL_COMBINE_FULL_IMAGE && !dense)) {
		rc = -ENOMEM;
		goto err_free;
	}
	rc = hl_shader_build(hl_shader_quad_vert, hl_shader_combine_frag, &c->program, log,
			     log_size);
	if (rc < 0)
		goto err_free;
	c->u_src = glGetUniformLocation(c->program, "u_src");
	c->u_origin = glGetUniformLocation(c->program, "u_origin");
	c->u_weight = glGetUniformLocation(c->program, "u_weight");
	rc = upload_sources(c, dense);
	if (rc < 0)
		goto err_free;
	c->target = hl_gl_texture_float(c->width, c->height, false, NULL);
	c->fbo = c->target ? hl_gl_framebuffer(c->target) : 0;
	if (!c->fbo) {
		if (log && log_size)
			snprintf(log, log_size, "cannot make an R32F render target");
		rc = -EIO;
		goto err_free;
	}
	free(dense);
	*ret = c;
	return 0;

err_free:
	free(dense);
	hl_gl_combiner_free(c);
	return rc;
}

void hl_gl_combiner_free(struct hl_gl_combiner *c)
{
	if (!c)
		return;
	if (c->src)
		for (int k = 0; k < c->n; k++)
			if (c->src[k])
				glDeleteTextures(1, &c->src[k]);
	if (c->fbo)
		glDeleteFramebuffers(1, &c->fbo);
	if (c->target)
		glDeleteTextures(1, &c->target);
	if (c->program)
		glDeleteProgram(c->program);
	free(c->src);
	free(c->boxes);
	free(c->current);
	free(c->scratch);
	free(c);
}

static void draw_source(struct hl_gl_combiner *c, int k, float weight)
{
	const struct hl_lid_box *b = &c->boxes[k];

	glViewport(b->x0, b->y0, b->x1 - b->x0, b->y1 - b->y0);
	glBindTexture(GL_TEXTURE_2D, c->src[k]);
	glUniform2i(c->u_origin, b->x0, b->y0);
	glUniform1f(c->u_weight, weight);
	glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
}

int hl_gl_combiner_update(struct hl_gl_combiner *c, const float *i)
{
	int changed = 0;
	bool full;

	for (int k = 0; k < c->n; k++) {
		if (!(i[k] >= 0.0f && i[k] <= 1.0f))
			return -EINVAL;
		changed += i[k] != c->current[k];
	}
	if (changed == 0 && c->drawn)
		return 0;
	full = c->mode == HL_GL_COMBINE_FULL_IMAGE || !c->drawn || ++c->since_full >= c->full_every;
	glBindFramebuffer(GL_FRAMEBUFFER, c->fbo);
	glUseProgram(c->program);
	glActiveTexture(GL_TEXTURE0);
	glUniform1i(c->u_src, 0);
	glDisable(GL_DEPTH_TEST);
	glEnable(GL_BLEND);
	glBlendEquation(GL_FUNC_ADD);
	glBlendFunc(GL_ONE, GL_ONE);
	if (full) {
		glViewport(0, 0, c->width, c->height);
		glClearColor(0, 0, 0, 0);
		glClear(GL_COLOR_BUFFER_BIT);
		for (int k = 0; k < c->n; k++)
			if (c->src[k] && (i[k] != 0.0f || c->mode == HL_GL_COMBINE_FULL_IMAGE))
				draw_source(c, k, i[k]);
		c->since_full = 0;
		c->drawn = true;
	} else {
		for (int k = 0; k < c->n; k++)
			if (c->src[k] && i[k] != c->current[k])
				draw_source(c, k, i[k] - c->current[k]);
	}
	glDisable(GL_BLEND);
	memcpy(c->current, i, sizeof(float) * c->n);
	return changed;
}

GLuint hl_gl_combiner_texture(const struct hl_gl_combiner *c)
{
	return c->target;
}

int hl_gl_combiner_read(struct hl_gl_combiner *c, float *out)
{
	glBindFramebuffer(GL_FRAMEBUFFER, c->fbo);
	return hl_gl_read_red_float(c->width, c->height, out, c->scratch);
}
