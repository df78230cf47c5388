/* SPDX-License-Identifier: MIT */
#include "lamp/preset.h"

#include <errno.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int hl_preset_new(int n_sources, struct hl_preset **ret)
{
	struct hl_preset *p;

	if (n_sources < 1 || n_sources > 4096)
		return -EINVAL;
	p = calloc(1, sizeof(*p));
	if (!p)
		return -ENOMEM;
	p->n_sources = n_sources;
	p->dim[0] = calloc(n_sources, 1);
	p->dim[1] = calloc(n_sources, 1);
	if (!p->dim[0] || !p->dim[1]) {
		hl_preset_free(p);
		return -ENOMEM;
	}
	*ret = p;
	return 0;
}

void hl_preset_free(struct hl_preset *p)
{
	if (!p)
		return;
	free(p->dim[0]);
	free(p->dim[1]);
	free(p);
}

/* A strict reader for exactly the preset's shape; it knows where it is for error messages. */
struct cursor {
	const char *s;
	int line, col;
	struct hl_preset_error *err;
};

static int bad(struct cursor *c, const char *fmt, const char *what)
{
	if (c->err) {
		c->err->line = c->line;
		c->err->column = c->col;
		snprintf(c->err->msg, sizeof(c->err->msg), fmt, what);
	}
	return -EBADMSG;
}

static void advance(struct cursor *c)
{
	if (*c->s == '\n') {
		c->line++;
		c->col = 1;
	} else {
		c->col++;
	}
	c->s++;
}

static void skip_space(struct cursor *c)
{
	while (*c->s == ' ' || *c->s == '\t' || *c->s == '\n' || *c->s == '\r')
		advance(c);
}

static int expect(struct cursor *c, char ch, const char *what)
{
	skip_space(c);
	if (*c->s != ch)
		return bad(c, "expected %s", what);
	advance(c);
	return 0;
}

static int read_key(struct cursor *c, char *buf, size_t size)
{
	size_t n = 0;

	if (expect(c, '"', "'\"' starting a key (\"left\" or \"right\")") < 0)
		return -EBADMSG;
	while (*c->s && *c->s != '"' && *c->s != '\n') {
		if (n + 1 < size)
			buf[n++] = *c->s;
		advance(c);
	}
	buf[n] = '\0';
	return expect(c, '"', "'\"' closing the key");
}

/* Reads [v, v, ...] into a growing array; values are integers 0..63. */
static int read_values(struct cursor *c, uint8_t **ret, int *ret_n)
{
	uint8_t *v = NULL;
	int n = 0, cap = 0;

	if (expect(c, '[', "'[' starting the list of dimming values") < 0)
		return -EBADMSG;
	skip_space(c);
	if (*c->s == ']') {
		free(v);
		return bad(c, "%s", "expected at least one dimming value");
	}
	for (;;) {
		struct cursor at;
		long x = 0;
		int digits = 0;

		skip_space(c);
		at = *c; /* errors about a value point at its start */
		while (*c->s >= '0' && *c->s <= '9' && digits < 4) {
			x = x * 10 + (*c->s - '0');
			digits++;
			advance(c);
		}
		if (digits == 0 || (*c->s >= '0' && *c->s <= '9') || x > HL_DIM_MAX) {
			free(v);
			return bad(&at, "%s", "expected a dimming value: an integer 0..63");
		}
		if (n == cap) {
			uint8_t *g;

			cap = cap ? 2 * cap : 128;
			if (cap > 4096) {
				free(v);
				return bad(c, "%s", "more than 4096 dimming values");
			}
			g = realloc(v, cap);
			if (!g) {
				free(v);
				return -ENOMEM;
			}
			v = g;
		}
		v[n++] = (uint8_t)x;
		skip_space(c);
		if (*c->s == ']') {
			advance(c);
			break;
		}
		if (*c->s != ',') {
			free(v);
			return bad(c, "%s", "expected ',' or ']' after a dimming value");
		}
		advance(c);
	}
	*ret = v;
	*ret_n = n;
	return 0;
}

