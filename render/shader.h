/* SPDX-License-Identifier: MIT */
/*
 * GLSL programs from the shaders under render/shaders/, which CMake embeds into the binary as
 * C strings (render/shaders.h, generated: hl_shader_<file stem>).
 *
 * Thread-safety: the thread that owns the current GL context (the render thread).
 */
#ifndef HL_RENDER_SHADER_H
#define HL_RENDER_SHADER_H

#include <stddef.h>

#include <GLES3/gl31.h>

/*
 * Compiles and links a vertex and a fragment shader into *ret_program.
 * 0, or -EINVAL with the compiler's or linker's info log in log (log_size bytes, optional);
 * on failure everything it created is deleted.
 */
int hl_shader_build(const char *vertex_src, const char *fragment_src, GLuint *ret_program,
		    char *log, size_t log_size);

/*
 * A shader source built from parts: main_src's #version line, then defines (lines, may be
 * empty), then include (a shared part such as render/shaders/lamp_lookup.glsl), then the rest
 * of main_src after a #line directive (so the compiler's line numbers are main_src's).
 * Allocated; the caller frees it. NULL when out of memory or main_src has no #version line.
 */
char *hl_shader_compose(const char *main_src, const char *defines, const char *include);

#endif
