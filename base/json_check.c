/* SPDX-License-Identifier: MIT */
/* Strict checks of JSON with key paths, lines and columns (base/json_check.h). */
#include "base/json_check.h"

#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct entry {
	char *path;
	int line, column;
};

struct hl_json_loc {
	struct entry *e;
	size_t n, cap;
};

struct scan {
	const char *p;
	const char *line_start;
	int line;
	char path[HL_JSON_PATH_MAX];
	struct hl_json_loc *loc;
	int err;
};

static void skip_ws(struct scan *s)
{
	for (; *s->p == ' ' || *s->p == '\t' || *s->p == '\r' || *s->p == '\n'; s->p++)
		if (*s->p == '\n') {
			s->line++;
			s->line_start = s->p + 1;
		}
}

static void add(struct scan *s, int line, int column)
{
	struct hl_json_loc *loc = s->loc;

	if (s->err)
		return;
	if (loc->n == loc->cap) {
		const size_t cap = loc->cap ? 2 * loc->cap : 64;
		struct entry *e = realloc(loc->e, cap * sizeof(*e));

		if (!e) {
			s->err = -ENOMEM;
			return;
		}
		loc->e = e;
		loc->cap = cap;
	}
	loc->e[loc->n].path = strdup(s->path);
	if (!loc->e[loc->n].path) {
		s->err = -ENOMEM;
		return;
	}
	loc->e[loc->n].line = line;
	loc->e[loc->n].column = column;
	loc->n++;
}

/* A string at s->p ('"'); its text (escapes other than \" and \\ kept as written) into out. */
static void string(struct scan *s, char *out, size_t size)
{
	size_t n = 0;

	s->p++;
	while (*s->p && *s->p != '"') {
		char c = *s->p++;

		if (c == '\\' && *s->p) {
			c = *s->p++;
			if (c != '"' && c != '\\' && n + 1 < size)
				out[n++] = '\\';
		}
		if (n + 1 < size)
			out[n++] = c;
	}
	if (*s->p == '"')
		s->p++;
	else
		s->err = -EBADMSG;
	if (size)
		out[n] = '\0';
}

static void value(struct scan *s, int depth);

/* Appends a component to s->path; false when it does not fit (then nothing is recorded). */
static bool push(struct scan *s, const char *fmt, const char *key, size_t index)
{
	const size_t len = strlen(s->path);
	int n;

	if (key)
		n = snprintf(s->path + len, sizeof(s->path) - len, fmt, len ? "." : "", key);
	else
		n = snprintf(s->path + len, sizeof(s->path) - len, fmt, index);
	if (n < 0 || (size_t)n >= sizeof(s->path) - len) {
		s->path[len] = '\0';
		return false;
	}
	return true;
}

static void object(struct scan *s, int depth)
{
	char key[HL_JSON_PATH_MAX];

	s->p++;
	for (;;) {
		const size_t len = strlen(s->path);
		int line, column;

		skip_ws(s);
		if (*s->p == '}') {
			s->p++;
			return;
		}
		if (*s->p != '"') {
			s->err = -EBADMSG;
			return;
		}
		line = s->line;
		column = (int)(s->p - s->line_start) + 1;
		string(s, key, sizeof(key));
		if (push(s, "%s%s", key, 0))
			add(s, line, column);
		skip_ws(s);
		if (*s->p != ':') {
			s->err = -EBADMSG;
			return;
		}
		s->p++;
		value(s, depth + 1);
		s->path[len] = '\0';
		if (s->err)
			return;
		skip_ws(s);
		if (*s->p == ',')
			s->p++;
		else if (*s->p != '}')
			s->err = -EBADMSG;
	}
}

static void array(struct scan *s, int depth)
{
	s->p++;
	for (size_t i = 0;; i++) {
		const size_t len = strlen(s->path);

		skip_ws(s);
		if (*s->p == ']') {
			s->p++;
			return;
		}
		if (push(s, "[%zu]", NULL, i))
			add(s, s->line, (int)(s->p - s->line_start) + 1);
		value(s, depth + 1);
		s->path[len] = '\0';
		if (s->err)
			return;
		skip_ws(s);
		if (*s->p == ',')
			s->p++;
		else if (*s->p != ']')
			s->err = -EBADMSG;
	}
}

