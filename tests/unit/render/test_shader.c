/* SPDX-License-Identifier: MIT */
/*
 * GLSL programs (GLES on Mesa llvmpipe via EGL surfaceless): a program that builds and draws the
 * colour it says; a vertex, a fragment and a link error each return -EINVAL with the info log
 * behind its prefix, leave *ret_program alone and leave no shader or program behind; a log too
 * small or absent; composed sources exact, refused without #version, and with the compiler's
 * line numbers those of main_src.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "render/shader.h"

#include "egl_fixture.h"

static const char vs_ok[] = "#version 300 es\n"
			    "out vec2 v_uv;\n"
			    "void main() {\n"
			    "\tvec2 c = vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1));\n"
			    "\tv_uv = c;\n"
			    "\tgl_Position = vec4(c * 2.0 - 1.0, 0.0, 1.0);\n"
			    "}\n";
static const char fs_ok[] = "#version 300 es\n"
			    "precision highp float;\n"
			    "in vec2 v_uv;\n"
			    "out vec4 o;\n"
			    "void main() { o = vec4(0.25, 0.5, 1.0, 1.0) + 0.0 * v_uv.x; }\n";

/*
 * The shader and program names after probe (a shader made before the call under test and
 * deleted) that exist now: none after a failed build. Mesa hands out names in rising order.
 */
static void expect_no_objects_after(GLuint probe)
{
	for (GLuint id = probe + 1; id < probe + 16; id++) {
		assert_int_equal(glIsShader(id), GL_FALSE);
		assert_int_equal(glIsProgram(id), GL_FALSE);
	}
}

static GLuint probe_name(void)
{
	const GLuint s = glCreateShader(GL_VERTEX_SHADER);

	assert_int_not_equal(s, 0);
	glDeleteShader(s);
	return s;
}

static void shader_build_links_and_draws_its_colour(void **state)
{
	GLuint prog = 0, tex, fbo;
	char log[256] = "untouched";
	uint8_t px[4 * 4 * 4];
	(void)state;

	assert_int_equal(hl_shader_build(vs_ok, fs_ok, &prog, log, sizeof(log)), 0);
	assert_int_not_equal(prog, 0);
	assert_int_equal(glIsProgram(prog), GL_TRUE);
	assert_string_equal(log, "untouched");
	glGenTextures(1, &tex);
	glBindTexture(GL_TEXTURE_2D, tex);
	glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, 4, 4);
	glGenFramebuffers(1, &fbo);
	glBindFramebuffer(GL_FRAMEBUFFER, fbo);
	glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
	assert_int_equal(glCheckFramebufferStatus(GL_FRAMEBUFFER), GL_FRAMEBUFFER_COMPLETE);
	glViewport(0, 0, 4, 4);
	glUseProgram(prog);
	glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
	glReadPixels(0, 0, 4, 4, GL_RGBA, GL_UNSIGNED_BYTE, px);
	assert_int_equal(glGetError(), GL_NO_ERROR);
	for (int i = 0; i < 16; i++) {
		assert_int_equal(px[4 * i + 0], 64);
		assert_int_equal(px[4 * i + 1], 128);
		assert_int_equal(px[4 * i + 2], 255);
		assert_int_equal(px[4 * i + 3], 255);
	}
	glBindFramebuffer(GL_FRAMEBUFFER, 0);
	glDeleteFramebuffers(1, &fbo);
	glDeleteTextures(1, &tex);
	glDeleteProgram(prog);
}

static void shader_vertex_error_returns_its_log_and_leaks_nothing(void **state)
{
	static const char vs_bad[] = "#version 300 es\nvoid main() {\n\tgl_Position = nope;\n}\n";
	GLuint prog = 12345, probe = probe_name();
	char log[1024] = "";
	(void)state;

	assert_int_equal(hl_shader_build(vs_bad, fs_ok, &prog, log, sizeof(log)), -EINVAL);
	assert_int_equal(prog, 12345);
	assert_memory_equal(log, "vertex shader: ", 15);
	assert_non_null(strstr(log, "nope")); /* the compiler's message names it */
	assert_non_null(strstr(log, "0:3(")); /* at line 3 */
	expect_no_objects_after(probe);
}

static void shader_fragment_error_returns_its_log_and_leaks_nothing(void **state)
{
	static const char fs_bad[] = "#version 300 es\nprecision highp float;\nout vec4 o;\n"
				     "void main() { o = vec3(1.0); }\n";
	GLuint prog = 12345, probe = probe_name();
	char log[1024] = "";
	(void)state;

	assert_int_equal(hl_shader_build(vs_ok, fs_bad, &prog, log, sizeof(log)), -EINVAL);
	assert_int_equal(prog, 12345);
	assert_memory_equal(log, "fragment shader: ", 17);
	assert_non_null(strstr(log, "0:4("));
	expect_no_objects_after(probe); /* the compiled vertex shader is gone too */
}

