/* SPDX-License-Identifier: MIT */
#include "render/gl_sensor.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <EGL/egl.h>
#include <GLES3/gl31.h>
#include <GLES2/gl2ext.h>

#include "render/gl_util.h"
#include "render/hemicube.h"
#include "render/sensor.h"
#include "render/shader.h"
#include "render/shaders.h"

#define NEAR_M 1e-5 /* reversed float depth: the near plane can sit almost at the eye */
#define CLIP_PLANES 4

struct hl_gl_sensor {
	struct hl_gl_sensor_config cfg;
	int n_lamps;
	struct hl_headlight_lamp lamps[HL_HEADLIGHT_MAX_LAMPS];
	int face; /* front face texels across: size times supersampling */
	int tile_w, tile_h, tiles_x, tiles_y, atlas_w, atlas_h;
	GLsizei n_vertices;
	GLuint scene_prog, rows_prog, reduce_prog, vao, vbo;
	GLuint sensors; /* RGBA32F, 4 x batch: eye, t, b, n */
	GLuint weights; /* R32F, one tile */
	GLuint lid[HL_HEADLIGHT_MAX_LAMPS];
	GLuint atlas, depth, atlas_fbo; /* multisampled R32F colour, D32F depth */
	GLuint rows, rows_fbo; /* R32F, tiles_x x atlas_h: the weighted sum of each tile row */
	GLuint out, out_fbo; /* R32F, tiles_x x tiles_y: one texel per sensor */
	PFNGLCLIPCONTROLEXTPROC clip_control;
	float *frames; /* 16 floats per sensor of a batch: eye, t, b, n */
	float *result, *scratch;
};

static int fail(char *log, size_t log_size, int rc, const char *fmt, ...)
{
	va_list ap;

	if (log && log_size) {
		va_start(ap, fmt);
		vsnprintf(log, log_size, fmt, ap);
		va_end(ap);
	}
	return rc;
}

static void lamp_uniforms(const struct hl_gl_sensor *s, GLuint program)
{
	glUniform1i(glGetUniformLocation(program, "u_lid0"), 1);
	glUniform1i(glGetUniformLocation(program, "u_lid1"), 2);
	hl_gl_lamp_uniforms(program, s->n_lamps, s->lamps);
}

/*
 * The weights of one tile: each (sub-)texel's exact projected solid angle, by the closed
 * forms of render/hemicube.c (with supersampling 1 the hemicube's own weights).
 */
static float *tile_weights(const struct hl_gl_sensor *s)
{
	const int f = s->face;
	const double step = 2.0 / f;
	float *w = malloc(sizeof(float) * (size_t)s->tile_w * s->tile_h);

	if (!w)
		return NULL;
	for (int row = 0; row < s->tile_h; row++)
		for (int col = 0; col < f; col++) {
			const double x0 = -1.0 + col * step;
			double v;

			if (row < f) {
				v = hl_hemicube_front_patch(x0, x0 + step, -1.0 + row * step,
							    -1.0 + (row + 1) * step);
			} else {
				const int z = (row - f) % (f / 2);

				v = hl_hemicube_side_patch(x0, x0 + step, z * step, (z + 1) * step);
			}
			w[(size_t)row * s->tile_w + col] = (float)v;
		}
	return w;
}

static bool sample_count_offered(GLenum target, GLenum format, int samples)
{
	GLint n = 0, counts[16];

	if (samples == 1)
		return true;
	glGetInternalformativ(target, format, GL_NUM_SAMPLE_COUNTS, 1, &n);
	n = n > 16 ? 16 : n;
	glGetInternalformativ(target, format, GL_SAMPLES, n, counts);
	for (int i = 0; i < n; i++)
		if (counts[i] == samples)
			return true;
	return false;
}