static void value(struct scan *s, int depth)
{
	char dummy[1];

	skip_ws(s);
	if (depth > 256) {
		s->err = -EBADMSG;
		return;
	}
	switch (*s->p) {
	case '{':
		object(s, depth);
		break;
	case '[':
		array(s, depth);
		break;
	case '"':
		string(s, dummy, sizeof(dummy));
		break;
	case '\0':
		s->err = -EBADMSG;
		break;
	default: /* number, true, false, null */
		while (*s->p && !strchr(",]} \t\r\n", *s->p))
			s->p++;
		break;
	}
}

int hl_json_loc_new(const char *text, struct hl_json_loc **ret)
{
	struct hl_json_loc *loc = calloc(1, sizeof(*loc));
	struct scan s = { .p = text, .line_start = text, .line = 1, .loc = loc };

	if (!loc)
		return -ENOMEM;
	value(&s, 0);
	if (s.err) {
		hl_json_loc_free(loc);
		return s.err;
	}
	*ret = loc;
	return 0;
}

void hl_json_loc_free(struct hl_json_loc *loc)
{
	if (!loc)
		return;
	for (size_t i = 0; i < loc->n; i++)
		free(loc->e[i].path);
	free(loc->e);
	free(loc);
}

void hl_json_loc_find(const struct hl_json_loc *loc, const char *path, int *ret_line,
		      int *ret_column)
{
	char p[HL_JSON_PATH_MAX];

	snprintf(p, sizeof(p), "%s", path);
	*ret_line = 1;
	*ret_column = 1;
	while (loc && *p) {
		char *dot, *bracket;

		for (size_t i = 0; i < loc->n; i++)
			if (!strcmp(loc->e[i].path, p)) {
				*ret_line = loc->e[i].line;
				*ret_column = loc->e[i].column;
				return;
			}
		dot = strrchr(p, '.');
		bracket = strrchr(p, '[');
		if (dot && (!bracket || dot > bracket))
			*dot = '\0';
		else if (bracket)
			*bracket = '\0';
		else
			*p = '\0';
	}
}

const char *hl_json_error_format(const struct hl_json_error *err, char *buf, size_t size)
{
	char where[64] = "";

	if (err->line > 0 && err->column > 0)
		snprintf(where, sizeof(where), ":%d:%d", err->line, err->column);
	else if (err->line > 0)
		snprintf(where, sizeof(where), ":%d", err->line);
	snprintf(buf, size, "%s%s: %s%s%s", err->file, where, err->key, *err->key ? ": " : "",
		 err->msg);
	return buf;
}

#define MAX_FILE_BYTES ((size_t)64 << 20) /* a JSON file we read: at most 64 MiB */

int hl_json_read_file(const char *path, char **ret, struct hl_json_error *err)
{
	FILE *f = fopen(path, "re");
	char *text = NULL;
	size_t size = 0, len = 0;
	int rc;

	if (err) {
		memset(err, 0, sizeof(*err));
		snprintf(err->file, sizeof(err->file), "%s", path);
	}
	if (!f) {
		rc = -errno;
		if (err)
			snprintf(err->msg, sizeof(err->msg), "cannot open: %s", strerror(-rc));
		return rc;
	}
	/* the buffer doubles (reading is linear in the file's size); it holds at most
	 * MAX_FILE_BYTES and the NUL, and one byte more tells a larger file apart */
	for (;;) {
		size_t n;

		if (len + 1 >= size) {
			const size_t want = size ? (size * 2 < MAX_FILE_BYTES + 2 ?
							    size * 2 :
							    MAX_FILE_BYTES + 2) :
						   65536;
			char *t = want > size ? realloc(text, want) : NULL;

			if (!t) {
				rc = want > size ? -ENOMEM : -EFBIG;
				if (err)
					snprintf(err->msg, sizeof(err->msg), "%s",
						 rc == -EFBIG ? "larger than 64 MiB" :
								"out of memory");
				goto err_free;
			}
			text = t;
			size = want;
		}
		n = fread(text + len, 1, size - len - 1, f);
		len += n;
		if (len > MAX_FILE_BYTES) {
			rc = -EFBIG;
			if (err)
				snprintf(err->msg, sizeof(err->msg), "larger than 64 MiB");
			goto err_free;
		}
		if (n == 0)
			break;
	}
	if (ferror(f)) {
		rc = -EIO;
		if (err)
			snprintf(err->msg, sizeof(err->msg), "read error");
		goto err_free;
	}
	text[len] = '\0';
	if (strlen(text) != len) {
		rc = -EBADMSG;
		if (err)
			snprintf(err->msg, sizeof(err->msg),
				 "expected JSON text, found a NUL byte");
		goto err_free;
	}
	fclose(f);
	*ret = text;
	return 0;

err_free:
	free(text);
	fclose(f);
	return rc;
}

