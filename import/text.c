/* SPDX-License-Identifier: MIT */
#include "import/text.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

void hl_text_init(struct hl_text *t, const char *buf, size_t len, const char *name,
		  struct hl_import_error *err)
{
	t->p = buf;
	t->end = buf + len;
	t->name = name;
	t->line = 1;
	t->col = 1;
	t->err = err;
}

static void vfill(struct hl_import_error *err, const char *name, int line, int col, const char *fmt,
		  va_list ap)
{
	char what[512];
	int n;

	vsnprintf(what, sizeof(what), fmt, ap);
	err->line = line;
	err->column = col;
	if (line > 0)
		n = snprintf(err->msg, sizeof(err->msg), "'%s':%d:%d: %s", name, line, col, what);
	else
		n = snprintf(err->msg, sizeof(err->msg), "'%s': %s", name, what);
	(void)n;
}

int hl_text_fail_at(struct hl_text *t, int line, int col, int rc, const char *fmt, ...)
{
	va_list ap;

	if (t->err) {
		va_start(ap, fmt);
		vfill(t->err, t->name, line, col, fmt, ap);
		va_end(ap);
	}
	return rc;
}

int hl_text_fail(struct hl_text *t, int rc, const char *fmt, ...)
{
	va_list ap;

	if (t->err) {
		va_start(ap, fmt);
		vfill(t->err, t->name, t->line, t->col, fmt, ap);
		va_end(ap);
	}
	return rc;
}

int hl_import_fail(struct hl_import_error *err, const char *name, int rc, const char *fmt, ...)
{
	va_list ap;

	if (err) {
		va_start(ap, fmt);
		vfill(err, name, 0, 0, fmt, ap);
		va_end(ap);
	}
	return rc;
}

bool hl_text_eof(const struct hl_text *t)
{
	return t->p >= t->end;
}

void hl_text_advance(struct hl_text *t)
{
	if (t->p >= t->end)
		return;
	if (*t->p == '\n') {
		t->line++;
		t->col = 1;
	} else {
		t->col++;
	}
	t->p++;
}

void hl_text_skip_blanks(struct hl_text *t, bool also_newlines, bool commas)
{
	while (t->p < t->end) {
		char c = *t->p;

		if (c == ' ' || c == '\t' || c == '\r' || (also_newlines && c == '\n') ||
		    (commas && c == ','))
			hl_text_advance(t);
		else
			break;
	}
}

bool hl_text_line(struct hl_text *t, const char **ret_s, size_t *ret_len)
{
	const char *s = t->p;
	size_t n;

	if (t->p >= t->end)
		return false;
	while (t->p < t->end && *t->p != '\n')
		t->p++;
	n = (size_t)(t->p - s);
	if (t->p < t->end)
		t->p++; /* the LF */
	t->line++;
	t->col = 1;
	if (n > 0 && s[n - 1] == '\r')
		n--;
	*ret_s = s;
	*ret_len = n;
	return true;
}

static bool is_digit(char c)
{
	return c >= '0' && c <= '9';
}

int hl_number_parse(const char *s, size_t len, double *ret)
{
	char buf[64];
	size_t i = 0, digits = 0;
	double v;

	if (len == 0 || len >= sizeof(buf))
		return -EBADMSG;
	if (s[i] == '+' || s[i] == '-')
		i++;
	while (i < len && is_digit(s[i])) {
		i++;
		digits++;
	}
	if (i < len && s[i] == '.') {
		i++;
		while (i < len && is_digit(s[i])) {
			i++;
			digits++;
		}
	}
	if (digits == 0)
		return -EBADMSG;
	if (i < len && (s[i] == 'e' || s[i] == 'E')) {
		size_t exp_digits = 0;

		i++;
		if (i < len && (s[i] == '+' || s[i] == '-'))
			i++;
		while (i < len && is_digit(s[i])) {
			i++;
			exp_digits++;
		}
		if (exp_digits == 0)
			return -EBADMSG;
	}
	if (i != len)
		return -EBADMSG;
	memcpy(buf, s, len);
	buf[len] = '\0';
	v = strtod(buf, NULL);
	if (!isfinite(v))
		return -EBADMSG;
	*ret = v;
	return 0;
}

