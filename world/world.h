/* SPDX-License-Identifier: MIT */
/*
 * A moving scene at one instant (docs/scenarios.md): where the ego vehicle and every road user
 * of a scenario are, and whether the road users' lamps are lit. The scenario clock
 * (hl_world_at) fills it from the scenario's paths; an external driving simulator can fill it
 * instead (hdlampd's pose input). The renderer, the glare at the road users' eyes and the
 * daemon's outputs all read this one state, so what is shown and what is judged are the same
 * instant.
 *
 * Thread-safety: plain data; hl_world_at() is a pure function of read-only data (any thread)
 * and allocates nothing.
 */
#ifndef HL_WORLD_WORLD_H
#define HL_WORLD_WORLD_H

#include <stdbool.h>
#include <stdint.h>

#include "world/road.h"
#include "world/scenario.h"
#include "world/state.h"

/*
 * The scenario's state at time t: every pose from its paths, every road user present with its
 * lamps lit; a scenario with a recorded track (world/track.h): the track's state at t.
 */
void hl_world_at(const struct hl_scenario *sc, double t_s, struct hl_world_state *ret);

/* The ego lamps' poses in the world frame for an ego pose (as hl_world_ego_lamps_at()). */
void hl_world_ego_lamps(const struct hl_scenario *sc, const struct hl_body_pose *ego,
			struct hl_lamp_pose ret[2]);
/* Road user i's eye point in the world for its pose (as hl_world_actor_eye_at()). */
void hl_world_actor_eye(const struct hl_scenario *sc, int i, const struct hl_body_pose *pose,
			double ret[3]);

void hl_world_ego_pose_at(const struct hl_scenario *sc, double t_s, struct hl_body_pose *ret);
/* The ego lamps' poses in the world frame (position world, yaw from world +x). */
void hl_world_ego_lamps_at(const struct hl_scenario *sc, double t_s, struct hl_lamp_pose ret[2]);
/* The driver's camera in the world frame at width x height. */
void hl_world_ego_camera_at(const struct hl_scenario *sc, double t_s, int width, int height,
			    struct hl_camera *ret);
/* Road user i (0-based, < n_actors) at t, and its eye point in the world. */
void hl_world_actor_pose_at(const struct hl_scenario *sc, int i, double t_s,
			    struct hl_body_pose *ret);
void hl_world_actor_eye_at(const struct hl_scenario *sc, int i, double t_s, double ret[3]);

#endif
