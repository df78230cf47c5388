/* SPDX-License-Identifier: MIT */
/*
 * The wire of one frame, bit by bit (docs/sil.md, "The virtual bus"). The frame is built as the
 * bits a transmitter sends, stuffed as it stuffs them, and only then counted and timed, so that
 * the stuff bits are those of the frame's real content.
 *
 * Classic CAN (ISO 11898-1; field list and CRC-15 x^15+x^14+x^10+x^8+x^7+x^4+x^3+1, i.e. 0x4599,
 * as CiA's "CRC" page gives them, https://www.can-cia.org/can-knowledge/can/crc/):
 *   SOF, 11-bit ID, RTR, IDE, r0, DLC, data, CRC-15                        (base format)
 *   SOF, 11-bit base ID, SRR, IDE, 18-bit extension, RTR, r1, r0, DLC, ... (extended format)
 * with a stuff bit after five equal bits from SOF to the end of the CRC sequence (the stuff bit
 * starts the next run), the CRC over the unstuffed bits; then CRC delimiter, ACK slot, ACK
 * delimiter, 7 EOF bits and 3 bits of intermission, never stuffed.
 *
 * CAN FD as ISO 11898-1:2015 has it (Vector's e-learning "Bit stuffing for CAN FD",
 * https://elearning.vector.com/mod/page/view.php?id=370; CiA's CRC page above; the CiA
 * dictionary's "stuff count", https://www.datajob.com/it/definizione/383/stuff-count):
 *   SOF, ID, RRS, IDE, FDF=1, res, BRS, ESI, DLC, data     (extended: base ID, SRR, IDE, ext.)
 *   dynamic stuffing from SOF to the end of the data field, the stuff bits included in the CRC;
 *   the stuff count: the dynamic stuff bits modulo 8 in a 3-bit Gray code and an even parity
 *   bit; the CRC sequence: CRC-17 (0x1685B) up to 16 data bytes, CRC-21 (0x102899) above
 *   (polynomials from CiA's page and Vector's "More data with the same security",
 *   https://elearning.vector.com/mod/page/view.php?id=369), its register started at 1 in the
 *   top bit as ISO's CRC asks (the CTU CAN FD IP core's history notes the change to "highest
 *   bit fixed in logic one to be compliant with CAN ISO FD"); the CRC field (stuff count and
 *   CRC sequence) opens with a fixed stuff bit and has one after every 4 of its bits, each the
 *   complement of the bit before it.
 * A dynamic stuff bit due right after the last data bit is not sent: the CRC field's first
 * fixed stuff bit, the complement of that bit, already breaks the run (our reading of the
 * rule "dynamic stuffing ends with the data field").
 *
 * Time: the nominal phase runs at bitrate; with BRS, the data phase (the bits after BRS up to
 * the last bit of the CRC field) at data_bitrate. Each phase's time is bits * 1e9 / rate
 * rounded to the nearest ns, and the frame's time the sum; the switch points' sample-point
 * fractions are folded into whole bits.
 */
#include "can/vbus.h"
#include "can/vbus_internal.h"

#include <stddef.h>

#define MAX_BITS 1024 /* an extended FD frame of 64 bytes has fewer than 800 */

struct wire {
	uint8_t bit[MAX_BITS]; /* as sent */
	unsigned n;
	uint8_t raw[MAX_BITS]; /* the frame's own bits, without stuff bits */
	unsigned n_raw;
	unsigned run; /* equal bits at the end of bit[] */
	unsigned stuff;
};

static void put(struct wire *w, unsigned b)
{
	w->run = w->n > 0 && w->bit[w->n - 1] == b ? w->run + 1 : 1;
	w->bit[w->n++] = (uint8_t)b;
}

/* A bit under the stuffing rule: after the fifth equal bit, its complement. */
static void put_stuffed(struct wire *w, unsigned b, bool stuff_after)
{
	w->raw[w->n_raw++] = (uint8_t)b;
	put(w, b);
	if (stuff_after && w->run == 5) {
		put(w, !b);
		w->stuff++;
	}
}

static void put_field(struct wire *w, uint32_t v, unsigned nbits, bool stuffed)
{
	for (unsigned i = nbits; i-- > 0;)
		put_stuffed(w, (v >> i) & 1, stuffed);
}

/* The bits of one CRC register, MSB first: shift b in. */
static uint32_t crc_bit(uint32_t reg, unsigned b, uint32_t poly, unsigned width)
{
	unsigned top = (reg >> (width - 1)) & 1;

	reg = (reg << 1) & ((1u << width) - 1);
	return top ^ b ? reg ^ poly : reg;
}

static uint32_t crc_bits(uint32_t reg, const uint8_t *bits, unsigned n, uint32_t poly,
			 unsigned width)
{
	for (unsigned i = 0; i < n; i++)
		reg = crc_bit(reg, bits[i], poly, width);
	return reg;
}

int hl_vbus_dlc(uint8_t len, bool fd)
{
	static const uint8_t fd_len[] = { 12, 16, 20, 24, 32, 48, 64 };

	if (len <= 8)
		return len;
	if (!fd)
		return -1;
	for (unsigned i = 0; i < sizeof(fd_len); i++)
		if (fd_len[i] == len)
			return 9 + (int)i;
	return -1;
}

bool hl_vbus_id_valid(uint32_t can_id)
{
	if (can_id & HL_DBC_EFF_FLAG)
		return (can_id & ~HL_DBC_EFF_FLAG) <= 0x1fffffffu;
	return can_id <= 0x7ffu;
}

