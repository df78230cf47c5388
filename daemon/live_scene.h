/* SPDX-License-Identifier: MIT */
/*
 * The daemon's moving scene (scene.*, pose.listen; docs/live-scenario.md, "Scenario and glare"): the
 * scenario, the regulation set of its glare limits, the live glare on the two lamps' grids and
 * the pose input, made and logged together and freed together.
 *
 * Thread-safety: new and free on hl_live_run's thread while no other thread uses the parts; the
 * parts' own headers say who may call them in between.
 */
#ifndef HL_DAEMON_LIVE_SCENE_H
#define HL_DAEMON_LIVE_SCENE_H

#include <stdbool.h>

#include "daemon/core/config.h"
#include "daemon/core/glare_live.h"
#include "daemon/loop/osi_input.h"
#include "daemon/loop/pose_input.h"
#include "world/osi_replay.h"
#include "lamp/lid.h"
#include "verdict/regulation.h"
#include "world/scenario.h"

struct hl_live_scene;

/*
 * cfg->scenario read (or with cfg->world, the world of ASAM OSI: docs/osi.md), its glare under cfg->glare_set (from cfg->regulations) planned on the
 * lamps' grids grids[0] (left), grids[1] (right) of n_lamps lamps (the glare takes two), the
 * pose input on cfg->pose_listen when set (made, not started). *ret is the caller's; NULL when
 * cfg->scenario and cfg->world are empty (no scene: 0). 0 or -errno (the scenario's, the set's, -EINVAL for
 * n_lamps != 2 or a set that is not a glare table, the pose input's), logged; on failure
 * *ret_config_error says whether the configuration is at fault (exit 2).
 */
int hl_live_scene_new(const struct hl_config *cfg, int n_lamps,
		      const struct hl_lid_grid *const *grids, struct hl_live_scene **ret,
		      bool *ret_config_error);
/* Frees the pose input (stopping it), then the glare, the set, the scenario. NULL: nothing. */
void hl_live_scene_free(struct hl_live_scene *s);

/* The parts, owned by s (NULL for a NULL s; the pose input NULL without pose.listen). */
const struct hl_scenario *hl_live_scene_scenario(const struct hl_live_scene *s);
/* scene.world osi:udp: the live input (made and its first message read, not started); else NULL. */
struct hl_osi_input *hl_live_scene_osi(const struct hl_live_scene *s);
/* scene.world osi:file: what the trace held; else NULL. */
const struct hl_osi_replay_report *hl_live_scene_osi_replay(const struct hl_live_scene *s);
struct hl_glare_live *hl_live_scene_glare(const struct hl_live_scene *s);
struct hl_pose_input *hl_live_scene_pose(const struct hl_live_scene *s);

#endif
