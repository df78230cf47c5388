/* SPDX-License-Identifier: MIT */
/*
 * can/e2e: CRCs against the published vectors, the P1 and P5 layouts, the counter logic.
 *
 * The CRC vectors are the examples of the AUTOSAR "Specification of CRC Routines" (CRC-8 SAE
 * J1850, CRC-8 0x2F, CRC-16 CCITT-FALSE tables) plus each CRC's catalogue check value over
 * "123456789" (reveng); they were cross-checked with an independent bit-wise Python
 * implementation. The P1 and P5 frame vectors were computed with that Python implementation:
 * P1: crc8_j1850(id_lo, id_hi, bytes 1..7); P5: crc16(bytes 2.., id_lo, id_hi).
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "can/e2e.h"

struct vector {
	uint8_t data[9];
	size_t len;
	uint8_t j1850, h2f;
	uint16_t ccitt;
};

static const struct vector vectors[] = {
	{ { 0x00, 0x00, 0x00, 0x00 }, 4, 0x59, 0x12, 0x84c0 },
	{ { 0xf2, 0x01, 0x83 }, 3, 0x37, 0xc2, 0xd374 },
	{ { 0x0f, 0xaa, 0x00, 0x55 }, 4, 0x79, 0xc6, 0x2023 },
	{ { 0x00, 0xff, 0x55, 0x11 }, 4, 0xb8, 0x77, 0xb8f9 },
	{ { 0x33, 0x22, 0x55, 0xaa, 0xbb, 0xcc, 0xdd, 0xee, 0xff }, 9, 0xcb, 0x11, 0xf53f },
	{ { 0x92, 0x6b, 0x55 }, 3, 0x8c, 0x33, 0x0745 },
	{ { 0xff, 0xff, 0xff, 0xff }, 4, 0x74, 0x6c, 0x1d0f },
};

static void e2e_crc_autosar_vectors(void **state)
{
	(void)state;
	for (size_t i = 0; i < sizeof(vectors) / sizeof(vectors[0]); i++) {
		assert_int_equal(hl_e2e_crc8_j1850(vectors[i].data, vectors[i].len),
				 vectors[i].j1850);
		assert_int_equal(hl_e2e_crc8_h2f(vectors[i].data, vectors[i].len), vectors[i].h2f);
		assert_int_equal(hl_e2e_crc16_ccitt(vectors[i].data, vectors[i].len),
				 vectors[i].ccitt);
	}
}

static void e2e_crc_check_values(void **state)
{
	const uint8_t *s = (const uint8_t *)"123456789";

	(void)state;
	assert_int_equal(hl_e2e_crc8_j1850(s, 9), 0x4b);
	assert_int_equal(hl_e2e_crc8_h2f(s, 9), 0xdf);
	assert_int_equal(hl_e2e_crc16_ccitt(s, 9), 0x29b1);
	/* the empty message: init ^ xorout */
	assert_int_equal(hl_e2e_crc8_j1850(s, 0), 0x00);
	assert_int_equal(hl_e2e_crc16_ccitt(s, 0), 0xffff);
}

/* The definitions, bit by bit, MSB first: the reference for the byte-wise tables. */
static uint8_t ref_crc8(uint8_t poly, const uint8_t *d, size_t n)
{
	uint8_t c = 0xff;

	for (size_t i = 0; i < n; i++) {
		c ^= d[i];
		for (int b = 0; b < 8; b++)
			c = (c & 0x80) ? (uint8_t)((c << 1) ^ poly) : (uint8_t)(c << 1);
	}
	return c ^ 0xff;
}

static uint16_t ref_crc16(const uint8_t *d, size_t n)
{
	uint16_t c = 0xffff;

	for (size_t i = 0; i < n; i++) {
		c ^= (uint16_t)(d[i] << 8);
		for (int b = 0; b < 8; b++)
			c = (c & 0x8000) ? (uint16_t)((c << 1) ^ 0x1021) : (uint16_t)(c << 1);
	}
	return c;
}

