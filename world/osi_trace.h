/* SPDX-License-Identifier: MIT */
/*
 * ASAM OSI binary trace files (.osi, docs/osi.md "Trace files"): each serialized message is
 * preceded by its length, a 4-byte little-endian unsigned integer that does not count itself.
 * This module only frames bytes; what a message says is world/osi_msg.h's.
 *
 * Reading maps the file and indexes every message (offset, length) at open; a message's bytes
 * are then a pointer into the map. A cut last message (a partial length prefix, or a prefix
 * promising more bytes than remain) is reported, not fatal: the messages before it stay usable.
 * A length over HL_OSI_TRACE_MAX_MSG is taken as corruption and the file is refused.
 * The file must not shrink while a trace of it is open (reading a map past a file's end faults);
 * one still growing is fine, what was added after the open is not seen.
 *
 * Thread-safety: after hl_osi_trace_open() returns, a trace is read-only: hl_osi_trace_count()
 * and hl_osi_trace_get() may be called from any number of threads at once; hl_osi_trace_free()
 * only when none of them runs any more. hl_osi_trace_write() works on the caller's FILE, whose
 * thread rules are stdio's.
 */
#ifndef HL_WORLD_OSI_TRACE_H
#define HL_WORLD_OSI_TRACE_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "world/osi_msg.h"

#define HL_OSI_TRACE_PREFIX 4 /* bytes of the length before each message */
#define HL_OSI_TRACE_MAX_MSG (64u << 20) /* bytes, one message; a longer length is corruption */

/* hl_osi_trace_open(): all messages indexed, or the file ends inside the last one. */
#define HL_OSI_TRACE_COMPLETE 0
#define HL_OSI_TRACE_TRUNCATED 1

struct hl_osi_trace;

/* Where the framing went wrong. */
struct hl_osi_trace_error {
	uint64_t offset; /* byte offset of the length prefix at fault */
	uint64_t expected; /* bytes expected from there: the prefix (4) or prefix + length */
	uint64_t found; /* bytes the file has from there */
	uint64_t length; /* the length the prefix says; 0 if the prefix itself is cut */
};

/* One message: buf points into the trace's map, valid until hl_osi_trace_free(). */
struct hl_osi_trace_msg {
	const uint8_t *buf;
	size_t len;
	uint64_t offset; /* of the message's bytes in the file (its prefix is 4 bytes before) */
};

/*
 * Opens and indexes path. Returns HL_OSI_TRACE_COMPLETE, or HL_OSI_TRACE_TRUNCATED with
 * *ret_err (may be NULL) saying where the cut message starts and what it needed; *ret is set
 * either way. Failures: -errno of open/fstat/mmap, -ENOMEM, or -EBADMSG for a length over
 * HL_OSI_TRACE_MAX_MSG (*ret_err says where; *ret untouched). An empty file is complete with
 * no messages.
 */
int hl_osi_trace_open(const char *path, struct hl_osi_trace **ret,
		      struct hl_osi_trace_error *ret_err);
void hl_osi_trace_free(struct hl_osi_trace *t);

/* Messages indexed (the cut one not counted). */
size_t hl_osi_trace_count(const struct hl_osi_trace *t);

/* Message i into *ret: 0, or -ERANGE for i >= hl_osi_trace_count() (*ret untouched). */
int hl_osi_trace_get(const struct hl_osi_trace *t, size_t i, struct hl_osi_trace_msg *ret);

/*
 * Appends one message to f: the 4-byte little-endian length, then the len bytes. 0, -EMSGSIZE
 * for len over HL_OSI_TRACE_MAX_MSG (nothing written), or -errno (-EIO if stdio set none) when
 * the write fails (then f may hold part of the record).
 */
int hl_osi_trace_write(FILE *f, const uint8_t *buf, size_t len);

/*
 * The message kind from a file name after OSI's naming convention,
 * <timestamp>_<type>_<osi-version>_<protobuf-version>_<number-of-frames>_<custom-name>.osi:
 * the second '_'-separated field of the base name, "gt" or "sv". 0, or -ENOENT when the name
 * has no such field or another type (sd, tu, tc, ...: not ours to read).
 */
int hl_osi_trace_kind_from_name(const char *path, enum hl_osi_kind *ret);

#endif
