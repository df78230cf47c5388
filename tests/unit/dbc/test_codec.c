/* SPDX-License-Identifier: MIT */
/*
 * dbc/codec: decode against hand-computed frames, encode back to the same bytes, and the
 * encode -> decode round trip of every signal of the shipped databases.
 *
 * How the vectors were computed by hand: Intel frames are read as one little-endian number
 * (byte 0 lowest), the signal being bits start..start+len-1 of it. Motorola frames are read as
 * a big-endian bit string (bit 0 = MSB of byte 0); the start bit s is the MSB of the signal,
 * at position 8*(s/8) + 7 - s%8 of that string.
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdbool.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "dbc/database.h"

static const char vectors_dbc[] =
	"BO_ 16 Vec: 16 ECU\n"
	" SG_ IntelCross : 12|12@1+ (1,0) [0|0] \"\" X\n" /* 0 */
	" SG_ MotoCross : 39|12@0+ (1,0) [0|0] \"\" X\n" /* 1: byte 4 + high nibble of 5 */
	" SG_ MotoCross2 : 51|12@0+ (1,0) [0|0] \"\" X\n" /* 2: low nibble of 6 + byte 7 */
	" SG_ Bit : 65|1@1+ (1,0) [0|0] \"\" X\n" /* 3: byte 8 bit 1 */
	" SG_ MotoBit : 79|1@0+ (1,0) [0|0] \"\" X\n" /* 4: byte 9 bit 7 */
	" SG_ Neg : 80|12@1- (0.5,10) [0|0] \"\" X\n" /* 5: byte 10 + low nibble of 11 */
	" SG_ MotoNeg : 103|8@0- (1,0) [0|0] \"\" X\n" /* 6: byte 12 */
	"BO_ 17 Wide: 16 ECU\n"
	" SG_ I64 : 0|64@1+ (1,0) [0|0] \"\" X\n"
	" SG_ M64 : 71|64@0+ (1,0) [0|0] \"\" X\n" /* bytes 8..15 */
	"BO_ 18 Odd: 16 ECU\n"
	" SG_ I64u : 4|64@1+ (1,0) [0|0] \"\" X\n" /* bytes 0..8, 9 bytes */
	"BO_ 19 Odd2: 16 ECU\n"
	" SG_ M64u : 3|64@0+ (1,0) [0|0] \"\" X\n" /* pos 4..67, 9 bytes */
	"BO_ 20 Floats: 16 ECU\n"
	" SG_ F : 0|32@1- (1,0) [0|0] \"\" X\n"
	" SG_ MF : 39|32@0- (1,0) [0|0] \"\" X\n" /* bytes 4..7 big endian */
	" SG_ D : 64|64@1- (1,0) [0|0] \"\" X\n"
	"BO_ 2566848766 Fd: 64 ECU\n" /* extended 0x18FF00FE, 64-byte CAN FD */
	" SG_ First : 0|8@1+ (1,0) [0|0] \"\" X\n"
	" SG_ Across : 500|8@1+ (1,0) [0|0] \"\" X\n" /* bits 500..507: bytes 62 and 63 */
	" SG_ MotoAcross : 499|8@0+ (1,0) [0|0] \"\" X\n" /* pos 500..507: bytes 62 and 63 */
	" SG_ MotoLast : 511|8@0+ (1,0) [0|0] \"\" X\n" /* byte 63 */
	"BO_ 200 Mux: 8 ECU\n"
	" SG_ Sel M : 0|8@1+ (1,0) [0|255] \"\" X\n"
	" SG_ A m0 : 8|16@1+ (1,0) [0|0] \"\" X\n"
	" SG_ B m1 : 8|8@1+ (1,0) [0|0] \"\" X\n"
	" SG_ Sub m2M : 8|8@1+ (1,0) [0|0] \"\" X\n"
	" SG_ C m3 : 16|8@1+ (1,0) [0|0] \"\" X\n"
	" SG_ Always : 56|8@1+ (1,0) [0|0] \"\" X\n"
	"SIG_VALTYPE_ 20 F : 1;\n"
	"SIG_VALTYPE_ 20 MF : 1;\n"
	"SIG_VALTYPE_ 20 D : 2;\n"
	"SG_MUL_VAL_ 200 C Sub 3-3, 5-7;\n"
	"SG_MUL_VAL_ 200 Sub Sel 2-2;\n";

static struct hl_dbc *db;

