/* SPDX-License-Identifier: MIT */
#include "world/world.h"

#include <math.h>

#include "world/track.h"

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
	if (sc->track) {
		hl_world_track_at(sc->track, t_s, ret);
		return;
	}
	ret->t_s = t_s;
	hl_world_ego_pose_at(sc, t_s, &ret->ego);
	ret->n_actors = sc->n_actors;
	for (int i = 0; i < sc->n_actors; i++)
		hl_world_actor_pose_at(sc, i, t_s, &ret->actor[i]);
	ret->lamps_on = sc->n_actors >= 32 ? UINT32_MAX : (1u << sc->n_actors) - 1u;
	ret->present = ret->lamps_on;
}

void hl_world_ego_pose_at(const struct hl_scenario *sc, double t_s, struct hl_body_pose *ret)
{
	if (sc->track) {
		struct hl_world_state w;

		hl_world_track_at(sc->track, t_s, &w);
		*ret = w.ego;
		return;
	}
	hl_path_pose(&sc->road, &sc->ego.path, t_s, ret);
}

void hl_world_ego_lamps_at(const struct hl_scenario *sc, double t_s, struct hl_lamp_pose ret[2])
{
	struct hl_body_pose pose;

	hl_world_ego_pose_at(sc, t_s, &pose);
	hl_world_ego_lamps(sc, &pose, ret);
}

void hl_world_ego_camera_at(const struct hl_scenario *sc, double t_s, int width, int height,
			    struct hl_camera *ret)
{
	const struct hl_camera *cam = &sc->ego.camera;
	const double c_h[3] = { 0.0, 0.0, 0.0 };
	struct hl_body_pose pose;
	double o[3], d[3];

	hl_world_ego_pose_at(sc, t_s, &pose);
	*ret = *cam;
	ret->width = width;
	ret->height = height;
	hl_body_to_world(&pose, cam->pos_m, ret->pos_m);
	/* Directions: the body's rotation only (the difference of two mapped points). */
	hl_body_to_world(&pose, c_h, o);
	hl_body_to_world(&pose, cam->dir, d);
	for (int i = 0; i < 3; i++)
		ret->dir[i] = d[i] - o[i];
	hl_body_to_world(&pose, cam->up, d);
	for (int i = 0; i < 3; i++)
		ret->up[i] = d[i] - o[i];
}

void hl_world_actor_pose_at(const struct hl_scenario *sc, int i, double t_s,
			    struct hl_body_pose *ret)
{
	if (sc->track) {
		struct hl_world_state w;

		hl_world_track_at(sc->track, t_s, &w);
		*ret = w.actor[i];
		return;
	}
	hl_path_pose(&sc->road, &sc->actor[i].path, t_s, ret);
}

void hl_world_actor_eye_at(const struct hl_scenario *sc, int i, double t_s, double ret[3])
{
	struct hl_body_pose pose;

	hl_world_actor_pose_at(sc, i, t_s, &pose);
	hl_world_actor_eye(sc, i, &pose, ret);
}
