/* SPDX-License-Identifier: MIT */
/*
 * A photometer (docs/lab.md, "How a bin is judged"): a point with a plane normal on a road user (or
 * anywhere in the world), measuring the illuminance the ego vehicle's two lamps give on its
 * plane, E = sum_l I_l cos(theta_l) / r_l^2, where I_l is the lamp's intensity toward the point
 * (a point lookup of its distribution, bilinear as hl_lid_grid_lookup(), negative rounding
 * residues of an incremental combination taken as 0), r_l the distance and
 * theta_l the angle between the light's direction of travel and the plane's inward normal (the
 * normal points out of the receiving face, toward where the light comes from: light arriving
 * from behind the plane counts 0). An eye (verdict/glare.h) is the special case of a plane
 * facing each lamp (cos theta = 1).
 *
 * Range: the horizontal straight-line distance from the midpoint of the ego's two lamps to the
 * photometer (the distance verdict/glare.h uses for the eye; docs/lab.md says why).
 *
 * Thread-safety: pure functions of their arguments; they allocate nothing.
 */
#ifndef HL_VERDICT_PHOTOMETER_H
#define HL_VERDICT_PHOTOMETER_H

#include "lamp/lid.h"
#include "world/camera.h"
#include "world/road.h"

struct hl_photometer_reading {
	double point_m[3], normal[3]; /* world */
	double r_m[2]; /* from each lamp (left, right) */
	double h_deg[2], v_deg[2]; /* the point in each lamp's angle system */
	double intensity_cd[2]; /* toward the point */
	double cos_theta[2]; /* clamped at 0 */
	double illuminance_lx; /* on the plane, both lamps */
	double range_m; /* horizontal, the lamps' midpoint to the point */
};

/* A point and a normal given in a body's frame (ISO 8855) in the world. */
void hl_photometer_place(const struct hl_body_pose *pose, const double pos_m[3],
			 const double normal[3], double ret_point[3], double ret_normal[3]);

/*
 * The reading at a world point with a world normal (unit length) under two lamps at lamps[]
 * (world poses, hl_world_ego_lamps()) on grids[] with distributions dense[] (cd). Returns the
 * illuminance (lx), also in ret.
 */
double hl_photometer_read(const struct hl_lamp_pose lamps[2],
			  const struct hl_lid_grid *const grids[2], const float *const dense[2],
			  const double point_m[3], const double normal[3],
			  struct hl_photometer_reading *ret);

#endif
