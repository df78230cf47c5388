/* SPDX-License-Identifier: MIT */
#include "render/shader.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static GLuint compile(GLenum type, const char *src, char *log, size_t log_size)
{
	GLuint s = glCreateShader(type);
	GLint ok = GL_FALSE;

	if (!s) {
		if (log && log_size)
			snprintf(log, log_size, "glCreateShader failed (0x%04x)", glGetError());
		return 0;
	}
	glShaderSource(s, 1, &src, NULL);
	glCompileShader(s);
	glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
	if (!ok) {
		if (log && log_size) {
			int n = snprintf(log, log_size, "%s shader: ",
					 type == GL_VERTEX_SHADER ? "vertex" : "fragment");

			if (n > 0 && (size_t)n < log_size)
				glGetShaderInfoLog(s, (GLsizei)(log_size - n), NULL, log + n);
		}
		glDeleteShader(s);
		return 0;
	}
	return s;
}

int hl_shader_build(const char *vertex_src, const char *fragment_src, GLuint *ret_program,
		    char *log, size_t log_size)
{
	GLuint vs, fs, prog;
	GLint ok = GL_FALSE;

	vs = compile(GL_VERTEX_SHADER, vertex_src, log, log_size);
	if (!vs)
		return -EINVAL;
	fs = compile(GL_FRAGMENT_SHADER, fragment_src, log, log_size);
	if (!fs) {
		glDeleteShader(vs);
		return -EINVAL;
	}
	prog = glCreateProgram();
	glAttachShader(prog, vs);
	glAttachShader(prog, fs);
	glLinkProgram(prog);
	glDeleteShader(vs);
	glDeleteShader(fs);
	glGetProgramiv(prog, GL_LINK_STATUS, &ok);
	if (!ok) {
		if (log && log_size) {
			int n = snprintf(log, log_size, "link: ");

			if (n > 0 && (size_t)n < log_size)
				glGetProgramInfoLog(prog, (GLsizei)(log_size - n), NULL, log + n);
		}
		glDeleteProgram(prog);
		return -EINVAL;
	}
	*ret_program = prog;
	return 0;
}

char *hl_shader_compose(const char *main_src, const char *defines, const char *include)
{
	const char *body = strchr(main_src, '\n');
	size_t n;
	char *src;

	if (!body || strncmp(main_src, "#version", 8) != 0)
		return NULL;
	n = strlen(main_src) + strlen(defines) + strlen(include) + 32;
	src = malloc(n);
	if (!src)
		return NULL;
	snprintf(src, n, "%.*s\n%s\n%s\n#line 2\n%s", (int)(body - main_src), main_src, defines,
		 include, body + 1);
	return src;
}
