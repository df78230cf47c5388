/* SPDX-License-Identifier: MIT */
/* What the restbus tells the ECU about a scenario instant: see daemon/loop/restbus_state.h. */
#include "daemon/loop/restbus_state.h"

#include <math.h>
#include <string.h>

#include "world/road.h"
#include "world/world.h"

#define DEG (M_PI / 180.0)
#define YAW_DT_S 0.005 /* half the central difference of the heading */
#define STANDING_MPS 0.5 /* below: the road's curvature, not yaw rate / speed */
#define ROAD_DS_M 0.5 /* half the central difference of the road's heading */

void hl_restbus_vehicle(const struct hl_scenario *sc, const struct hl_world_state *w,
			enum hl_light_switch sw, bool adb, struct hl_vehicle_state *ret)
{
	struct hl_body_pose now, a, b;
	double yaw, k;

	hl_world_ego_pose_at(sc, w->t_s, &now);
	hl_world_ego_pose_at(sc, w->t_s - YAW_DT_S, &a);
	hl_world_ego_pose_at(sc, w->t_s + YAW_DT_S, &b);
	yaw = remainder(b.heading_rad - a.heading_rad, 2 * M_PI) / (2 * YAW_DT_S);
	if (now.speed_mps > STANDING_MPS) {
		k = yaw / now.speed_mps;
	} else {
		struct hl_pose2 p, q;

		hl_road_centre(&sc->road, now.s_m - ROAD_DS_M, &p);
		hl_road_centre(&sc->road, now.s_m + ROAD_DS_M, &q);
		k = remainder(q.heading_rad - p.heading_rad, 2 * M_PI) / (2 * ROAD_DS_M);
	}
	ret->speed_mps = now.speed_mps;
	ret->yaw_rate_rad_s = yaw;
	ret->steering_rad = HL_RESTBUS_STEERING_RATIO * atan(HL_RESTBUS_WHEELBASE_M * k);
	ret->light_switch = sw;
	ret->adb_enable = adb;
}

void hl_restbus_vehicle_live(const struct hl_world_state *w, const struct hl_world_state *prev,
			     enum hl_light_switch sw, bool adb, struct hl_vehicle_state *ret)
{
	const double v = isfinite(w->ego.speed_mps) ? w->ego.speed_mps : 0.0;
	double yaw = 0.0;

	if (prev && prev->t_s < w->t_s)
		yaw = remainder(w->ego.heading_rad - prev->ego.heading_rad, 2 * M_PI) /
		      (w->t_s - prev->t_s);
	ret->speed_mps = v;
	ret->yaw_rate_rad_s = yaw;
	ret->steering_rad = v > STANDING_MPS ? HL_RESTBUS_STEERING_RATIO *
						       atan(HL_RESTBUS_WHEELBASE_M * yaw / v) :
					       0.0;
	ret->light_switch = sw;
	ret->adb_enable = adb;
}

/* The camera's place and axes in the world. */
struct cam_frame {
	double pos[3], fwd[3], left[3];
};

static void cam_frame(const struct hl_world_state *w, const struct hl_restbus_camera *cam,
		      struct cam_frame *ret)
{
	hl_body_to_world(&w->ego, cam->pos_m, ret->pos);
	ret->fwd[0] = cos(w->ego.heading_rad);
	ret->fwd[1] = sin(w->ego.heading_rad);
	ret->fwd[2] = 0;
	ret->left[0] = -ret->fwd[1];
	ret->left[1] = ret->fwd[0];
	ret->left[2] = 0;
}

/* Distance from p (world) to the nearest point of road user i's body box. */
static double box_distance(const struct hl_actor *a, const struct hl_body_pose *pose,
			   const double p[3])
{
	const double c = cos(pose->heading_rad), s = sin(pose->heading_rad);
	const double dx = p[0] - pose->pos_m[0], dy = p[1] - pose->pos_m[1];
	const double local[3] = { dx * c + dy * s, -dx * s + dy * c, p[2] - pose->pos_m[2] };
	const double lo[3] = { -a->size_m[0], -a->size_m[1] / 2, 0 };
	const double hi[3] = { 0, a->size_m[1] / 2, a->size_m[2] };
	double d2 = 0;

	for (int k = 0; k < 3; k++) {
		const double q = fmin(fmax(local[k], lo[k]), hi[k]);

		d2 += (local[k] - q) * (local[k] - q);
	}
	return sqrt(d2);
}