int hl_json_fail(const struct hl_json_ctx *c, const char *path, const char *fmt, ...)
{
	va_list ap;

	if (!c->err)
		return -EBADMSG;
	snprintf(c->err->file, sizeof(c->err->file), "%s", c->name);
	snprintf(c->err->key, sizeof(c->err->key), "%s", path);
	hl_json_loc_find(c->loc, path, &c->err->line, &c->err->column);
	va_start(ap, fmt);
	vsnprintf(c->err->msg, sizeof(c->err->msg), fmt, ap);
	va_end(ap);
	return -EBADMSG;
}

int hl_json_parse(const char *text, const char *name, struct json_t **ret_root,
		  struct hl_json_loc **ret_loc, struct hl_json_error *err)
{
	struct hl_json_loc *loc;
	json_error_t jerr;
	json_t *root;
	int rc;

	if (err) {
		memset(err, 0, sizeof(*err));
		snprintf(err->file, sizeof(err->file), "%s", name);
	}
	root = json_loads(text, JSON_REJECT_DUPLICATES, &jerr);
	if (!root) {
		if (err) { /* jansson's place, at least line 1, column 1 */
			err->line = jerr.line > 0 ? jerr.line : 1;
			err->column = jerr.column > 0 ? jerr.column : 1;
			snprintf(err->msg, sizeof(err->msg), "%s", jerr.text);
		}
		return -EBADMSG;
	}
	rc = hl_json_loc_new(text, &loc);
	if (rc < 0) {
		if (err)
			snprintf(err->msg, sizeof(err->msg), "%s", strerror(-rc));
		json_decref(root);
		return rc;
	}
	*ret_root = root;
	*ret_loc = loc;
	return 0;
}

const char *hl_json_type_name(const struct json_t *j)
{
	switch (json_typeof(j)) {
	case JSON_OBJECT:
		return "an object";
	case JSON_ARRAY:
		return "an array";
	case JSON_STRING:
		return "a string";
	case JSON_INTEGER:
	case JSON_REAL:
		return "a number";
	case JSON_TRUE:
	case JSON_FALSE:
		return "a boolean";
	default:
		return "null";
	}
}

/* path.key (or key at the top) into buf. */
const char *hl_json_join(char *buf, size_t size, const char *path, const char *key)
{
	/* A path too long for buf is cut; it then names an ancestor's place. */
	if (snprintf(buf, size, "%s%s%s", path, *path ? "." : "", key) >= (int)size)
		buf[size - 1] = '\0';
	return buf;
}

const char *hl_json_index(char *buf, size_t size, const char *path, size_t i)
{
	if (snprintf(buf, size, "%s[%zu]", path, i) >= (int)size)
		buf[size - 1] = '\0';
	return buf;
}