static int setup(void **state)
{
	struct hl_dbc_error err;

	(void)state;
	if (hl_dbc_parse(vectors_dbc, strlen(vectors_dbc), &db, &err) < 0) {
		print_error("%d:%d: %s\n", err.line, err.column, err.msg);
		return -1;
	}
	return 0;
}

static int teardown(void **state)
{
	(void)state;
	hl_dbc_free(db);
	return 0;
}

/* Decodes m from data and returns the value of signal index sig; fails if it is absent. */
static struct hl_dbc_value value_of(const struct hl_dbc_message *m, const uint8_t *data, size_t len,
				    int sig)
{
	struct hl_dbc_value v[64];
	int n = hl_dbc_decode(m, data, len, v);

	assert_true(n > 0);
	for (int i = 0; i < n; i++)
		if ((int)v[i].signal == sig)
			return v[i];
	fail_msg("signal %d not decoded", sig);
	return v[0];
}

/* Encoding the decoded raw value of each signal into zeros gives back the frame's bits. */
static void assert_reencodes(const struct hl_dbc_message *m, const uint8_t *data)
{
	uint8_t out[64] = { 0 };

	for (int k = 0; k < m->n_signals; k++) {
		uint64_t raw;

		assert_int_equal(hl_dbc_signal_get_raw(&m->signals[k], data, m->size, &raw), 0);
		assert_int_equal(hl_dbc_signal_set_raw(&m->signals[k], raw, out, m->size), 0);
	}
	assert_memory_equal(out, data, m->size);
}

static void dbc_intel_and_motorola_crossing_bytes(void **state)
{
	const struct hl_dbc_message *m = hl_dbc_find_message(db, "Vec");
	uint8_t d[16] = { 0 };

	(void)state;
	d[1] = 0xa0; /* IntelCross: bits 12..15 = 0xA (low nibble of the value) */
	d[2] = 0xbc; /* bits 16..23 = 0xBC: value 0xBCA */
	d[4] = 0xab; /* MotoCross: MSB byte 4 bit 7, 0xAB then the high nibble of byte 5 */
	d[5] = 0xc0;
	d[6] = 0x0d; /* MotoCross2: start 51 = byte 6 bit 3: low nibble 0xD, then byte 7 */
	d[7] = 0xef;
	assert_int_equal(value_of(m, d, 16, 0).raw, 0xbca);
	assert_true(value_of(m, d, 16, 0).phys == 3018.0);
	assert_int_equal(value_of(m, d, 16, 1).raw, 0xabc);
	assert_int_equal(value_of(m, d, 16, 2).raw, 0xdef);
	assert_reencodes(m, d);
}

static void dbc_one_bit_signals(void **state)
{
	const struct hl_dbc_message *m = hl_dbc_find_message(db, "Vec");
	uint8_t d[16] = { 0 };

	(void)state;
	assert_int_equal(value_of(m, d, 16, 3).raw, 0);
	assert_int_equal(value_of(m, d, 16, 4).raw, 0);
	d[8] = 0x02;
	d[9] = 0x80;
	assert_int_equal(value_of(m, d, 16, 3).raw, 1);
	assert_int_equal(value_of(m, d, 16, 4).raw, 1);
	assert_reencodes(m, d);
	d[8] = 0xfd; /* every other bit set: still 0 */
	d[9] = 0x7f;
	assert_int_equal(value_of(m, d, 16, 3).raw, 0);
	assert_int_equal(value_of(m, d, 16, 4).raw, 0);
}

