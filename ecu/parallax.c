/* SPDX-License-Identifier: MIT */
#include "ecu/parallax.h"

#include <math.h>

#include "lamp/angles.h"

#define DEG (M_PI / 180.0)

void hl_ecu_mount_point(const struct hl_ecu_mount *m, double h_deg, double v_deg, double range_m,
			double ret_p[3])
{
	double x[3], y[3], z[3], d[3];

	hl_mount_basis(m->yaw_deg, m->pitch_deg, x, y, z);
	hl_angles_to_dir(HL_ANGLES_A, h_deg * DEG, v_deg * DEG, d);
	for (int i = 0; i < 3; i++)
		ret_p[i] = m->pos_m[i] + range_m * (d[0] * x[i] + d[1] * y[i] + d[2] * z[i]);
}

void hl_ecu_mount_angles(const struct hl_ecu_mount *m, enum hl_angles sys, const double p[3],
			 double *ret_h_deg, double *ret_v_deg)
{
	double d[3], h, v;

	hl_mount_to_local(m->pos_m, m->yaw_deg, m->pitch_deg, p, d);
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
