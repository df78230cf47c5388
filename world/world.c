/* SPDX-License-Identifier: MIT */
#include "world/world.h"

#include <math.h>

#define DEG (M_PI / 180.0)

void hl_world_ego_lamps(const struct hl_scenario *sc, const struct hl_body_pose *ego,
			struct hl_lamp_pose ret[2])
{
	for (int l = 0; l < 2; l++) {
		ret[l] = sc->ego.lamp[l];
		hl_body_to_world(ego, sc->ego.lamp[l].pos_m, ret[l].pos_m);
		ret[l].yaw_deg = remainder(sc->ego.lamp[l].yaw_deg + ego->heading_rad / DEG, 360.0);
	}
}

void hl_world_actor_eye(const struct hl_scenario *sc, int i, const struct hl_body_pose *pose,
			double ret[3])
{
	hl_body_to_world(pose, sc->actor[i].eye_m, ret);
}

void hl_world_at(const struct hl_scenario *sc, double t_s, struct hl_world_state *ret)
{
	ret->t_s = t_s;
	hl_scenario_ego_pose(sc, t_s, &ret->ego);
	ret->n_actors = sc->n_actors;
	for (int i = 0; i < sc->n_actors; i++)
		hl_scenario_actor_pose(sc, i, t_s, &ret->actor[i]);
	ret->lamps_on = sc->n_actors >= 32 ? UINT32_MAX : (1u << sc->n_actors) - 1u;
}
