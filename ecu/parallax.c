/* SPDX-License-Identifier: MIT */
#include "ecu/parallax.h"

#include <math.h>

#include "lamp/angles.h"

#define DEG (M_PI / 180.0)

/* The mount's axes in the vehicle frame: x (right), y (up), z (forward). */
static void basis(const struct hl_ecu_mount *m, double x[3], double y[3], double z[3])
{
	const double cy = cos(m->yaw_deg * DEG), sy = sin(m->yaw_deg * DEG);
	const double cp = cos(m->pitch_deg * DEG), sp = sin(m->pitch_deg * DEG);

	z[0] = cp * cy;
	z[1] = cp * sy;
	z[2] = sp;
	x[0] = sy;
	x[1] = -cy;
	x[2] = 0.0;
	/* y = x cross z: up, tilted back by the pitch */
	y[0] = x[1] * z[2] - x[2] * z[1];
	y[1] = x[2] * z[0] - x[0] * z[2];
	y[2] = x[0] * z[1] - x[1] * z[0];
}

void hl_ecu_mount_point(const struct hl_ecu_mount *m, double h_deg, double v_deg, double range_m,
			double ret_p[3])
{
	double x[3], y[3], z[3], d[3];

	basis(m, x, y, z);
	hl_angles_to_dir(HL_ANGLES_A, h_deg * DEG, v_deg * DEG, d);
	for (int i = 0; i < 3; i++)
		ret_p[i] = m->pos_m[i] + range_m * (d[0] * x[i] + d[1] * y[i] + d[2] * z[i]);
}

void hl_ecu_mount_angles(const struct hl_ecu_mount *m, enum hl_angles sys, const double p[3],
			 double *ret_h_deg, double *ret_v_deg)
{
	double x[3], y[3], z[3], r[3], d[3], h, v;

	basis(m, x, y, z);
	for (int i = 0; i < 3; i++)
		r[i] = p[i] - m->pos_m[i];
	d[0] = r[0] * x[0] + r[1] * x[1] + r[2] * x[2];
	d[1] = r[0] * y[0] + r[1] * y[1] + r[2] * y[2];
	d[2] = r[0] * z[0] + r[1] * z[1] + r[2] * z[2];
	hl_angles_from_dir(sys, d, &h, &v);
	*ret_h_deg = h / DEG;
	*ret_v_deg = v / DEG;
}

void hl_ecu_box_to_lamp(const struct hl_ecu_mount *camera, const struct hl_ecu_mount *lamp,
			enum hl_angles sys, double h_left_deg, double h_right_deg,
			double v_bottom_deg, double v_top_deg, double range_m,
			struct hl_ecu_box *ret)
{
	const double hs[3] = { h_left_deg, (h_left_deg + h_right_deg) / 2, h_right_deg };
	const double vs[3] = { v_bottom_deg, (v_bottom_deg + v_top_deg) / 2, v_top_deg };

	*ret = (struct hl_ecu_box){ INFINITY, -INFINITY, INFINITY, -INFINITY };
	for (int i = 0; i < 3; i++) {
		for (int j = 0; j < 3; j++) {
			double p[3], h, v;

			hl_ecu_mount_point(camera, hs[i], vs[j], range_m, p);
			hl_ecu_mount_angles(lamp, sys, p, &h, &v);
			ret->h0_deg = fmin(ret->h0_deg, h);
			ret->h1_deg = fmax(ret->h1_deg, h);
			ret->v0_deg = fmin(ret->v0_deg, v);
			ret->v1_deg = fmax(ret->v1_deg, v);
		}
	}
}
