/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <GLES3/gl31.h>

#include "render/egl.h"
#include "render/shader.h"
#include "render/shaders.h"

static void egl_headless_context_reports_renderer(void **state)
{
	struct hl_egl *egl = NULL;
	struct hl_egl_error err = { "" };
	GLint major = 0, minor = 0;

	(void)state;
	unsetenv("EGL_PLATFORM");
	assert_int_equal(hl_egl_new(&egl, &err), 0);
	printf("platform %s, renderer %s, %s\n", hl_egl_platform(egl), hl_egl_renderer(egl),
	       hl_egl_version(egl));
	assert_true(strcmp(hl_egl_platform(egl), "device") == 0 ||
		    strcmp(hl_egl_platform(egl), "surfaceless") == 0);
	assert_true(strlen(hl_egl_renderer(egl)) > 0);
	assert_non_null(strstr(hl_egl_version(egl), "OpenGL ES"));
	glGetIntegerv(GL_MAJOR_VERSION, &major);
	glGetIntegerv(GL_MINOR_VERSION, &minor);
	assert_true(major > 3 || (major == 3 && minor >= 1));
	assert_true(hl_egl_float_targets(egl));
	assert_false(hl_egl_has_gl_extension(egl, "GL_HL_no_such_extension"));
	hl_egl_free(egl);
}

static void egl_forced_missing_platform_is_a_clear_error(void **state)
{
	struct hl_egl *egl = NULL;
	struct hl_egl_error err = { "" };

	(void)state;
	setenv("EGL_PLATFORM", "nonexistent", 1);
	assert_int_equal(hl_egl_new(&egl, &err), -ENODEV);
	assert_null(egl);
	assert_non_null(strstr(err.msg, "nonexistent"));
	unsetenv("EGL_PLATFORM");
}

static void egl_forced_surfaceless_platform(void **state)
{
	struct hl_egl *egl = NULL;
	struct hl_egl_error err = { "" };

	(void)state;
	setenv("EGL_PLATFORM", "surfaceless", 1);
	assert_int_equal(hl_egl_new(&egl, &err), 0);
	assert_string_equal(hl_egl_platform(egl), "surfaceless");
	hl_egl_free(egl);
	unsetenv("EGL_PLATFORM");
	hl_egl_free(NULL);
}

static void shader_build_returns_info_log(void **state)
{
	struct hl_egl *egl = NULL;
	struct hl_egl_error err;
	GLuint prog = 0;
	char log[1024] = "", *src;

	(void)state;
	assert_int_equal(hl_egl_new(&egl, &err), 0);
	/* the headlight pass needs the shared lamp lookup: alone it does not compile */
	assert_int_equal(hl_shader_build(hl_shader_quad_vert, hl_shader_headlight_frag, &prog, log,
					 sizeof(log)),
			 -EINVAL);
	assert_non_null(strstr(log, "u_lid0"));
	src = hl_shader_compose(hl_shader_headlight_frag, "#define HL_PASS 0",
				hl_shader_lamp_lookup);
	assert_non_null(src);
	{
		static const char head[] = "#version 300 es\n#define HL_PASS 0\n";

		assert_true(strncmp(src, head, sizeof(head) - 1) == 0);
	}
	assert_int_equal(hl_shader_build(hl_shader_quad_vert, src, &prog, log, sizeof(log)), 0);
	free(src);
	assert_true(prog != 0);
	glDeleteProgram(prog);
	prog = 0;
	assert_null(hl_shader_compose("void main() {}\n", "", hl_shader_lamp_lookup));
	assert_int_equal(hl_shader_build(hl_shader_quad_vert,
					 "#version 300 es\nvoid main() { undefined_thing(); }\n",
					 &prog, log, sizeof(log)),
			 -EINVAL);
	assert_int_equal(prog, 0);
	assert_non_null(strstr(log, "fragment shader"));
	assert_non_null(strstr(log, "undefined_thing"));
	hl_egl_free(egl);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(egl_headless_context_reports_renderer),
		cmocka_unit_test(egl_forced_missing_platform_is_a_clear_error),
		cmocka_unit_test(egl_forced_surfaceless_platform),
		cmocka_unit_test(shader_build_returns_info_log),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
