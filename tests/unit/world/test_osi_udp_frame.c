/* SPDX-License-Identifier: MIT */
/*
 * world/osi_udp_frame.c: the datagrams of the splitter byte for byte against esmini's framing
 * written out here (counter 1, 2, ... with the last negated, size, little-endian); messages of 1,
 * 2 and many parts reassembled; every way a stream goes wrong (a missing middle part, a repeat, a
 * new message before the old one ended, garbage of 0 to 7 bytes, a message over the limit) with
 * the result and the counters it must give; no allocation while feeding.
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

#include "alloc_count.h"
#include "world/osi_udp_frame.h"

#define DGRAM_MAX (HL_OSI_UDP_HEADER + HL_OSI_UDP_PART_DEFAULT)

static uint8_t *pattern(size_t len, unsigned seed)
{
	uint8_t *p = malloc(len ? len : 1);

	assert_non_null(p);
	for (size_t i = 0; i < len; i++)
		p[i] = (uint8_t)(i * 13 + seed * 5 + (i >> 9));
	return p;
}

/* The header by hand: esmini's struct { int counter; unsigned int datasize; } on x86. */
static void hand_header(uint8_t *d, int32_t counter, uint32_t size)
{
	uint32_t c = (uint32_t)counter;

	for (int b = 0; b < 4; b++) {
		d[b] = (uint8_t)(c >> (8 * b));
		d[4 + b] = (uint8_t)(size >> (8 * b));
	}
}

static size_t hand_dgram(uint8_t *d, int32_t counter, uint32_t size, const uint8_t *part)
{
	hand_header(d, counter, size);
	memcpy(d + 8, part, size);
	return 8 + (size_t)size;
}

static struct hl_osi_udp_reasm *reasm(size_t max_msg)
{
	struct hl_osi_udp_reasm *r = NULL;

	assert_int_equal(hl_osi_udp_reasm_new(max_msg, &r), 0);
	assert_non_null(r);
	return r;
}

static void expect_stats(const struct hl_osi_udp_reasm *r, uint64_t messages, uint64_t dropped,
			 uint64_t bad_header, uint64_t orphans)
{
	struct hl_osi_udp_stats s;

	hl_osi_udp_reasm_stats(r, &s);
	assert_int_equal(s.messages, messages);
	assert_int_equal(s.dropped, dropped);
	assert_int_equal(s.bad_header, bad_header);
	assert_int_equal(s.orphans, orphans);
}

static enum hl_osi_udp_result feed(struct hl_osi_udp_reasm *r, const uint8_t *d, size_t len)
{
	const uint8_t *msg = NULL;
	size_t n = 0;

	return hl_osi_udp_reasm_feed(r, d, len, &msg, &n);
}

/* Splits a message of len bytes in parts of part_max, checks each datagram, feeds them all. */
static void split_and_reassemble(size_t len, size_t part_max, size_t want_parts)
{
	struct hl_osi_udp_reasm *r = reasm(HL_OSI_UDP_MSG_DEFAULT);
	uint8_t *msg = pattern(len, (unsigned)len);
	uint8_t *d = malloc(HL_OSI_UDP_HEADER + part_max);
	const uint8_t *got = NULL;
	size_t n = hl_osi_udp_split_count(len, part_max), got_len = 0;

	assert_non_null(d);
	assert_int_equal(n, want_parts);
	for (size_t i = 0; i < n; i++) {
		size_t part = i + 1 < n ? part_max : len - i * part_max;
		int dl = hl_osi_udp_split(msg, len, part_max, i, d, HL_OSI_UDP_HEADER + part_max);
		uint8_t want[8];

		assert_int_equal(dl, (int)(HL_OSI_UDP_HEADER + part));
		hand_header(want, i + 1 < n ? (int32_t)(i + 1) : -(int32_t)(i + 1), (uint32_t)part);
		assert_memory_equal(d, want, 8);
		assert_memory_equal(d + 8, msg + i * part_max, part);
		assert_int_equal(hl_osi_udp_reasm_feed(r, d, (size_t)dl, &got, &got_len),
				 i + 1 < n ? HL_OSI_UDP_PART : HL_OSI_UDP_MESSAGE);
	}
	assert_int_equal(got_len, len);
	assert_memory_equal(got, msg, len);
	assert_int_equal(hl_osi_udp_split(msg, len, part_max, n, d, HL_OSI_UDP_HEADER + part_max),
			 -ERANGE);
	expect_stats(r, 1, 0, 0, 0);
	free(d);
	free(msg);
	hl_osi_udp_reasm_free(r);
}

