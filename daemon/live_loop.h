/* SPDX-License-Identifier: MIT */
/*
 * The daemon's loop judge (loop.*; docs/loop.md): daemon/loop/loop_latency.h for the scene's
 * scenario, with the file its event lines go to (loop.events), made and logged together.
 *
 * Thread-safety: new and free on hl_live_run's thread while no other thread uses the judge; the
 * judge's header says who may call it in between.
 */
#ifndef HL_DAEMON_LIVE_LOOP_H
#define HL_DAEMON_LIVE_LOOP_H

#include <stdbool.h>

#include "daemon/core/config.h"
#include "daemon/loop/loop_latency.h"
#include "world/scenario.h"

struct hl_live_loop;

/*
 * The judge of scenario sc (NULL: none) when a restbus, a report, an end or event lines are
 * asked for (restbus.interface, loop.report, loop.exit_at_end, loop.events); loop.events "-"
 * is stdout, a path is opened here. *ret is the caller's; NULL when there is nothing to judge
 * (0). 0 or -errno (the events file's, the judge's), logged; on failure *ret_config_error says
 * whether the configuration is at fault (exit 2: the events file cannot be opened).
 */
int hl_live_loop_new(const struct hl_config *cfg, const struct hl_scenario *sc,
		     struct hl_live_loop **ret, bool *ret_config_error);
/* Frees the judge, then closes the events file. NULL: nothing. */
void hl_live_loop_free(struct hl_live_loop *lp);

/* The judge, owned by lp (NULL for a NULL lp). */
struct hl_loop_latency *hl_live_loop_latency(const struct hl_live_loop *lp);

#endif
