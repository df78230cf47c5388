/* SPDX-License-Identifier: MIT */
/* The SPSC ring: exact counts, in-order and newest reading, and a threaded stress test. */
#include <errno.h>
#include <poll.h>
#include <pthread.h>
#include <sched.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <time.h>
#include <cmocka.h>

#include "daemon/core/ring.h"
#include "testutil.h"

#define LAMPS 2
#define SOURCES 95

/* Every field of snapshot n is a function of n, so a torn read shows. */
static void fill(struct hl_snapshot *s, uint64_t n)
{
	s->t_push_ns = (int64_t)(n * 3 + 1);
	for (int l = 0; l < LAMPS; l++) {
		s->lamps[l].cycle_seq = n + (uint64_t)l;
		s->lamps[l].t_rx_first_ns = (int64_t)(n * 7 + l);
		s->lamps[l].t_complete_ns = (int64_t)(n * 11 + l);
		s->lamps[l].status = (uint32_t)(n % 3);
		s->lamps[l].counter = (uint8_t)(n % 15);
	}
	for (int k = 0; k < LAMPS * SOURCES; k++)
		s->i[k] = (float)((n + (uint64_t)k) % 64) / 63.0f;
}

static bool intact(const struct hl_snapshot *s)
{
	const uint64_t n = s->seq;

	if (s->t_push_ns != (int64_t)(n * 3 + 1) || s->n_lamps != LAMPS || s->n_sources != SOURCES)
		return false;
	for (int l = 0; l < LAMPS; l++)
		if (s->lamps[l].cycle_seq != n + (uint64_t)l ||
		    s->lamps[l].t_rx_first_ns != (int64_t)(n * 7 + l) ||
		    s->lamps[l].t_complete_ns != (int64_t)(n * 11 + l) ||
		    s->lamps[l].status != (uint32_t)(n % 3) ||
		    s->lamps[l].counter != (uint8_t)(n % 15))
			return false;
	for (int k = 0; k < LAMPS * SOURCES; k++)
		if (s->i[k] != (float)((n + (uint64_t)k) % 64) / 63.0f)
			return false;
	return true;
}

static void ring_rejects_bad_shapes(void **state)
{
	struct hl_ring *r = NULL;
	(void)state;

	assert_int_equal(hl_ring_new(3, 1, 1, &r), -EINVAL);
	assert_int_equal(hl_ring_new(1, 1, 1, &r), -EINVAL);
	assert_int_equal(hl_ring_new(4, 0, 1, &r), -EINVAL);
	assert_int_equal(hl_ring_new(4, HL_RING_MAX_LAMPS + 1, 1, &r), -EINVAL);
	assert_int_equal(hl_ring_new(4, 1, 0, &r), -EINVAL);
	assert_null(r);
	hl_ring_free(NULL);
	hl_snapshot_free(NULL);
}

static void ring_consumer_sees_latest_and_counts_superseded(void **state)
{
	struct hl_ring *r;
	struct hl_snapshot *in, *out;
	struct hl_ring_counts c;
	(void)state;

	assert_int_equal(hl_ring_new(4, LAMPS, SOURCES, &r), 0);
	assert_int_equal(hl_snapshot_new(r, &in), 0);
	assert_int_equal(hl_snapshot_new(r, &out), 0);
	assert_false(hl_ring_take_newest(r, out));
	for (uint64_t n = 0; n < 3; n++) {
		fill(in, n);
		hl_ring_push(r, in);
		assert_true(in->seq == n);
	}
	assert_true(hl_ring_take_newest(r, out));
	assert_true(out->seq == 2 && intact(out));
	assert_false(hl_ring_take_newest(r, out));
	/* ten more than the ring holds: the newest is still there */
	for (uint64_t n = 3; n < 13; n++) {
		fill(in, n);
		hl_ring_push(r, in);
	}
	assert_true(hl_ring_take_newest(r, out));
	assert_true(out->seq == 12 && intact(out));
	hl_ring_counts(r, &c);
	assert_true(c.pushed == 13 && c.consumed == 2 && c.superseded == 11 && c.dropped == 0);
	hl_snapshot_free(in);
	hl_snapshot_free(out);
	hl_ring_free(r);
}