/* The token at the cursor: up to blank, newline or (with commas) comma. */
static size_t token_len(const struct hl_text *t, bool commas)
{
	const char *q = t->p;

	while (q < t->end && *q != ' ' && *q != '\t' && *q != '\r' && *q != '\n' &&
	       !(commas && *q == ','))
		q++;
	return (size_t)(q - t->p);
}

static void show_token(const char *s, size_t n, char *out, size_t size)
{
	size_t j = 0;

	for (size_t i = 0; i < n && j + 5 < size; i++) {
		unsigned char c = (unsigned char)s[i];

		if (c >= 0x20 && c < 0x7f && c != '\'')
			out[j++] = (char)c;
		else
			j += (size_t)snprintf(out + j, size - j, "\\x%02x", c);
		if (i == 23 && n > 24) {
			snprintf(out + j, size - j, "...");
			return;
		}
	}
	out[j < size ? j : size - 1] = '\0';
}

int hl_text_number(struct hl_text *t, bool commas, const char *what, double *ret)
{
	size_t n;
	char shown[128];

	hl_text_skip_blanks(t, true, commas);
	if (hl_text_eof(t))
		return hl_text_fail(t, -EBADMSG, "expected %s, found the end of the file", what);
	n = token_len(t, commas);
	if (hl_number_parse(t->p, n, ret) < 0) {
		show_token(t->p, n, shown, sizeof(shown));
		return hl_text_fail(t, -EBADMSG,
				    "expected %s (a finite decimal number), found '%s'", what,
				    shown);
	}
	for (size_t i = 0; i < n; i++)
		hl_text_advance(t);
	return 0;
}

int hl_text_int(struct hl_text *t, bool commas, const char *what, long min, long max, long *ret)
{
	int line, col, rc;
	double v;

	hl_text_skip_blanks(t, true, commas);
	line = t->line; /* a number never spans lines: this is where it is */
	col = t->col;
	rc = hl_text_number(t, commas, what, &v);
	if (rc < 0)
		return rc;
	if (v != floor(v) || v < (double)min || v > (double)max)
		return hl_text_fail_at(t, line, col, -EBADMSG,
				       "expected %s, an integer from %ld to %ld, found %g", what,
				       min, max, v);
	*ret = (long)v;
	return 0;
}

int hl_import_read_file(const char *path, char **ret_buf, size_t *ret_len,
			struct hl_import_error *err)
{
	struct stat st;
	char *buf;
	size_t got = 0;
	int fd, rc;

	fd = open(path, O_RDONLY | O_CLOEXEC);
	if (fd < 0) {
		rc = -errno;
		return hl_import_fail(err, path, rc, "cannot open: %s", strerror(-rc));
	}
	if (fstat(fd, &st) < 0) {
		rc = -errno;
		hl_import_fail(err, path, rc, "cannot stat: %s", strerror(-rc));
		goto err_close_fd;
	}
	if (!S_ISREG(st.st_mode)) {
		rc = hl_import_fail(err, path, -EINVAL, "not a regular file");
		goto err_close_fd;
	}
	if ((unsigned long long)st.st_size > HL_IMPORT_MAX_FILE) {
		rc = hl_import_fail(err, path, -EFBIG, "larger than %u bytes", HL_IMPORT_MAX_FILE);
		goto err_close_fd;
	}
	buf = malloc((size_t)st.st_size + 1);
	if (!buf) {
		rc = hl_import_fail(err, path, -ENOMEM, "out of memory");
		goto err_close_fd;
	}
	while (got < (size_t)st.st_size) {
		ssize_t n = read(fd, buf + got, (size_t)st.st_size - got);

		if (n < 0 && errno == EINTR)
			continue;
		if (n <= 0) {
			rc = n < 0 ? -errno : -EIO;
			hl_import_fail(err, path, rc, "cannot read: %s", strerror(-rc));
			free(buf);
			goto err_close_fd;
		}
		got += (size_t)n;
	}
	buf[got] = '\0';
	close(fd);
	*ret_buf = buf;
	*ret_len = got;
	return 0;

err_close_fd:
	close(fd);
	return rc;
}
