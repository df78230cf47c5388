/* SPDX-License-Identifier: MIT */
#include "lamp/preset.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <jansson.h>

#include "base/json_check.h"

int hl_preset_new(int n_sources, struct hl_preset **ret)
{
	struct hl_preset *p;

	if (n_sources < 1 || n_sources > HL_PRESET_MAX_SOURCES)
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

/* The shared JSON error as the preset's: the key path leads the message. Returns rc. */
static int to_preset_error(int rc, const struct hl_json_error *je, struct hl_preset_error *err)
{
	if (err) {
		err->line = je->line;
		err->column = je->column;
		snprintf(err->msg, sizeof(err->msg), "%s%s%s", je->key, je->key[0] ? ": " : "",
			 je->msg);
	}
	return rc;
}

/* root.side: an array of 1..HL_PRESET_MAX_SOURCES integers 0..63 into vals. */
static int read_values(const struct hl_json_ctx *c, const json_t *root, enum hl_side side,
		       uint8_t *vals, int *ret_n)
{
	const char *key = hl_side_name(side);
	const json_t *a = json_object_get(root, key);
	char p[HL_JSON_PATH_MAX];

	if (!a)
		return hl_json_fail(c, key,
				    "missing: expected both \"left\" and \"right\", each a list of "
				    "dimming values");
	if (!json_is_array(a) || json_array_size(a) == 0 ||
	    json_array_size(a) > HL_PRESET_MAX_SOURCES)
		return hl_json_fail(c, key, "expected a list of 1 to %d dimming values, found %s",
				    HL_PRESET_MAX_SOURCES,
				    !json_is_array(a)	    ? hl_json_type_name(a) :
				    json_array_size(a) == 0 ? "an empty list" :
							      "more");
	for (size_t k = 0; k < json_array_size(a); k++) {
		int v;

		if (hl_json_int(c, hl_json_index(p, sizeof(p), key, k), json_array_get(a, k), 0,
				HL_DIM_MAX, &v) < 0)
			return -EBADMSG;
		vals[k] = (uint8_t)v;
	}
	*ret_n = (int)json_array_size(a);
	return 0;
}

/* text (the contents of the file name) into a preset; err filled on failure. */
static int parse(const char *text, const char *name, struct hl_preset **ret,
		 struct hl_json_error *err)
{
	static const char *const keys[] = { "left", "right", NULL };
	struct hl_json_ctx c = { .name = name, .err = err };
	uint8_t *vals = NULL;
	int counts[2] = { 0, 0 }, rc;
	struct hl_preset *p = NULL;
	struct hl_json_loc *loc = NULL;
	json_t *root = NULL;

	rc = hl_json_parse(text, name, &root, &loc, err);
	if (rc < 0)
		return rc;
	c.loc = loc;
	vals = malloc(2 * HL_PRESET_MAX_SOURCES);
	if (!vals) {
		rc = -ENOMEM;
		snprintf(err->msg, sizeof(err->msg), "out of memory");
		goto out;
	}
	if (hl_json_check_object(&c, "", root, keys) < 0 ||
	    read_values(&c, root, HL_SIDE_LEFT, vals, &counts[0]) < 0 ||
	    read_values(&c, root, HL_SIDE_RIGHT, vals + HL_PRESET_MAX_SOURCES, &counts[1]) < 0) {
		rc = -EBADMSG;
		goto out;
	}
	if (counts[0] != counts[1]) {
		rc = hl_json_fail(&c, "right",
				  "has %d dimming values; expected as many as \"left\" (%d)",
				  counts[1], counts[0]);
		goto out;
	}
	rc = hl_preset_new(counts[0], &p);
	if (rc < 0) {
		snprintf(err->msg, sizeof(err->msg), "%s", strerror(-rc));
		goto out;
	}
	memcpy(p->dim[HL_SIDE_LEFT], vals, counts[0]);
	memcpy(p->dim[HL_SIDE_RIGHT], vals + HL_PRESET_MAX_SOURCES, counts[1]);
	*ret = p;
out:
	free(vals);
	hl_json_loc_free(loc);
	json_decref(root);
	return rc;
}

int hl_preset_parse(const char *text, struct hl_preset **ret, struct hl_preset_error *err)
{
	struct hl_json_error je;

	return to_preset_error(parse(text, "", ret, &je), &je, err);
}

int hl_preset_read(const char *path, struct hl_preset **ret, struct hl_preset_error *err)
{
	struct hl_json_error je;
	char *text;
	int rc;

	rc = hl_json_read_file(path, &text, &je);
	if (rc == 0) {
		rc = parse(text, path, ret, &je);
		free(text);
	}
	return rc < 0 ? to_preset_error(rc, &je, err) : 0;
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
