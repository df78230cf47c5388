/* SPDX-License-Identifier: MIT */
/*
 * Angle systems of docs/design.md §4. Lamp space: +z forward (optical axis), +x right seen
 * from behind the lamp, +y up. Angles in radians.
 *   type A (turn about the vertical axis, then elevate): H = atan2(x, z), V = atan2(y, hypot(x, z))
 *   type B (tilt about the horizontal axis, then turn):  V = atan2(y, z), H = atan2(x, hypot(y, z))
 */
#ifndef HL_RENDER_ANGLES_H
#define HL_RENDER_ANGLES_H

#include "lamp/lid.h"

/* (H, V) of direction d (need not be unit length, must not be zero). */
void hl_angles_from_dir(enum hl_angles system, const double d[3], double *ret_h_rad,
			double *ret_v_rad);
/* Unit direction of (H, V). */
void hl_angles_to_dir(enum hl_angles system, double h_rad, double v_rad, double ret_d[3]);

/*
 * Axes of a lamp or camera mounted with yaw (about the vehicle's z axis, positive to the left,
 * ISO 8855) then pitch (positive up), in the vehicle frame: x (right seen from behind), y (up,
 * tilted back by the pitch), z (optical axis). The lamp pose of world/camera.h and the ECU's
 * mounts (ecu/parallax.h) both use it.
 */
void hl_mount_basis(double yaw_deg, double pitch_deg, double ret_x[3], double ret_y[3],
		    double ret_z[3]);
/* Point p (vehicle frame) in the space of a mount at pos with that yaw and pitch. */
void hl_mount_to_local(const double pos_m[3], double yaw_deg, double pitch_deg, const double p[3],
		       double ret[3]);

#endif