static int make_targets(struct hl_gl_sensor *s, char *log, size_t log_size)
{
	const int ms = s->cfg.msaa;
	float *w;

	if (!sample_count_offered(GL_TEXTURE_2D_MULTISAMPLE, GL_R32F, ms) ||
	    !sample_count_offered(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, ms))
		return fail(log, log_size, -ENOTSUP, "%d samples per texel not offered for R32F",
			    ms);
	glGenTextures(1, &s->atlas);
	glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, s->atlas);
	glTexStorage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, ms, GL_R32F, s->atlas_w, s->atlas_h,
				  GL_TRUE);
	glGenRenderbuffers(1, &s->depth);
	glBindRenderbuffer(GL_RENDERBUFFER, s->depth);
	glRenderbufferStorageMultisample(GL_RENDERBUFFER, ms, GL_DEPTH_COMPONENT32F, s->atlas_w,
					 s->atlas_h);
	glGenFramebuffers(1, &s->atlas_fbo);
	glBindFramebuffer(GL_FRAMEBUFFER, s->atlas_fbo);
	glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D_MULTISAMPLE,
			       s->atlas, 0);
	glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, s->depth);
	if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
		glBindFramebuffer(GL_FRAMEBUFFER, 0);
		return fail(log, log_size, -EIO,
			    "the %dx%d sensor atlas (%d samples) is incomplete", s->atlas_w,
			    s->atlas_h, ms);
	}
	glBindFramebuffer(GL_FRAMEBUFFER, 0);
	s->rows = hl_gl_texture_float(s->tiles_x, s->atlas_h, false, NULL);
	s->rows_fbo = s->rows ? hl_gl_framebuffer(s->rows) : 0;
	s->out = hl_gl_texture_float(s->tiles_x, s->tiles_y, false, NULL);
	s->out_fbo = s->out ? hl_gl_framebuffer(s->out) : 0;
	glBindFramebuffer(GL_FRAMEBUFFER, 0);
	s->sensors = hl_gl_texture_float(4, s->cfg.batch, true, NULL);
	w = tile_weights(s);
	if (!w)
		return -ENOMEM;
	s->weights = hl_gl_texture_float(s->tile_w, s->tile_h, false, w);
	free(w);
	if (!s->rows_fbo || !s->out_fbo || !s->sensors || !s->weights)
		return fail(log, log_size, -EIO, "cannot make the sensor textures");
	return 0;
}

static int make_mesh(struct hl_gl_sensor *s, const struct hl_scene_mesh *mesh)
{
	const GLsizei stride = sizeof(struct hl_scene_mesh_vertex);

	s->n_vertices = (GLsizei)mesh->n_vertices;
	glGenVertexArrays(1, &s->vao);
	glGenBuffers(1, &s->vbo);
	glBindVertexArray(s->vao);
	glBindBuffer(GL_ARRAY_BUFFER, s->vbo);
	glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(stride * mesh->n_vertices), mesh->v,
		     GL_STATIC_DRAW);
	glEnableVertexAttribArray(0);
	glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride,
			      (const void *)offsetof(struct hl_scene_mesh_vertex, pos));
	glEnableVertexAttribArray(1);
	glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride,
			      (const void *)offsetof(struct hl_scene_mesh_vertex, nrm));
	glEnableVertexAttribArray(2);
	glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, stride,
			      (const void *)offsetof(struct hl_scene_mesh_vertex, albedo));
	glEnableVertexAttribArray(3);
	glVertexAttribPointer(3, 4, GL_FLOAT, GL_FALSE, stride,
			      (const void *)offsetof(struct hl_scene_mesh_vertex, sphere));
	glBindVertexArray(0);
	glBindBuffer(GL_ARRAY_BUFFER, 0);
	return glGetError() == GL_NO_ERROR ? 0 : -EIO;
}

static void program_uniforms(struct hl_gl_sensor *s)
{
	glUseProgram(s->scene_prog);
	glUniform1i(glGetUniformLocation(s->scene_prog, "u_sensors"), 0);
	glUniform1i(glGetUniformLocation(s->scene_prog, "u_tiles_x"), s->tiles_x);
	glUniform2i(glGetUniformLocation(s->scene_prog, "u_tile"), s->tile_w, s->tile_h);
	glUniform1i(glGetUniformLocation(s->scene_prog, "u_face"), s->face);
	glUniform2f(glGetUniformLocation(s->scene_prog, "u_atlas"), (float)s->atlas_w,
		    (float)s->atlas_h);
	glUniform1f(glGetUniformLocation(s->scene_prog, "u_near"), (float)NEAR_M);
	lamp_uniforms(s, s->scene_prog);
	glUseProgram(s->rows_prog);
	glUniform1i(glGetUniformLocation(s->rows_prog, "u_atlas"), 0);
	glUniform1i(glGetUniformLocation(s->rows_prog, "u_weights"), 1);
	glUniform1i(glGetUniformLocation(s->rows_prog, "u_samples"), s->cfg.msaa);
	glUniform2i(glGetUniformLocation(s->rows_prog, "u_tile"), s->tile_w, s->tile_h);
	glUseProgram(s->reduce_prog);
	glUniform1i(glGetUniformLocation(s->reduce_prog, "u_rows"), 0);
	glUniform1i(glGetUniformLocation(s->reduce_prog, "u_tile_h"), s->tile_h);
	glUseProgram(0);
}

