/* SPDX-License-Identifier: MIT */
/*
 * Where the daemon's world at an instant comes from (docs/osi.md; the scenario clock:
 * docs/scenarios.md, "Scenario time in the daemon"): a live input's newest state (the pose
 * input once it had a message; the ASAM OSI input always, no road users before its first), else
 * the scenario (its paths or its recorded track) at the scenario time the caller's clock gives.
 * The render thread and the restbus both ask here, so the frame and the ECU's inputs come from
 * the same world.
 *
 * Thread-safety: the inputs' own rules (their latest() from any thread); the feed is read-only.
 */
#ifndef HL_DAEMON_LOOP_WORLD_FEED_H
#define HL_DAEMON_LOOP_WORLD_FEED_H

#include <stdbool.h>
#include <stdint.h>

#include "daemon/core/frame.h"
#include "daemon/loop/osi_input.h"
#include "daemon/loop/pose_input.h"
#include "world/scenario.h"
#include "world/world.h"

struct hl_world_feed {
	const struct hl_scenario *sc; /* NULL: no scene */
	struct hl_pose_input *pose; /* NULL: none */
	struct hl_osi_input *osi; /* NULL: none */
};

/* Whether a live input, not the scenario clock, gives the world. */
static inline bool hl_world_feed_live(const struct hl_world_feed *f)
{
	return f->osi != NULL;
}

/*
 * The world into *ret and where it came from: HL_SCENE_POSE or HL_SCENE_OSI with the message's
 * arrival in *ret_rx_ns, else clock_source (the caller's clock: HL_SCENE_LOG or
 * HL_SCENE_CLOCK) with the scenario at clock_t_s; HL_SCENE_NONE without a scenario (*ret
 * untouched).
 */
enum hl_scene_source hl_world_feed_at(const struct hl_world_feed *f, double clock_t_s,
				      enum hl_scene_source clock_source, struct hl_world_state *ret,
				      int64_t *ret_rx_ns);

#endif