static void dbc_negative_signed(void **state)
{
	const struct hl_dbc_message *m = hl_dbc_find_message(db, "Vec");
	uint8_t d[16] = { 0 };
	uint8_t e[16] = { 0 };
	uint64_t raw;

	(void)state;
	d[10] = 0x34; /* Neg: 12 bits 0xE34 = -460; phys = -460 * 0.5 + 10 = -220 */
	d[11] = 0xfe; /* the high nibble belongs to no signal */
	d[12] = 0x80; /* MotoNeg: -128 */
	assert_int_equal((int64_t)value_of(m, d, 16, 5).raw, -460);
	assert_true(value_of(m, d, 16, 5).phys == -220.0);
	assert_int_equal((int64_t)value_of(m, d, 16, 6).raw, -128);
	assert_true(value_of(m, d, 16, 6).phys == -128.0);
	/* and back: -220 -> raw -460 -> the 12 bits 0xE34 */
	assert_int_equal(hl_dbc_signal_raw_from_phys(&m->signals[5], -220.0, &raw), 0);
	assert_int_equal((int64_t)raw, -460);
	assert_int_equal(hl_dbc_signal_encode(&m->signals[5], -220.0, e, 16), 0);
	assert_int_equal(hl_dbc_signal_encode(&m->signals[6], -128.0, e, 16), 0);
	assert_int_equal(e[10], 0x34);
	assert_int_equal(e[11], 0x0e);
	assert_int_equal(e[12], 0x80);
	/* the 12-bit range is -2048..2047: phys -1014..1033.5 */
	assert_int_equal(hl_dbc_signal_raw_from_phys(&m->signals[5], 1033.5, &raw), 0);
	assert_int_equal(raw, 2047);
	assert_int_equal(hl_dbc_signal_raw_from_phys(&m->signals[5], 1034.0, &raw), -ERANGE);
	assert_int_equal(hl_dbc_signal_raw_from_phys(&m->signals[5], -1014.0, &raw), 0);
	assert_int_equal((int64_t)raw, -2048);
	assert_int_equal(hl_dbc_signal_raw_from_phys(&m->signals[5], -1014.5, &raw), -ERANGE);
	assert_int_equal(hl_dbc_signal_raw_from_phys(&m->signals[6], NAN, &raw), -ERANGE);
}

static void dbc_64_bit_signals(void **state)
{
	const struct hl_dbc_message *w = hl_dbc_find_message(db, "Wide");
	const struct hl_dbc_message *o = hl_dbc_find_message(db, "Odd");
	const struct hl_dbc_message *o2 = hl_dbc_find_message(db, "Odd2");
	const uint8_t d[16] = { 1,    2,    3,	  4,	5,    6,    7,	  8,
				0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88 };
	/* 72-bit little-endian number 0x0F_FEDCBA98_76543210 shifted right by 4 */
	const uint8_t u[16] = { 0x10, 0x32, 0x54, 0x76, 0x98, 0xba, 0xdc, 0xfe, 0x0f };
	/* big-endian bits 4..67: low nibble of byte 0, bytes 1..7, high nibble of byte 8 */
	const uint8_t v[16] = { 0x0f, 0xed, 0xcb, 0xa9, 0x87, 0x65, 0x43, 0x21, 0xa0 };
	uint8_t e[16] = { 0 };

	(void)state;
	assert_int_equal(value_of(w, d, 16, 0).raw, 0x0807060504030201ull);
	assert_int_equal(value_of(w, d, 16, 1).raw, 0x1122334455667788ull);
	assert_int_equal(value_of(o, u, 16, 0).raw, 0xffedcba987654321ull);
	assert_int_equal(value_of(o2, v, 16, 0).raw, 0xfedcba987654321aull);
	assert_reencodes(w, d);
	assert_reencodes(o, u);
	assert_reencodes(o2, v);
	assert_int_equal(hl_dbc_signal_set_raw(&o->signals[0], 0xffedcba987654321ull, e, 16), 0);
	assert_memory_equal(e, u, 16);
}

static void dbc_float_and_double(void **state)
{
	const struct hl_dbc_message *m = hl_dbc_find_message(db, "Floats");
	/* 1.5f = 0x3FC00000 (LE), -2.25f = 0xC0100000 (BE), pi = 0x400921FB54442D18 (LE) */
	const uint8_t d[16] = { 0x00, 0x00, 0xc0, 0x3f, 0xc0, 0x10, 0x00, 0x00,
				0x18, 0x2d, 0x44, 0x54, 0xfb, 0x21, 0x09, 0x40 };
	uint8_t e[16] = { 0 };

	(void)state;
	assert_true(value_of(m, d, 16, 0).phys == 1.5);
	assert_int_equal(value_of(m, d, 16, 0).raw, 0x3fc00000);
	assert_true(value_of(m, d, 16, 1).phys == -2.25);
	assert_true(value_of(m, d, 16, 2).phys == 3.141592653589793);
	assert_int_equal(hl_dbc_signal_encode(&m->signals[0], 1.5, e, 16), 0);
	assert_int_equal(hl_dbc_signal_encode(&m->signals[1], -2.25, e, 16), 0);
	assert_int_equal(hl_dbc_signal_encode(&m->signals[2], 3.141592653589793, e, 16), 0);
	assert_memory_equal(e, d, 16);
	assert_int_equal(hl_dbc_signal_encode(&m->signals[0], 1e39, e, 16), -ERANGE);
}