/* j must be an object whose keys are all in allowed (NULL-terminated). */
int hl_json_check_object(const struct hl_json_ctx *c, const char *path, const struct json_t *j,
			 const char *const *allowed)
{
	char sub[HL_JSON_PATH_MAX], list[256];
	const char *key;
	json_t *val;
	size_t n = 0;

	if (!json_is_object(j))
		return hl_json_fail(c, path, "expected an object, found %s", hl_json_type_name(j));
	list[0] = '\0';
	for (const char *const *a = allowed; *a && n < sizeof(list); a++)
		n += snprintf(list + n, sizeof(list) - n, "%s%s", a == allowed ? "" : ", ", *a);
	json_object_foreach((json_t *)j, key, val)
	{
		const char *const *a;

		for (a = allowed; *a; a++)
			if (!strcmp(*a, key))
				break;
		if (!*a)
			return hl_json_fail(c, hl_json_join(sub, sizeof(sub), path, key),
					    "unknown key '%s'; expected one of: %s", key, list);
	}
	return 0;
}

int hl_json_number(const struct hl_json_ctx *c, const char *path, const struct json_t *j,
		   const struct hl_json_range *r, double *ret)
{
	double x;

	if (!json_is_number(j))
		return hl_json_fail(c, path, "expected a number in %c%g, %g] %s, found %s",
				    r->lo_open ? '(' : '[', r->lo, r->hi, r->unit,
				    hl_json_type_name(j));
	x = json_number_value(j);
	if (!isfinite(x) || (r->lo_open ? !(x > r->lo) : !(x >= r->lo)) || !(x <= r->hi))
		return hl_json_fail(c, path,
				    "%g is out of range: expected a number in %c%g, %g] %s", x,
				    r->lo_open ? '(' : '[', r->lo, r->hi, r->unit);
	*ret = x;
	return 0;
}

/* obj.key as a number in r; absent: an error when required, else *ret keeps its default. */
int hl_json_get_number(const struct hl_json_ctx *c, const char *path, const struct json_t *obj,
		       const char *key, bool required, const struct hl_json_range *r, double *ret)
{
	const struct json_t *j = json_object_get(obj, key);
	char sub[HL_JSON_PATH_MAX];

	hl_json_join(sub, sizeof(sub), path, key);
	if (!j) {
		if (required)
			return hl_json_fail(c, sub, "missing: expected a number in %c%g, %g] %s",
					    r->lo_open ? '(' : '[', r->lo, r->hi, r->unit);
		return 0;
	}
	return hl_json_number(c, sub, j, r, ret);
}

int hl_json_int(const struct hl_json_ctx *c, const char *path, const struct json_t *j, int lo,
		int hi, int *ret)
{
	if (!json_is_integer(j))
		return hl_json_fail(c, path, "expected an integer in [%d, %d], found %s", lo, hi,
				    json_is_real(j) ? "a number with a decimal point" :
						      hl_json_type_name(j));
	if (json_integer_value(j) < lo || json_integer_value(j) > hi)
		return hl_json_fail(c, path,
				    "%lld is out of range: expected an integer in [%d, %d]",
				    (long long)json_integer_value(j), lo, hi);
	*ret = (int)json_integer_value(j);
	return 0;
}

int hl_json_get_int(const struct hl_json_ctx *c, const char *path, const struct json_t *obj,
		    const char *key, bool required, int lo, int hi, int *ret)
{
	const struct json_t *j = json_object_get(obj, key);
	char sub[HL_JSON_PATH_MAX];

	hl_json_join(sub, sizeof(sub), path, key);
	if (!j) {
		if (required)
			return hl_json_fail(c, sub, "missing: expected an integer in [%d, %d]", lo,
					    hi);
		return 0;
	}
	return hl_json_int(c, sub, j, lo, hi, ret);
}