int hl_gl_sensor_new(const struct hl_egl *egl, const struct hl_scene_mesh *mesh, int n_lamps,
		     const struct hl_headlight_lamp *lamps, const struct hl_gl_sensor_config *cfg,
		     struct hl_gl_sensor **ret, char *log, size_t log_size)
{
	static const char *const needed[] = { "GL_EXT_clip_cull_distance", "GL_EXT_clip_control" };
	struct hl_gl_sensor *s;
	GLint max_size = 0;
	char *scene_frag;
	int rc;

	if (n_lamps < 1 || n_lamps > HL_HEADLIGHT_MAX_LAMPS || cfg->size < 2 ||
	    cfg->size > HL_HEMICUBE_MAX_SIZE || cfg->size % 2 || cfg->supersample < 1 ||
	    cfg->supersample > 16 || cfg->msaa < 1 || cfg->batch < 1 || cfg->batch > 65536 ||
	    !(cfg->sky_cd_m2 >= 0.0))
		return fail(log, log_size, -EINVAL, "bad sensor configuration");
	for (int k = 0; k < n_lamps; k++)
		if (hl_lid_grid_check(&lamps[k].grid) < 0)
			return fail(log, log_size, -EINVAL, "bad grid of lamp %d", k);
	if (!hl_egl_float_targets(egl))
		return fail(log, log_size, -ENOTSUP,
			    "no float render targets (EXT_color_buffer_float)");
	for (size_t i = 0; i < sizeof(needed) / sizeof(needed[0]); i++)
		if (!hl_egl_has_gl_extension(egl, needed[i]))
			return fail(log, log_size, -ENOTSUP, "%s is not offered", needed[i]);
	s = calloc(1, sizeof(*s));
	if (!s)
		return -ENOMEM;
	s->cfg = *cfg;
	s->n_lamps = n_lamps;
	memcpy(s->lamps, lamps, sizeof(*lamps) * n_lamps);
	s->clip_control = (PFNGLCLIPCONTROLEXTPROC)eglGetProcAddress("glClipControlEXT");
	s->face = cfg->size * cfg->supersample;
	s->tile_w = s->face;
	s->tile_h = 3 * s->face;
	/* Tiles in rows of an atlas about as wide as high. */
	s->tiles_x = (int)ceil(sqrt(3.0 * cfg->batch));
	s->tiles_x = s->tiles_x > cfg->batch ? cfg->batch : s->tiles_x;
	s->tiles_y = (cfg->batch + s->tiles_x - 1) / s->tiles_x;
	s->atlas_w = s->tiles_x * s->tile_w;
	s->atlas_h = s->tiles_y * s->tile_h;
	glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
	if (!s->clip_control) {
		rc = fail(log, log_size, -ENOTSUP, "glClipControlEXT cannot be loaded");
		goto err_free;
	}
	if (s->atlas_w > max_size || s->atlas_h > max_size) {
		rc = fail(log, log_size, -EINVAL,
			  "a %dx%d sensor atlas exceeds the %d texels the driver offers: fewer "
			  "sensors per batch or a smaller sensor",
			  s->atlas_w, s->atlas_h, max_size);
		goto err_free;
	}
	s->frames = malloc(sizeof(float) * 16 * cfg->batch);
	s->result = malloc(sizeof(float) * (size_t)s->tiles_x * s->tiles_y);
	s->scratch = malloc(sizeof(float) * 4 * (size_t)s->tiles_x * s->tiles_y);
	if (!s->frames || !s->result || !s->scratch) {
		rc = -ENOMEM;
		goto err_free;
	}
	scene_frag = hl_shader_compose(hl_shader_sensor_scene_frag, "", hl_shader_lamp_lookup);
	rc = scene_frag ? hl_shader_build(hl_shader_sensor_scene_vert, scene_frag, &s->scene_prog,
					  log, log_size) :
			  -ENOMEM;
	free(scene_frag);
	if (rc == 0)
		rc = hl_shader_build(hl_shader_sensor_quad_vert, hl_shader_sensor_rows_frag,
				     &s->rows_prog, log, log_size);
	if (rc == 0)
		rc = hl_shader_build(hl_shader_sensor_quad_vert, hl_shader_sensor_reduce_frag,
				     &s->reduce_prog, log, log_size);
	if (rc < 0)
		goto err_free;
	for (int k = 0; k < n_lamps; k++) {
		s->lid[k] =
			hl_gl_texture_float(lamps[k].grid.width, lamps[k].grid.height, false, NULL);
		if (!s->lid[k]) {
			rc = fail(log, log_size, -EIO, "cannot make the distribution textures");
			goto err_free;
		}
	}
	rc = make_targets(s, log, log_size);
	if (rc < 0)
		goto err_free;
	rc = make_mesh(s, mesh);
	if (rc < 0) {
		fail(log, log_size, rc, "cannot upload the scene mesh");
		goto err_free;
	}
	program_uniforms(s);
	if (glGetError() != GL_NO_ERROR) {
		rc = fail(log, log_size, -EIO, "GL error while setting up the sensors");
		goto err_free;
	}
	*ret = s;
	return 0;

err_free:
	hl_gl_sensor_free(s);
	return rc;
}