static void udp_one_part(void **state)
{
	(void)state;
	split_and_reassemble(1, HL_OSI_UDP_PART_DEFAULT, 1);
	split_and_reassemble(HL_OSI_UDP_PART_DEFAULT, HL_OSI_UDP_PART_DEFAULT, 1);
}

static void udp_two_parts(void **state)
{
	(void)state;
	split_and_reassemble(HL_OSI_UDP_PART_DEFAULT + 1, HL_OSI_UDP_PART_DEFAULT, 2);
	split_and_reassemble(2 * HL_OSI_UDP_PART_DEFAULT, HL_OSI_UDP_PART_DEFAULT, 2);
}

static void udp_many_parts(void **state)
{
	(void)state;
	split_and_reassemble(100000, HL_OSI_UDP_PART_DEFAULT, 13);
	split_and_reassemble(1000, 7, 143);
	split_and_reassemble(200000, HL_OSI_UDP_PART_MAX, 4);
}

/* esmini sends nothing for an empty message; so does the splitter. */
static void udp_empty_message_is_no_datagram(void **state)
{
	uint8_t d[DGRAM_MAX];

	(void)state;
	assert_int_equal(hl_osi_udp_split_count(0, HL_OSI_UDP_PART_DEFAULT), 0);
	assert_int_equal(hl_osi_udp_split((const uint8_t *)"", 0, HL_OSI_UDP_PART_DEFAULT, 0, d,
					  sizeof(d)),
			 -ERANGE);
}

static void udp_split_argument_errors(void **state)
{
	uint8_t msg[100] = { 0 }, d[DGRAM_MAX];

	(void)state;
	assert_int_equal(hl_osi_udp_split(msg, 100, 0, 0, d, sizeof(d)), -EINVAL);
	assert_int_equal(hl_osi_udp_split(msg, 100, HL_OSI_UDP_PART_MAX + 1, 0, d, sizeof(d)),
			 -EINVAL);
	assert_int_equal(hl_osi_udp_split(msg, 100, 50, 0, d, 57), -EMSGSIZE);
	assert_int_equal(hl_osi_udp_split(msg, 100, 50, 0, d, 58), 58);
	assert_int_equal(hl_osi_udp_split(msg, 100, 50, 2, d, 58), -ERANGE);
}

/* Parts 1, 3 (2 lost): dropped at 3; the last part -4 is then an orphan; the next message is
 * whole. */
static void udp_missing_middle_part(void **state)
{
	struct hl_osi_udp_reasm *r = reasm(1000);
	uint8_t d[64];
	const uint8_t *got = NULL;
	size_t got_len = 0;

	(void)state;
	assert_int_equal(feed(r, d, hand_dgram(d, 1, 4, (const uint8_t *)"aaaa")), HL_OSI_UDP_PART);
	assert_int_equal(feed(r, d, hand_dgram(d, 3, 4, (const uint8_t *)"cccc")),
			 HL_OSI_UDP_OUT_OF_ORDER);
	expect_stats(r, 0, 1, 0, 0);
	assert_int_equal(feed(r, d, hand_dgram(d, -4, 2, (const uint8_t *)"dd")),
			 HL_OSI_UDP_OUT_OF_ORDER);
	expect_stats(r, 0, 1, 0, 1);
	assert_int_equal(feed(r, d, hand_dgram(d, 1, 3, (const uint8_t *)"xyz")), HL_OSI_UDP_PART);
	hand_dgram(d, -2, 2, (const uint8_t *)"!!");
	assert_int_equal(hl_osi_udp_reasm_feed(r, d, 10, &got, &got_len), HL_OSI_UDP_MESSAGE);
	assert_int_equal(got_len, 5);
	assert_memory_equal(got, "xyz!!", 5);
	expect_stats(r, 1, 1, 0, 1);
	hl_osi_udp_reasm_free(r);
}

/* Parts 1, 2, 2 (a repeat), -3: the repeat drops the message, -3 is an orphan. */
static void udp_repeated_part(void **state)
{
	struct hl_osi_udp_reasm *r = reasm(1000);
	uint8_t d[64];

	(void)state;
	assert_int_equal(feed(r, d, hand_dgram(d, 1, 1, (const uint8_t *)"a")), HL_OSI_UDP_PART);
	assert_int_equal(feed(r, d, hand_dgram(d, 2, 1, (const uint8_t *)"b")), HL_OSI_UDP_PART);
	assert_int_equal(feed(r, d, hand_dgram(d, 2, 1, (const uint8_t *)"b")),
			 HL_OSI_UDP_OUT_OF_ORDER);
	assert_int_equal(feed(r, d, hand_dgram(d, -3, 1, (const uint8_t *)"c")),
			 HL_OSI_UDP_OUT_OF_ORDER);
	expect_stats(r, 0, 1, 0, 1);

	/* a repeated single-part message is two messages: each is whole */
	assert_int_equal(feed(r, d, hand_dgram(d, -1, 1, (const uint8_t *)"z")),
			 HL_OSI_UDP_MESSAGE);
	assert_int_equal(feed(r, d, hand_dgram(d, -1, 1, (const uint8_t *)"z")),
			 HL_OSI_UDP_MESSAGE);
	expect_stats(r, 2, 1, 0, 1);
	hl_osi_udp_reasm_free(r);
}

