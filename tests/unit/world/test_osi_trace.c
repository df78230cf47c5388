/* SPDX-License-Identifier: MIT */
/*
 * world/osi_trace.c: messages written with hl_osi_trace_write() read back byte for byte; the
 * file's bytes checked against OSI's framing written out here by hand; cut files reported with
 * the offset and what was expected; an absurd length refused; OSI's file naming convention.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "testutil.h"
#include "world/osi_trace.h"

/* A message of len bytes whose content depends on seed and position. */
static uint8_t *pattern(size_t len, unsigned seed)
{
	uint8_t *p = malloc(len ? len : 1);

	assert_non_null(p);
	for (size_t i = 0; i < len; i++)
		p[i] = (uint8_t)(i * 31 + seed * 7 + (i >> 8));
	return p;
}

static void write_bytes(const char *path, const void *buf, size_t len)
{
	FILE *f = fopen(path, "wb");

	assert_non_null(f);
	assert_int_equal(fwrite(buf, 1, len, f), len);
	assert_int_equal(fclose(f), 0);
}

static void trace_round_trip_0_1_1000_100000_bytes(void **state)
{
	static const size_t lens[] = { 0, 1, 1000, 100000 };
	uint8_t *msg[4];
	char path[256];
	struct hl_osi_trace *t = NULL;
	struct hl_osi_trace_msg m;
	uint64_t off = 0;
	FILE *f;

	(void)state;
	test_path(path, sizeof(path), "round.osi");
	f = fopen(path, "wb");
	assert_non_null(f);
	for (int i = 0; i < 4; i++) {
		msg[i] = pattern(lens[i], (unsigned)i);
		assert_int_equal(hl_osi_trace_write(f, msg[i], lens[i]), 0);
	}
	assert_int_equal(fclose(f), 0);

	assert_int_equal(hl_osi_trace_open(path, &t, NULL), HL_OSI_TRACE_COMPLETE);
	assert_int_equal(hl_osi_trace_count(t), 4);
	for (int i = 0; i < 4; i++) {
		assert_int_equal(hl_osi_trace_get(t, (size_t)i, &m), 0);
		off += HL_OSI_TRACE_PREFIX;
		assert_int_equal(m.offset, off);
		assert_int_equal(m.len, lens[i]);
		if (lens[i])
			assert_memory_equal(m.buf, msg[i], lens[i]);
		off += lens[i];
		free(msg[i]);
	}
	assert_int_equal(hl_osi_trace_get(t, 4, &m), -ERANGE);
	hl_osi_trace_free(t);
	unlink(path);
}

/* The bytes on disk are OSI's: a 4-byte little-endian length, then the message. */
static void trace_writes_little_endian_prefix(void **state)
{
	static const uint8_t want[] = { 0x03, 0x00, 0x00, 0x00, 'a', 'b',
					'c',  0x00, 0x01, 0x00, 0x00 };
	uint8_t *big = pattern(256, 1);
	uint8_t got[sizeof(want) + 256];
	char path[256];
	FILE *f;

	(void)state;
	test_path(path, sizeof(path), "le.osi");
	f = fopen(path, "wb");
	assert_non_null(f);
	assert_int_equal(hl_osi_trace_write(f, (const uint8_t *)"abc", 3), 0);
	assert_int_equal(hl_osi_trace_write(f, big, 256), 0);
	assert_int_equal(fclose(f), 0);
	f = fopen(path, "rb");
	assert_non_null(f);
	assert_int_equal(fread(got, 1, sizeof(got) + 1, f), sizeof(got));
	fclose(f);
	assert_memory_equal(got, want, sizeof(want));
	assert_memory_equal(got + sizeof(want), big, 256);
	free(big);
	unlink(path);
}

static void trace_empty_file_has_no_messages(void **state)
{
	struct hl_osi_trace *t = NULL;
	char path[256];

	(void)state;
	test_path(path, sizeof(path), "empty.osi");
	write_bytes(path, "", 0);
	assert_int_equal(hl_osi_trace_open(path, &t, NULL), HL_OSI_TRACE_COMPLETE);
	assert_int_equal(hl_osi_trace_count(t), 0);
	hl_osi_trace_free(t);
	unlink(path);
}

