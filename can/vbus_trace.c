/* SPDX-License-Identifier: MIT */
/*
 * The virtual bus's traces: candump -L lines (can/candump.h) and Vector BLF.
 *
 * BLF has no public specification; the layout below is the one python-can's reader and writer
 * (can/io/blf.py, after Toby Lorenz's "Vector BLF" library) read and write, little endian:
 *   file header, 144 bytes: "LOGG", header size (u32), application ID and version (4 x u8),
 *     BLF version (4 x u8), file size (u64), uncompressed size (u64), object count (u32),
 *     objects read (u32), start and stop time as Windows SYSTEMTIME (8 x u16: year, month,
 *     day of week, day, hour, minute, second, milliseconds; local time), zeros to 144;
 *   objects, each "LOBJ", header size (u16), header version (u16), object size (u32), object
 *     type (u32); version 1 headers go on with flags (u32: 2 = time stamp in ns), client index
 *     (u16), object version (u16) and the time stamp (u64) since the file's start time;
 *   LOG_CONTAINER (10) objects at the top level hold the others: compression method (u16, 0 =
 *     none), 6 bytes reserved, uncompressed size (u32), 4 bytes reserved, then the objects;
 *     a container is followed by (object size % 4) bytes of padding, as the reader skips them;
 *   CAN_MESSAGE2 (86): channel (u16), flags (u8, bit 0 = transmitted), DLC (u8), ID (u32,
 *     bit 31 = extended), 8 data bytes, frame length in ns (u32), bit count (u8), 3 reserved;
 *   CAN_FD_MESSAGE_64 (101): channel, DLC, valid data bytes, tx count (u8 each), ID (u32),
 *     frame length in ns (u32), flags (u32: 0x1000 FD, 0x2000 BRS, 0x4000 ESI), the two bit
 *     timing configurations, the BRS and CRC delimiter time offsets (u32 each), bit count
 *     (u16), direction (u8, 0 = received), extended data offset (u8), CRC (u32), the data.
 * The start time has millisecond resolution: the objects' ns time stamps count from the trace's
 * opening instant cut down to its millisecond, so that a reader adding them to the start time
 * gets the frame's instant to the ns.
 */
#include "can/vbus_internal.h"

#include <errno.h>
#include <linux/can.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "can/candump.h"

#define BLF_HEADER_SIZE 144
#define BLF_CONTAINER_DATA (128 * 1024) /* bytes of objects per log container */
#define BLF_LOG_CONTAINER 10
#define BLF_CAN_MESSAGE2 86
#define BLF_CAN_FD_MESSAGE_64 101
#define BLF_TIME_ONE_NANS 2
#define BLF_CHANNEL 1

struct hl_vbus_trace {
	FILE *f;
	bool log;
	char iface[IFNAMSIZ];
	int64_t epoch_ns;
	int64_t start_ms; /* BLF: the start time, ms since the Unix epoch */
	int64_t stop_ms;
	uint8_t *buf; /* BLF: the open container's objects */
	size_t used;
	uint32_t objects;
	uint64_t uncompressed;
	int err; /* the first failure, -errno */
};

static int64_t floor_div(int64_t a, int64_t b)
{
	return a / b - (a % b != 0 && (a < 0) != (b < 0));
}

static void le16(uint8_t *p, uint16_t v)
{
	p[0] = (uint8_t)v;
	p[1] = (uint8_t)(v >> 8);
}

static void le32(uint8_t *p, uint32_t v)
{
	le16(p, (uint16_t)v);
	le16(p + 2, (uint16_t)(v >> 16));
}

static void le64(uint8_t *p, uint64_t v)
{
	le32(p, (uint32_t)v);
	le32(p + 4, (uint32_t)(v >> 32));
}

static int fail(struct hl_vbus_trace *t, int rc)
{
	if (t->err == 0)
		t->err = rc;
	return rc;
}

static int put(struct hl_vbus_trace *t, const void *p, size_t n)
{
	if (n && fwrite(p, 1, n, t->f) != n)
		return fail(t, errno ? -errno : -EIO);
	return 0;
}