static void e2e_crc_tables_match_definition(void **state)
{
	uint8_t d[64];

	(void)state;
	srand(1);
	for (int it = 0; it < 2000; it++) {
		size_t n = (size_t)(it % 65);

		for (size_t i = 0; i < n; i++)
			d[i] = (uint8_t)rand();
		assert_int_equal(hl_e2e_crc8_j1850(d, n), ref_crc8(0x1d, d, n));
		assert_int_equal(hl_e2e_crc8_h2f(d, n), ref_crc8(0x2f, d, n));
		assert_int_equal(hl_e2e_crc16_ccitt(d, n), ref_crc16(d, n));
	}
}

static void e2e_config_parse(void **state)
{
	struct hl_e2e_config c;

	(void)state;
	assert_int_equal(hl_e2e_config_parse("P1 dataid=0x0123", &c), 0);
	assert_int_equal(c.profile, HL_E2E_P1);
	assert_int_equal(c.data_id, 0x0123);
	assert_int_equal(hl_e2e_config_parse("P5 dataid=816", &c), 0);
	assert_int_equal(c.profile, HL_E2E_P5);
	assert_int_equal(c.data_id, 816);
	assert_int_equal(hl_e2e_config_parse("none", &c), 0);
	assert_int_equal(c.profile, HL_E2E_NONE);
	assert_int_equal(hl_e2e_config_parse("P2 dataid=1", &c), -EINVAL);
	assert_int_equal(hl_e2e_config_parse("P1", &c), -EINVAL);
	assert_int_equal(hl_e2e_config_parse("P1 dataid=0x10000", &c), -EINVAL);
	assert_int_equal(hl_e2e_config_parse("P1 dataid=", &c), -EINVAL);
	assert_int_equal(hl_e2e_config_parse("P1 dataid=0x12 x", &c), -EINVAL);
	assert_int_equal(hl_e2e_config_parse("P1 id=1", &c), -EINVAL);
}

static void e2e_p1_protect_and_check(void **state)
{
	const struct hl_e2e_config c = { HL_E2E_P1, 0x0123 };
	uint8_t d[8] = {
		0, 0x50, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66
	}; /* page 5 in the high nibble */
	uint16_t crc;

	(void)state;
	assert_int_equal(hl_e2e_protect(&c, d, 8, 9), 0);
	assert_int_equal(d[1], 0x59); /* counter in the low nibble, page kept */
	assert_int_equal(d[0], 0x49);
	assert_int_equal(hl_e2e_counter(&c, d), 9);
	assert_int_equal(hl_e2e_check(&c, d, 8), 0);
	assert_int_equal(hl_e2e_crc(&c, d, 8, &crc), 0);
	assert_int_equal(crc, 0x49);
	d[7] ^= 0x01;
	assert_int_equal(hl_e2e_check(&c, d, 8), -EBADMSG);
	d[7] ^= 0x01;
	d[0] ^= 0x80;
	assert_int_equal(hl_e2e_check(&c, d, 8), -EBADMSG);
	/* the data ID is part of the CRC */
	d[0] ^= 0x80;
	assert_int_equal(hl_e2e_check(&(struct hl_e2e_config){ HL_E2E_P1, 0x0124 }, d, 8),
			 -EBADMSG);
	assert_int_equal(hl_e2e_protect(&c, d, 8, 15), -EINVAL); /* 15 is not a P1 counter */
	assert_int_equal(hl_e2e_protect(&c, d, 1, 0), -EMSGSIZE);
	assert_int_equal(hl_e2e_check(&c, d, 1), -EMSGSIZE);
}

static void e2e_p1_hd84_frame(void **state)
{
	/* hdlamp dbc encode ... HL_Dim_L HL_Page_L=0 LED_001=15/63 LED_008=1 --counter 3 */
	const struct hl_e2e_config c = { HL_E2E_P1, 0x0320 };
	const uint8_t d[8] = { 0x60, 0x03, 0x0f, 0x00, 0x00, 0x00, 0x00, 0xfc };

	(void)state;
	assert_int_equal(hl_e2e_check(&c, d, 8), 0);
	assert_int_equal(hl_e2e_counter(&c, d), 3);
}