/* Parts 1, 2 of message A, then 1, -2 of message B: A dropped, B whole. */
static void udp_new_message_before_old_finished(void **state)
{
	struct hl_osi_udp_reasm *r = reasm(1000);
	uint8_t d[64];
	const uint8_t *got = NULL;
	size_t got_len = 0;

	(void)state;
	assert_int_equal(feed(r, d, hand_dgram(d, 1, 2, (const uint8_t *)"A1")), HL_OSI_UDP_PART);
	assert_int_equal(feed(r, d, hand_dgram(d, 2, 2, (const uint8_t *)"A2")), HL_OSI_UDP_PART);
	assert_int_equal(feed(r, d, hand_dgram(d, 1, 2, (const uint8_t *)"B1")), HL_OSI_UDP_PART);
	expect_stats(r, 0, 1, 0, 0);
	hand_dgram(d, -2, 2, (const uint8_t *)"B2");
	assert_int_equal(hl_osi_udp_reasm_feed(r, d, 10, &got, &got_len), HL_OSI_UDP_MESSAGE);
	assert_int_equal(got_len, 4);
	assert_memory_equal(got, "B1B2", 4);

	/* a single-part message in the middle of another: the other dropped, it whole */
	assert_int_equal(feed(r, d, hand_dgram(d, 1, 2, (const uint8_t *)"C1")), HL_OSI_UDP_PART);
	hand_dgram(d, -1, 1, (const uint8_t *)"D");
	assert_int_equal(hl_osi_udp_reasm_feed(r, d, 9, &got, &got_len), HL_OSI_UDP_MESSAGE);
	assert_int_equal(got_len, 1);
	assert_int_equal(got[0], 'D');
	expect_stats(r, 2, 2, 0, 0);

	/* a reset forgets without counting */
	assert_int_equal(feed(r, d, hand_dgram(d, 1, 2, (const uint8_t *)"E1")), HL_OSI_UDP_PART);
	hl_osi_udp_reasm_reset(r);
	assert_int_equal(feed(r, d, hand_dgram(d, -2, 2, (const uint8_t *)"E2")),
			 HL_OSI_UDP_OUT_OF_ORDER);
	expect_stats(r, 2, 2, 0, 1);
	hl_osi_udp_reasm_free(r);
}

/* 0 to 7 bytes: no header; a message in progress survives them. */
static void udp_garbage_0_to_7_bytes(void **state)
{
	struct hl_osi_udp_reasm *r = reasm(1000);
	uint8_t junk[8] = { 0xff, 0xff, 0xff, 0xff, 1, 0, 0, 0 };
	uint8_t d[64];
	const uint8_t *got = NULL;
	size_t got_len = 0;

	(void)state;
	assert_int_equal(feed(r, d, hand_dgram(d, 1, 3, (const uint8_t *)"abc")), HL_OSI_UDP_PART);
	for (size_t n = 0; n < 8; n++)
		assert_int_equal(feed(r, junk, n), HL_OSI_UDP_BAD_HEADER);
	expect_stats(r, 0, 0, 8, 0);
	hand_dgram(d, -2, 1, (const uint8_t *)"d");
	assert_int_equal(hl_osi_udp_reasm_feed(r, d, 9, &got, &got_len), HL_OSI_UDP_MESSAGE);
	assert_int_equal(got_len, 4);
	assert_memory_equal(got, "abcd", 4);
	hl_osi_udp_reasm_free(r);
}