static void dbc_multiplexed_pages(void **state)
{
	struct hl_dbc *hd;
	struct hl_dbc_error err;
	const struct hl_dbc_message *m;
	struct hl_dbc_value v[128];
	/* page 5 (sources 41..48), counter 9; the sources 63,0,1,2,62,31,32,7 packed 6 bits each,
	 * little endian: 0x3F | 0<<6 | 1<<12 | 2<<18 | 62<<24 | 31<<30 | 32<<36 | 7<<42 */
	const uint8_t d[8] = { 0xaa, 0x59, 0x3f, 0x10, 0x08, 0xfe, 0x07, 0x1e };
	const int want[8] = { 63, 0, 1, 2, 62, 31, 32, 7 };
	int n;

	(void)state;
	assert_int_equal(hl_dbc_parse_file(HL_DBC_DIR "/hd84.dbc", &hd, &err), 0);
	m = hl_dbc_find_id(hd, 0x320);
	assert_string_equal(m->name, "HL_Dim_L");
	n = hl_dbc_decode(m, d, 8, v);
	assert_int_equal(n, 11);
	assert_string_equal(m->signals[v[0].signal].name, "HL_CRC_L");
	assert_int_equal(v[0].raw, 0xaa);
	assert_string_equal(m->signals[v[1].signal].name, "HL_Alive_L");
	assert_int_equal(v[1].raw, 9);
	assert_string_equal(m->signals[v[2].signal].name, "HL_Page_L");
	assert_int_equal(v[2].raw, 5);
	for (int j = 0; j < 8; j++) {
		char name[16];

		snprintf(name, sizeof(name), "LED_%03d", 41 + j);
		assert_string_equal(m->signals[v[3 + j].signal].name, name);
		assert_int_equal(v[3 + j].raw, want[j]);
		assert_true(v[3 + j].phys == want[j] * (1.0 / 63));
	}
	/* page 11 has 7 sources; the 96th slot (bits 58..63) is the beam mode */
	{
		const uint8_t p11[8] = { 0, 0xb0, 0, 0, 0, 0, 0, 0x0c };

		n = hl_dbc_decode(m, p11, 8, v);
		assert_int_equal(n, 3 + 7 + 1);
		assert_string_equal(m->signals[v[9].signal].name, "LED_095");
		assert_string_equal(m->signals[v[10].signal].name, "HL_Mode_L");
		assert_int_equal(v[10].raw, 3);
	}
	/* pages 12..15 select nothing */
	{
		const uint8_t p12[8] = { 0, 0xc0, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff };

		assert_int_equal(hl_dbc_decode(m, p12, 8, v), 3);
	}
	hl_dbc_free(hd);
}

static void dbc_extended_multiplexing(void **state)
{
	const struct hl_dbc_message *m = hl_dbc_find_message(db, "Mux");
	struct hl_dbc_value v[16];
	uint8_t d[8] = { 2, 6, 0x77, 0, 0, 0, 0, 0x55 };
	int n;

	(void)state;
	/* Sel = 2 selects Sub; Sub = 6 lies in 5-7 and selects C */
	n = hl_dbc_decode(m, d, 8, v);
	assert_int_equal(n, 4);
	assert_string_equal(m->signals[v[0].signal].name, "Sel");
	assert_string_equal(m->signals[v[1].signal].name, "Always");
	assert_int_equal(v[1].raw, 0x55);
	assert_string_equal(m->signals[v[2].signal].name, "Sub");
	assert_int_equal(v[2].raw, 6);
	assert_string_equal(m->signals[v[3].signal].name, "C");
	assert_int_equal(v[3].raw, 0x77);
	assert_true(hl_dbc_signal_present(m, hl_dbc_find_signal(m, "C"), d, 8));
	d[1] = 4; /* not in 3-3, 5-7 */
	assert_int_equal(hl_dbc_decode(m, d, 8, v), 3);
	assert_false(hl_dbc_signal_present(m, hl_dbc_find_signal(m, "C"), d, 8));
	d[1] = 3;
	assert_int_equal(hl_dbc_decode(m, d, 8, v), 4);
	d[0] = 0; /* Sel = 0: A (16 bits), no Sub, so no C either even though byte 1 is 3 */
	n = hl_dbc_decode(m, d, 8, v);
	assert_int_equal(n, 3);
	assert_string_equal(m->signals[v[2].signal].name, "A");
	assert_int_equal(v[2].raw, 0x7703);
	assert_false(hl_dbc_signal_present(m, hl_dbc_find_signal(m, "C"), d, 8));
	d[0] = 1;
	n = hl_dbc_decode(m, d, 8, v);
	assert_int_equal(n, 3);
	assert_string_equal(m->signals[v[2].signal].name, "B");
}