/* Two good messages (5 and 2 bytes: records at 0 and 9), then a cut third record at 15. */
static void trace_cut_in_the_prefix(void **state)
{
	static const uint8_t file[] = { 5, 0, 0, 0, 'h', 'e', 'l', 'l', 'o',
					2, 0, 0, 0, 'o', 'k', 7,   0 };
	struct hl_osi_trace_error err;
	struct hl_osi_trace *t = NULL;
	struct hl_osi_trace_msg m;
	char path[256];

	(void)state;
	test_path(path, sizeof(path), "cut_prefix.osi");
	write_bytes(path, file, sizeof(file));
	memset(&err, 0xff, sizeof(err));
	assert_int_equal(hl_osi_trace_open(path, &t, &err), HL_OSI_TRACE_TRUNCATED);
	assert_non_null(t);
	assert_int_equal(err.offset, 15);
	assert_int_equal(err.expected, 4);
	assert_int_equal(err.found, 2);
	assert_int_equal(err.length, 0);
	assert_int_equal(hl_osi_trace_count(t), 2);
	assert_int_equal(hl_osi_trace_get(t, 1, &m), 0);
	assert_int_equal(m.offset, 13);
	assert_int_equal(m.len, 2);
	assert_memory_equal(m.buf, "ok", 2);
	hl_osi_trace_free(t);
	unlink(path);
}

/* One good message, then a prefix promising 300 bytes of which 3 are there. */
static void trace_cut_in_the_body(void **state)
{
	static const uint8_t file[] = { 1, 0, 0, 0, 'x', 0x2c, 0x01, 0, 0, 'a', 'b', 'c' };
	struct hl_osi_trace_error err;
	struct hl_osi_trace *t = NULL;
	struct hl_osi_trace_msg m;
	char path[256];

	(void)state;
	test_path(path, sizeof(path), "cut_body.osi");
	write_bytes(path, file, sizeof(file));
	assert_int_equal(hl_osi_trace_open(path, &t, &err), HL_OSI_TRACE_TRUNCATED);
	assert_int_equal(err.offset, 5);
	assert_int_equal(err.length, 300);
	assert_int_equal(err.expected, 304);
	assert_int_equal(err.found, 7);
	assert_int_equal(hl_osi_trace_count(t), 1);
	assert_int_equal(hl_osi_trace_get(t, 0, &m), 0);
	assert_int_equal(m.len, 1);
	assert_int_equal(m.buf[0], 'x');
	hl_osi_trace_free(t);

	/* NULL for the error is fine */
	t = NULL;
	assert_int_equal(hl_osi_trace_open(path, &t, NULL), HL_OSI_TRACE_TRUNCATED);
	hl_osi_trace_free(t);
	unlink(path);
}

/* A length over the limit (here 0xFFFFFFF0, as random bytes would give) refuses the file. */
static void trace_absurd_length_refused(void **state)
{
	static const uint8_t file[] = { 2, 0, 0, 0, 'o', 'k', 0xf0, 0xff, 0xff, 0xff, 1, 2, 3 };
	struct hl_osi_trace_error err;
	struct hl_osi_trace *t = (struct hl_osi_trace *)&err; /* untouched on failure */
	char path[256];

	(void)state;
	test_path(path, sizeof(path), "absurd.osi");
	write_bytes(path, file, sizeof(file));
	assert_int_equal(hl_osi_trace_open(path, &t, &err), -EBADMSG);
	assert_ptr_equal(t, (struct hl_osi_trace *)&err);
	assert_int_equal(err.offset, 6);
	assert_int_equal(err.length, 0xfffffff0u);
	assert_int_equal(err.expected, 0xfffffff0ull + 4);
	assert_int_equal(err.found, 7);
	unlink(path);
}