static void ring_pop_reads_in_order_and_counts_dropped(void **state)
{
	struct hl_ring *r;
	struct hl_snapshot *in, *out;
	struct hl_ring_counts c;
	(void)state;

	assert_int_equal(hl_ring_new(4, LAMPS, SOURCES, &r), 0);
	assert_int_equal(hl_snapshot_new(r, &in), 0);
	assert_int_equal(hl_snapshot_new(r, &out), 0);
	for (uint64_t n = 0; n < 3; n++) {
		fill(in, n);
		hl_ring_push(r, in);
	}
	for (uint64_t n = 0; n < 3; n++) {
		assert_true(hl_ring_pop(r, out));
		assert_true(out->seq == n && intact(out));
	}
	assert_false(hl_ring_pop(r, out));
	/* 6 pushed behind the reader's back into 4 slots: 5..8 are there, 3 and 4 are gone */
	for (uint64_t n = 3; n < 9; n++) {
		fill(in, n);
		hl_ring_push(r, in);
	}
	assert_true(hl_ring_pop(r, out));
	assert_true(out->seq == 5 && intact(out));
	assert_true(hl_ring_take_newest(r, out)); /* skips 6 and 7 */
	assert_true(out->seq == 8 && intact(out));
	hl_ring_counts(r, &c);
	assert_true(c.pushed == 9 && c.consumed == 5 && c.dropped == 2 && c.superseded == 2);
	assert_true(c.pushed == c.consumed + c.superseded + c.dropped);
	hl_snapshot_free(in);
	hl_snapshot_free(out);
	hl_ring_free(r);
}

#define STRESS_SLOTS 8
#define STRESS_PAUSE (2 * STRESS_SLOTS) /* the producer waits after these, once */

struct stress {
	struct hl_ring *ring;
	uint64_t n_push;
	atomic_bool go; /* the consumer lets the producer on after STRESS_PAUSE */
	double push_hz; /* printed, never asserted: a loaded machine is slower */
};