uint64_t hl_vbus_arbitration_key(uint32_t can_id)
{
	/* The arbitration bits as sent, MSB first: base ID, RTR/SRR, IDE, extension, RTR. */
	if (can_id & HL_DBC_EFF_FLAG) {
		uint32_t id = can_id & 0x1fffffffu;

		return (uint64_t)(id >> 18) << 21 | 1u << 20 | 1u << 19 | (id & 0x3ffffu) << 1;
	}
	return (uint64_t)can_id << 21;
}

/* The header up to DLC, stuffed as it goes; *ret_brs_end: bits up to and including BRS. */
static void put_header(struct wire *w, uint32_t can_id, int dlc, bool fd, bool brs,
		       unsigned *ret_brs_end)
{
	put_stuffed(w, 0, true); /* SOF */
	if (can_id & HL_DBC_EFF_FLAG) {
		uint32_t id = can_id & 0x1fffffffu;

		put_field(w, id >> 18, 11, true);
		put_stuffed(w, 1, true); /* SRR */
		put_stuffed(w, 1, true); /* IDE */
		put_field(w, id & 0x3ffffu, 18, true);
		put_stuffed(w, 0, true); /* RTR (classic) / RRS (FD) */
		if (!fd)
			put_stuffed(w, 0, true); /* r1 */
	} else {
		put_field(w, can_id, 11, true);
		put_stuffed(w, 0, true); /* RTR / RRS */
		put_stuffed(w, 0, true); /* IDE */
	}
	if (fd) {
		put_stuffed(w, 1, true); /* FDF */
		put_stuffed(w, 0, true); /* res */
		put_stuffed(w, brs, true);
		*ret_brs_end = w->n;
		put_stuffed(w, 0, true); /* ESI: error active */
	} else {
		put_stuffed(w, 0, true); /* r0 */
		*ret_brs_end = w->n;
	}
	put_field(w, (uint32_t)dlc, 4, true);
}

static void put_classic_body(struct wire *w, const uint8_t *data, uint8_t len)
{
	for (unsigned i = 0; i < len; i++)
		put_field(w, data[i], 8, true);
	/* CRC-15 over the unstuffed bits from SOF to the end of the data field. */
	put_field(w, crc_bits(0, w->raw, w->n_raw, 0x4599, 15), 15, true);
}

static void put_fd_body(struct wire *w, const uint8_t *data, uint8_t len)
{
	static const uint8_t gray[8] = { 0, 1, 3, 2, 6, 7, 5, 4 };
	unsigned width = len > 16 ? 21 : 17;
	uint32_t poly = len > 16 ? 0x102899u : 0x1685bu;
	uint32_t crc, count;
	unsigned g, field_bits, since_fixed = 0;

	for (unsigned i = 0; i < len; i++)
		for (unsigned k = 8; k-- > 0;)
			put_stuffed(w, (data[i] >> k) & 1, !(i == len - 1U && k == 0));
	g = gray[w->stuff % 8];
	count = g << 1 | (((g >> 2) ^ (g >> 1) ^ g) & 1); /* even parity over the Gray code */
	/* ISO's CRC: over the stuffed bits from SOF and the stuff count, started at 1 << (w-1). */
	crc = crc_bits(1u << (width - 1), w->bit, w->n, poly, width);
	for (unsigned k = 4; k-- > 0;)
		crc = crc_bit(crc, (count >> k) & 1, poly, width);
	field_bits = 4 + width;
	for (unsigned i = 0; i < field_bits; i++) {
		unsigned b = i < 4 ? (count >> (3 - i)) & 1 : (crc >> (field_bits - 1 - i)) & 1;

		if (since_fixed == 0 || since_fixed == 4) {
			put(w, !w->bit[w->n - 1]);
			w->stuff++;
			since_fixed = 0;
		}
		put(w, b);
		since_fixed++;
	}
}

static int64_t bits_ns(unsigned bits, uint32_t rate)
{
	return (int64_t)(((uint64_t)bits * 1000000000u + rate / 2) / rate);
}

int64_t hl_vbus_wire(uint32_t can_id, const uint8_t *data, uint8_t len, bool fd, bool brs,
		     uint32_t bitrate, uint32_t data_bitrate, unsigned *ret_bits,
		     unsigned *ret_stuff, int64_t *ret_ns_ifs)
{
	struct wire w = { .n = 0 };
	int dlc = hl_vbus_dlc(len, fd);
	unsigned brs_end, crc_end, nominal, fast;

	if (dlc < 0 || !hl_vbus_id_valid(can_id) || (brs && !fd) || bitrate == 0 ||
	    (brs && data_bitrate == 0) || (len > 0 && !data))
		return -1;
	put_header(&w, can_id, dlc, fd, brs, &brs_end);
	if (fd)
		put_fd_body(&w, data, len);
	else
		put_classic_body(&w, data, len);
	crc_end = w.n;
	for (unsigned i = 0; i < 10; i++) /* CRC delimiter, ACK slot and delimiter, EOF */
		put(&w, i != 1);
	fast = fd && brs ? crc_end - brs_end : 0;
	nominal = w.n - fast;
	if (ret_bits)
		*ret_bits = w.n + 3;
	if (ret_stuff)
		*ret_stuff = w.stuff;
	if (ret_ns_ifs)
		*ret_ns_ifs =
			bits_ns(nominal + 3, bitrate) + (fast ? bits_ns(fast, data_bitrate) : 0);
	return bits_ns(nominal, bitrate) + (fast ? bits_ns(fast, data_bitrate) : 0);
}
