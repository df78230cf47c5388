/* SPDX-License-Identifier: MIT */
/*
 * What test_inputs and test_inputs_decoder share: the shipped dbc/hd84_inputs.dbc read and
 * parsed, its input map and a decoder, as a cmocka fixture (setup / teardown).
 */
#ifndef HL_TEST_INPUTS_FIXTURE_H
#define HL_TEST_INPUTS_FIXTURE_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "can/inputs.h"

static inline char *read_text(size_t *ret_len)
{
	char path[512];
	FILE *f;
	char *buf;
	long n;

	snprintf(path, sizeof(path), "%s/dbc/hd84_inputs.dbc", getenv("HL_SOURCE_DIR"));
	f = fopen(path, "rb");
	assert_non_null(f);
	fseek(f, 0, SEEK_END);
	n = ftell(f);
	fseek(f, 0, SEEK_SET);
	buf = malloc((size_t)n + 1);
	assert_non_null(buf);
	assert_int_equal(fread(buf, 1, (size_t)n, f), (size_t)n);
	buf[n] = '\0';
	fclose(f);
	*ret_len = (size_t)n;
	return buf;
}

static inline struct hl_dbc *parse(const char *text)
{
	struct hl_dbc *db = NULL;
	struct hl_dbc_error err;

	if (hl_dbc_parse(text, strlen(text), &db, &err) < 0)
		fail_msg("%d:%d: %s", err.line, err.column, err.msg);
	return db;
}

struct fixture {
	struct hl_dbc *db;
	struct hl_inputs_map *map;
	struct hl_inputs_decoder *dec;
};

static inline int setup(void **state)
{
	struct fixture *f = calloc(1, sizeof(*f));
	char msg[256] = "";
	size_t len;
	char *text = read_text(&len);

	f->db = parse(text);
	free(text);
	if (hl_inputs_map_new(f->db, &f->map, msg, sizeof(msg)) < 0)
		fail_msg("%s", msg);
	assert_int_equal(hl_inputs_decoder_new(f->map, &f->dec), 0);
	*state = f;
	return 0;
}

static inline int teardown(void **state)
{
	struct fixture *f = *state;

	hl_inputs_decoder_free(f->dec);
	hl_inputs_map_free(f->map);
	hl_dbc_free(f->db);
	free(f);
	return 0;
}

#endif
