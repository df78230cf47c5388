/* SPDX-License-Identifier: MIT */
/* The daemon's loop judge: see daemon/live_loop.h. */
#include "daemon/live_loop.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "daemon/live_log.h"

#define ECU_CYCLE_MS 20.0 /* the dimming period of docs/design.md §1 */

struct hl_live_loop {
	struct hl_loop_latency *loop;
	FILE *events; /* loop.events when a file */
};

/*
 * The loop's judge (daemon/loop/loop_latency.h): with a scenario and a restbus, a report, an end or
 * event lines asked for. loop.events opens here (a bad path is a configuration error).
 */
static int setup(struct hl_live_loop *lp, const struct hl_config *cfg, const struct hl_scenario *sc,
		 bool *config_error)
{
	struct hl_loop_latency_config lc = {
		.sc = sc,
		.ecu_cycle_ms = ECU_CYCLE_MS,
		.reaction_ms = cfg->loop_reaction_ms,
		.camera = cfg->restbus_interface[0] != '\0',
	};
	int rc;

	if (strcmp(cfg->loop_events, "-") == 0) {
		lc.events = stdout;
	} else if (cfg->loop_events[0]) {
		lp->events = fopen(cfg->loop_events, "we");
		if (!lp->events) {
			hl_live_log("loop.events '%s': %s; expected a file it can write",
				    cfg->loop_events, strerror(errno));
			*config_error = true;
			return -errno;
		}
		lc.events = lp->events;
	}
	rc = hl_loop_latency_new(&lc, &lp->loop);
	if (rc < 0) {
		hl_live_log("loop: %s", strerror(-rc));
		return rc;
	}
	hl_live_log(
		"loop: glare over a road user's limit allowed %g ms after it enters the camera's "
		"view%s",
		lc.reaction_ms, lc.camera ? "" : " (no restbus: none allowed)");
	return 0;
}

int hl_live_loop_new(const struct hl_config *cfg, const struct hl_scenario *sc,
		     struct hl_live_loop **ret, bool *ret_config_error)
{
	struct hl_live_loop *lp;
	bool config_error = false;
	int rc;

	if (!sc || !(cfg->restbus_interface[0] || cfg->loop_report[0] || cfg->loop_junit[0] ||
		     cfg->loop_exit_at_end || cfg->loop_events[0])) {
		*ret = NULL;
		return 0;
	}
	lp = calloc(1, sizeof(*lp));
	if (!lp) {
		*ret_config_error = false;
		return -ENOMEM;
	}
	rc = setup(lp, cfg, sc, &config_error);
	if (rc < 0) {
		hl_live_loop_free(lp);
		*ret_config_error = config_error;
		return rc;
	}
	*ret = lp;
	return 0;
}

void hl_live_loop_free(struct hl_live_loop *lp)
{
	if (!lp)
		return;
	hl_loop_latency_free(lp->loop); /* after the restbus and the status that use it */
	if (lp->events)
		fclose(lp->events);
	free(lp);
}

struct hl_loop_latency *hl_live_loop_latency(const struct hl_live_loop *lp)
{
	return lp ? lp->loop : NULL;
}
