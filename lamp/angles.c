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