static void systemtime(uint8_t *p, int64_t ms)
{
	time_t sec = (time_t)floor_div(ms, 1000);
	struct tm tm;

	memset(p, 0, 16);
	if (!localtime_r(&sec, &tm))
		return;
	le16(p, (uint16_t)(tm.tm_year + 1900));
	le16(p + 2, (uint16_t)(tm.tm_mon + 1));
	le16(p + 4, (uint16_t)tm.tm_wday);
	le16(p + 6, (uint16_t)tm.tm_mday);
	le16(p + 8, (uint16_t)tm.tm_hour);
	le16(p + 10, (uint16_t)tm.tm_min);
	le16(p + 12, (uint16_t)tm.tm_sec);
	le16(p + 14, (uint16_t)(ms - floor_div(ms, 1000) * 1000));
}

static int blf_header(struct hl_vbus_trace *t, uint64_t file_size)
{
	uint8_t h[BLF_HEADER_SIZE] = { 'L', 'O', 'G', 'G' };

	le32(h + 4, BLF_HEADER_SIZE);
	/* h[8..11]: application 0 (none registered), version 0.0.0 */
	h[12] = 2; /* the BLF version python-can writes and Vector's tools read */
	h[13] = 6;
	h[14] = 8;
	h[15] = 1;
	le64(h + 16, file_size);
	le64(h + 24, t->uncompressed);
	le32(h + 32, t->objects);
	systemtime(h + 40, t->start_ms);
	systemtime(h + 56, t->stop_ms);
	return put(t, h, sizeof(h));
}

/* Writes the open container, uncompressed. */
static int blf_flush(struct hl_vbus_trace *t)
{
	uint8_t h[32] = { 'L', 'O', 'B', 'J' };
	static const uint8_t pad[4];
	uint32_t size = (uint32_t)(sizeof(h) + t->used);
	int rc;

	if (t->used == 0)
		return 0;
	le16(h + 4, 16);
	le16(h + 6, 1);
	le32(h + 8, size);
	le32(h + 12, BLF_LOG_CONTAINER);
	le16(h + 16, 0); /* no compression */
	le32(h + 24, (uint32_t)t->used);
	rc = put(t, h, sizeof(h));
	if (rc == 0)
		rc = put(t, t->buf, t->used);
	if (rc == 0)
		rc = put(t, pad, size % 4);
	t->uncompressed += sizeof(h) + t->used;
	t->used = 0;
	return rc;
}

static int blf_write(struct hl_vbus_trace *t, const struct hl_vbus_frame *f, int64_t frame_ns,
		     unsigned bits)
{
	int64_t abs_ns = t->epoch_ns + f->t_ns;
	uint32_t id = f->can_id & HL_DBC_EFF_FLAG ? f->can_id : f->can_id & 0x7ffu;
	size_t body = f->fd ? 40u + f->len : 24u;
	size_t size = 32 + body, padded = (size + 3) & ~(size_t)3;
	uint8_t *o;
	int rc;

	if (t->used + padded > BLF_CONTAINER_DATA) {
		rc = blf_flush(t);
		if (rc < 0)
			return rc;
	}
	o = t->buf + t->used;
	memset(o, 0, padded);
	memcpy(o, "LOBJ", 4);
	le16(o + 4, 32);
	le16(o + 6, 1);
	le32(o + 8, (uint32_t)size);
	le32(o + 12, f->fd ? BLF_CAN_FD_MESSAGE_64 : BLF_CAN_MESSAGE2);
	le32(o + 16, BLF_TIME_ONE_NANS);
	le64(o + 24, (uint64_t)(abs_ns - t->start_ms * 1000000));
	o += 32;
	if (f->fd) {
		o[0] = BLF_CHANNEL;
		o[1] = (uint8_t)hl_vbus_dlc(f->len, true);
		o[2] = f->len;
		le32(o + 4, id);
		le32(o + 8, (uint32_t)frame_ns);
		le32(o + 12, 0x1000u | (f->brs ? 0x2000u : 0));
		le16(o + 32, (uint16_t)bits);
		/* o[34]: direction 0, received */
		memcpy(o + 40, f->data, f->len);
	} else {
		le16(o, BLF_CHANNEL);
		o[3] = f->len; /* o[2]: flags 0, received */
		le32(o + 4, id);
		memcpy(o + 8, f->data, f->len);
		le32(o + 16, (uint32_t)frame_ns);
		o[20] = (uint8_t)(bits > 255 ? 255 : bits);
	}
	t->used += padded;
	t->objects++;
	t->stop_ms = floor_div(abs_ns, 1000000);
	return 0;
}

