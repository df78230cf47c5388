/* SPDX-License-Identifier: MIT */
/*
 * The frame stream (docs/daemon.md): a TCP and/or Unix socket; every client receives the
 * newest published frame - the 192-byte header (daemon/core/frame.h) and the pixels, or the pixels
 * only in raw mode (for ffmpeg -f rawvideo). A client that reads slower than frames are
 * published skips to the newest (counted); it never holds a pool frame while it reads, so it
 * cannot delay the renderer or other clients, and its memory is one frame, fixed at accept.
 *
 * Clients send nothing: a client that sends a byte is dropped (reason input). A client that
 * shuts down its sending side (shutdown(SHUT_WR), "nc -N") and keeps reading stays connected
 * and keeps receiving frames; from then on it is not polled for input.
 *
 * A client is dropped, and counted by reason (enum hl_stream_drop):
 * - disconnected: its connection is gone: at once for a Unix socket closed by the peer
 *   (POLLHUP), for TCP when a send fails (a peer that closed resets at the next frame sent);
 * - stalled: it has a frame to take and has taken no byte of it for stall_timeout_ms
 *   (CLOCK_MONOTONIC);
 * - evicted: a new client came while all max_clients slots were taken, and this was the client
 *   behind (its frame in progress HL_STREAM_BEHIND_FRAMES or more older than the newest) that
 *   had taken no byte for longest; a new client finding no client behind is refused (closed
 *   at once, counted);
 * - input: it sent a byte.
 * Stalled, evicted and input drops reset the connection (SO_LINGER 0): the kernel discards
 * what the client did not take instead of keeping it for a peer that does not read.
 *
 * The stream subscribes to the pool: every published frame wakes it (hl_stream_new to
 * hl_stream_free).
 *
 * Thread-safety: new/start/stop/free/counts from the main thread; hl_stream_counts and
 * hl_stream_wake from any thread. The stream runs its own thread.
 */
#ifndef HL_DAEMON_OUT_STREAM_H
#define HL_DAEMON_OUT_STREAM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "daemon/core/frame_pool.h"

#define HL_STREAM_MAX_CLIENTS 64
#define HL_STREAM_BEHIND_FRAMES 3 /* frames newer than the one a client is sending: behind */

enum hl_stream_drop {
	HL_STREAM_DROP_DISCONNECTED,
	HL_STREAM_DROP_STALLED,
	HL_STREAM_DROP_EVICTED,
	HL_STREAM_DROP_INPUT,
	HL_STREAM_DROP_N,
};

struct hl_stream_counts {
	uint64_t accepted, refused; /* refused: all slots taken by clients not behind */
	uint64_t clients, clients_behind; /* now (behind: as of the stream's last look) */
	uint64_t dropped[HL_STREAM_DROP_N]; /* by reason */
	uint64_t frames_sent, frames_skipped, bytes_sent;
	uint64_t frames_copied; /* frames whose unsent rest went to the client's buffer */
	uint64_t input_reads, input_eofs; /* recv calls on clients; half-closes seen */
};

struct hl_stream;

/*
 * tcp "host:port" or "" (off), unix_path or "" (off); max_clients 1..HL_STREAM_MAX_CLIENTS;
 * stall_timeout_ms >= 1. err says which address or value failed.
 */
int hl_stream_new(const char *tcp, const char *unix_path, bool raw, int max_clients,
		  int stall_timeout_ms, struct hl_frame_pool *pool, struct hl_stream **ret,
		  char *err, size_t err_size);
void hl_stream_free(struct hl_stream *s);
/*
 * Starts the stream thread (hl-stream); rt_priority > 0 puts it at SCHED_FIFO (the daemon
 * gives it one step below the CAN and render threads: it never delays them, and the other
 * jobs of a busy machine cannot delay the frames to the clients). 0 or -errno.
 */
int hl_stream_start(struct hl_stream *s, int rt_priority);
void hl_stream_stop(struct hl_stream *s);
void hl_stream_wake(struct hl_stream *s);
void hl_stream_counts(struct hl_stream *s, struct hl_stream_counts *ret);
/* The TCP port actually bound (for "host:0"), 0 when off. */
int hl_stream_tcp_port(const struct hl_stream *s);
/* "disconnected", "stalled", "evicted", "input": the label of a drop reason. */
const char *hl_stream_drop_name(enum hl_stream_drop why);

#endif