static enum hl_object_class classify(const struct hl_actor *a, const struct hl_body_pose *ego,
				     const struct hl_body_pose *pose)
{
	const double c = cos(pose->heading_rad - ego->heading_rad);

	if (a->kind == HL_ACTOR_PEDESTRIAN)
		return HL_OBJECT_PEDESTRIAN;
	if (c <= -cos(45 * DEG))
		return HL_OBJECT_ONCOMING;
	if (c >= cos(45 * DEG))
		return HL_OBJECT_PRECEDING;
	return HL_OBJECT_OTHER;
}

static bool project(const struct hl_actor *a, const struct hl_body_pose *pose,
		    const struct cam_frame *cf, struct hl_camera_object *ret)
{
	double hmin = INFINITY, hmax = -INFINITY, vmin = INFINITY, vmax = -INFINITY;

	for (int k = 0; k < 8; k++) {
		const double local[3] = { (k & 1) ? -a->size_m[0] : 0,
					  (k & 2) ? a->size_m[1] / 2 : -a->size_m[1] / 2,
					  (k & 4) ? a->size_m[2] : 0 };
		double p[3], d[3], f, r, u, h, v;

		hl_body_to_world(pose, local, p);
		for (int j = 0; j < 3; j++)
			d[j] = p[j] - cf->pos[j];
		f = d[0] * cf->fwd[0] + d[1] * cf->fwd[1];
		r = -(d[0] * cf->left[0] + d[1] * cf->left[1]);
		u = d[2];
		if (!(f > 0))
			return false;
		h = atan2(r, f) / DEG;
		v = atan2(u, hypot(r, f)) / DEG;
		hmin = fmin(hmin, h);
		hmax = fmax(hmax, h);
		vmin = fmin(vmin, v);
		vmax = fmax(vmax, v);
	}
	ret->h_left_deg = hmin;
	ret->h_right_deg = hmax;
	ret->v_bottom_deg = vmin;
	ret->v_top_deg = vmax;
	ret->distance_m = box_distance(a, pose, cf->pos);
	return true;
}

bool hl_restbus_object(const struct hl_scenario *sc, const struct hl_world_state *w, int i,
		       const struct hl_restbus_camera *cam, struct hl_camera_object *ret)
{
	struct cam_frame cf;

	cam_frame(w, cam, &cf);
	if (!project(&sc->actor[i], &w->actor[i], &cf, ret))
		return false;
	ret->id = (unsigned)i + 1;
	ret->cls = classify(&sc->actor[i], &w->ego, &w->actor[i]);
	ret->confidence = 1.0;
	return true;
}

void hl_restbus_objects(const struct hl_scenario *sc, const struct hl_world_state *w,
			const struct hl_restbus_camera *cam, int max, struct hl_camera_objects *ret,
			struct hl_restbus_unseen *ret_unseen)
{
	const double hh = cam->fov_h_deg / 2, hv = cam->fov_v_deg / 2;
	struct hl_camera_object seen[HL_SCN_MAX_ACTORS];
	int n = 0;

	memset(ret_unseen, 0, sizeof(*ret_unseen));
	if (max > HL_INPUTS_MAX_OBJECTS)
		max = HL_INPUTS_MAX_OBJECTS;
	for (int i = 0; i < w->n_actors && i < sc->n_actors; i++) {
		struct hl_camera_object o;
		int j;

		if (!hl_world_present(w, i))
			continue;
		if (!hl_restbus_object(sc, w, i, cam, &o)) {
			ret_unseen->behind++;
			continue;
		}
		if (o.distance_m > cam->range_m) {
			ret_unseen->beyond_range++;
			continue;
		}
		if (o.h_right_deg < -hh || o.h_left_deg > hh || o.v_top_deg < -hv ||
		    o.v_bottom_deg > hv) {
			ret_unseen->outside_fov++;
			continue;
		}
		o.h_left_deg = fmax(o.h_left_deg, -hh);
		o.h_right_deg = fmin(o.h_right_deg, hh);
		o.v_bottom_deg = fmax(o.v_bottom_deg, -hv);
		o.v_top_deg = fmin(o.v_top_deg, hv);
		/* insertion by distance: the nearest first (ties: the scenario's order) */
		for (j = n; j > 0 && seen[j - 1].distance_m > o.distance_m; j--)
			seen[j] = seen[j - 1];
		seen[j] = o;
		n++;
	}
	ret->n = n < max ? n : max;
	ret_unseen->over_max = n - ret->n;
	memcpy(ret->obj, seen, sizeof(seen[0]) * (size_t)ret->n);
}
