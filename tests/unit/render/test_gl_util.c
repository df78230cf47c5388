/* SPDX-License-Identifier: MIT */
/*
 * The small GL helpers (GLES on Mesa llvmpipe via EGL surfaceless): float textures uploaded and
 * read back exactly through a framebuffer (R32F and RGBA32F, the red channel), refusals that
 * return 0 or -EIO and leave no GL error behind, and the lamp uniforms as the program reads
 * them: position, rotation rows the lamp's axes, the angle system, the grid's mapping.
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "render/gl_util.h"
#include "render/shader.h"

#include "egl_fixture.h"

static void gl_red_float_texture_reads_back_exactly(void **state)
{
	static const float data[3 * 2] = { 0.0f, -1.5f, 3.25e7f, 1e-30f, 42.0f, -0.0f };
	float out[6], scratch[4 * 6];
	GLuint tex, fbo;
	(void)state;

	tex = hl_gl_texture_float(3, 2, false, data);
	assert_int_not_equal(tex, 0);
	fbo = hl_gl_framebuffer(tex);
	assert_int_not_equal(fbo, 0);
	memset(out, 0x7f, sizeof(out));
	assert_int_equal(hl_gl_read_red_float(3, 2, out, scratch), 0);
	assert_memory_equal(out, data, sizeof(data)); /* bit for bit, -0 included */
	glBindFramebuffer(GL_FRAMEBUFFER, 0);
	glDeleteFramebuffers(1, &fbo);
	glDeleteTextures(1, &tex);
	assert_int_equal(glGetError(), GL_NO_ERROR);
}

static void gl_rgba_float_texture_reads_back_its_red_channel(void **state)
{
	float data[2 * 2 * 4], out[4], scratch[16];
	GLuint tex, fbo;
	(void)state;

	for (int i = 0; i < 16; i++)
		data[i] = (float)(i * 10 + 1);
	tex = hl_gl_texture_float(2, 2, true, data);
	assert_int_not_equal(tex, 0);
	fbo = hl_gl_framebuffer(tex);
	assert_int_not_equal(fbo, 0);
	assert_int_equal(hl_gl_read_red_float(2, 2, out, scratch), 0);
	for (int i = 0; i < 4; i++)
		assert_true(out[i] == data[4 * i]);
	glBindFramebuffer(GL_FRAMEBUFFER, 0);
	glDeleteFramebuffers(1, &fbo);
	glDeleteTextures(1, &tex);
	/* NULL data: storage only */
	tex = hl_gl_texture_float(5, 1, false, NULL);
	assert_int_not_equal(tex, 0);
	glDeleteTextures(1, &tex);
	assert_int_equal(glGetError(), GL_NO_ERROR);
}

static void gl_refusals_return_0_or_eio_and_clear_the_error(void **state)
{
	float out[4], scratch[16];
	(void)state;

	assert_int_equal(hl_gl_texture_float(0, 4, false, NULL), 0);
	assert_int_equal(glGetError(), GL_NO_ERROR);
	assert_int_equal(hl_gl_texture_float(4, -1, true, NULL), 0);
	assert_int_equal(glGetError(), GL_NO_ERROR);
	/* no texture: an incomplete framebuffer, deleted, the default bound again */
	assert_int_equal(hl_gl_framebuffer(0), 0);
	{
		GLint bound = -1;

		glGetIntegerv(GL_FRAMEBUFFER_BINDING, &bound);
		assert_int_equal(bound, 0);
	}
	/* surfaceless: the default framebuffer cannot be read */
	assert_int_equal(hl_gl_read_red_float(2, 2, out, scratch), -EIO);
	assert_int_equal(glGetError(), GL_NO_ERROR);
}

static const char vs[] = "#version 300 es\n"
			 "void main() {\n"
			 "\tvec2 c = vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1));\n"
			 "\tgl_Position = vec4(c * 2.0 - 1.0, 0.0, 1.0);\n"
			 "}\n";