static int log_write(struct hl_vbus_trace *t, const struct hl_vbus_frame *f)
{
	struct hl_candump_frame c = {
		.t_us = floor_div(t->epoch_ns + f->t_ns, 1000), /* candump's µs, cut as a timeval */
		.fd = f->fd,
	};
	char line[HL_CANDUMP_MAX_LINE];
	int n;

	memcpy(c.iface, t->iface, sizeof(c.iface));
	c.frame.can_id = f->can_id & HL_DBC_EFF_FLAG ? (f->can_id & CAN_EFF_MASK) | CAN_EFF_FLAG :
						       f->can_id;
	c.frame.len = f->len;
	c.frame.flags = f->brs ? CANFD_BRS : 0;
	memcpy(c.frame.data, f->data, f->len);
	n = hl_candump_format(&c, line, sizeof(line) - 1);
	if (n < 0)
		return fail(t, n);
	line[n++] = '\n';
	return put(t, line, (size_t)n);
}

int hl_vbus_trace_open(const char *path, const char *iface, int64_t epoch_ns, int64_t now_ns,
		       struct hl_vbus_trace **ret)
{
	size_t n = strlen(path);
	struct hl_vbus_trace *t;
	int rc;

	if (n < 4 || (strcmp(path + n - 4, ".log") != 0 && strcmp(path + n - 4, ".blf") != 0))
		return -EINVAL;
	t = calloc(1, sizeof(*t));
	if (!t)
		return -ENOMEM;
	t->log = strcmp(path + n - 4, ".log") == 0;
	snprintf(t->iface, sizeof(t->iface), "%s", iface);
	t->epoch_ns = epoch_ns;
	t->start_ms = t->stop_ms = floor_div(epoch_ns + now_ns, 1000000);
	if (!t->log) {
		t->buf = malloc(BLF_CONTAINER_DATA);
		if (!t->buf) {
			rc = -ENOMEM;
			goto err_free;
		}
	}
	t->f = fopen(path, t->log ? "we" : "w+be");
	if (!t->f) {
		rc = -errno;
		goto err_free;
	}
	if (!t->log) {
		t->uncompressed = BLF_HEADER_SIZE;
		rc = blf_header(t, BLF_HEADER_SIZE); /* completed on close */
		if (rc < 0)
			goto err_close;
	}
	*ret = t;
	return 0;

err_close:
	fclose(t->f);
err_free:
	free(t->buf);
	free(t);
	return rc;
}

bool hl_vbus_trace_is_log(const struct hl_vbus_trace *t)
{
	return t->log;
}

int hl_vbus_trace_write(struct hl_vbus_trace *t, const struct hl_vbus_frame *f, int64_t frame_ns,
			unsigned bits)
{
	return t->log ? log_write(t, f) : blf_write(t, f, frame_ns, bits);
}

int hl_vbus_trace_close(struct hl_vbus_trace *t)
{
	int rc;

	if (!t)
		return 0;
	if (!t->log) {
		long size;

		blf_flush(t);
		size = ftell(t->f);
		if (size < 0 || fseek(t->f, 0, SEEK_SET) < 0)
			fail(t, -errno);
		else
			blf_header(t, (uint64_t)size);
	}
	if (fclose(t->f) != 0)
		fail(t, -errno);
	rc = t->err;
	free(t->buf);
	free(t);
	return rc;
}
