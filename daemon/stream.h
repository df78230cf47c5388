/* SPDX-License-Identifier: MIT */
/*
 * The frame stream (docs/daemon.md): a TCP and/or Unix socket; every client receives the
 * newest published frame - the 192-byte header (daemon/frame.h) and the pixels, or the pixels
 * only in raw mode (for ffmpeg -f rawvideo). A client that reads slower than frames are
 * published skips to the newest (counted); it never holds a pool frame while it reads, so it
 * cannot delay the renderer or other clients, and its memory is one frame, fixed at accept.
 *
 * Clients send nothing; whatever they send is read and dropped. A client that shuts down its
 * sending side (shutdown(SHUT_WR), "nc -N") and keeps reading stays connected and keeps
 * receiving frames; from then on it is not polled for input. A client is dropped when its
 * connection is gone: at once for a Unix socket closed by the peer (POLLHUP), for TCP when a
 * send fails (a peer that closed resets the connection at the next frame sent to it).
 *
 * The stream subscribes to the pool: every published frame wakes it (hl_stream_new to
 * hl_stream_free).
 *
 * Thread-safety: new/start/stop/free/counts from the main thread; hl_stream_wake from any
 * thread. The stream runs its own thread.
 */
#ifndef HL_DAEMON_STREAM_H
#define HL_DAEMON_STREAM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "daemon/frame_pool.h"

struct hl_stream_counts {
	uint64_t accepted, rejected, clients; /* rejected: over max_clients; clients: now */
	uint64_t frames_sent, frames_skipped, bytes_sent;
	uint64_t frames_copied; /* frames whose unsent rest went to the client's buffer */
	uint64_t input_reads, input_eofs; /* recv calls on clients; half-closes seen */
};

struct hl_stream;

/* tcp "host:port" or "" (off), unix_path or "" (off). err says which address failed. */
int hl_stream_new(const char *tcp, const char *unix_path, bool raw, int max_clients,
		  struct hl_frame_pool *pool, struct hl_stream **ret, char *err, size_t err_size);
void hl_stream_free(struct hl_stream *s);
int hl_stream_start(struct hl_stream *s);
void hl_stream_stop(struct hl_stream *s);
void hl_stream_wake(struct hl_stream *s);
void hl_stream_counts(struct hl_stream *s, struct hl_stream_counts *ret);
/* The TCP port actually bound (for "host:0"), 0 when off. */
int hl_stream_tcp_port(const struct hl_stream *s);

#endif