/* Uses every lamp uniform, so none is optimised away. */
static const char fs[] = "#version 300 es\n"
			 "precision highp float;\n"
			 "uniform int u_n_lamps;\n"
			 "uniform vec3 u_lamp_pos[2];\n"
			 "uniform mat3 u_lamp_to_lamp[2];\n"
			 "uniform int u_angles[2];\n"
			 "uniform vec4 u_grid[2];\n"
			 "uniform ivec2 u_grid_size[2];\n"
			 "out vec4 o;\n"
			 "void main() {\n"
			 "\tfloat s = float(u_n_lamps);\n"
			 "\tfor (int k = 0; k < 2; k++)\n"
			 "\t\ts += dot(u_lamp_pos[k], u_lamp_to_lamp[k] * vec3(1.0)) +\n"
			 "\t\t     float(u_angles[k] + u_grid_size[k].x + u_grid_size[k].y) +\n"
			 "\t\t     dot(u_grid[k], vec4(1.0));\n"
			 "\to = vec4(s);\n"
			 "}\n";

static void gl_lamp_uniforms_as_the_program_reads_them(void **state)
{
	struct hl_headlight_lamp lamps[2] = {
		{ .pose = { { 0.5, 0.7, 0.65 }, 2.0, -0.57 },
		  .grid = { 9, 5, HL_ANGLES_A, -40.0f, 40.0f, -10.0f, 10.0f } },
		{ .pose = { { 0.5, -0.7, 0.65 }, -3.0, 1.0 },
		  .grid = { 201, 101, HL_ANGLES_B, -20.0f, 30.0f, -5.0f, 20.0f } },
	};
	GLuint prog;
	char log[1024];
	(void)state;

	if (hl_shader_build(vs, fs, &prog, log, sizeof(log)) < 0)
		fail_msg("%s", log);
	glUseProgram(prog);
	hl_gl_lamp_uniforms(prog, 2, lamps);
	assert_int_equal(glGetError(), GL_NO_ERROR);
	{
		GLint n = -1;

		glGetUniformiv(prog, glGetUniformLocation(prog, "u_n_lamps"), &n);
		assert_int_equal(n, 2);
	}
	for (int k = 0; k < 2; k++) {
		const struct hl_headlight_lamp *l = &lamps[k];
		char name[64];
		float pos[3], m[9], g[4];
		GLint angles = -1, size[2] = { -1, -1 };
		double ax[3], ay[3], az[3];

		snprintf(name, sizeof(name), "u_lamp_pos[%d]", k);
		glGetUniformfv(prog, glGetUniformLocation(prog, name), pos);
		for (int i = 0; i < 3; i++)
			assert_true(pos[i] == (float)l->pose.pos_m[i]);
		/* column-major: element (row r, column c) at m[3 c + r]; row r is lamp axis r */
		hl_lamp_basis(&l->pose, ax, ay, az);
		snprintf(name, sizeof(name), "u_lamp_to_lamp[%d]", k);
		glGetUniformfv(prog, glGetUniformLocation(prog, name), m);
		for (int c = 0; c < 3; c++) {
			assert_true(m[3 * c + 0] == (float)ax[c]);
			assert_true(m[3 * c + 1] == (float)ay[c]);
			assert_true(m[3 * c + 2] == (float)az[c]);
		}
		snprintf(name, sizeof(name), "u_angles[%d]", k);
		glGetUniformiv(prog, glGetUniformLocation(prog, name), &angles);
		assert_int_equal(angles, k == 0 ? 0 : 1);
		snprintf(name, sizeof(name), "u_grid[%d]", k);
		glGetUniformfv(prog, glGetUniformLocation(prog, name), g);
		assert_true(g[0] == l->grid.h_first_deg);
		assert_true(g[1] == l->grid.v_last_deg);
		snprintf(name, sizeof(name), "u_grid_size[%d]", k);
		glGetUniformiv(prog, glGetUniformLocation(prog, name), size);
		assert_int_equal(size[0], l->grid.width);
		assert_int_equal(size[1], l->grid.height);
		/* samples per degree: (9 - 1) / 80 and (5 - 1) / 20; (201 - 1) / 50, (101 - 1) / 25 */
		assert_true(g[2] == (k == 0 ? 0.1f : 4.0f));
		assert_true(g[3] == (k == 0 ? 0.2f : 4.0f));
	}
	glDeleteProgram(prog);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(gl_red_float_texture_reads_back_exactly),
		cmocka_unit_test(gl_rgba_float_texture_reads_back_its_red_channel),
		cmocka_unit_test(gl_refusals_return_0_or_eio_and_clear_the_error),
		cmocka_unit_test(gl_lamp_uniforms_as_the_program_reads_them),
	};

	return cmocka_run_group_tests(tests, egl_setup, egl_teardown);
}
