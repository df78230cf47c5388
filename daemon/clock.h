/* SPDX-License-Identifier: MIT */
/*
 * The daemon's clock: CLOCK_MONOTONIC in ns, for latency stamps, deadlines and intervals.
 * (A replay's own timeline is the candump log's business, in can/candump_log.h.)
 *
 * Thread-safety: any thread.
 */
#ifndef HL_DAEMON_CLOCK_H
#define HL_DAEMON_CLOCK_H

#include <errno.h>
#include <stdint.h>
#include <time.h>

static inline int64_t hl_clock_monotonic_ns(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

/* Sleeps until CLOCK_MONOTONIC reaches t_ns (signals do not cut the sleep short). */
static inline void hl_clock_sleep_until_ns(int64_t t_ns)
{
	const struct timespec ts = { .tv_sec = t_ns / 1000000000, .tv_nsec = t_ns % 1000000000 };

	while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR) {
	}
}

#endif
