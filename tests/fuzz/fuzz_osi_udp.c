/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target: the input split into datagrams (each a 2-byte little-endian length, then
 * that many bytes) fed to an OSI UDP reassembler never crashes or reads out of bounds; every
 * completed message fits the limit and is decoded; the input itself, split as esmini splits a
 * message and fed after a reset, comes back whole and byte for byte.
 */
#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "world/osi_msg.h"
#include "world/osi_udp_frame.h"

#define MAX_MSG (1u << 20) /* bytes: small, so that too_large is reached */

static struct hl_osi_udp_reasm *reasm;
static struct hl_osi_frame *frame;
static uint8_t dgram[HL_OSI_UDP_HEADER + HL_OSI_UDP_PART_MAX];

static void decode(const uint8_t *msg, size_t len)
{
	char why[256];

	if (!len || len > MAX_MSG)
		abort();
	hl_osi_decode(msg, len, HL_OSI_GROUND_TRUTH, frame, why, sizeof(why));
	hl_osi_decode(msg, len, HL_OSI_SENSOR_VIEW, frame, why, sizeof(why));
}

/* data split by esmini's framing in parts of part_max: the reassembler hands it back. */
static void round_trip(const uint8_t *data, size_t size, size_t part_max)
{
	const size_t n = hl_osi_udp_split_count(size, part_max);
	const uint8_t *msg = NULL;
	size_t len = 0;

	hl_osi_udp_reasm_reset(reasm);
	for (size_t i = 0; i < n; i++) {
		const int dlen = hl_osi_udp_split(data, size, part_max, i, dgram, sizeof(dgram));
		enum hl_osi_udp_result res;

		if (dlen < 0)
			abort();
		res = hl_osi_udp_reasm_feed(reasm, dgram, (size_t)dlen, &msg, &len);
		if (res != (i + 1 == n ? HL_OSI_UDP_MESSAGE : HL_OSI_UDP_PART))
			abort();
	}
	if (n && (len != size || memcmp(msg, data, size) != 0))
		abort();
	if (hl_osi_udp_split(data, size, part_max, n, dgram, sizeof(dgram)) != -ERANGE)
		abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	size_t off = 0;

	if (!reasm) {
		frame = hl_osi_frame_new();
		if (!frame || hl_osi_udp_reasm_new(MAX_MSG, &reasm) < 0)
			abort();
	}
	hl_osi_udp_reasm_reset(reasm);
	while (off + 2 <= size) {
		size_t n = (size_t)data[off] | (size_t)data[off + 1] << 8;
		const uint8_t *msg = NULL;
		size_t len = 0;

		off += 2;
		if (n > size - off)
			n = size - off;
		if (hl_osi_udp_reasm_feed(reasm, data + off, n, &msg, &len) == HL_OSI_UDP_MESSAGE)
			decode(msg, len);
		off += n;
	}
	if (size)
		round_trip(data, size, 1 + (size_t)data[0] * 64);
	return 0;
}
