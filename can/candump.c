/* SPDX-License-Identifier: MIT */
#include "can/candump.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

struct cursor {
	const char *s, *start, *end;
	struct hl_candump_error *err;
};

static int bad(struct cursor *c, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

static int bad(struct cursor *c, const char *fmt, ...)
{
	va_list ap;

	c->err->column = (int)(c->s - c->start) + 1;
	va_start(ap, fmt);
	vsnprintf(c->err->msg, sizeof(c->err->msg), fmt, ap);
	va_end(ap);
	return -EBADMSG;
}

static int hex(char ch)
{
	if (ch >= '0' && ch <= '9')
		return ch - '0';
	if (ch >= 'A' && ch <= 'F')
		return ch - 'A' + 10;
	if (ch >= 'a' && ch <= 'f')
		return ch - 'a' + 10;
	return -1;
}

static bool at(const struct cursor *c, char ch)
{
	return c->s < c->end && *c->s == ch;
}

static bool fd_len_valid(unsigned len)
{
	return len <= 8 || len == 12 || len == 16 || len == 20 || len == 24 || len == 32 ||
	       len == 48 || len == 64;
}

static int parse_time(struct cursor *c, int64_t *ret)
{
	int64_t sec = 0, usec = 0;
	int digits = 0;

	if (!at(c, '('))
		return bad(c, "expected '(' starting the timestamp");
	c->s++;
	while (c->s < c->end && *c->s >= '0' && *c->s <= '9' && digits < 12) {
		sec = sec * 10 + (*c->s++ - '0');
		digits++;
	}
	if (digits == 0 || (c->s < c->end && *c->s >= '0' && *c->s <= '9'))
		return bad(c, "expected 1 to 12 digits of seconds");
	if (!at(c, '.'))
		return bad(c, "expected '.' between seconds and microseconds");
	c->s++;
	for (digits = 0; digits < 6 && c->s < c->end && *c->s >= '0' && *c->s <= '9'; digits++)
		usec = usec * 10 + (*c->s++ - '0');
	if (digits == 0 || (c->s < c->end && *c->s >= '0' && *c->s <= '9'))
		return bad(c, "expected 1 to 6 digits of microseconds");
	for (; digits < 6; digits++)
		usec *= 10;
	if (!at(c, ')'))
		return bad(c, "expected ')' closing the timestamp");
	c->s++;
	*ret = sec * 1000000 + usec;
	return 0;
}

static int parse_iface(struct cursor *c, char *iface)
{
	size_t n = 0;

	if (!at(c, ' '))
		return bad(c, "expected ' ' after the timestamp");
	c->s++;
	while (c->s<c->end && * c->s> ' ' && *c->s < 0x7f) {
		if (n + 1 >= IFNAMSIZ)
			return bad(c, "expected an interface name of at most %d characters",
				   IFNAMSIZ - 1);
		iface[n++] = *c->s++;
	}
	iface[n] = '\0';
	if (n == 0)
		return bad(c, "expected an interface name");
	if (!at(c, ' '))
		return bad(c, "expected ' ' after the interface name");
	c->s++;
	return 0;
}

static int parse_id(struct cursor *c, canid_t *ret)
{
	const char *p = c->s;
	canid_t id = 0;
	int n = 0;

	while (p + n < c->end && hex(p[n]) >= 0 && n < 9)
		n++;
	if (p + n >= c->end || p[n] != '#' || (n != 3 && n != 8)) {
		if (n != 3 && n != 8)
			return bad(c,
				   "expected a CAN ID of 3 (standard) or 8 (extended) hex digits");
		c->s += n;
		return bad(c, "expected '#' after the CAN ID");
	}
	for (int i = 0; i < n; i++)
		id = id << 4 | (canid_t)hex(p[i]);
	if (n == 3) {
		if (id > CAN_SFF_MASK)
			return bad(c, "expected a standard ID 000..7FF, found %03X", id);
	} else if (id & CAN_ERR_FLAG) {
		if (id & ~(CAN_ERR_FLAG | CAN_ERR_MASK))
			return bad(c, "expected an error frame ID 2xxxxxxx, found %08X", id);
	} else {
		if (id > CAN_EFF_MASK)
			return bad(c, "expected an extended ID 00000000..1FFFFFFF, found %08X", id);
		id |= CAN_EFF_FLAG;
	}
	c->s += n + 1;
	*ret = id;
	return 0;
}

static int parse_data(struct cursor *c, struct canfd_frame *cf, unsigned max)
{
	unsigned n = 0;

	while (c->s < c->end && hex(*c->s) >= 0) {
		if (n == max)
			return bad(c, "expected at most %u data bytes", max);
		if (c->s + 1 >= c->end || hex(c->s[1]) < 0) {
			c->s++;
			return bad(c, "expected a second hex digit of the data byte");
		}
		cf->data[n++] = (uint8_t)(hex(c->s[0]) << 4 | hex(c->s[1]));
		c->s += 2;
		if (at(c, '.') && c->s + 1 < c->end && hex(c->s[1]) >= 0)
			c->s++;
	}
	cf->len = (uint8_t)n;
	return 0;
}

int hl_candump_parse(const char *line, size_t len, struct hl_candump_frame *ret,
		     struct hl_candump_error *ret_err)
{
	struct hl_candump_error dummy;
	struct hl_candump_frame f = { 0 };
	struct cursor c = { line, line, line + len, ret_err ? ret_err : &dummy };
	int rc;

	*c.err = (struct hl_candump_error){ 0 };
	while (c.end > c.s && (c.end[-1] == '\n' || c.end[-1] == '\r'))
		c.end--;
	rc = parse_time(&c, &f.t_us);
	if (rc == 0)
		rc = parse_iface(&c, f.iface);
	if (rc == 0)
		rc = parse_id(&c, &f.frame.can_id);
	if (rc < 0)
		return rc;
	if (at(&c, '#')) {
		int flags;

		if (f.frame.can_id & CAN_ERR_FLAG)
			return bad(&c, "expected data after an error frame's '#', not CAN FD");
		c.s++;
		flags = c.s < c.end ? hex(*c.s) : -1;
		if (flags < 0)
			return bad(&c, "expected one hex digit of CAN FD flags after '##'");
		c.s++;
		f.fd = true;
		f.frame.flags = (uint8_t)flags;
		rc = parse_data(&c, &f.frame, CANFD_MAX_DLEN);
		if (rc == 0 && !fd_len_valid(f.frame.len))
			return bad(
				&c,
				"expected a CAN FD length (0..8, 12, 16, 20, 24, 32, 48, 64), found %u bytes",
				f.frame.len);
	} else if (at(&c, 'R') || at(&c, 'r')) {
		c.s++;
		f.frame.can_id |= CAN_RTR_FLAG;
		if (c.s < c.end && *c.s >= '0' && *c.s <= '8')
			f.frame.len = (uint8_t)(*c.s++ - '0');
	} else {
		/* no data bytes is a frame of DLC 0; for an error frame that is how python-can's
		 * candump writer puts it, the kernel's frame with its data zeroed */
		rc = parse_data(&c, &f.frame, CAN_MAX_DLEN);
		if (rc == 0 && at(&c, '_')) {
			int dlc;

			if (f.frame.len != CAN_MAX_DLEN)
				return bad(&c, "expected '_<DLC>' only after 8 data bytes");
			c.s++;
			dlc = c.s < c.end ? hex(*c.s) : -1;
			if (dlc < 9)
				return bad(&c, "expected a DLC 9..F after '_'");
			f.len8_dlc = (uint8_t)dlc;
			c.s++;
		}
	}
	if (rc < 0)
		return rc;
	if (c.end - c.s >= 2 && c.s[0] == ' ' && (c.s[1] == 'R' || c.s[1] == 'T')) {
		f.dir = c.s[1];
		c.s += 2;
	}
	if (c.s != c.end)
		return bad(&c, "expected the end of the line after the frame");
	*ret = f;
	return 0;
}

int hl_candump_format(const struct hl_candump_frame *f, char *buf, size_t size)
{
	const struct canfd_frame *cf = &f->frame;
	char tmp[HL_CANDUMP_MAX_LINE];
	static const char digits[] = "0123456789ABCDEF";
	int n;

	if (f->t_us < 0 || cf->len > (f->fd ? CANFD_MAX_DLEN : CAN_MAX_DLEN) || !f->iface[0] ||
	    memchr(f->iface, '\0', IFNAMSIZ) == NULL)
		return -EINVAL;
	n = snprintf(tmp, sizeof(tmp), "(%010lld.%06lld) %s ", (long long)(f->t_us / 1000000),
		     (long long)(f->t_us % 1000000), f->iface);
	if (cf->can_id & (CAN_EFF_FLAG | CAN_ERR_FLAG))
		n += snprintf(tmp + n, sizeof(tmp) - n, "%08X#",
			      cf->can_id & (CAN_ERR_FLAG | CAN_EFF_MASK));
	else
		n += snprintf(tmp + n, sizeof(tmp) - n, "%03X#", cf->can_id & CAN_SFF_MASK);
	if (f->fd) {
		tmp[n++] = '#';
		tmp[n++] = digits[cf->flags & 0xf];
	} else if (cf->can_id & CAN_RTR_FLAG) {
		tmp[n++] = 'R';
		if (cf->len)
			tmp[n++] = digits[cf->len];
	}
	if (f->fd || !(cf->can_id & CAN_RTR_FLAG)) {
		for (int i = 0; i < cf->len; i++) {
			tmp[n++] = digits[cf->data[i] >> 4];
			tmp[n++] = digits[cf->data[i] & 0xf];
		}
		if (!f->fd && cf->len == CAN_MAX_DLEN && f->len8_dlc > CAN_MAX_DLEN &&
		    f->len8_dlc <= 15) {
			tmp[n++] = '_';
			tmp[n++] = digits[f->len8_dlc];
		}
	}
	if (f->dir == 'R' || f->dir == 'T') {
		tmp[n++] = ' ';
		tmp[n++] = f->dir;
	}
	tmp[n] = '\0';
	if ((size_t)n + 1 > size)
		return -ENOSPC;
	memcpy(buf, tmp, n + 1);
	return n;
}
