/* SPDX-License-Identifier: MIT */
#include "can/e2e.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

/* MSB-first CRC registers, bit by bit: payloads are at most 64 bytes, and a table would buy
 * little next to the decode itself. */
static uint8_t crc8_update(uint8_t reg, uint8_t poly, const uint8_t *data, size_t len)
{
	for (size_t i = 0; i < len; i++) {
		reg ^= data[i];
		for (int b = 0; b < 8; b++)
			reg = (reg & 0x80) ? (uint8_t)((reg << 1) ^ poly) : (uint8_t)(reg << 1);
	}
	return reg;
}

static uint16_t crc16_update(uint16_t reg, const uint8_t *data, size_t len)
{
	for (size_t i = 0; i < len; i++) {
		reg ^= (uint16_t)(data[i] << 8);
		for (int b = 0; b < 8; b++)
			reg = (reg & 0x8000) ? (uint16_t)((reg << 1) ^ 0x1021) :
					       (uint16_t)(reg << 1);
	}
	return reg;
}

uint8_t hl_e2e_crc8_j1850(const uint8_t *data, size_t len)
{
	return crc8_update(0xff, 0x1d, data, len) ^ 0xff;
}

uint8_t hl_e2e_crc8_h2f(const uint8_t *data, size_t len)
{
	return crc8_update(0xff, 0x2f, data, len) ^ 0xff;
}

uint16_t hl_e2e_crc16_ccitt(const uint8_t *data, size_t len)
{
	return crc16_update(0xffff, data, len);
}

int hl_e2e_config_parse(const char *text, struct hl_e2e_config *ret)
{
	struct hl_e2e_config c = { HL_E2E_NONE, 0 };
	const char *s = text;
	char *end;
	unsigned long id;

	while (*s == ' ')
		s++;
	if (strcmp(s, "none") == 0 || *s == '\0') {
		*ret = c;
		return 0;
	}
	if (strncmp(s, "P1 ", 3) == 0)
		c.profile = HL_E2E_P1;
	else if (strncmp(s, "P5 ", 3) == 0)
		c.profile = HL_E2E_P5;
	else
		return -EINVAL;
	s += 3;
	while (*s == ' ')
		s++;
	if (strncmp(s, "dataid=", 7) != 0)
		return -EINVAL;
	s += 7;
	if (!(*s >= '0' && *s <= '9'))
		return -EINVAL;
	errno = 0;
	id = strtoul(s, &end, 0);
	if (errno || id > 0xffff)
		return -EINVAL;
	while (*end == ' ')
		end++;
	if (*end)
		return -EINVAL;
	c.data_id = (uint16_t)id;
	*ret = c;
	return 0;
}

const char *hl_e2e_profile_name(enum hl_e2e_profile profile)
{
	switch (profile) {
	case HL_E2E_P1:
		return "P1";
	case HL_E2E_P5:
		return "P5";
	default:
		return "none";
	}
}

size_t hl_e2e_min_len(enum hl_e2e_profile profile)
{
	switch (profile) {
	case HL_E2E_P1:
		return 2;
	case HL_E2E_P5:
		return 3;
	default:
		return 0;
	}
}

unsigned hl_e2e_counter_max(enum hl_e2e_profile profile)
{
	switch (profile) {
	case HL_E2E_P1:
		return 14;
	case HL_E2E_P5:
		return 255;
	default:
		return 0;
	}
}

int hl_e2e_crc(const struct hl_e2e_config *c, const uint8_t *data, size_t len, uint16_t *ret_crc)
{
	const uint8_t id[2] = { (uint8_t)(c->data_id & 0xff), (uint8_t)(c->data_id >> 8) };

	if (c->profile == HL_E2E_NONE)
		return -EINVAL;
	if (len < hl_e2e_min_len(c->profile))
		return -EMSGSIZE;
	if (c->profile == HL_E2E_P1) {
		uint8_t reg = crc8_update(0xff, 0x1d, id, 2);

		*ret_crc = crc8_update(reg, 0x1d, data + 1, len - 1) ^ 0xff;
	} else {
		uint16_t reg = crc16_update(0xffff, data + 2, len - 2);

		*ret_crc = crc16_update(reg, id, 2);
	}
	return 0;
}

int hl_e2e_protect(const struct hl_e2e_config *c, uint8_t *data, size_t len, unsigned counter)
{
	uint16_t crc;
	int rc;

	if (c->profile == HL_E2E_NONE || counter > hl_e2e_counter_max(c->profile))
		return -EINVAL;
	if (len < hl_e2e_min_len(c->profile))
		return -EMSGSIZE;
	if (c->profile == HL_E2E_P1)
		data[1] = (uint8_t)((data[1] & 0xf0) | counter);
	else
		data[2] = (uint8_t)counter;
	rc = hl_e2e_crc(c, data, len, &crc);
	if (rc < 0)
		return rc;
	if (c->profile == HL_E2E_P1) {
		data[0] = (uint8_t)crc;
	} else {
		data[0] = (uint8_t)(crc & 0xff);
		data[1] = (uint8_t)(crc >> 8);
	}
	return 0;
}

int hl_e2e_check(const struct hl_e2e_config *c, const uint8_t *data, size_t len)
{
	uint16_t crc, got;
	int rc = hl_e2e_crc(c, data, len, &crc);

	if (rc < 0)
		return rc;
	got = c->profile == HL_E2E_P1 ? data[0] : (uint16_t)(data[0] | data[1] << 8);
	return got == crc ? 0 : -EBADMSG;
}

unsigned hl_e2e_counter(const struct hl_e2e_config *c, const uint8_t *data)
{
	switch (c->profile) {
	case HL_E2E_P1:
		return data[1] & 0x0f;
	case HL_E2E_P5:
		return data[2];
	default:
		return 0;
	}
}

int hl_e2e_counter_check(unsigned max, unsigned prev, unsigned cur, unsigned *ret_lost)
{
	unsigned delta;

	if (prev > max || cur > max)
		return -EINVAL;
	delta = (cur + (max + 1) - prev) % (max + 1);
	*ret_lost = 0;
	if (delta == 0)
		return HL_E2E_COUNTER_REPEATED;
	if (delta == 1)
		return HL_E2E_COUNTER_OK;
	*ret_lost = delta - 1;
	return HL_E2E_COUNTER_LOST;
}