static void dbc_fd_64_bytes_extended_id(void **state)
{
	const struct hl_dbc_message *m;
	struct hl_dbc_counters c = { 0 };
	struct hl_dbc_value v[8];
	uint8_t d[64] = { 0 };
	int n;

	(void)state;
	d[0] = 0x42;
	d[62] = 0xbc; /* Across (Intel): bits 500..503 = high nibble of byte 62 (0xB) ... */
	d[63] = 0xda; /* ... and bits 504..507 = low nibble of byte 63 (0xA): 0xAB */
	/* MotoAcross: low nibble of byte 62 (0xC), then high nibble of byte 63 (0xD): 0xCD */
	n = hl_dbc_decode_frame(db, 0x18ff00fe | HL_DBC_EFF_FLAG, d, 64, &c, &m, v);
	assert_int_equal(n, 4);
	assert_string_equal(m->name, "Fd");
	assert_true(m->extended);
	assert_int_equal(v[0].raw, 0x42);
	assert_int_equal(v[1].raw, 0xab);
	assert_int_equal(v[2].raw, 0xcd);
	assert_int_equal(v[3].raw, 0xda);
	assert_int_equal(c.decoded, 1);
	/* short frame: rejected, counted, nothing read */
	assert_int_equal(hl_dbc_decode_frame(db, 0x18ff00fe | HL_DBC_EFF_FLAG, d, 48, &c, &m, v),
			 -EMSGSIZE);
	assert_int_equal(c.short_frame, 1);
	/* the same 29 bits without the extended flag are another (unknown) ID */
	assert_int_equal(hl_dbc_decode_frame(db, 0x18ff00fe, d, 64, &c, &m, v), -ENOENT);
	assert_int_equal(c.unknown_id, 1);
	assert_int_equal(c.decoded, 1);
}

static void dbc_encode_range_and_rounding(void **state)
{
	const struct hl_dbc_message *m = hl_dbc_find_message(db, "Mux");
	const struct hl_dbc_signal *sel = hl_dbc_find_signal(m, "Sel");
	uint8_t d[8] = { 0 };
	uint64_t raw;

	(void)state;
	assert_int_equal(hl_dbc_signal_raw_from_phys(sel, 254.6, &raw), 0);
	assert_int_equal(raw, 255);
	assert_int_equal(hl_dbc_signal_raw_from_phys(sel, 255.6, &raw), -ERANGE); /* max 255 */
	assert_int_equal(hl_dbc_signal_raw_from_phys(sel, -0.6, &raw), -ERANGE);
	assert_int_equal(hl_dbc_signal_encode(sel, 300, d, 8), -ERANGE);
	assert_int_equal(hl_dbc_signal_encode(sel, 7, d, 0), -EMSGSIZE);
	assert_int_equal(hl_dbc_signal_get_raw(sel, d, 0, &raw), -EMSGSIZE);
	assert_int_equal(hl_dbc_signal_encode(sel, 7, d, 8), 0);
	assert_int_equal(d[0], 7);
}

/* Random raw values within each signal's bits and [min, max]; with multiplexors set first. */
static uint64_t random_raw(const struct hl_dbc_signal *s)
{
	uint64_t r = ((uint64_t)rand() << 42) ^ ((uint64_t)rand() << 21) ^ (uint64_t)rand();
	uint64_t top = s->length == 64 ? UINT64_MAX : ((uint64_t)1 << s->length) - 1;

	if (s->min < s->max && s->type == HL_DBC_INTEGER && !s->is_signed && s->offset == 0) {
		double hi = floor(s->max / s->factor + 1e-9);

		if (hi < (double)top)
			top = (uint64_t)hi;
	}
	return top == UINT64_MAX ? r : r % (top + 1);
}

