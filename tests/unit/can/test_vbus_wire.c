/* SPDX-License-Identifier: MIT */
/*
 * can/vbus_wire: the wire time of frames against their bit strings, written out. Each string
 * is the frame as sent from SOF to the end of the CRC sequence (classic) or CRC field (FD);
 * fields are separated by spaces and every stuff bit is written in brackets. The strings were
 * made outside the code under test (a script, not kept) and are checked here first — the CRC
 * by long division of the unstuffed bits, the stuff bits where the rule puts them — and the
 * classic ones again by tests/it/test_canwire.py with a bit-level model of its own
 * (tests/it/canwire.py); then hl_vbus_wire() against their length.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "can/vbus.h"

struct bits {
	uint8_t wire[1024]; /* as sent */
	bool stuff[1024]; /* wire[i] is a stuff bit */
	unsigned n, n_stuff;
	uint8_t raw[1024]; /* without the stuff bits */
	unsigned n_raw;
};

static struct bits parse(const char *s)
{
	struct bits b = { .n = 0 };

	for (; *s; s++) {
		bool stuffed = *s == '[';

		if (*s == ' ' || *s == ']')
			continue;
		if (stuffed)
			s++;
		assert_true(*s == '0' || *s == '1');
		b.wire[b.n] = (uint8_t)(*s - '0');
		b.stuff[b.n++] = stuffed;
		if (stuffed)
			b.n_stuff++;
		else
			b.raw[b.n_raw++] = (uint8_t)(*s - '0');
	}
	return b;
}

/* The remainder of (bits with init XORed into the first width bits) * x^width / poly. */
static uint32_t long_division(const uint8_t *bits, unsigned n, uint32_t poly, unsigned width,
			      uint32_t init)
{
	uint8_t d[1100];
	uint32_t rem = 0;

	memcpy(d, bits, n);
	memset(d + n, 0, width);
	for (unsigned i = 0; i < width && i < n; i++)
		d[i] ^= (init >> (width - 1 - i)) & 1;
	for (unsigned i = 0; i < n; i++) {
		if (!d[i])
			continue;
		d[i] = 0; /* the generator's x^width term */
		for (unsigned k = 0; k < width; k++)
			d[i + 1 + k] ^= (poly >> (width - 1 - k)) & 1;
	}
	for (unsigned k = 0; k < width; k++)
		rem = rem << 1 | d[n + k];
	return rem;
}

static uint32_t tail_value(const uint8_t *bits, unsigned n, unsigned width)
{
	uint32_t v = 0;

	for (unsigned i = n - width; i < n; i++)
		v = v << 1 | bits[i];
	return v;
}

/* Classic stuffing: a stuff bit exactly after every fifth equal bit, the complement. */
static void assert_classic_stuffing(const struct bits *b)
{
	unsigned run = 0;

	for (unsigned i = 0; i < b->n; i++) {
		if (run == 5) {
			assert_true(b->stuff[i]);
			assert_int_not_equal(b->wire[i], b->wire[i - 1]);
		} else {
			assert_false(b->stuff[i]);
		}
		run = i > 0 && b->wire[i] == b->wire[i - 1] ? run + 1 : 1;
	}
}

static void assert_classic(const char *s, uint32_t can_id, const uint8_t *data, uint8_t len,
			   uint16_t crc)
{
	struct bits b = parse(s);
	unsigned bits, stuff;
	int64_t ifs;

	assert_classic_stuffing(&b);
	assert_int_equal(tail_value(b.raw, b.n_raw, 15), crc);
	assert_int_equal(long_division(b.raw, b.n_raw - 15, 0x4599, 15, 0), crc);
	/* + CRC delimiter, ACK slot, ACK delimiter, 7 EOF; + 3 intermission; 2 us a bit */
	assert_int_equal(hl_vbus_wire(can_id, data, len, false, false, 500000, 2000000, &bits,
				      &stuff, &ifs),
			 (b.n + 10) * 2000);
	assert_int_equal(bits, b.n + 13);
	assert_int_equal(stuff, b.n_stuff);
	assert_int_equal(ifs, (b.n + 13) * 2000);
}

static void wire_classic_most_stuffing(void **state)
{
	static const uint8_t zero[8];

	(void)state;
	/* ID 0x000, 8 bytes of 0: a stuff bit after every fifth bit from SOF to the CRC. */
	assert_classic("0 0000[1]00000[1]00 0 0 0[1] 1000 00[1]00000[1]0 0000[1]0000 "
		       "0[1]00000[1]00 000[1]00000[1] 00000[1]000 00[1]00000[1]0 0000[1]0000 "
		       "0[1]00000[1]00 001010001011011",
		       0x000, zero, 8, 0x145b);
}

static void wire_classic_plain(void **state)
{
	static const uint8_t data[] = { 0x11, 0x22, 0x33, 0x44 };

	(void)state;
	assert_classic("0 00100100011 0 0 0 0100 000[1]10001 00100010 00110011 01000100 "
		       "001000111011010",
		       0x123, data, 4, 0x11da);
	/* 0x7FF without data: ten ones need two stuff bits, RTR..DLC a third. */
	assert_classic("0 11111[0]11111[0]1 0 0 0 00[1]00 010011100101111", 0x7ff, NULL, 0, 0x272f);
}

