/* SPDX-License-Identifier: MIT */
#include "render/gl_util.h"

#include <errno.h>
#include <stddef.h>
#include <stdio.h>

GLuint hl_gl_texture_float(int width, int height, bool rgba, const float *data)
{
	GLuint tex = 0;

	glGenTextures(1, &tex);
	glBindTexture(GL_TEXTURE_2D, tex);
	glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
	glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
	glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
	glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
	glTexStorage2D(GL_TEXTURE_2D, 1, rgba ? GL_RGBA32F : GL_R32F, width, height);
	glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
	if (data)
		glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, rgba ? GL_RGBA : GL_RED,
				GL_FLOAT, data);
	if (glGetError() != GL_NO_ERROR) {
		glDeleteTextures(1, &tex);
		return 0;
	}
	return tex;
}

GLuint hl_gl_framebuffer(GLuint tex)
{
	GLuint fbo = 0;

	glGenFramebuffers(1, &fbo);
	glBindFramebuffer(GL_FRAMEBUFFER, fbo);
	glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
	if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
		glBindFramebuffer(GL_FRAMEBUFFER, 0);
		glDeleteFramebuffers(1, &fbo);
		return 0;
	}
	return fbo;
}

int hl_gl_read_red_float(int width, int height, float *out, float *scratch)
{
	GLint format = 0, type = 0;
	const size_t n = (size_t)width * height;

	glPixelStorei(GL_PACK_ALIGNMENT, 4);
	glGetIntegerv(GL_IMPLEMENTATION_COLOR_READ_FORMAT, &format);
	glGetIntegerv(GL_IMPLEMENTATION_COLOR_READ_TYPE, &type);
	if (format == GL_RED && type == GL_FLOAT) {
		glReadPixels(0, 0, width, height, GL_RED, GL_FLOAT, out);
	} else {
		/* RGBA/FLOAT is the pair every float colour buffer must support. */
		glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, scratch);
		for (size_t i = 0; i < n; i++)
			out[i] = scratch[4 * i];
	}
	return glGetError() == GL_NO_ERROR ? 0 : -EIO;
}

void hl_gl_lamp_uniforms(GLuint program, int n_lamps, const struct hl_headlight_lamp *lamps)
{
	glUniform1i(glGetUniformLocation(program, "u_n_lamps"), n_lamps);
	for (int k = 0; k < n_lamps; k++) {
		const struct hl_headlight_lamp *l = &lamps[k];
		const struct hl_lid_grid *g = &l->grid;
		double ax[3], ay[3], az[3];
		float m[9], p[3];
		char name[64];

		hl_lamp_basis(&l->pose, ax, ay, az);
		/* Column-major: lamp = M w, so row r of M is lamp axis r. */
		for (int i = 0; i < 3; i++) {
			m[i * 3 + 0] = (float)ax[i];
			m[i * 3 + 1] = (float)ay[i];
			m[i * 3 + 2] = (float)az[i];
			p[i] = (float)l->pose.pos_m[i];
		}
		snprintf(name, sizeof(name), "u_lamp_pos[%d]", k);
		glUniform3fv(glGetUniformLocation(program, name), 1, p);
		snprintf(name, sizeof(name), "u_lamp_to_lamp[%d]", k);
		glUniformMatrix3fv(glGetUniformLocation(program, name), 1, GL_FALSE, m);
		snprintf(name, sizeof(name), "u_angles[%d]", k);
		glUniform1i(glGetUniformLocation(program, name), g->angles == HL_ANGLES_A ? 0 : 1);
		snprintf(name, sizeof(name), "u_grid[%d]", k);
		glUniform4f(glGetUniformLocation(program, name), g->h_first_deg, g->v_last_deg,
			    (g->width - 1) / (g->h_last_deg - g->h_first_deg),
			    (g->height - 1) / (g->v_last_deg - g->v_first_deg));
		snprintf(name, sizeof(name), "u_grid_size[%d]", k);
		glUniform2i(glGetUniformLocation(program, name), g->width, g->height);
	}
}
