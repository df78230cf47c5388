/* SPDX-License-Identifier: MIT */
/*
 * hdlampd's configuration file (daemon/core/config.h: hl_config_load): an INI file read with inih,
 * each key handed to hl_config_set with the line it is on, and a key set twice warned about
 * with both lines.
 */
#include <ctype.h>
#include <errno.h>
#include <ini.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "daemon/core/config.h"

/* A key line of the file: where inih will find it. */
struct key_line {
	char section[64], name[64];
	int line;
	bool used; /* handed to the handler */
};

struct load_ctx {
	struct hl_config *cfg;
	const char *path;
	struct hl_config_error *err, scratch;
	struct key_line *lines;
	int n_lines;
	int rc, bad_line; /* the first refused key's line */
};

/* Trims white space at both ends of s[0..n) into dst. */
static void trimmed(char *dst, size_t size, const char *s, size_t n)
{
	while (n && isspace((unsigned char)*s))
		s++, n--;
	while (n && isspace((unsigned char)s[n - 1]))
		n--;
	snprintf(dst, size, "%.*s", (int)(n < size ? n : size - 1), s);
}

/*
 * The key lines of the file in order, with their sections, as inih reads them (a section
 * header, "name = value" or "name : value", ; and # comments). inih (as Debian builds it)
 * gives the handler no line number; this scan does.
 */
static int scan_lines(FILE *f, struct load_ctx *c)
{
	char buf[4096], section[64] = "";
	int line = 0, cap = 0;

	rewind(f);
	while (fgets(buf, sizeof(buf), f)) {
		const char *p = buf, *end;
		size_t n;

		line++;
		if (line == 1 && strncmp(p, "\xEF\xBB\xBF", 3) == 0)
			p += 3; /* a UTF-8 byte order mark, which inih skips too */
		while (*p == ' ' || *p == '\t')
			p++;
		if (*p == ';' || *p == '#' || *p == '\n' || *p == '\r' || !*p)
			continue;
		if (*p == '[') {
			if ((end = strchr(p, ']')))
				trimmed(section, sizeof(section), p + 1, (size_t)(end - p - 1));
			continue;
		}
		n = strcspn(p, "=:");
		if (!p[n])
			continue;
		if (c->n_lines == cap) {
			struct key_line *kl = realloc(c->lines, sizeof(*kl) * (cap ? cap * 2 : 32));

			if (!kl)
				return -ENOMEM;
			c->lines = kl;
			cap = cap ? cap * 2 : 32;
		}
		c->lines[c->n_lines] = (struct key_line){ .line = line };
		snprintf(c->lines[c->n_lines].section, sizeof(c->lines[0].section), "%s", section);
		trimmed(c->lines[c->n_lines].name, sizeof(c->lines[0].name), p, n);
		c->n_lines++;
	}
	rewind(f);
	return 0;
}

static void warn(struct hl_config_error *err, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));

static void warn(struct hl_config_error *err, const char *fmt, ...)
{
	va_list ap;

	if (err->n_warnings < HL_CONFIG_MAX_WARNINGS) {
		va_start(ap, fmt);
		vsnprintf(err->warnings[err->n_warnings], sizeof(err->warnings[0]), fmt, ap);
		va_end(ap);
	}
	err->n_warnings++;
}

static int on_pair(void *user, const char *section, const char *name, const char *value)
{
	struct load_ctx *c = user;
	int line = 0, first = 0;

	if (c->rc < 0)
		return 0;
	/* this key's next line in the file; an earlier one of the same key is a duplicate */
	for (int i = 0; i < c->n_lines && !line; i++) {
		if (strcmp(c->lines[i].section, section) != 0 ||
		    strcmp(c->lines[i].name, name) != 0)
			continue;
		if (c->lines[i].used && !first)
			first = c->lines[i].line;
		if (!c->lines[i].used) {
			c->lines[i].used = true;
			line = c->lines[i].line;
		}
	}
	if (first && line)
		warn(c->err,
		     "'%s':%d: warning: key '%s.%s' set again (first at line %d); the last "
		     "value counts",
		     c->path, line, section, name, first);
	c->rc = hl_config_set(c->cfg, section, name, value, c->path, line, c->err);
	if (c->rc < 0)
		c->bad_line = line;
	return c->rc == 0;
}

int hl_config_load(struct hl_config *cfg, const char *path, struct hl_config_error *err)
{
	struct load_ctx c = { .cfg = cfg, .path = path, .err = err ? err : &c.scratch };
	struct stat st;
	FILE *f;
	int line, rc = 0;

	c.err->n_warnings = 0;
	f = fopen(path, "re");
	if (!f) {
		rc = -errno;
		snprintf(c.err->msg, sizeof(c.err->msg), "'%s': %s", path, strerror(errno));
		return rc;
	}
	/* fopen() opens a directory and reading it yields nothing: refuse it */
	if (fstat(fileno(f), &st) == 0 && S_ISDIR(st.st_mode)) {
		snprintf(c.err->msg, sizeof(c.err->msg), "'%s': a directory; expected an INI file",
			 path);
		rc = -EINVAL;
		goto out;
	}
	rc = scan_lines(f, &c);
	if (rc < 0) {
		snprintf(c.err->msg, sizeof(c.err->msg), "'%s': %s", path, strerror(-rc));
		goto out;
	}
	line = ini_parse_file(f, on_pair, &c);
	/* the first fault is either the refused key (err says why) or a syntax error before it */
	if (c.rc < 0 && (c.bad_line == line || c.bad_line == 0)) {
		rc = -EINVAL;
	} else if (line != 0 || c.rc < 0) {
		snprintf(c.err->msg, sizeof(c.err->msg),
			 "'%s':%d: expected [section], key = value, or a ; comment", path,
			 line ? line : c.bad_line);
		rc = -EINVAL;
	}
out:
	free(c.lines);
	fclose(f);
	return rc;
}
