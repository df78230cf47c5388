/* SPDX-License-Identifier: MIT */
/*
 * The daemon's live verdicts (verdict.*): daemon/core/verdicts.h made for the lamps as the
 * assembler and the LID files give them, the sets and the beam mode's source logged.
 *
 * Thread-safety: hl_live_run's thread.
 */
#ifndef HL_DAEMON_LIVE_VERDICTS_H
#define HL_DAEMON_LIVE_VERDICTS_H

#include <stdbool.h>

#include "can/assembler.h"
#include "daemon/core/config.h"
#include "daemon/core/verdicts.h"
#include "lamp/lid.h"

/*
 * The verdicts for n_lamps lamps called lamp_names[l] on grids[l], at their default mounted
 * poses; the beam mode from the first lamp whose cycles carry a mode signal in a. *ret is the
 * caller's (hl_verdicts_free()). 0 or -errno as hl_verdicts_new(), logged; on failure
 * *ret_config_error says whether the configuration is at fault (exit 2; not for -ENOMEM).
 */
int hl_live_verdicts_new(const struct hl_config *cfg, const struct hl_assembler *a, int n_lamps,
			 const char *const *lamp_names, const struct hl_lid_grid *const *grids,
			 struct hl_verdicts **ret, bool *ret_config_error);

#endif
