/* SPDX-License-Identifier: MIT */
/*
 * hdlampd's run (docs/design.md §2), one wiring for both modes: CAN thread -> ring -> render
 * thread -> frame pool -> outputs (stream, HTTP, GPIO strobe, captures), with the main thread as the
 * event loop (signals, status); or, with the renderer off (--no-render), CAN thread -> ring ->
 * the main thread, which prints one JSON line per status change (and per complete lamp cycle
 * with print_cycles) and a summary of every counter at exit. Returns the process exit code.
 */
#ifndef HL_DAEMON_LIVE_H
#define HL_DAEMON_LIVE_H

#include <stdbool.h>

#include "daemon/core/config.h"
#include "daemon/core/suite_live.h"

struct hl_live_args {
	const char *config_path; /* re-read on SIGHUP; NULL: nothing to re-read */
	char *const *overrides; /* SECTION.KEY=VALUE given on the command line, re-applied */
	int n_overrides;
	char *const *lamp_names; /* can.lamps split, in order */
	int n_lamps;
	unsigned ring_slots;
	bool render; /* false: decode only, JSON lines on stdout */
	bool print_cycles; /* decode only: a line per complete lamp cycle */
	struct hl_suite_live *suite; /* hdlampd --suite: measures every frame; NULL: none */
	const char **ret_end; /* NULL, or where the run's end goes ("scenario_end", "signal", ...) */
	const char *trace; /* ecu.model: the virtual bus traced to this .log or .blf; NULL: not */
};

int hl_live_run(const struct hl_config *cfg, const struct hl_live_args *args);

#endif
