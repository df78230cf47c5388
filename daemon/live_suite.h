/* SPDX-License-Identifier: MIT */
/*
 * hdlampd --suite (docs/lab.md "In real time"): a suite's variants one after the other in real
 * time, each a whole run of the daemon (hl_live_run) on its generated scenario with
 * loop.exit_at_end, measured on every published frame (daemon/core/suite_live.h: /status,
 * /metrics, the live page), against the ECU in process (ecu.model) or the ECU on a CAN
 * interface (can.interface and restbus.interface); each run's report in DIR/runs/ID.json, and
 * at the end DIR/report.json, junit.xml, index.html and the plots, as hdlamp suite run writes
 * them; with ecu.model the virtual bus of each run traced to DIR/traces/ID.log. A signal stops the variant running and the suite: the variants not run are errors.
 */
#ifndef HL_DAEMON_LIVE_SUITE_H
#define HL_DAEMON_LIVE_SUITE_H

#include "daemon/core/config.h"
#include "daemon/live.h"

struct hl_live_suite_options {
	const char *suite; /* a shipped suite's name or a .json path */
	const char *out; /* NULL: suite-NAME in the working directory */
	const char *only; /* NULL, or a scenario's or a variant's id */
};

/*
 * Runs it. The exit code: 0 every test held, 3 one failed (or a bin went unmeasured, or a run
 * did not finish), 2 bad input or configuration (logged), 1 a run or an output failed.
 */
int hl_live_suite_run(const struct hl_config *cfg, const struct hl_live_args *args,
		      const struct hl_live_suite_options *so);

#endif
