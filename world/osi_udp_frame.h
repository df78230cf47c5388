/* SPDX-License-Identifier: MIT */
/*
 * esmini's framing of OSI messages in UDP datagrams (docs/osi.md "UDP (esmini's framing)").
 * esmini splits each serialized message into parts; every datagram is an 8-byte header and one
 * part:
 *
 *   bytes 0..3  counter: int32, 1, 2, 3, ... for the parts of a message, the last one negated
 *               (a message in one datagram: -1)
 *   bytes 4..7  size: uint32, the bytes of the part that follow (the datagram is 8 + size)
 *   bytes 8..   the part, at most 8192 bytes by esmini's default
 *
 * esmini writes the header in its host's byte order; every host it runs on is little-endian, and
 * so we read and write it. A message of 0 bytes is sent as no datagram at all.
 *
 * The reassembler takes datagrams one by one and hands back whole messages. It is strict: a part
 * is taken only when it is the next one of the message in progress; any gap, repetition or
 * reordering drops the message (UDP loses and reorders; a half-right message is worth nothing).
 * A first part (counter 1 or -1) always starts a new message, dropping an unfinished one.
 *
 * Thread-safety: a reassembler is one thread's (the receiving one). hl_osi_udp_split() is
 * reentrant. Only hl_osi_udp_reasm_new() allocates; feeding allocates nothing.
 */
#ifndef HL_WORLD_OSI_UDP_FRAME_H
#define HL_WORLD_OSI_UDP_FRAME_H

#include <stddef.h>
#include <stdint.h>

#define HL_OSI_UDP_PORT 48198 /* esmini's default destination port */
#define HL_OSI_UDP_HEADER 8 /* bytes before each part */
#define HL_OSI_UDP_PART_DEFAULT 8192 /* bytes of message per datagram, esmini's default */
#define HL_OSI_UDP_PART_MAX 65499 /* bytes: the largest part that fits an IPv4 UDP datagram */
#define HL_OSI_UDP_MSG_DEFAULT (16u << 20) /* bytes, a reassembler's message limit */

struct hl_osi_udp_reasm;

/* What became of one datagram. */
enum hl_osi_udp_result {
	HL_OSI_UDP_MESSAGE, /* it completed a message: *ret_msg, *ret_len */
	HL_OSI_UDP_PART, /* a part kept; more to come */
	HL_OSI_UDP_BAD_HEADER, /* ignored: under 8 bytes, size not the datagram's length - 8, size
				  0, counter 0 or INT32_MIN; a message in progress is kept */
	HL_OSI_UDP_OUT_OF_ORDER, /* not the next part of a message in progress (a gap, a repeat,
				    or no message in progress): ignored, the message dropped */
	HL_OSI_UDP_TOO_LARGE, /* the message would pass the limit: it and this part dropped */
};

/* Counts since hl_osi_udp_reasm_new(). */
struct hl_osi_udp_stats {
	uint64_t messages; /* completed */
	uint64_t dropped; /* messages begun and abandoned: gap, repeat, restart, too large */
	uint64_t bad_header; /* datagrams */
	uint64_t orphans; /* parts with no message in progress (its start lost, or dropped) */
};

/*
 * A reassembler for messages up to max_msg bytes (1 .. UINT32_MAX; the buffer is allocated
 * here, once). 0, -EINVAL or -ENOMEM.
 */
int hl_osi_udp_reasm_new(size_t max_msg, struct hl_osi_udp_reasm **ret);
void hl_osi_udp_reasm_free(struct hl_osi_udp_reasm *r);

/*
 * Takes one datagram (len bytes). On HL_OSI_UDP_MESSAGE *ret_msg points at the message in the
 * reassembler's buffer, valid until the next feed, reset or free; otherwise *ret_msg and
 * *ret_len are untouched.
 */
enum hl_osi_udp_result hl_osi_udp_reasm_feed(struct hl_osi_udp_reasm *r, const uint8_t *dgram,
					     size_t len, const uint8_t **ret_msg, size_t *ret_len);

/* Forgets a message in progress (not counted as dropped): after a pause of the sender. */
void hl_osi_udp_reasm_reset(struct hl_osi_udp_reasm *r);

void hl_osi_udp_reasm_stats(const struct hl_osi_udp_reasm *r, struct hl_osi_udp_stats *ret);

/* "message", "part", "bad header", "out of order", "too large". */
const char *hl_osi_udp_result_name(enum hl_osi_udp_result res);

/*
 * The number of datagrams a message of len bytes takes with part_max bytes a part: 0 for an
 * empty message, as esmini sends none.
 */
size_t hl_osi_udp_split_count(size_t len, size_t part_max);

/*
 * Writes datagram i (0-based) of msg (len bytes) split in parts of part_max bytes (1 ..
 * HL_OSI_UDP_PART_MAX) into dgram (size bytes, at least HL_OSI_UDP_HEADER + the part). Returns
 * the datagram's length, -EINVAL for a bad part_max, -ERANGE for i past the last part,
 * -EMSGSIZE when the parts would not fit esmini's int32 counter or dgram is too small.
 */
int hl_osi_udp_split(const uint8_t *msg, size_t len, size_t part_max, size_t i, uint8_t *dgram,
		     size_t size);

#endif