static void e2e_p5_protect_and_check(void **state)
{
	const struct hl_e2e_config c = { HL_E2E_P5, 0x0333 };
	uint8_t d[16] = { 0 };
	uint16_t crc;

	(void)state;
	for (int i = 3; i < 16; i++)
		d[i] = (uint8_t)(i - 2);
	assert_int_equal(hl_e2e_protect(&c, d, 16, 7), 0);
	assert_int_equal(d[2], 7);
	assert_int_equal(d[0], 0xed); /* 0xE1ED little endian */
	assert_int_equal(d[1], 0xe1);
	assert_int_equal(hl_e2e_crc(&c, d, 16, &crc), 0);
	assert_int_equal(crc, 0xe1ed);
	assert_int_equal(hl_e2e_check(&c, d, 16), 0);
	assert_int_equal(hl_e2e_counter(&c, d), 7);
	d[15] ^= 0x40;
	assert_int_equal(hl_e2e_check(&c, d, 16), -EBADMSG);
	d[15] ^= 0x40;
	d[1] ^= 0x01;
	assert_int_equal(hl_e2e_check(&c, d, 16), -EBADMSG);
	assert_int_equal(hl_e2e_protect(&c, d, 16, 256), -EINVAL);
	assert_int_equal(hl_e2e_protect(&c, d, 2, 0), -EMSGSIZE);
	assert_int_equal(hl_e2e_check(&(struct hl_e2e_config){ HL_E2E_NONE, 0 }, d, 16), -EINVAL);
}

static void e2e_counter_ok_repeated_lost(void **state)
{
	unsigned lost = 99;

	(void)state;
	assert_int_equal(hl_e2e_counter_check(14, 3, 4, &lost), HL_E2E_COUNTER_OK);
	assert_int_equal(lost, 0);
	assert_int_equal(hl_e2e_counter_check(14, 14, 0, &lost), HL_E2E_COUNTER_OK); /* wrap */
	assert_int_equal(hl_e2e_counter_check(14, 4, 4, &lost), HL_E2E_COUNTER_REPEATED);
	assert_int_equal(lost, 0);
	assert_int_equal(hl_e2e_counter_check(14, 4, 7, &lost), HL_E2E_COUNTER_LOST);
	assert_int_equal(lost, 2);
	assert_int_equal(hl_e2e_counter_check(14, 13, 1, &lost), HL_E2E_COUNTER_LOST);
	assert_int_equal(lost, 2); /* 14 and 0 missed */
	assert_int_equal(hl_e2e_counter_check(14, 5, 4, &lost), HL_E2E_COUNTER_LOST);
	assert_int_equal(lost, 13);
	assert_int_equal(hl_e2e_counter_check(255, 255, 0, &lost), HL_E2E_COUNTER_OK);
	assert_int_equal(hl_e2e_counter_check(255, 250, 4, &lost), HL_E2E_COUNTER_LOST);
	assert_int_equal(lost, 9);
	assert_int_equal(hl_e2e_counter_check(14, 15, 0, &lost), -EINVAL);
	assert_int_equal(hl_e2e_counter_check(14, 0, 15, &lost), -EINVAL);
	assert_int_equal(hl_e2e_counter_max(HL_E2E_P1), 14);
	assert_int_equal(hl_e2e_counter_max(HL_E2E_P5), 255);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(e2e_crc_autosar_vectors),
		cmocka_unit_test(e2e_crc_check_values),
		cmocka_unit_test(e2e_crc_tables_match_definition),
		cmocka_unit_test(e2e_config_parse),
		cmocka_unit_test(e2e_p1_protect_and_check),
		cmocka_unit_test(e2e_p1_hd84_frame),
		cmocka_unit_test(e2e_p5_protect_and_check),
		cmocka_unit_test(e2e_counter_ok_repeated_lost),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
