/* SPDX-License-Identifier: MIT */
/*
 * The one monotonic clock: CLOCK_MONOTONIC in ns, for latency stamps, deadlines and intervals,
 * and the sleep to an absolute deadline on it. (A replay's own timeline is the candump log's
 * business, in can/candump_log.h; the scenario's time is world/scenario_clock.h's.)
 *
 * Thread-safety: any thread.
 */
#ifndef HL_BASE_CLOCK_H
#define HL_BASE_CLOCK_H

#include <stdint.h>

/* CLOCK_MONOTONIC now, in ns. */
int64_t hl_clock_monotonic_ns(void);

/*
 * Sleeps until CLOCK_MONOTONIC reaches t_ns (absolute). A signal does not cut the sleep short,
 * unless stop (may be NULL) is non-zero when it arrives: then it returns early.
 */
void hl_clock_sleep_until_ns(int64_t t_ns, const volatile int *stop);

#endif