/* The limit itself: HL_OSI_TRACE_MAX_MSG + 1 refused, by the writer and the reader. */
static void trace_limit_is_64_mib(void **state)
{
	uint8_t file[4] = { 0x01, 0x00, 0x00, 0x04 }; /* 64 MiB + 1 */
	struct hl_osi_trace_error err;
	struct hl_osi_trace *t = NULL;
	char path[256];
	FILE *f;

	(void)state;
	test_path(path, sizeof(path), "limit.osi");
	write_bytes(path, file, sizeof(file));
	assert_int_equal(hl_osi_trace_open(path, &t, &err), -EBADMSG);
	assert_int_equal(err.offset, 0);
	assert_int_equal(err.length, HL_OSI_TRACE_MAX_MSG + 1ull);

	/* exactly the limit is a length we accept: here cut, so reported, not refused */
	file[0] = 0x00;
	write_bytes(path, file, sizeof(file));
	assert_int_equal(hl_osi_trace_open(path, &t, &err), HL_OSI_TRACE_TRUNCATED);
	assert_int_equal(err.length, HL_OSI_TRACE_MAX_MSG);
	hl_osi_trace_free(t);

	f = fopen(path, "wb");
	assert_non_null(f);
	assert_int_equal(hl_osi_trace_write(f, file, HL_OSI_TRACE_MAX_MSG + (size_t)1), -EMSGSIZE);
	assert_int_equal(ftell(f), 0);
	fclose(f);
	unlink(path);
}

static void trace_open_errors(void **state)
{
	struct hl_osi_trace *t = NULL;
	char path[256];

	(void)state;
	test_path(path, sizeof(path), "missing.osi");
	assert_int_equal(hl_osi_trace_open(path, &t, NULL), -ENOENT);
	assert_int_equal(hl_osi_trace_open("/", &t, NULL), -EINVAL);
	assert_null(t);
	hl_osi_trace_free(NULL);
}

static void trace_kind_from_name(void **state)
{
	enum hl_osi_kind k = HL_OSI_SENSOR_VIEW;

	(void)state;
	assert_int_equal(
		hl_osi_trace_kind_from_name("20210818T150542Z_gt_312_300_1523_highway.osi", &k), 0);
	assert_int_equal(k, HL_OSI_GROUND_TRUTH);
	assert_int_equal(hl_osi_trace_kind_from_name(
				 "/data/x_y/20210818T150542Z_sv_312_300_1523_hw.osi", &k),
			 0);
	assert_int_equal(k, HL_OSI_SENSOR_VIEW);
	k = HL_OSI_GROUND_TRUTH;
	/* other types of the convention, and names outside it */
	assert_int_equal(hl_osi_trace_kind_from_name("20210818T150542Z_sd_312_300_1523_hw.osi", &k),
			 -ENOENT);
	assert_int_equal(hl_osi_trace_kind_from_name("20210818T150542Z_svc_37_300_1_x.osi", &k),
			 -ENOENT);
	assert_int_equal(hl_osi_trace_kind_from_name("trace.osi", &k), -ENOENT);
	assert_int_equal(hl_osi_trace_kind_from_name("a_gt", &k), -ENOENT);
	assert_int_equal(hl_osi_trace_kind_from_name("gt_a_b.osi", &k), -ENOENT);
	assert_int_equal(hl_osi_trace_kind_from_name("/x_gt_y/trace.osi", &k), -ENOENT);
	assert_int_equal(hl_osi_trace_kind_from_name("", &k), -ENOENT);
	assert_int_equal(k, HL_OSI_GROUND_TRUTH);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(trace_round_trip_0_1_1000_100000_bytes),
		cmocka_unit_test(trace_writes_little_endian_prefix),
		cmocka_unit_test(trace_empty_file_has_no_messages),
		cmocka_unit_test(trace_cut_in_the_prefix),
		cmocka_unit_test(trace_cut_in_the_body),
		cmocka_unit_test(trace_absurd_length_refused),
		cmocka_unit_test(trace_limit_is_64_mib),
		cmocka_unit_test(trace_open_errors),
		cmocka_unit_test(trace_kind_from_name),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