/* Headers that lie: size against the datagram's length, size 0, counter 0 and INT32_MIN. */
static void udp_bad_headers(void **state)
{
	struct hl_osi_udp_reasm *r = reasm(1000);
	uint8_t d[64];
	size_t n;

	(void)state;
	n = hand_dgram(d, -1, 4, (const uint8_t *)"abcd");
	assert_int_equal(feed(r, d, n - 1), HL_OSI_UDP_BAD_HEADER); /* size says more */
	assert_int_equal(feed(r, d, n + 1), HL_OSI_UDP_BAD_HEADER); /* size says less */
	assert_int_equal(feed(r, d, hand_dgram(d, -1, 0, (const uint8_t *)"")),
			 HL_OSI_UDP_BAD_HEADER);
	assert_int_equal(feed(r, d, hand_dgram(d, 0, 1, (const uint8_t *)"a")),
			 HL_OSI_UDP_BAD_HEADER);
	assert_int_equal(feed(r, d, hand_dgram(d, INT32_MIN, 1, (const uint8_t *)"a")),
			 HL_OSI_UDP_BAD_HEADER);
	/* big-endian header (a sender on the other byte order): counter 1 reads as 16777216 */
	memcpy(d, "\x00\x00\x00\x01\x00\x00\x00\x01z", 9);
	assert_int_equal(feed(r, d, 9), HL_OSI_UDP_BAD_HEADER);
	expect_stats(r, 0, 0, 6, 0);
	hl_osi_udp_reasm_free(r);
}

/* A limit of 10 bytes: 10 pass, 11 do not, whether in the first part or a later one. */
static void udp_too_large(void **state)
{
	struct hl_osi_udp_reasm *r = reasm(10);
	uint8_t d[64];
	const uint8_t *got = NULL;
	size_t got_len = 0;

	(void)state;
	hand_dgram(d, -1, 10, (const uint8_t *)"0123456789");
	assert_int_equal(hl_osi_udp_reasm_feed(r, d, 18, &got, &got_len), HL_OSI_UDP_MESSAGE);
	assert_int_equal(got_len, 10);
	assert_int_equal(feed(r, d, hand_dgram(d, -1, 11, (const uint8_t *)"0123456789a")),
			 HL_OSI_UDP_TOO_LARGE);
	expect_stats(r, 1, 1, 0, 0);
	assert_int_equal(feed(r, d, hand_dgram(d, 1, 6, (const uint8_t *)"012345")),
			 HL_OSI_UDP_PART);
	assert_int_equal(feed(r, d, hand_dgram(d, 2, 5, (const uint8_t *)"6789a")),
			 HL_OSI_UDP_TOO_LARGE);
	assert_int_equal(feed(r, d, hand_dgram(d, -3, 1, (const uint8_t *)"b")),
			 HL_OSI_UDP_OUT_OF_ORDER);
	expect_stats(r, 1, 2, 0, 1);
	hl_osi_udp_reasm_free(r);
}

static void udp_new_argument_errors(void **state)
{
	struct hl_osi_udp_reasm *r = NULL;

	(void)state;
	assert_int_equal(hl_osi_udp_reasm_new(0, &r), -EINVAL);
	assert_null(r);
	hl_osi_udp_reasm_free(NULL);
	assert_string_equal(hl_osi_udp_result_name(HL_OSI_UDP_OUT_OF_ORDER), "out of order");
}

/* Feeding a long, broken stream allocates nothing. */
static void udp_feed_allocates_nothing(void **state)
{
	struct hl_osi_udp_reasm *r;
	static uint8_t d[DGRAM_MAX];
	size_t n = hl_osi_udp_split_count(50000, HL_OSI_UDP_PART_DEFAULT);
	uint8_t *msg;

	(void)state;
	if (!HL_COUNT_ALLOCS)
		skip(); /* before allocating: a skip leaves the test at once */
	r = reasm(HL_OSI_UDP_MSG_DEFAULT);
	msg = pattern(50000, 3);
	allocs = 0;
	for (int round = 0; round < 20; round++) {
		for (size_t i = 0; i < n; i++) {
			int dl;

			if (round % 3 == 1 && i == 2)
				continue; /* a lost part */
			dl = hl_osi_udp_split(msg, 50000, HL_OSI_UDP_PART_DEFAULT, i, d, sizeof(d));
			assert_true(dl > 0);
			feed(r, d, (size_t)dl);
			feed(r, d, (size_t)round % 8); /* garbage */
		}
	}
	assert_int_equal(allocs, 0);
	allocs = -1;
	expect_stats(r, 13, 7, 20 * 7 - 7, 7 * 3);
	free(msg);
	hl_osi_udp_reasm_free(r);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(udp_one_part),
		cmocka_unit_test(udp_two_parts),
		cmocka_unit_test(udp_many_parts),
		cmocka_unit_test(udp_empty_message_is_no_datagram),
		cmocka_unit_test(udp_split_argument_errors),
		cmocka_unit_test(udp_missing_middle_part),
		cmocka_unit_test(udp_repeated_part),
		cmocka_unit_test(udp_new_message_before_old_finished),
		cmocka_unit_test(udp_garbage_0_to_7_bytes),
		cmocka_unit_test(udp_bad_headers),
		cmocka_unit_test(udp_too_large),
		cmocka_unit_test(udp_new_argument_errors),
		cmocka_unit_test(udp_feed_allocates_nothing),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
