/* SPDX-License-Identifier: MIT */
/* OSI binary trace files: index at open, messages as pointers into a read-only map. */
#include "world/osi_trace.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

struct entry {
	uint64_t offset; /* of the message's bytes */
	uint32_t len;
};

struct hl_osi_trace {
	const uint8_t *map; /* NULL for an empty file */
	size_t map_len;
	struct entry *entry;
	size_t n, cap;
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

static void set_error(struct hl_osi_trace_error *err, uint64_t offset, uint64_t expected,
		      uint64_t found, uint64_t length)
{
	if (!err)
		return;
	err->offset = offset;
	err->expected = expected;
	err->found = found;
	err->length = length;
}

static int push(struct hl_osi_trace *t, uint64_t offset, uint32_t len)
{
	if (t->n == t->cap) {
		size_t cap = t->cap ? t->cap * 2 : 256;
		struct entry *e = realloc(t->entry, cap * sizeof(*e));

		if (!e)
			return -ENOMEM;
		t->entry = e;
		t->cap = cap;
	}
	t->entry[t->n].offset = offset;
	t->entry[t->n].len = len;
	t->n++;
	return 0;
}

/* Walks the map; HL_OSI_TRACE_COMPLETE, HL_OSI_TRACE_TRUNCATED or -errno. */
static int index_messages(struct hl_osi_trace *t, struct hl_osi_trace_error *err)
{
	uint64_t pos = 0, size = t->map_len;

	while (pos < size) {
		uint64_t left = size - pos;
		uint32_t len;
		int r;

		if (left < HL_OSI_TRACE_PREFIX) {
			set_error(err, pos, HL_OSI_TRACE_PREFIX, left, 0);
			return HL_OSI_TRACE_TRUNCATED;
		}
		len = get_le32(t->map + pos);
		if (len > HL_OSI_TRACE_MAX_MSG) {
			set_error(err, pos, HL_OSI_TRACE_PREFIX + (uint64_t)len, left, len);
			return -EBADMSG;
		}
		if (left - HL_OSI_TRACE_PREFIX < len) {
			set_error(err, pos, HL_OSI_TRACE_PREFIX + (uint64_t)len, left, len);
			return HL_OSI_TRACE_TRUNCATED;
		}
		r = push(t, pos + HL_OSI_TRACE_PREFIX, len);
		if (r < 0)
			return r;
		pos += HL_OSI_TRACE_PREFIX + (uint64_t)len;
	}
	return HL_OSI_TRACE_COMPLETE;
}

int hl_osi_trace_open(const char *path, struct hl_osi_trace **ret,
		      struct hl_osi_trace_error *ret_err)
{
	struct hl_osi_trace *t;
	struct stat st;
	int fd, r;

	fd = open(path, O_RDONLY | O_CLOEXEC);
	if (fd < 0)
		return -errno;
	if (fstat(fd, &st) < 0) {
		r = -errno;
		goto err_close_fd;
	}
	if (!S_ISREG(st.st_mode)) {
		r = -EINVAL;
		goto err_close_fd;
	}
	t = calloc(1, sizeof(*t));
	if (!t) {
		r = -ENOMEM;
		goto err_close_fd;
	}
	if (st.st_size > 0) {
		void *map;

		if ((uint64_t)st.st_size > SIZE_MAX) {
			r = -EFBIG;
			goto err_free;
		}
		map = mmap(NULL, (size_t)st.st_size, PROT_READ, MAP_PRIVATE, fd, 0);
		if (map == MAP_FAILED) {
			r = -errno;
			goto err_free;
		}
		t->map = map;
		t->map_len = (size_t)st.st_size;
	}
	/* The map keeps the file; the descriptor is not needed past this point. */
	close(fd);
	fd = -1;

	r = index_messages(t, ret_err);
	if (r < 0)
		goto err_free;
	*ret = t;
	return r;

err_free:
	hl_osi_trace_free(t);
err_close_fd:
	if (fd >= 0)
		close(fd);
	return r;
}

void hl_osi_trace_free(struct hl_osi_trace *t)
{
	if (!t)
		return;
	if (t->map)
		munmap((void *)t->map, t->map_len);
	free(t->entry);
	free(t);
}

size_t hl_osi_trace_count(const struct hl_osi_trace *t)
{
	return t->n;
}

int hl_osi_trace_get(const struct hl_osi_trace *t, size_t i, struct hl_osi_trace_msg *ret)
{
	if (i >= t->n)
		return -ERANGE;
	ret->offset = t->entry[i].offset;
	ret->len = t->entry[i].len;
	ret->buf = t->map + t->entry[i].offset; /* one past the end for an empty last message */
	return 0;
}

int hl_osi_trace_write(FILE *f, const uint8_t *buf, size_t len)
{
	uint8_t prefix[HL_OSI_TRACE_PREFIX];

	if (len > HL_OSI_TRACE_MAX_MSG)
		return -EMSGSIZE;
	put_le32(prefix, (uint32_t)len);
	errno = 0;
	if (fwrite(prefix, 1, sizeof(prefix), f) != sizeof(prefix) ||
	    (len > 0 && fwrite(buf, 1, len, f) != len))
		return errno ? -errno : -EIO;
	return 0;
}

int hl_osi_trace_kind_from_name(const char *path, enum hl_osi_kind *ret)
{
	const char *base = strrchr(path, '/');
	const char *type, *end;
	size_t n;

	base = base ? base + 1 : path;
	type = strchr(base, '_');
	if (!type)
		return -ENOENT;
	type++;
	end = strchr(type, '_');
	if (!end)
		return -ENOENT;
	n = (size_t)(end - type);
	if (n == 2 && memcmp(type, "gt", 2) == 0) {
		*ret = HL_OSI_GROUND_TRUTH;
		return 0;
	}
	if (n == 2 && memcmp(type, "sv", 2) == 0) {
		*ret = HL_OSI_SENSOR_VIEW;
		return 0;
	}
	return -ENOENT;
}
