/* SPDX-License-Identifier: MIT */
/* Where the daemon's world at an instant comes from: see daemon/loop/world_feed.h. */
#include "daemon/loop/world_feed.h"

#include <math.h>

enum hl_scene_source hl_world_feed_at(const struct hl_world_feed *f, double clock_t_s,
				      enum hl_scene_source clock_source, struct hl_world_state *ret,
				      int64_t *ret_rx_ns)
{
	if (!f->sc)
		return HL_SCENE_NONE;
	if (f->pose && hl_pose_input_latest(f->pose, ret, ret_rx_ns))
		return HL_SCENE_POSE;
	if (f->osi) {
		if (!hl_osi_input_latest(f->osi, ret, ret_rx_ns)) {
			*ret = (struct hl_world_state){ .n_actors =
								0 }; /* before the first: none */
			ret->ego.s_m = NAN;
			*ret_rx_ns = 0;
		}
		return HL_SCENE_OSI;
	}
	hl_world_at(f->sc, clock_t_s, ret);
	return clock_source;
}