static void shader_link_error_returns_its_log_and_leaks_nothing(void **state)
{
	/* v_uv is a vec2 out of the vertex shader and a vec3 into the fragment shader */
	static const char fs_mismatch[] = "#version 300 es\nprecision highp float;\n"
					  "in vec3 v_uv;\nout vec4 o;\n"
					  "void main() { o = vec4(v_uv, 1.0); }\n";
	GLuint prog = 12345, probe = probe_name();
	char log[1024] = "";
	(void)state;

	assert_int_equal(hl_shader_build(vs_ok, fs_mismatch, &prog, log, sizeof(log)), -EINVAL);
	assert_int_equal(prog, 12345);
	assert_memory_equal(log, "link: ", 6);
	assert_non_null(strstr(log, "v_uv"));
	expect_no_objects_after(probe);
}

static void shader_log_small_or_absent_is_safe(void **state)
{
	static const char vs_bad[] = "#version 300 es\nvoid main() { x; }\n";
	GLuint prog = 0;
	char log[16];
	(void)state;

	memset(log, 'x', sizeof(log));
	assert_int_equal(hl_shader_build(vs_bad, fs_ok, &prog, log, 8), -EINVAL);
	assert_string_equal(log, "vertex "); /* the prefix cut to 7 bytes and terminated */
	assert_int_equal(log[8], 'x'); /* nothing written past log_size */
	memset(log, 'x', sizeof(log));
	assert_int_equal(hl_shader_build(vs_bad, fs_ok, &prog, log, 0), -EINVAL);
	assert_int_equal(log[0], 'x');
	assert_int_equal(hl_shader_build(vs_bad, fs_ok, &prog, NULL, 0), -EINVAL);
	assert_int_equal(hl_shader_build(vs_ok, fs_ok, &prog, NULL, 0), 0);
	glDeleteProgram(prog);
}

static void shader_compose_exact_text_and_main_src_line_numbers(void **state)
{
	static const char main_src[] = "#version 300 es\nprecision highp float;\nout vec4 o;\n"
				       "void main() { o = vec4(A + f(), 0.0, 0.0, 1.0); }\n";
	static const char broken[] = "#version 300 es\nprecision highp float;\nout vec4 o;\n"
				     "void main() { o = vec4(A + f(), 0.0, 0.0, 1.0); oops; }\n";
	GLuint prog = 0;
	char log[1024] = "", *src;
	(void)state;

	src = hl_shader_compose(main_src, "#define A 0.5", "highp float f() { return 0.25; }");
	assert_non_null(src);
	assert_string_equal(src,
			    "#version 300 es\n#define A 0.5\nhighp float f() { return 0.25; }\n"
			    "#line 2\nprecision highp float;\nout vec4 o;\n"
			    "void main() { o = vec4(A + f(), 0.0, 0.0, 1.0); }\n");
	if (hl_shader_build(vs_ok, src, &prog, log, sizeof(log)) != 0)
		fail_msg("%s", log);
	glDeleteProgram(prog);
	free(src);
	/* an error on main_src's line 4 is reported at line 4, after 3 inserted lines */
	src = hl_shader_compose(broken, "#define A 0.5", "highp float f() { return 0.25; }");
	assert_non_null(src);
	assert_int_equal(hl_shader_build(vs_ok, src, &prog, log, sizeof(log)), -EINVAL);
	assert_non_null(strstr(log, "0:4("));
	free(src);
	src = hl_shader_compose(main_src, "", "");
	assert_string_equal(src,
			    "#version 300 es\n\n\n#line 2\nprecision highp float;\n"
			    "out vec4 o;\nvoid main() { o = vec4(A + f(), 0.0, 0.0, 1.0); }\n");
	free(src);
	assert_null(hl_shader_compose("precision highp float;\n#version 300 es\n", "", ""));
	assert_null(hl_shader_compose("#version 300 es", "", "")); /* no line after it */
	assert_null(hl_shader_compose("", "", ""));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(shader_build_links_and_draws_its_colour),
		cmocka_unit_test(shader_vertex_error_returns_its_log_and_leaks_nothing),
		cmocka_unit_test(shader_fragment_error_returns_its_log_and_leaks_nothing),
		cmocka_unit_test(shader_link_error_returns_its_log_and_leaks_nothing),
		cmocka_unit_test(shader_log_small_or_absent_is_safe),
		cmocka_unit_test(shader_compose_exact_text_and_main_src_line_numbers),
	};

	return cmocka_run_group_tests(tests, egl_setup, egl_teardown);
}
