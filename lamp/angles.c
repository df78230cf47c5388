/* SPDX-License-Identifier: MIT */
#include "lamp/angles.h"

#include <math.h>

void hl_angles_from_dir(enum hl_angles system, const double d[3], double *ret_h_rad,
			double *ret_v_rad)
{
	if (system == HL_ANGLES_A) {
		*ret_h_rad = atan2(d[0], d[2]);
		*ret_v_rad = atan2(d[1], hypot(d[0], d[2]));
	} else {
		*ret_v_rad = atan2(d[1], d[2]);
		*ret_h_rad = atan2(d[0], hypot(d[1], d[2]));
	}
}

void hl_angles_to_dir(enum hl_angles system, double h_rad, double v_rad, double ret_d[3])
{
	if (system == HL_ANGLES_A) {
		ret_d[0] = cos(v_rad) * sin(h_rad);
		ret_d[1] = sin(v_rad);
		ret_d[2] = cos(v_rad) * cos(h_rad);
	} else {
		ret_d[0] = sin(h_rad);
		ret_d[1] = cos(h_rad) * sin(v_rad);
		ret_d[2] = cos(h_rad) * cos(v_rad);
	}
}

void hl_mount_basis(double yaw_deg, double pitch_deg, double x[3], double y[3], double z[3])
{
	const double deg = M_PI / 180.0;
	const double cy = cos(yaw_deg * deg), sy = sin(yaw_deg * deg);
	const double cp = cos(pitch_deg * deg), sp = sin(pitch_deg * deg);

	/* The optical axis after yaw then pitch; x is the vehicle's right (-y) turned by the yaw. */
	z[0] = cp * cy;
	z[1] = cp * sy;
	z[2] = sp;
	x[0] = sy;
	x[1] = -cy;
	x[2] = 0.0;
	/* y = x cross z */
	y[0] = x[1] * z[2] - x[2] * z[1];
	y[1] = x[2] * z[0] - x[0] * z[2];
	y[2] = x[0] * z[1] - x[1] * z[0];
}

void hl_mount_to_local(const double pos_m[3], double yaw_deg, double pitch_deg, const double p[3],
		       double ret[3])
{
	double x[3], y[3], z[3], d[3];

	hl_mount_basis(yaw_deg, pitch_deg, x, y, z);
	for (int i = 0; i < 3; i++)
		d[i] = p[i] - pos_m[i];
	ret[0] = d[0] * x[0] + d[1] * x[1] + d[2] * x[2];
	ret[1] = d[0] * y[0] + d[1] * y[1] + d[2] * y[2];
	ret[2] = d[0] * z[0] + d[1] * z[1] + d[2] * z[2];
}
