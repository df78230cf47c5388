/* SPDX-License-Identifier: MIT */
/* A photometer on a plane: see verdict/photometer.h. */
#include "verdict/photometer.h"

#include <math.h>
#include <string.h>

#include "lamp/angles.h"

#define DEG (180.0 / M_PI)

void hl_photometer_place(const struct hl_body_pose *pose, const double pos_m[3],
			 const double normal[3], double ret_point[3], double ret_normal[3])
{
	const double c = cos(pose->heading_rad), s = sin(pose->heading_rad);

	hl_body_to_world(pose, pos_m, ret_point);
	ret_normal[0] = c * normal[0] - s * normal[1];
	ret_normal[1] = s * normal[0] + c * normal[1];
	ret_normal[2] = normal[2];
}

double hl_photometer_read(const struct hl_lamp_pose lamps[2],
			  const struct hl_lid_grid *const grids[2], const float *const dense[2],
			  const double point_m[3], const double normal[3],
			  struct hl_photometer_reading *ret)
{
	double mid[2];

	memset(ret, 0, sizeof(*ret));
	memcpy(ret->point_m, point_m, sizeof(ret->point_m));
	memcpy(ret->normal, normal, sizeof(ret->normal));
	for (int l = 0; l < 2; l++) {
		double p[3], d[3], h, v, r, c;

		hl_lamp_to_lamp_space(&lamps[l], point_m, p);
		r = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
		ret->r_m[l] = r;
		hl_angles_from_dir(grids[l]->angles, p, &h, &v);
		ret->h_deg[l] = h * DEG;
		ret->v_deg[l] = v * DEG;
		ret->intensity_cd[l] = hl_lid_grid_lookup(grids[l], dense[l], (float)ret->h_deg[l],
							  (float)ret->v_deg[l]);
		/* an incrementally combined distribution (lamp/combine.h) can hold -1e-9 cd where every
		 * source is off: rounding, not light */
		if (ret->intensity_cd[l] < 0.0)
			ret->intensity_cd[l] = 0.0;
		/* the light travels from the lamp to the point (world frame); the normal faces it */
		for (int k = 0; k < 3; k++)
			d[k] = r > 0.0 ? (point_m[k] - lamps[l].pos_m[k]) / r : 0.0;
		c = -(d[0] * normal[0] + d[1] * normal[1] + d[2] * normal[2]);
		ret->cos_theta[l] = c > 0.0 ? c : 0.0;
		if (r > 0.0)
			ret->illuminance_lx += ret->intensity_cd[l] * ret->cos_theta[l] / (r * r);
	}
	mid[0] = 0.5 * (lamps[0].pos_m[0] + lamps[1].pos_m[0]);
	mid[1] = 0.5 * (lamps[0].pos_m[1] + lamps[1].pos_m[1]);
	ret->range_m = hypot(point_m[0] - mid[0], point_m[1] - mid[1]);
	return ret->illuminance_lx;
}
