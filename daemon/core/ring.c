/* SPDX-License-Identifier: MIT */
#include "daemon/core/ring.h"

#include <errno.h>
#include <poll.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/eventfd.h>
#include <unistd.h>

/* A slot's state word: sequence number << 2 | owner tag. */
enum tag {
	EMPTY = 0,
	WRITING = 1, /* the producer's */
	READY = 2, /* nobody's: the consumer may claim it, the producer may overwrite it */
	READING = 3, /* the consumer's */
};

#define STATE(seq, tag) ((uint64_t)(seq) << 2 | (tag))
#define TAG(state) ((enum tag)((state)&3u))
#define SEQ(state) ((state) >> 2)

struct slot {
	_Alignas(64) _Atomic uint64_t state;
	struct hl_snapshot snap; /* its i points into the ring's pool */
};

struct hl_ring {
	unsigned n_slots;
	int n_lamps, n_sources;
	struct slot *slots;
	float *pool;
	int wake_fd; /* an eventfd: the producer writes after each push, the consumer polls it */
	_Alignas(64) _Atomic uint64_t head; /* snapshots pushed; written by the producer only */
	_Alignas(64) uint64_t tail; /* next snapshot the consumer wants; consumer only */
	_Atomic uint64_t consumed, superseded, dropped; /* written by the consumer only */
};

int hl_ring_new(unsigned slots, int n_lamps, int n_sources, struct hl_ring **ret)
{
	const size_t per = (size_t)n_lamps * n_sources;
	struct hl_ring *r;

	if (slots < 2 || (slots & (slots - 1)) || n_lamps < 1 || n_lamps > HL_RING_MAX_LAMPS ||
	    n_sources < 1 || n_sources > 65536)
		return -EINVAL;
	r = calloc(1, sizeof(*r));
	if (!r)
		return -ENOMEM;
	r->wake_fd = eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
	if (r->wake_fd < 0) {
		const int err = errno;

		free(r);
		return -err;
	}
	r->n_slots = slots;
	r->n_lamps = n_lamps;
	r->n_sources = n_sources;
	r->slots = aligned_alloc(64, sizeof(*r->slots) * slots);
	r->pool = calloc(slots * per, sizeof(float));
	if (!r->slots || !r->pool) {
		hl_ring_free(r);
		return -ENOMEM;
	}
	memset(r->slots, 0, sizeof(*r->slots) * slots);
	for (unsigned s = 0; s < slots; s++) {
		atomic_init(&r->slots[s].state, STATE(0, EMPTY));
		r->slots[s].snap.n_lamps = n_lamps;
		r->slots[s].snap.n_sources = n_sources;
		r->slots[s].snap.i = r->pool + s * per;
	}
	atomic_init(&r->head, 0);
	*ret = r;
	return 0;
}

void hl_ring_free(struct hl_ring *ring)
{
	if (!ring)
		return;
	close(ring->wake_fd);
	free(ring->slots);
	free(ring->pool);
	free(ring);
}

int hl_snapshot_new(const struct hl_ring *ring, struct hl_snapshot **ret)
{
	struct hl_snapshot *s = calloc(1, sizeof(*s));

	if (!s)
		return -ENOMEM;
	s->n_lamps = ring->n_lamps;
	s->n_sources = ring->n_sources;
	s->i = calloc((size_t)ring->n_lamps * ring->n_sources, sizeof(float));
	if (!s->i) {
		free(s);
		return -ENOMEM;
	}
	*ret = s;
	return 0;
}

void hl_snapshot_free(struct hl_snapshot *s)
{
	if (!s)
		return;
	free(s->i);
	free(s);
}

/* Copies everything but the buffer pointer. */
static void copy_snapshot(struct hl_snapshot *dst, const struct hl_snapshot *src)
{
	float *i = dst->i;

	memcpy(i, src->i, sizeof(float) * (size_t)src->n_lamps * src->n_sources);
	*dst = *src;
	dst->i = i;
}

