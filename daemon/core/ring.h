/* SPDX-License-Identifier: MIT */
/*
 * The ring between the CAN thread and the render thread (docs/design.md §2): single producer,
 * single consumer, lock-free, a fixed power-of-two number of slots of intensity-list snapshots,
 * all allocated at start.
 *
 * Ownership: the CAN thread is the only caller of hl_ring_push(); the render thread is the
 * only caller of hl_ring_take_newest() / hl_ring_pop() / hl_ring_wait(). hl_ring_counts() and
 * hl_ring_wake_fd() may be called from any thread. Nothing else is thread-safe.
 *
 * The ring owns an eventfd that every push makes readable: the consumer sleeps on it
 * (hl_ring_wait, or poll the fd with others and call hl_ring_wait(ring, 0) to reset it).
 *
 * Each slot has a state word (its snapshot's sequence number and who owns it: empty, being
 * written, ready, being read) that the two threads change only by compare-and-swap, so a slot's
 * payload is only ever touched by its owner and is copied with a plain memcpy. The producer
 * writes into the oldest slot the consumer is not reading, so it never waits; the consumer
 * claims a ready slot, copies it out and hands it back, so it never sees a torn snapshot.
 * Every pushed snapshot ends up counted exactly once:
 *   consumed    taken by the consumer;
 *   superseded  skipped by hl_ring_take_newest() because a newer one was taken;
 *   dropped     overwritten before hl_ring_pop() (in-order reading) got to it;
 * and pushed = consumed + superseded + dropped + pending.
 */
#ifndef HL_DAEMON_CORE_RING_H
#define HL_DAEMON_CORE_RING_H

#include <stdbool.h>
#include <stdint.h>

#include "can/assembler.h"

/* a snapshot carries every lamp the assembler decodes */
#define HL_RING_MAX_LAMPS HL_ASM_MAX_LAMPS

/* Per-lamp status bits of a snapshot. */
#define HL_LAMP_VALID 0x1u /* at least one complete cycle seen */
#define HL_LAMP_STALE 0x2u /* no complete cycle within timeout_ms */

struct hl_lamp_snapshot {
	uint64_t cycle_seq; /* complete cycles of this lamp so far */
	int64_t t_rx_first_ns; /* kernel receive time of the cycle's first frame */
	int64_t t_complete_ns; /* when the cycle was complete, on the input's clock */
	int64_t t_complete_mono_ns; /* the same moment on CLOCK_MONOTONIC (the push) */
	uint32_t status; /* HL_LAMP_* */
	uint8_t counter; /* the ECU's alive counter of the cycle */
	int64_t mode; /* the cycle's HdlBeamMode raw value, -1 without one (valid with HL_LAMP_VALID) */
};

/* A snapshot of all lamps; i holds n_lamps * n_sources relative currents, lamp-major. */
struct hl_snapshot {
	uint64_t seq; /* set by hl_ring_push: 0, 1, 2, ... */
	int64_t t_push_ns;
	int64_t t_event_ns; /* when what this snapshot reports happened (the producer's clock) */
	/*
	 * A replay: when the log's current pass began on its timeline (the due time of the pass's
	 * first frame, as t_complete_ns), so a lamp's cycle is t_complete_ns - t_pass_ns into the
	 * pass (the scenario clock, docs/scenarios.md); 0 for a live bus.
	 */
	int64_t t_pass_ns;
	uint32_t status; /* the producer's global status bits */
	uint32_t bus; /* the producer's bus state */
	int32_t link_errno; /* why the input is down, 0 when up */
	int n_lamps, n_sources;
	struct hl_lamp_snapshot lamps[HL_RING_MAX_LAMPS];
	float *i;
};

struct hl_ring_counts {
	uint64_t pushed, consumed, superseded, dropped;
};

struct hl_ring;

/* slots: power of two, >= 2. 0, -EINVAL, -ENOMEM. */
int hl_ring_new(unsigned slots, int n_lamps, int n_sources, struct hl_ring **ret);
void hl_ring_free(struct hl_ring *ring);

/* A snapshot buffer shaped for this ring (the caller's, for push and take). 0, -ENOMEM. */
int hl_snapshot_new(const struct hl_ring *ring, struct hl_snapshot **ret);
void hl_snapshot_free(struct hl_snapshot *s);

/* Producer: copies s in (s->seq is set) and wakes the consumer; never blocks, never allocates. */
void hl_ring_push(struct hl_ring *ring, struct hl_snapshot *s);

/*
 * Consumer: copies the newest snapshot not yet taken into ret and returns true, or returns
 * false when there is nothing new. Older unread snapshots count as superseded.
 */
bool hl_ring_take_newest(struct hl_ring *ring, struct hl_snapshot *ret);
/* Consumer, in order: the oldest unread snapshot still in the ring; lapped ones are dropped. */
bool hl_ring_pop(struct hl_ring *ring, struct hl_snapshot *ret);

void hl_ring_counts(const struct hl_ring *ring, struct hl_ring_counts *ret);
/* Snapshots pushed that the consumer has not reached yet (any thread; a snapshot in time). */
uint64_t hl_ring_pending(const struct hl_ring *ring);
unsigned hl_ring_slots(const struct hl_ring *ring);

/* The eventfd a push makes readable (owned by the ring; poll it, do not read or close it). */
int hl_ring_wake_fd(const struct hl_ring *ring);
/* Consumer: waits up to timeout_ms (0: not at all, -1: forever) for a push and resets the fd. */
void hl_ring_wait(struct hl_ring *ring, int timeout_ms);

#endif