void hl_gl_sensor_free(struct hl_gl_sensor *s)
{
	GLuint tex[7];

	if (!s)
		return;
	tex[0] = s->sensors;
	tex[1] = s->weights;
	tex[2] = s->lid[0];
	tex[3] = s->lid[1];
	tex[4] = s->atlas;
	tex[5] = s->out;
	tex[6] = s->rows;
	for (size_t i = 0; i < sizeof(tex) / sizeof(tex[0]); i++)
		if (tex[i])
			glDeleteTextures(1, &tex[i]);
	if (s->depth)
		glDeleteRenderbuffers(1, &s->depth);
	if (s->atlas_fbo)
		glDeleteFramebuffers(1, &s->atlas_fbo);
	if (s->out_fbo)
		glDeleteFramebuffers(1, &s->out_fbo);
	if (s->rows_fbo)
		glDeleteFramebuffers(1, &s->rows_fbo);
	if (s->vbo)
		glDeleteBuffers(1, &s->vbo);
	if (s->vao)
		glDeleteVertexArrays(1, &s->vao);
	if (s->scene_prog)
		glDeleteProgram(s->scene_prog);
	if (s->rows_prog)
		glDeleteProgram(s->rows_prog);
	if (s->reduce_prog)
		glDeleteProgram(s->reduce_prog);
	free(s->frames);
	free(s->result);
	free(s->scratch);
	free(s);
}

int hl_gl_sensor_upload(struct hl_gl_sensor *s, int k, const float *dense)
{
	const struct hl_lid_grid *g = &s->lamps[k].grid;

	glBindTexture(GL_TEXTURE_2D, s->lid[k]);
	glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
	glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, g->width, g->height, GL_RED, GL_FLOAT, dense);
	return glGetError() == GL_NO_ERROR ? 0 : -EIO;
}