void hl_ring_push(struct hl_ring *r, struct hl_snapshot *s)
{
	const uint64_t n = atomic_load_explicit(&r->head, memory_order_relaxed);

	s->seq = n;
	for (;;) {
		/* the oldest slot the consumer is not reading (empty ones first) */
		unsigned best = r->n_slots;
		uint64_t best_state = 0;

		for (unsigned i = 0; i < r->n_slots; i++) {
			const uint64_t st =
				atomic_load_explicit(&r->slots[i].state, memory_order_relaxed);

			if (TAG(st) == READING)
				continue;
			if (best == r->n_slots || TAG(st) == EMPTY ||
			    (TAG(best_state) != EMPTY && SEQ(st) < SEQ(best_state))) {
				best = i;
				best_state = st;
				if (TAG(st) == EMPTY)
					break;
			}
		}
		/* With two or more slots and one reader there is always one; the CAS fails only
		 * when the consumer claimed that slot just now. */
		if (atomic_compare_exchange_strong_explicit(&r->slots[best].state, &best_state,
							    STATE(n, WRITING), memory_order_acquire,
							    memory_order_relaxed)) {
			copy_snapshot(&r->slots[best].snap, s);
			atomic_store_explicit(&r->slots[best].state, STATE(n, READY),
					      memory_order_release);
			atomic_store_explicit(&r->head, n + 1, memory_order_release);
			/* an eventfd write does not block while its counter is far from the max; a
			 * failed one only delays the consumer to its own timeout */
			if (write(r->wake_fd, &(uint64_t){ 1 }, sizeof(uint64_t)) < 0) {
			}
			return;
		}
	}
}

/* Claims the slot holding snapshot seq, copies it out and hands it back. */
static bool take_seq(struct hl_ring *r, uint64_t seq, struct hl_snapshot *ret)
{
	for (unsigned i = 0; i < r->n_slots; i++) {
		uint64_t st = STATE(seq, READY);

		if (atomic_compare_exchange_strong_explicit(
			    &r->slots[i].state, &st, STATE(seq, READING), memory_order_acquire,
			    memory_order_relaxed)) {
			copy_snapshot(ret, &r->slots[i].snap);
			atomic_store_explicit(&r->slots[i].state, STATE(seq, READY),
					      memory_order_release);
			return true;
		}
	}
	return false; /* overwritten (or being overwritten) by the producer */
}

static void count(_Atomic uint64_t *c, uint64_t n)
{
	if (n)
		atomic_store_explicit(c, atomic_load_explicit(c, memory_order_relaxed) + n,
				      memory_order_relaxed);
}

bool hl_ring_take_newest(struct hl_ring *r, struct hl_snapshot *ret)
{
	for (;;) {
		const uint64_t head = atomic_load_explicit(&r->head, memory_order_acquire);

		if (head == r->tail)
			return false;
		if (take_seq(r, head - 1, ret)) {
			count(&r->superseded, head - 1 - r->tail);
			count(&r->consumed, 1);
			r->tail = head;
			return true;
		}
		/* the producer lapped us meanwhile: a newer one is there now */
	}
}

bool hl_ring_pop(struct hl_ring *r, struct hl_snapshot *ret)
{
	for (;;) {
		const uint64_t head = atomic_load_explicit(&r->head, memory_order_acquire);
		uint64_t oldest = head;

		if (head == r->tail)
			return false;
		if (take_seq(r, r->tail, ret)) {
			count(&r->consumed, 1);
			r->tail++;
			return true;
		}
		/* gone: skip to the oldest snapshot still in the ring */
		for (unsigned i = 0; i < r->n_slots; i++) {
			const uint64_t st =
				atomic_load_explicit(&r->slots[i].state, memory_order_relaxed);

			if (TAG(st) == READY && SEQ(st) > r->tail && SEQ(st) < oldest)
				oldest = SEQ(st);
		}
		if (oldest == head)
			oldest = head - 1; /* only the newest is left (it will be ready) */
		count(&r->dropped, oldest - r->tail);
		r->tail = oldest;
	}
}

void hl_ring_counts(const struct hl_ring *r, struct hl_ring_counts *ret)
{
	struct hl_ring *m = (struct hl_ring *)r; /* atomic loads need a non-const object */

	ret->consumed = atomic_load_explicit(&m->consumed, memory_order_relaxed);
	ret->superseded = atomic_load_explicit(&m->superseded, memory_order_relaxed);
	ret->dropped = atomic_load_explicit(&m->dropped, memory_order_relaxed);
	ret->pushed = atomic_load_explicit(&m->head, memory_order_acquire);
}

uint64_t hl_ring_pending(const struct hl_ring *r)
{
	struct hl_ring_counts c;

	hl_ring_counts(r, &c);
	return c.pushed - c.consumed - c.superseded - c.dropped;
}

unsigned hl_ring_slots(const struct hl_ring *r)
{
	return r->n_slots;
}

int hl_ring_wake_fd(const struct hl_ring *ring)
{
	return ring->wake_fd;
}

void hl_ring_wait(struct hl_ring *ring, int timeout_ms)
{
	struct pollfd pfd = { .fd = ring->wake_fd, .events = POLLIN };
	uint64_t wakes;

	if (poll(&pfd, 1, timeout_ms) > 0 && read(ring->wake_fd, &wakes, sizeof(wakes)) < 0) {
		/* reset lost: the next wait returns at once */
	}
}
