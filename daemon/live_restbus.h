/* SPDX-License-Identifier: MIT */
/*
 * The daemon's restbus (restbus.*; docs/loop.md): daemon/loop/restbus.h with the input
 * database (restbus.dbc, or the shipped hd84_inputs.dbc) and the camera from the
 * configuration, logged.
 *
 * Thread-safety: hl_live_run's thread.
 */
#ifndef HL_DAEMON_LIVE_RESTBUS_H
#define HL_DAEMON_LIVE_RESTBUS_H

#include <stdbool.h>

#include "daemon/core/config.h"
#include "daemon/loop/loop_latency.h"
#include "daemon/loop/pose_input.h"
#include "daemon/loop/restbus.h"
#include "world/scenario.h"

/*
 * The restbus on cfg->restbus_interface for scenario sc, poses from pose (NULL: the scenario's
 * clock), camera cycles told to loop (NULL: none); sc, pose and loop must outlive it. Made,
 * not started. *ret is the caller's (hl_restbus_free()); NULL without restbus.interface or
 * without a scenario (0). 0 or -errno (-ENOENT: no shipped databases; the restbus'), logged;
 * on failure *ret_config_error says whether the configuration is at fault (exit 2).
 */
int hl_live_restbus_new(const struct hl_config *cfg, const struct hl_scenario *sc,
			struct hl_pose_input *pose, struct hl_osi_input *osi,
			struct hl_loop_latency *loop, struct hl_restbus **ret,
			bool *ret_config_error);

#endif
