/* SPDX-License-Identifier: MIT */
/*
 * The virtual bus in real time (docs/sil.md, "Real time"): a thread of its own drives the bus
 * on CLOCK_MONOTONIC — it sleeps until the next frame ends or the next event of its hook (the
 * ECU node's steps) is due, or until a node sends (the bus's notify), delivers what has ended
 * by then and runs the hook's events at their own times. The bus's time is CLOCK_MONOTONIC ns.
 *
 * Thread-safety: start and stop from one thread; the hook runs on the driver's thread, as do
 * the bus's deliveries.
 */
#ifndef HL_CAN_VBUS_RT_H
#define HL_CAN_VBUS_RT_H

#include <stdint.h>

#include "can/vbus.h"

struct hl_vbus_rt_hook {
	int64_t (*next)(void *ctx); /* the time of its next event, INT64_MAX: none */
	/* runs the events due at t (<= now); < 0 stops the driver (kept as its error) */
	int (*run)(void *ctx, int64_t t);
	void *ctx;
};

struct hl_vbus_rt_counts {
	uint64_t wakeups;
	uint64_t events; /* hook runs */
	int64_t late_max_ns; /* the latest a hook event ran behind its time */
};

struct hl_vbus_rt;

/* Starts the thread (hl-vbus). hook may be NULL. 0 or -errno. */
int hl_vbus_rt_start(struct hl_vbus *b, const struct hl_vbus_rt_hook *hook,
		     struct hl_vbus_rt **ret);
/* Stops and joins the thread. NULL is fine. */
void hl_vbus_rt_stop(struct hl_vbus_rt *rt);
/* The hook's error that stopped the driver, 0 while it runs. */
int hl_vbus_rt_error(struct hl_vbus_rt *rt);
void hl_vbus_rt_counts(struct hl_vbus_rt *rt, struct hl_vbus_rt_counts *ret);

#endif