static int64_t now_ns(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

static void *producer(void *arg)
{
	struct stress *st = arg;
	struct hl_snapshot *s;
	int64_t t0;

	if (hl_snapshot_new(st->ring, &s) < 0)
		return NULL;
	t0 = now_ns();
	for (uint64_t n = 0; n < st->n_push; n++) {
		if (n == STRESS_PAUSE)
			while (!atomic_load(&st->go))
				sched_yield();
		fill(s, n);
		hl_ring_push(st->ring, s);
	}
	st->push_hz = (double)st->n_push / ((double)(now_ns() - t0) / 1e9);
	hl_snapshot_free(s);
	return NULL;
}

/*
 * The producer pushes as fast as it can; the consumer reads with random stalls, mixing
 * newest-first and in-order reading, and checks every snapshot it gets is whole and newer than
 * the last. At the end the counts add up exactly. Both loss paths are taken whatever the
 * machine's speed: the producer first laps the ring twice and waits, the consumer pops
 * (dropping the lapped ones) and takes the newest (superseding the rest), then both run free.
 * Run under ThreadSanitizer in CI.
 */
static void ring_stress_no_torn_snapshot_and_counts_add_up(void **state)
{
	struct stress st = { .n_push = 400000 };
	struct hl_snapshot *out;
	struct hl_ring_counts c;
	unsigned long long rng = 99;
	uint64_t got = 0, last = 0;
	bool first = true;
	pthread_t t;
	(void)state;

	atomic_init(&st.go, false);
	assert_int_equal(hl_ring_new(STRESS_SLOTS, LAMPS, SOURCES, &st.ring), 0);
	assert_int_equal(hl_snapshot_new(st.ring, &out), 0);
	assert_int_equal(pthread_create(&t, NULL, producer, &st), 0);
	/* an event, not a duration: the producer stops at STRESS_PAUSE until told to go on */
	do {
		hl_ring_counts(st.ring, &c);
	} while (c.pushed < STRESS_PAUSE);
	assert_true(hl_ring_pop(st.ring, out)); /* 0..7 were overwritten: the oldest left is 8 */
	assert_true(out->seq == STRESS_PAUSE - STRESS_SLOTS && intact(out));
	assert_true(hl_ring_take_newest(st.ring, out)); /* 15, superseding 9..14 */
	assert_true(out->seq == STRESS_PAUSE - 1 && intact(out));
	hl_ring_counts(st.ring, &c);
	assert_true(c.consumed == 2 && c.dropped == STRESS_SLOTS && c.superseded == 6);
	first = false;
	last = out->seq;
	got = 2;
	atomic_store(&st.go, true);
	for (;;) {
		hl_ring_counts(st.ring, &c);
		const bool done = c.pushed == st.n_push;
		const bool ok = (test_rand(&rng) & 1) ? hl_ring_take_newest(st.ring, out) :
							hl_ring_pop(st.ring, out);

		if (ok) {
			assert_true(intact(out));
			assert_true(first || out->seq > last);
			first = false;
			last = out->seq;
			got++;
		} else if (done) {
			break;
		}
		/* random stalls: nothing, a spin, or a sleep of up to 50 µs */
		switch (test_rand(&rng) % 4) {
		case 0: {
			struct timespec ts = { 0, (long)(test_rand(&rng) % 50000) };
			nanosleep(&ts, NULL);
			break;
		}
		case 1:
			for (volatile int spin = 0; spin < (int)(test_rand(&rng) % 2000); spin++)
				;
			break;
		default:
			break;
		}
	}
	assert_int_equal(pthread_join(t, NULL), 0);
	hl_ring_counts(st.ring, &c);
	print_message("producer %.0f kHz; pushed %llu consumed %llu superseded %llu dropped %llu\n",
		      st.push_hz / 1e3, (unsigned long long)c.pushed,
		      (unsigned long long)c.consumed, (unsigned long long)c.superseded,
		      (unsigned long long)c.dropped);
	assert_true(c.pushed == st.n_push);
	assert_true(c.consumed == got);
	assert_true(c.pushed == c.consumed + c.superseded + c.dropped);
	assert_true(last == st.n_push - 1);
	assert_true(c.superseded >= 6 && c.dropped >= STRESS_SLOTS); /* both paths were taken */
	hl_snapshot_free(out);
	hl_ring_free(st.ring);
}

static bool readable(int fd)
{
	struct pollfd pfd = { .fd = fd, .events = POLLIN };

	return poll(&pfd, 1, 0) == 1 && (pfd.revents & POLLIN);
}

static void ring_push_makes_its_wake_fd_readable(void **state)
{
	struct hl_ring *r;
	struct hl_snapshot *s;

	(void)state;
	assert_int_equal(hl_ring_new(4, LAMPS, SOURCES, &r), 0);
	assert_int_equal(hl_snapshot_new(r, &s), 0);
	assert_true(hl_ring_wake_fd(r) >= 0);
	assert_false(readable(hl_ring_wake_fd(r)));
	fill(s, 0);
	hl_ring_push(r, s);
	hl_ring_push(r, s);
	assert_true(readable(hl_ring_wake_fd(r)));
	hl_ring_wait(r, 0); /* resets it, whatever the number of pushes */
	assert_false(readable(hl_ring_wake_fd(r)));
	assert_true(hl_ring_take_newest(r, s));
	assert_int_equal(s->seq, 1);
	hl_snapshot_free(s);
	hl_ring_free(r);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(ring_rejects_bad_shapes),
		cmocka_unit_test(ring_consumer_sees_latest_and_counts_superseded),
		cmocka_unit_test(ring_pop_reads_in_order_and_counts_dropped),
		cmocka_unit_test(ring_stress_no_torn_snapshot_and_counts_add_up),
		cmocka_unit_test(ring_push_makes_its_wake_fd_readable),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
