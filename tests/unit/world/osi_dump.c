/* SPDX-License-Identifier: MIT */
/*
 * osi_dump: one serialized OSI message on stdin, decoded by world/osi_msg.c, printed as one JSON
 * object on stdout (doubles %.17g with a point, so they read back to the same bits, -0.0 too;
 * NAN as null) for test_osi_second_encoder.py to compare with what it encoded. Exit 0, 1 (not
 * decoded: the reason on stderr) or 2 (usage).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "world/osi_msg.h"

static void usage(FILE *out)
{
	fprintf(out, "usage: osi_dump --kind ground-truth|sensor-view < message\n"
		     "Decodes one serialized osi3.GroundTruth or osi3.SensorView and prints it as "
		     "JSON.\n");
}

static void num(double v)
{
	if (isnan(v))
		fputs("null", stdout);
	else if (isinf(v))
		fputs(v > 0 ? "Infinity" : "-Infinity", stdout);
	else {
		char text[32];

		/* "-0" would read back as the integer 0: a double always shows a point. */
		snprintf(text, sizeof(text), "%.17g", v);
		fputs(text, stdout);
		if (!strpbrk(text, ".e"))
			fputs(".0", stdout);
	}
}

static void vec(const char *name, const double v[3])
{
	printf(", \"%s\": [", name);
	for (int k = 0; k < 3; k++) {
		if (k)
			fputs(", ", stdout);
		num(v[k]);
	}
	fputs("]", stdout);
}

static void print_frame(const struct hl_osi_frame *f)
{
	printf("{\"kind\": \"%s\"", hl_osi_kind_name(f->kind));
	if (f->has_version)
		printf(", \"version\": [%u, %u, %u]", f->version[0], f->version[1], f->version[2]);
	if (f->has_timestamp)
		printf(", \"t_ns\": %lld", (long long)f->t_ns);
	if (f->has_host)
		printf(", \"host_id\": %llu", (unsigned long long)f->host_id);
	fputs(", \"objects\": [", stdout);
	for (int i = 0; i < f->n_objects; i++) {
		const struct hl_osi_object *o = &f->object[i];

		printf("%s{\"type\": %d", i ? ", " : "", o->type);
		if (o->has_id)
			printf(", \"id\": %llu", (unsigned long long)o->id);
		if (o->has_classification)
			printf(", \"vehicle_type\": %d, \"head_light\": %d, \"high_beam\": %d, "
			       "\"brake_light\": %d, \"tail_light\": %d",
			       o->vehicle_type, o->head_light, o->high_beam, o->brake_light,
			       o->tail_light);
		vec("dim_m", o->dim_m);
		vec("pos_m", o->pos_m);
		vec("rpy_rad", o->rpy_rad);
		vec("vel_mps", o->vel_mps);
		fputs("}", stdout);
	}
	fputs("], \"boundaries\": [", stdout);
	for (int i = 0; i < f->n_boundaries; i++) {
		const struct hl_osi_boundary *b = &f->boundary[i];

		printf("%s{\"id\": %llu, \"type\": %d, \"points\": [", i ? ", " : "",
		       (unsigned long long)b->id, b->type);
		for (int k = b->first; k < b->first + b->n; k++) {
			printf("%s{\"width_m\": ", k > b->first ? ", " : "");
			num(f->point_width_m[k]);
			vec("pos_m", f->point[k]);
			fputs("}", stdout);
		}
		fputs("]}", stdout);
	}
	fputs("]}\n", stdout);
}

/* All of stdin into a new buffer; NULL without memory or on a read error. */
static uint8_t *read_all(size_t *ret_len)
{
	size_t len = 0, cap = 65536;
	uint8_t *buf = malloc(cap), *bigger;

	while (buf) {
		len += fread(buf + len, 1, cap - len, stdin);
		if (ferror(stdin))
			break;
		if (feof(stdin)) {
			*ret_len = len;
			return buf;
		}
		cap *= 2;
		bigger = realloc(buf, cap);
		if (!bigger)
			break;
		buf = bigger;
	}
	free(buf);
	return NULL;
}

int main(int argc, char **argv)
{
	enum hl_osi_kind kind;
	struct hl_osi_frame *f;
	enum hl_osi_decode_result r;
	uint8_t *buf;
	size_t len;
	char why[256];

	if (argc == 2 && strcmp(argv[1], "--help") == 0) {
		usage(stdout);
		return 0;
	}
	if (argc != 3 || strcmp(argv[1], "--kind") != 0 || hl_osi_kind_parse(argv[2], &kind) < 0) {
		usage(stderr);
		return 2;
	}
	buf = read_all(&len);
	f = hl_osi_frame_new();
	if (!buf || !f) {
		fprintf(stderr, "osi_dump: stdin: cannot read it (or out of memory)\n");
		free(buf);
		hl_osi_frame_free(f);
		return 1;
	}
	r = hl_osi_decode(buf, len, kind, f, why, sizeof(why));
	if (r == HL_OSI_DECODE_OK)
		print_frame(f);
	else
		fprintf(stderr, "osi_dump: %s: %s\n",
			r == HL_OSI_DECODE_TOO_MANY ? "too many" : "malformed", why);
	free(buf);
	hl_osi_frame_free(f);
	return r == HL_OSI_DECODE_OK ? 0 : 1;
}
