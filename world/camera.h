/* SPDX-License-Identifier: MIT */
/*
 * A pinhole camera in the vehicle frame (ISO 8855: x forward, y left, z up, metres), and the
 * pose of a lamp: where it sits and where it points, which defines lamp space (docs/design.md §4:
 * +z the optical axis, +x right seen from behind, +y up).
 *
 * Pixel (col, row): row 0 is the top of the image; pixel centres are at (col + 0.5, row + 0.5).
 * Plain values: any thread.
 */
#ifndef HL_WORLD_CAMERA_H
#define HL_WORLD_CAMERA_H

struct hl_camera {
	double pos_m[3];
	double dir[3]; /* viewing direction, need not be unit */
	double up[3]; /* roughly up; must not be parallel to dir */
	double fov_y_deg; /* vertical field of view */
	int width, height; /* pixels */
};

/* Orthonormal basis: right, up, forward (world frame). */
void hl_camera_basis(const struct hl_camera *cam, double ret_right[3], double ret_up[3],
		     double ret_fwd[3]);
/* Direction (not unit) of the ray through image point (x, y) in pixels, e.g. (col+0.5, row+0.5). */
void hl_camera_ray(const struct hl_camera *cam, double x, double y, double ret_dir[3]);
/* Image point of world point p; returns 0, or -EDOM when p is not in front of the camera. */
int hl_camera_project(const struct hl_camera *cam, const double p[3], double *ret_x, double *ret_y);
/*
 * The OpenEXR standard attributes, 4x4 row-major, row-vector convention (p' = p M, as Imath):
 * worldToCamera maps to a left-handed camera space (+x right, +y up, +z the viewing
 * direction); worldToNDC maps to NDC (x right, y down, (0,0) top-left and (1,1) bottom-right
 * of the display window) after division by w.
 */
void hl_camera_world_to_camera(const struct hl_camera *cam, float ret_m[16]);
void hl_camera_world_to_ndc(const struct hl_camera *cam, float ret_m[16]);

struct hl_lamp_pose {
	double pos_m[3]; /* vehicle frame */
	double yaw_deg; /* about the vehicle z axis, positive to the left (ISO 8855) */
	double pitch_deg; /* positive up; the default aim is 1 % down */
};

#define HL_LAMP_Y_M 0.7 /* default lateral offset of each lamp */
#define HL_LAMP_Z_M 0.65 /* default mounting height */

/* Default pose of side 0 (left: y +0.7 m) or 1 (right: y -0.7 m), x 0, z 0.65 m, aimed 1 % down. */
void hl_lamp_pose_default(int side, struct hl_lamp_pose *ret);
/* Lamp-space axes in the vehicle frame: x (right), y (up), z (optical axis). */
void hl_lamp_basis(const struct hl_lamp_pose *pose, double ret_x[3], double ret_y[3],
		   double ret_z[3]);
/* World point p into lamp space (metres, relative to the lamp). */
void hl_lamp_to_lamp_space(const struct hl_lamp_pose *pose, const double p[3], double ret[3]);

#endif
