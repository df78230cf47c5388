/* SPDX-License-Identifier: MIT */
/*
 * The world at one instant (docs/scenarios.md): where the ego vehicle and every road user are,
 * whether each is in the world and its lamps lit. Made by the scenario clock (world/world.h),
 * a recording (world/track.h) or a live input (the pose input, ASAM OSI); read by the
 * renderer, the glare, the verdicts and the restbus.
 *
 * Thread-safety: plain data.
 */
#ifndef HL_WORLD_STATE_H
#define HL_WORLD_STATE_H

#include <stdbool.h>
#include <stdint.h>

#include "world/road.h"

#define HL_SCN_MAX_ACTORS 16 /* road users of a scenario, at most */

struct hl_world_state {
	double t_s; /* scenario time */
	struct hl_body_pose ego;
	int n_actors; /* the scenario's road users, in its order */
	struct hl_body_pose actor[HL_SCN_MAX_ACTORS];
	uint32_t lamps_on; /* bit i: road user i's lamps are lit */
	uint32_t present; /* bit i: road user i is in the world (a recording's may leave) */
};

/* Whether road user i is in the world state (drawn, judged, reported). */
static inline bool hl_world_present(const struct hl_world_state *w, int i)
{
	return i >= 0 && i < w->n_actors && i < 32 && (w->present >> i) & 1u;
}

#endif