int hl_preset_parse(const char *text, struct hl_preset **ret, struct hl_preset_error *err)
{
	struct cursor c = { text, 1, 1, err };
	uint8_t *vals[2] = { NULL, NULL };
	int counts[2] = { 0, 0 }, rc;
	struct hl_preset *p;

	rc = expect(&c, '{', "'{' starting the preset object");
	while (rc == 0) {
		char key[32];
		int side;

		struct cursor at;

		skip_space(&c);
		at = c; /* errors about the key point at its start */
		rc = read_key(&c, key, sizeof(key));
		if (rc < 0)
			break;
		side = hl_side_from_name(key);
		if (side < 0 || vals[side]) {
			rc = bad(&at,
				 side < 0 ? "unknown key '%s'; expected \"left\" or \"right\"" :
					    "key '%s' given twice",
				 key);
			break;
		}
		rc = expect(&c, ':', "':' after the key");
		if (rc == 0)
			rc = read_values(&c, &vals[side], &counts[side]);
		if (rc < 0)
			break;
		skip_space(&c);
		if (*c.s == '}') {
			advance(&c);
			break;
		}
		rc = expect(&c, ',', "',' or '}' after a lamp's list");
	}
	if (rc == 0) {
		skip_space(&c);
		if (*c.s)
			rc = bad(&c, "%s", "expected the end of the file after '}'");
		else if (!vals[0] || !vals[1])
			rc = bad(&c, "%s", "expected both \"left\" and \"right\"");
		else if (counts[0] != counts[1])
			rc = bad(&c, "%s", "expected as many values for \"left\" as for \"right\"");
	}
	if (rc == 0)
		rc = hl_preset_new(counts[0], &p);
	if (rc == 0) {
		memcpy(p->dim[0], vals[0], counts[0]);
		memcpy(p->dim[1], vals[1], counts[1]);
		*ret = p;
	}
	free(vals[0]);
	free(vals[1]);
	return rc;
}

int hl_preset_read(const char *path, struct hl_preset **ret, struct hl_preset_error *err)
{
	FILE *f = fopen(path, "re");
	char *text;
	long size;
	int rc;

	if (err)
		*err = (struct hl_preset_error){ 0 };
	if (!f) {
		rc = -errno;
		if (err)
			snprintf(err->msg, sizeof(err->msg), "%s", strerror(errno));
		return rc;
	}
	if (fseek(f, 0, SEEK_END) < 0 || (size = ftell(f)) < 0 || fseek(f, 0, SEEK_SET) < 0 ||
	    size > (1 << 20)) {
		fclose(f);
		if (err)
			snprintf(err->msg, sizeof(err->msg),
				 "not a readable file of at most 1 MiB");
		return -EBADMSG;
	}
	text = malloc(size + 1);
	if (!text) {
		fclose(f);
		return -ENOMEM;
	}
	if (fread(text, 1, size, f) != (size_t)size) {
		free(text);
		fclose(f);
		return -EIO;
	}
	fclose(f);
	text[size] = '\0';
	if (strlen(text) != (size_t)size) {
		free(text);
		if (err)
			snprintf(err->msg, sizeof(err->msg), "contains a NUL byte");
		return -EBADMSG;
	}
	rc = hl_preset_parse(text, ret, err);
	free(text);
	return rc;
}

int hl_preset_write(const struct hl_preset *p, const char *path)
{
	FILE *f = fopen(path, "we");

	if (!f)
		return -errno;
	fprintf(f, "{\n");
	for (int s = 0; s < 2; s++) {
		fprintf(f, "  \"%s\": [", hl_side_name(s));
		for (int k = 0; k < p->n_sources; k++)
			fprintf(f, "%s%s%u", k ? "," : "", k % 16 == 0 ? "\n    " : " ",
				p->dim[s][k]);
		fprintf(f, "\n  ]%s\n", s == 0 ? "," : "");
	}
	fprintf(f, "}\n");
	if (fclose(f) != 0)
		return -EIO;
	return 0;
}

int hl_side_from_name(const char *name)
{
	if (strcmp(name, "left") == 0)
		return HL_SIDE_LEFT;
	if (strcmp(name, "right") == 0)
		return HL_SIDE_RIGHT;
	return -EINVAL;
}

const char *hl_side_name(enum hl_side side)
{
	return side == HL_SIDE_LEFT ? "left" : "right";
}

void hl_preset_intensities(const struct hl_preset *p, enum hl_side side, float *i)
{
	for (int k = 0; k < p->n_sources; k++)
		i[k] = (float)p->dim[side][k] / HL_DIM_MAX;
}
