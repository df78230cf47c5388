/* SPDX-License-Identifier: MIT */
/*
 * The CAN thread (docs/architecture.md): receives frames from SocketCAN or a candump log,
 * assembles lamp cycles and pushes a snapshot into the ring for every complete cycle and every
 * status change (stale, recovered, bus state, interface down/up). On a live bus it never
 * waits for the consumer; a --fast replay (no bus to keep up with) waits for free slots
 * rather than overrun them.
 *
 * Timeouts run on CLOCK_MONOTONIC for a live bus and on the log's own timeline for a replay,
 * so a replay reports the same cycles and the same stale times at any speed.
 *
 * The input's state and counters live in one place: the CAN thread copies them, under a lock,
 * into one struct hl_input_status (on every push and at least every 100 ms), and every reader
 * - /status, /metrics, the log, the exit summary - takes a copy of that.
 *
 * Thread-safety: hl_can_input_start/stop from the main thread; hl_can_input_status,
 * hl_can_input_report and hl_can_input_filters from any thread; everything else runs on the
 * CAN thread.
 */
#ifndef HL_DAEMON_CORE_CAN_INPUT_H
#define HL_DAEMON_CORE_CAN_INPUT_H

#include <stdbool.h>
#include <stdio.h>

#include "can/assembler.h"
#include "can/candump_log.h"
#include "can/socket.h"
#include "daemon/core/ring.h"

/* Global status bits of a snapshot (hl_snapshot.status). */
#define HL_INPUT_LINK_UP 0x1u /* the interface is open (always set for a replay) */
#define HL_INPUT_DONE 0x2u /* the replay reached its end: the last snapshot */

struct hl_can_input_config {
	const char *iface; /* either this ... */
	const char *replay; /* ... or a candump log ("-" for stdin) */
	bool replay_fast; /* as fast as possible instead of the log's timing */
	bool replay_loop; /* again and again ... */
	uint64_t replay_passes; /* ... until this many passes, 0 = endlessly */
	FILE *log; /* where the thread logs rare events (malformed log lines), e.g. stderr */
	int rt_priority; /* SCHED_FIFO priority the thread sets itself to; 0: none (sched.h) */
};

struct hl_can_input;

/* Opens the log (not the interface: that is retried by the thread). 0 or -errno. */
int hl_can_input_new(const struct hl_can_input_config *cfg, struct hl_assembler *a,
		     struct hl_ring *ring, struct hl_can_input **ret);
void hl_can_input_free(struct hl_can_input *in);

int hl_can_input_start(struct hl_can_input *in);
/* Asks the thread to stop and joins it. */
void hl_can_input_stop(struct hl_can_input *in);

/* The ring's eventfd (hl_ring_wake_fd), readable after every push. */
int hl_can_input_wake_fd(const struct hl_can_input *in);

/* A consistent copy of the input's state and counters for other threads: the initial state
 * from hl_can_input_new, then updated on every push and at least every 100 ms. */
struct hl_input_status {
	int n_lamps;
	struct hl_lamp_counters lamps[HL_ASM_MAX_LAMPS];
	bool stale[HL_ASM_MAX_LAMPS];
	struct hl_asm_counters frames;
	bool link_up, is_socket, done; /* done: the replay reached its end */
	int link_errno;
	char bus[32]; /* the bus state's name, "replay" for a log */
	char iface[32]; /* the SocketCAN interface; empty for a log */
	struct hl_can_socket_stats socket; /* a SocketCAN input's counters (is_socket) */
	struct hl_candump_log_stats log; /* a replay's counters (!is_socket) */
};

void hl_can_input_status(struct hl_can_input *in, struct hl_input_status *ret);

/*
 * The kernel filter of a SocketCAN input (every lamp message of the database, nothing else):
 * its count and in *ret the filters, owned by the input; 0 and NULL for a replay. Fixed at
 * hl_can_input_new, so any thread.
 */
int hl_can_input_filters(const struct hl_can_input *in, const struct can_filter **ret);

/* Writes the input's counters (the copy hl_can_input_status returns) as a JSON object's
 * members (no braces). */
void hl_can_input_report(struct hl_can_input *in, FILE *f);

#endif