static void wire_classic_extended(void **state)
{
	static const uint8_t data[] = { 0x01, 0x02 };

	(void)state;
	/* 0x18FEF100: base 0x63F, SRR, IDE, extension 0x2F100, RTR, r1, r0 */
	assert_classic("0 1100011111[0]1 1 1 101111000100000[1]000 0 0[1] 0 0010 0000[1]0001 "
		       "00000[1]010 0011100011111[0]10",
		       0x18fef100u | HL_DBC_EFF_FLAG, data, 2, 0x1c7e);
}

/*
 * FD: the CRC-17 runs over the bits as sent (dynamic stuff bits included) and the stuff count,
 * from a register started at 1 << 16; the CRC field has a fixed stuff bit before every 4 bits.
 */
static void assert_fd(const char *s, bool brs, unsigned stuff_count_bits, uint32_t crc, int64_t ns,
		      int64_t ns_ifs)
{
	static const uint8_t data[12] = { 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11 };
	struct bits b = parse(s);
	uint8_t covered[1024];
	unsigned n = 0, bits, stuff;
	int64_t ifs;

	/* Everything before the CRC field (4 + 17 bits and 6 fixed stuff bits) as sent, then the
	 * field's first 4 bits that are no stuff bit: the stuff count. */
	for (unsigned i = 0; i < b.n - 27; i++)
		covered[n++] = b.wire[i];
	for (unsigned i = b.n - 27, k = 0; k < 4; i++)
		if (!b.stuff[i]) {
			covered[n++] = b.wire[i];
			k++;
		}
	assert_int_equal(tail_value(covered, n, 4), stuff_count_bits);
	assert_int_equal(long_division(covered, n, 0x1685b, 17, 1u << 16), crc);
	assert_int_equal(
		hl_vbus_wire(0x123, data, 12, true, brs, 500000, 2000000, &bits, &stuff, &ifs), ns);
	assert_int_equal(bits, b.n + 13);
	assert_int_equal(stuff, b.n_stuff);
	assert_int_equal(ifs, ns_ifs);
}

static void wire_fd_with_and_without_brs(void **state)
{
	(void)state;
	/*
	 * 12 bytes 00..0B, 11 dynamic stuff bits: Gray 010, parity 1. With BRS the 17 bits from SOF
	 * to BRS and the 10 after the CRC field run at 500 kbit/s, the 139 between at 2 Mbit/s:
	 * 27 * 2000 + 139 * 500 = 123500 ns, + 3 * 2000 of intermission.
	 */
	assert_fd("0 00100100011 0 0 1 0 1 0 1001 00000[1]000 00[1]00000[1]1 00000[1]010 "
		  "0000[1]0011 00000[1]100 000[1]00101 00000[1]110 0000[1]0111 00001000 "
		  "00[1]001001 00001010 0000[1]1011 [0]0101[0]0101[0]1111[0]1000[1]1001[0]1",
		  true, 0x5, 0x0bf13, 123500, 129500);
	/* Without BRS all 166 bits at 500 kbit/s. */
	assert_fd("0 00100100011 0 0 1 0 0 0 1001 00000[1]000 00[1]00000[1]1 00000[1]010 "
		  "0000[1]0011 00000[1]100 000[1]00101 00000[1]110 0000[1]0111 00001000 "
		  "00[1]001001 00001010 0000[1]1011 [0]0101[0]1011[0]1000[1]0010[1]1100[1]0",
		  false, 0x5, 0x17058, 332000, 338000);
}

static void wire_fd_lengths_and_crc21(void **state)
{
	uint8_t data[64] = { 0 };
	unsigned bits, stuff;
	int64_t ns;

	(void)state;
	/* 20 bytes (CRC-21) all at the nominal rate; 13 bytes is no FD length, 9 no classic one. */
	ns = hl_vbus_wire(0x100, data, 20, true, false, 500000, 2000000, &bits, &stuff, NULL);
	assert_true(ns > 0);
	assert_int_equal(ns, (int64_t)(bits - 3) * 2000);
	assert_int_equal(hl_vbus_wire(0x100, data, 13, true, false, 500000, 2000000, &bits, &stuff,
				      NULL),
			 -1);
	assert_int_equal(hl_vbus_wire(0x100, data, 9, false, false, 500000, 0, NULL, NULL, NULL),
			 -1);
	assert_int_equal(hl_vbus_wire(0x800, data, 1, false, false, 500000, 0, NULL, NULL, NULL),
			 -1);
	assert_int_equal(
		hl_vbus_wire(0x100, data, 1, false, true, 500000, 2000000, NULL, NULL, NULL), -1);
	/* 64 bytes with BRS at 1 Mbit/s nominal and 5 Mbit/s data: the nearest ns of each phase. */
	assert_true(hl_vbus_wire(0x1fffffffu | HL_DBC_EFF_FLAG, data, 64, true, true, 1000000,
				 5000000, &bits, &stuff, NULL) > 0);
	assert_true(bits < 800);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(wire_classic_most_stuffing),
		cmocka_unit_test(wire_classic_plain),
		cmocka_unit_test(wire_classic_extended),
		cmocka_unit_test(wire_fd_with_and_without_brs),
		cmocka_unit_test(wire_fd_lengths_and_crc21),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