/* obj.key as one of names (NULL-terminated); its index into *ret. */
int hl_json_get_enum(const struct hl_json_ctx *c, const char *path, const struct json_t *obj,
		     const char *key, bool required, const char *const *names, int *ret)
{
	const struct json_t *j = json_object_get(obj, key);
	char sub[HL_JSON_PATH_MAX], list[160];
	size_t n = 0;

	list[0] = '\0';
	for (const char *const *a = names; *a && n < sizeof(list); a++)
		n += snprintf(list + n, sizeof(list) - n, "%s\"%s\"", a == names ? "" : ", ", *a);
	hl_json_join(sub, sizeof(sub), path, key);
	if (!j) {
		if (required)
			return hl_json_fail(c, sub, "missing: expected one of %s", list);
		return 0;
	}
	if (!json_is_string(j))
		return hl_json_fail(c, sub, "expected one of %s, found %s", list,
				    hl_json_type_name(j));
	for (int k = 0; names[k]; k++)
		if (!strcmp(names[k], json_string_value(j))) {
			*ret = k;
			return 0;
		}
	return hl_json_fail(c, sub, "expected one of %s, found \"%s\"", list, json_string_value(j));
}

int hl_json_get_string(const struct hl_json_ctx *c, const char *path, const struct json_t *obj,
		       const char *key, bool required, char *out, size_t size)
{
	const struct json_t *j = json_object_get(obj, key);
	char sub[HL_JSON_PATH_MAX];

	hl_json_join(sub, sizeof(sub), path, key);
	if (!j) {
		if (required)
			return hl_json_fail(c, sub, "missing: expected a non-empty string");
		return 0;
	}
	if (!json_is_string(j) || !json_string_length(j))
		return hl_json_fail(c, sub, "expected a non-empty string, found %s",
				    json_is_string(j) ? "an empty one" : hl_json_type_name(j));
	if (json_string_length(j) >= size)
		return hl_json_fail(c, sub, "expected at most %zu characters, found %zu", size - 1,
				    json_string_length(j));
	memcpy(out, json_string_value(j), json_string_length(j) + 1);
	return 0;
}

/* obj.key as [x, y, z], each in r[k]. */
int hl_json_get_vec3(const struct hl_json_ctx *c, const char *path, const struct json_t *obj,
		     const char *key, bool required, const struct hl_json_range r[3], double ret[3])
{
	const struct json_t *j = json_object_get(obj, key);
	char sub[HL_JSON_PATH_MAX], el[HL_JSON_PATH_MAX];

	hl_json_join(sub, sizeof(sub), path, key);
	if (!j) {
		if (required)
			return hl_json_fail(c, sub, "missing: expected [x, y, z] in %s", r[0].unit);
		return 0;
	}
	if (!json_is_array(j) || json_array_size(j) != 3)
		return hl_json_fail(c, sub, "expected [x, y, z] in %s, found %s", r[0].unit,
				    json_is_array(j) ? "another number of elements" :
						       hl_json_type_name(j));
	for (int k = 0; k < 3; k++)
		if (hl_json_number(c, hl_json_index(el, sizeof(el), sub, k), json_array_get(j, k),
				   &r[k], &ret[k]) < 0)
			return -EBADMSG;
	return 0;
}

int hl_json_parse_struct(const char *text, const char *name, size_t size,
			 hl_json_struct_fn parse_root, void **ret, struct hl_json_error *err)
{
	struct hl_json_ctx c = { .name = name, .err = err };
	struct hl_json_loc *loc = NULL;
	json_t *root = NULL;
	void *out;
	int rc;

	rc = hl_json_parse(text, name, &root, &loc, err);
	if (rc < 0)
		return rc;
	out = calloc(1, size);
	if (!out) {
		rc = -ENOMEM;
		if (err)
			snprintf(err->msg, sizeof(err->msg), "%s", strerror(-rc));
		goto err_free;
	}
	c.loc = loc;
	rc = parse_root(&c, root, out);
	if (rc < 0)
		goto err_free;
	hl_json_loc_free(loc);
	json_decref(root);
	*ret = out;
	return 0;

err_free:
	free(out);
	hl_json_loc_free(loc);
	json_decref(root);
	return rc;
}

int hl_json_read_struct(const char *path, size_t size, hl_json_struct_fn parse_root, void **ret,
			struct hl_json_error *err)
{
	char *text;
	int rc = hl_json_read_file(path, &text, err);

	if (rc < 0)
		return rc;
	rc = hl_json_parse_struct(text, path, size, parse_root, ret, err);
	free(text);
	return rc;
}