static void round_trip_file(const char *path, int iterations)
{
	struct hl_dbc *hd;
	struct hl_dbc_error err;
	long checked = 0;

	assert_int_equal(hl_dbc_parse_file(path, &hd, &err), 0);
	for (int i = 0; i < hl_dbc_n_messages(hd); i++) {
		const struct hl_dbc_message *m = hl_dbc_message(hd, i);
		bool seen[128] = { false };

		for (int it = 0; it < iterations; it++) {
			uint8_t d[64] = { 0 }, e[64] = { 0 };
			struct hl_dbc_value v[128], w[128];
			int n;

			/* in signal order: the multiplexor comes first in the shipped files, so
			 * setting every signal and letting the page pick is one random frame */
			for (int k = 0; k < m->n_signals; k++)
				if (m->signals[k].mux_parent < 0)
					hl_dbc_signal_set_raw(&m->signals[k],
							      random_raw(&m->signals[k]), d,
							      m->size);
			for (int k = 0; k < m->n_signals; k++)
				if (m->signals[k].mux_parent >= 0 &&
				    hl_dbc_signal_present(m, &m->signals[k], d, m->size))
					hl_dbc_signal_set_raw(&m->signals[k],
							      random_raw(&m->signals[k]), d,
							      m->size);
			n = hl_dbc_decode(m, d, m->size, v);
			assert_true(n > 0);
			for (int k = 0; k < n; k++) {
				const struct hl_dbc_signal *s = &m->signals[v[k].signal];

				/* physical -> bits, into a fresh frame */
				assert_int_equal(hl_dbc_signal_encode(s, v[k].phys, e, m->size), 0);
				if (s->factor != 1)
					assert_true(fabs(v[k].phys - (double)v[k].raw / 63) <
						    1e-15);
				seen[v[k].signal] = true;
				checked++;
			}
			assert_memory_equal(e, d, m->size);
			assert_int_equal(hl_dbc_decode(m, e, m->size, w), n);
			for (int k = 0; k < n; k++) {
				assert_int_equal(w[k].signal, v[k].signal);
				assert_int_equal(w[k].raw, v[k].raw);
				assert_true(w[k].phys == v[k].phys);
			}
		}
		/* every signal of the message took part (pages are picked at random) */
		for (int k = 0; k < m->n_signals; k++)
			assert_true(seen[k]);
	}
	assert_true(checked > 2000 * hl_dbc_n_messages(hd));
	hl_dbc_free(hd);
}

static void dbc_round_trip_shipped_databases(void **state)
{
	(void)state;
	srand(84);
	round_trip_file(HL_DBC_DIR "/hd84.dbc", 2000);
	round_trip_file(HL_DBC_DIR "/hd84_fd.dbc", 2000);
}

/* Every signal of both files, every raw value 0..63 (LEDs) / 0..max: exhaustive for 6 bits. */
static void dbc_round_trip_every_led_value(void **state)
{
	static const char *const files[] = { HL_DBC_DIR "/hd84.dbc", HL_DBC_DIR "/hd84_fd.dbc" };

	(void)state;
	for (int f = 0; f < 2; f++) {
		struct hl_dbc *hd;
		struct hl_dbc_error err;
		int leds = 0;

		assert_int_equal(hl_dbc_parse_file(files[f], &hd, &err), 0);
		for (int i = 0; i < hl_dbc_n_messages(hd); i++) {
			const struct hl_dbc_message *m = hl_dbc_message(hd, i);

			for (int k = 0; k < m->n_signals; k++) {
				const struct hl_dbc_signal *s = &m->signals[k];

				if (s->length != 6 || strncmp(s->name, "LED_", 4) != 0)
					continue; /* HL_Mode_x is 6 bits too, of 0..3 */
				leds++;
				for (uint64_t r = 0; r < 64; r++) {
					uint8_t e[64] = { 0 };
					uint64_t back;

					assert_int_equal(
						hl_dbc_signal_encode(s, hl_dbc_signal_phys(s, r), e,
								     m->size),
						0);
					assert_int_equal(
						hl_dbc_signal_get_raw(s, e, m->size, &back), 0);
					assert_int_equal(back, r);
				}
			}
		}
		assert_int_equal(leds, 2 * 95);
		hl_dbc_free(hd);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(dbc_intel_and_motorola_crossing_bytes),
		cmocka_unit_test(dbc_one_bit_signals),
		cmocka_unit_test(dbc_negative_signed),
		cmocka_unit_test(dbc_64_bit_signals),
		cmocka_unit_test(dbc_float_and_double),
		cmocka_unit_test(dbc_multiplexed_pages),
		cmocka_unit_test(dbc_extended_multiplexing),
		cmocka_unit_test(dbc_fd_64_bytes_extended_id),
		cmocka_unit_test(dbc_encode_range_and_rounding),
		cmocka_unit_test(dbc_round_trip_shipped_databases),
		cmocka_unit_test(dbc_round_trip_every_led_value),
	};

	return cmocka_run_group_tests(tests, setup, teardown);
}
