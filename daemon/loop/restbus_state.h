/* SPDX-License-Identifier: MIT */
/*
 * What the restbus tells the ECU about a scenario instant (docs/ecu-inputs.md): the vehicle
 * state from the ego's path, and the front camera's object list — each road user's body box
 * projected into the angles of a camera behind the windscreen.
 *
 * The camera: a point pos_m in the ego's body frame (ISO 8855: x forward, y left, z up, origin
 * on the ground below the front bumper), looking along the ego's +x, level. A point at
 * (forward f, right r, up u) from it has the type A angles of docs/design.md §4,
 * H = atan2(r, f), V = atan2(u, hypot(r, f)) (H positive right, V positive up). An object's box
 * is the extent of H and V over its body box's eight corners.
 *
 * An object is sent when every corner lies in front of the camera (f > 0), its distance (from
 * the camera to the nearest point of its body box) is within range_m, and its box overlaps the
 * field of view (|H| <= fov_h/2, |V| <= fov_v/2); its box is then clipped to the field of view,
 * as the camera sees only that part. Class: a pedestrian is "pedestrian"; any other road user
 * is "oncoming" when its heading is within 45 degrees of the opposite of the ego's, "preceding"
 * within 45 degrees of the ego's, else "other". Id: its index in the scenario + 1. Confidence:
 * 1 (the simulation knows). When more than max objects qualify, the nearest are sent and the
 * rest counted.
 *
 * Thread-safety: pure functions of read-only data; any thread; nothing allocates.
 */
#ifndef HL_DAEMON_LOOP_RESTBUS_STATE_H
#define HL_DAEMON_LOOP_RESTBUS_STATE_H

#include <stdbool.h>

#include "can/inputs.h"
#include "world/scenario.h"
#include "world/world.h"

#define HL_RESTBUS_WHEELBASE_M 2.8 /* the steering model's wheelbase */
#define HL_RESTBUS_STEERING_RATIO 15.0 /* steering wheel angle / road wheel angle */

struct hl_restbus_camera {
	double pos_m[3]; /* ego body frame */
	double fov_h_deg, fov_v_deg; /* full angles */
	double range_m;
};

/* Why road users were not in a camera cycle (each counted once per cycle, first reason). */
struct hl_restbus_unseen {
	int behind; /* a corner at or behind the camera's plane */
	int beyond_range;
	int outside_fov;
	int over_max; /* qualified, but more than max objects did */
};

/*
 * The vehicle state at w's instant: speed and yaw rate of the ego's path at w->t_s (the yaw
 * rate as the heading's central difference over +-5 ms), the steering wheel angle of a
 * kinematic single-track model, HL_RESTBUS_STEERING_RATIO * atan(HL_RESTBUS_WHEELBASE_M * k),
 * with the path's curvature k = yaw rate / speed (above 0.5 m/s; standing: the road's curvature
 * at the ego), and the given light switch and ADB enable.
 */
void hl_restbus_vehicle(const struct hl_scenario *sc, const struct hl_world_state *w,
			enum hl_light_switch sw, bool adb, struct hl_vehicle_state *ret);
/*
 * The same for a live world that has no path (an OSI simulator's): the speed of w's ego, the
 * yaw rate as the heading's difference from prev (an earlier state, t_s < w's; NULL or not
 * earlier: 0), the steering angle from yaw rate / speed (standing: 0).
 */
void hl_restbus_vehicle_live(const struct hl_world_state *w, const struct hl_world_state *prev,
			     enum hl_light_switch sw, bool adb, struct hl_vehicle_state *ret);

/* One road user's object as the camera sees it, unclipped: false when a corner is at or behind
 * the camera's plane. */
bool hl_restbus_object(const struct hl_scenario *sc, const struct hl_world_state *w, int i,
		       const struct hl_restbus_camera *cam, struct hl_camera_object *ret);

/* The camera cycle at w: up to max (<= HL_INPUTS_MAX_OBJECTS) objects, nearest first, clipped
 * to the field of view; why the others are missing in *ret_unseen. */
void hl_restbus_objects(const struct hl_scenario *sc, const struct hl_world_state *w,
			const struct hl_restbus_camera *cam, int max, struct hl_camera_objects *ret,
			struct hl_restbus_unseen *ret_unseen);

#endif
