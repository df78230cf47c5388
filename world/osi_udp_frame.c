/* SPDX-License-Identifier: MIT */
/* esmini's OSI datagrams: split a message into them, reassemble it from them. */
#include "world/osi_udp_frame.h"

#include <errno.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

struct hl_osi_udp_reasm {
	uint8_t *buf;
	size_t max_msg;
	size_t len; /* bytes of the message in progress */
	int32_t next; /* the counter the next part must carry (its absolute value); 0: none */
	struct hl_osi_udp_stats stats;
};

static uint32_t get_le32(const uint8_t *p)
{
	return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static void put_le32(uint8_t *p, uint32_t v)
{
	p[0] = (uint8_t)v;
	p[1] = (uint8_t)(v >> 8);
	p[2] = (uint8_t)(v >> 16);
	p[3] = (uint8_t)(v >> 24);
}

int hl_osi_udp_reasm_new(size_t max_msg, struct hl_osi_udp_reasm **ret)
{
	struct hl_osi_udp_reasm *r;

	if (max_msg == 0 || max_msg > UINT32_MAX)
		return -EINVAL;
	r = calloc(1, sizeof(*r));
	if (!r)
		return -ENOMEM;
	r->buf = malloc(max_msg);
	if (!r->buf) {
		free(r);
		return -ENOMEM;
	}
	r->max_msg = max_msg;
	*ret = r;
	return 0;
}

void hl_osi_udp_reasm_free(struct hl_osi_udp_reasm *r)
{
	if (!r)
		return;
	free(r->buf);
	free(r);
}

void hl_osi_udp_reasm_reset(struct hl_osi_udp_reasm *r)
{
	r->len = 0;
	r->next = 0;
}

void hl_osi_udp_reasm_stats(const struct hl_osi_udp_reasm *r, struct hl_osi_udp_stats *ret)
{
	*ret = r->stats;
}

/* Abandons the message in progress, if any, counting it. */
static void drop(struct hl_osi_udp_reasm *r)
{
	if (r->next)
		r->stats.dropped++;
	hl_osi_udp_reasm_reset(r);
}

enum hl_osi_udp_result hl_osi_udp_reasm_feed(struct hl_osi_udp_reasm *r, const uint8_t *dgram,
					     size_t len, const uint8_t **ret_msg, size_t *ret_len)
{
	int32_t counter, index;
	uint32_t size;
	bool last;

	if (len < HL_OSI_UDP_HEADER) {
		r->stats.bad_header++;
		return HL_OSI_UDP_BAD_HEADER;
	}
	counter = (int32_t)get_le32(dgram);
	size = get_le32(dgram + 4);
	if (counter == 0 || counter == INT32_MIN || size == 0 || size != len - HL_OSI_UDP_HEADER) {
		r->stats.bad_header++;
		return HL_OSI_UDP_BAD_HEADER;
	}
	last = counter < 0;
	index = last ? -counter : counter;

	if (index == 1) {
		drop(r); /* a new message: an unfinished one is lost */
	} else if (index != r->next) {
		if (r->next)
			drop(r);
		else
			r->stats.orphans++;
		return HL_OSI_UDP_OUT_OF_ORDER;
	}
	if (size > r->max_msg - r->len) {
		r->stats.dropped++; /* this message, begun with this part or before */
		hl_osi_udp_reasm_reset(r);
		return HL_OSI_UDP_TOO_LARGE;
	}
	memcpy(r->buf + r->len, dgram + HL_OSI_UDP_HEADER, size);
	r->len += size;
	if (!last) {
		/* no part can follow a counter of INT32_MAX */
		if (index == INT32_MAX) {
			drop(r);
			return HL_OSI_UDP_OUT_OF_ORDER;
		}
		r->next = index + 1;
		return HL_OSI_UDP_PART;
	}
	*ret_msg = r->buf;
	*ret_len = r->len;
	r->stats.messages++;
	r->len = 0;
	r->next = 0;
	return HL_OSI_UDP_MESSAGE;
}

const char *hl_osi_udp_result_name(enum hl_osi_udp_result res)
{
	switch (res) {
	case HL_OSI_UDP_MESSAGE:
		return "message";
	case HL_OSI_UDP_PART:
		return "part";
	case HL_OSI_UDP_BAD_HEADER:
		return "bad header";
	case HL_OSI_UDP_OUT_OF_ORDER:
		return "out of order";
	case HL_OSI_UDP_TOO_LARGE:
		return "too large";
	}
	return "?";
}

size_t hl_osi_udp_split_count(size_t len, size_t part_max)
{
	if (part_max == 0)
		return 0;
	return len / part_max + (len % part_max != 0);
}

int hl_osi_udp_split(const uint8_t *msg, size_t len, size_t part_max, size_t i, uint8_t *dgram,
		     size_t size)
{
	size_t n, off, part;
	int32_t counter;

	if (part_max == 0 || part_max > HL_OSI_UDP_PART_MAX)
		return -EINVAL;
	n = hl_osi_udp_split_count(len, part_max);
	if (n > INT32_MAX)
		return -EMSGSIZE;
	if (i >= n)
		return -ERANGE;
	off = i * part_max;
	part = len - off < part_max ? len - off : part_max;
	if (size < HL_OSI_UDP_HEADER + part)
		return -EMSGSIZE;
	counter = (int32_t)(i + 1);
	if (i + 1 == n)
		counter = -counter;
	put_le32(dgram, (uint32_t)counter);
	put_le32(dgram + 4, (uint32_t)part);
	memcpy(dgram + HL_OSI_UDP_HEADER, msg + off, part);
	return (int)(HL_OSI_UDP_HEADER + part);
}
