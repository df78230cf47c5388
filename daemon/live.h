/* SPDX-License-Identifier: MIT */
/*
 * hdlampd's live mode: CAN thread -> ring -> render thread -> frame pool -> outputs, with the
 * main thread as the event loop (signals, status). Returns the process exit code.
 */
#ifndef HL_DAEMON_LIVE_H
#define HL_DAEMON_LIVE_H

#include "daemon/config.h"

struct hl_live_args {
	const char *config_path; /* re-read on SIGHUP; NULL: nothing to re-read */
	char *const *overrides; /* SECTION.KEY=VALUE given on the command line, re-applied */
	int n_overrides;
	unsigned ring_slots;
};

int hl_live_run(const struct hl_config *cfg, const struct hl_live_args *args);

#endif
