/* SPDX-License-Identifier: MIT */
/*
 * End-to-end protection (E2E) of CAN payloads: the CRCs and the counter logic, in one place.
 *
 * CRCs (parameters as in the reveng catalogue and AUTOSAR SWS CRC Library; none reflected):
 *   CRC-8/SAE-J1850   poly 0x1D,   init 0xFF,   xorout 0xFF    (check "123456789" = 0x4B)
 *   CRC-8/AUTOSAR     poly 0x2F,   init 0xFF,   xorout 0xFF    (8H2F, check = 0xDF)
 *   CRC-16/CCITT-FALSE poly 0x1021, init 0xFFFF, xorout 0x0000 (check = 0x29B1)
 *
 * Profiles, as the BO_ attribute HdlE2E names them ("P1 dataid=0x0123", "P5 dataid=0x0330",
 * "none"):
 *   P1  8-bit CRC-8/SAE-J1850 in byte 0 over the data ID (low byte, high byte) and bytes
 *       1..len-1; 4-bit counter 0..14 in the low nibble of byte 1 (15 is invalid). This is
 *       AUTOSAR profile 1's layout (CRC offset 0, counter offset 8, data ID mode "both"); the
 *       CRC uses the standard J1850 start and final XOR 0xFF, as docs/dbc.md fixes them for hdlamp
 *       (AUTOSAR profile 1 itself runs the J1850 polynomial with 0x00 / 0x00).
 *   P5  AUTOSAR profile 5: CRC-16/CCITT-FALSE over bytes 2..len-1, then the data ID low and
 *       high byte; stored little endian in bytes 0 and 1; 8-bit counter 0..255 in byte 2.
 *
 * Thread-safety: all functions are pure and may be called from any thread.
 */
#ifndef HL_CAN_E2E_H
#define HL_CAN_E2E_H

#include <stddef.h>
#include <stdint.h>

enum hl_e2e_profile {
	HL_E2E_NONE,
	HL_E2E_P1,
	HL_E2E_P5,
};

struct hl_e2e_config {
	enum hl_e2e_profile profile;
	uint16_t data_id;
};

enum hl_e2e_counter_status {
	HL_E2E_COUNTER_OK, /* exactly one step on */
	HL_E2E_COUNTER_REPEATED, /* the same value again */
	HL_E2E_COUNTER_LOST, /* more than one step: *ret_lost frames were missed */
};

/* One-shot CRCs. */
uint8_t hl_e2e_crc8_j1850(const uint8_t *data, size_t len);
uint8_t hl_e2e_crc8_h2f(const uint8_t *data, size_t len);
uint16_t hl_e2e_crc16_ccitt(const uint8_t *data, size_t len);

/* "P1 dataid=0x0123", "P5 dataid=816", "none" (dataid decimal or 0x hex, 0..0xFFFF). 0 or
 * -EINVAL. */
int hl_e2e_config_parse(const char *text, struct hl_e2e_config *ret);
/* Profile name ("P1", "P5", "none"). */
const char *hl_e2e_profile_name(enum hl_e2e_profile profile);
/* Smallest payload a profile can protect (bytes), 0 for none. */
size_t hl_e2e_min_len(enum hl_e2e_profile profile);
/* Largest counter value: 14 (P1), 255 (P5), 0 (none). */
unsigned hl_e2e_counter_max(enum hl_e2e_profile profile);

/* The CRC the payload should carry. -EMSGSIZE if too short, -EINVAL for profile none. */
int hl_e2e_crc(const struct hl_e2e_config *c, const uint8_t *data, size_t len, uint16_t *ret_crc);
/* Writes the counter and then the CRC. 0, -EMSGSIZE, -EINVAL (counter above the maximum). */
int hl_e2e_protect(const struct hl_e2e_config *c, uint8_t *data, size_t len, unsigned counter);
/* 0 when the CRC matches, -EBADMSG when not, -EMSGSIZE, -EINVAL. */
int hl_e2e_check(const struct hl_e2e_config *c, const uint8_t *data, size_t len);
/* The counter the payload carries (len >= hl_e2e_min_len()). */
unsigned hl_e2e_counter(const struct hl_e2e_config *c, const uint8_t *data);

/*
 * Compares a received counter with the previous one of the same message; counters run 0..max
 * and wrap. Returns an enum hl_e2e_counter_status and, for LOST, the number of missed values in
 * *ret_lost (else 0); -EINVAL when either value is above max.
 */
int hl_e2e_counter_check(unsigned max, unsigned prev, unsigned cur, unsigned *ret_lost);

#endif