/* One draw: count <= batch sensors into the atlas, reduced into s->result. */
static int run_batch(struct hl_gl_sensor *s, size_t count, const double *p, const double *n)
{
	const int used_y = (int)((count + s->tiles_x - 1) / s->tiles_x);

	for (size_t i = 0; i < count; i++) {
		double t[3], b[3];
		float *r = s->frames + 16 * i;

		hl_hemicube_frame(n + 3 * i, t, b);
		for (int j = 0; j < 3; j++) {
			r[j] = (float)(p[3 * i + j] + HL_SENSOR_OFFSET_M * n[3 * i + j]);
			r[4 + j] = (float)t[j];
			r[8 + j] = (float)b[j];
			r[12 + j] = (float)n[3 * i + j];
		}
		r[3] = r[7] = r[11] = r[15] = 0.0f;
	}
	glBindTexture(GL_TEXTURE_2D, s->sensors);
	glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
	glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 4, (GLsizei)count, GL_RGBA, GL_FLOAT, s->frames);

	/* The sensor maps: only the rows of tiles in use are cleared and drawn. */
	glBindFramebuffer(GL_FRAMEBUFFER, s->atlas_fbo);
	glViewport(0, 0, s->atlas_w, s->atlas_h);
	glEnable(GL_SCISSOR_TEST);
	glScissor(0, 0, s->atlas_w, used_y * s->tile_h);
	glDisable(GL_BLEND);
	glDisable(GL_CULL_FACE);
	glDepthMask(GL_TRUE);
	glClearColor((float)s->cfg.sky_cd_m2, 0.0f, 0.0f, 0.0f);
	glClearDepthf(0.0f);
	glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
	if (s->n_vertices > 0) {
		s->clip_control(GL_LOWER_LEFT_EXT, GL_ZERO_TO_ONE_EXT);
		glEnable(GL_DEPTH_TEST);
		glDepthFunc(GL_GREATER);
		for (int i = 0; i < CLIP_PLANES; i++)
			glEnable(GL_CLIP_DISTANCE0_EXT + i);
		glUseProgram(s->scene_prog);
		glActiveTexture(GL_TEXTURE0);
		glBindTexture(GL_TEXTURE_2D, s->sensors);
		glActiveTexture(GL_TEXTURE1);
		glBindTexture(GL_TEXTURE_2D, s->lid[0]);
		glActiveTexture(GL_TEXTURE2);
		glBindTexture(GL_TEXTURE_2D, s->n_lamps > 1 ? s->lid[1] : s->lid[0]);
		glBindVertexArray(s->vao);
		glDrawArraysInstanced(GL_TRIANGLES, 0, s->n_vertices, (GLsizei)(5 * count));
		glBindVertexArray(0);
		for (int i = 0; i < CLIP_PLANES; i++)
			glDisable(GL_CLIP_DISTANCE0_EXT + i);
		glDepthFunc(GL_LESS);
		glDisable(GL_DEPTH_TEST);
		s->clip_control(GL_LOWER_LEFT_EXT, GL_NEGATIVE_ONE_TO_ONE_EXT);
	}
	glDisable(GL_SCISSOR_TEST);

	/* The weighted sum of each tile row, then one fragment per sensor sums its rows. */
	glBindFramebuffer(GL_FRAMEBUFFER, s->rows_fbo);
	glViewport(0, 0, s->tiles_x, used_y * s->tile_h);
	glUseProgram(s->rows_prog);
	glActiveTexture(GL_TEXTURE0);
	glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, s->atlas);
	glActiveTexture(GL_TEXTURE1);
	glBindTexture(GL_TEXTURE_2D, s->weights);
	glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
	glBindFramebuffer(GL_FRAMEBUFFER, s->out_fbo);
	glViewport(0, 0, s->tiles_x, used_y);
	glUseProgram(s->reduce_prog);
	glActiveTexture(GL_TEXTURE0);
	glBindTexture(GL_TEXTURE_2D, s->rows);
	glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
	glUseProgram(0);
	return hl_gl_read_red_float(s->tiles_x, used_y, s->result, s->scratch);
}

int hl_gl_sensor_run(struct hl_gl_sensor *s, size_t count, const double *p, const double *n,
		     double *ret_lx)
{
	for (size_t off = 0; off < count; off += (size_t)s->cfg.batch) {
		const size_t m = count - off < (size_t)s->cfg.batch ? count - off :
								      (size_t)s->cfg.batch;
		const int rc = run_batch(s, m, p + 3 * off, n + 3 * off);

		if (rc < 0)
			return rc;
		for (size_t i = 0; i < m; i++)
			ret_lx[off + i] = s->result[i];
	}
	return 0;
}

int hl_gl_sensor_gi_batch(void *userdata, size_t count, const double *p, const double *n,
			  double *ret_lx)
{
	return hl_gl_sensor_run(userdata, count, p, n, ret_lx);
}

void hl_gl_sensor_config_for(const struct hl_egl *egl, int size, int aa, int batch,
			     struct hl_gl_sensor_config *ret)
{
	const bool msaa = aa > 1 && hl_egl_float_targets(egl) &&
			  sample_count_offered(GL_TEXTURE_2D_MULTISAMPLE, GL_R32F, 4) &&
			  sample_count_offered(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, 4);

	*ret = (struct hl_gl_sensor_config){
		.size = size,
		.supersample = msaa ? (aa + 1) / 2 : aa,
		.msaa = msaa ? 4 : 1,
		.batch = batch,
	};
}
