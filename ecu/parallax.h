/* SPDX-License-Identifier: MIT */
/*
 * From the camera's view to a lamp's (docs/ecu.md, "Parallax"). The camera and the lamps sit at
 * different places on the car, so an object at angles (h, v) from the camera is at other angles
 * from each lamp; the nearer the object, the larger the difference (0.7 m of lateral offset is
 * 0.8° at 50 m, 4° at 10 m).
 *
 * A mount is a pose in the vehicle frame (ISO 8855: x forward, y left, z up, metres) with the
 * conventions of the scenario files' lamp poses (docs/scenarios.md): yaw about z, positive to
 * the left, then pitch, positive up. Its space is lamp space (docs/design.md §4): +z the axis,
 * +x right seen from behind, +y up.
 *
 * The camera's angles are type A in the camera's space (H = atan2(x, z) positive right,
 * V = atan2(y, hypot(x, z)) positive up), and an object's distance is the range from the
 * camera along the line of sight. A point at (h, v, distance) from the camera is placed in the
 * vehicle frame and seen from the lamp in the angle system of the lamp's LID grid.
 *
 * Thread-safety: pure functions.
 */
#ifndef HL_ECU_PARALLAX_H
#define HL_ECU_PARALLAX_H

#include "lamp/lid.h"

struct hl_ecu_mount {
	double pos_m[3]; /* vehicle frame */
	double yaw_deg; /* positive left */
	double pitch_deg; /* positive up */
};

/* The box of an object in one lamp's angles, degrees. */
struct hl_ecu_box {
	double h0_deg, h1_deg, v0_deg, v1_deg;
};

/* Vehicle-frame point at angles (type A, degrees) and range_m from the mount. */
void hl_ecu_mount_point(const struct hl_ecu_mount *m, double h_deg, double v_deg, double range_m,
			double ret_p[3]);
/* Angles (degrees) of vehicle-frame point p seen from the mount in angle system sys. */
void hl_ecu_mount_angles(const struct hl_ecu_mount *m, enum hl_angles sys, const double p[3],
			 double *ret_h_deg, double *ret_v_deg);

/*
 * The camera's box [h_left, h_right] x [v_bottom, v_top] at range_m, seen from lamp in system
 * sys: the bounding box of the box's four corners, its edges' midpoints and its centre, each
 * placed at range_m from the camera. range_m > 0.
 */
void hl_ecu_box_to_lamp(const struct hl_ecu_mount *camera, const struct hl_ecu_mount *lamp,
			enum hl_angles sys, double h_left_deg, double h_right_deg,
			double v_bottom_deg, double v_top_deg, double range_m,
			struct hl_ecu_box *ret);

#endif
