/* SPDX-License-Identifier: MIT */
/*
 * Independent computations for the ECU's tests (header-only): source windows from the dense
 * grids and a naive double-precision sum, and the camera-to-lamp geometry written out with
 * plain trigonometry for level, unturned or yawed mounts. The library's own code is never
 * called here.
 */
#ifndef HL_TESTS_ECU_NAIVE_H
#define HL_TESTS_ECU_NAIVE_H

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>

#include "ecu/windows.h"
#include "lamp/lid.h"

#define NAIVE_DEG (M_PI / 180.0)

/* Windows by the rule of ecu/windows.h from the dense grids. Returns 0, -1 without memory. */
static inline int naive_windows(const struct hl_lid *lid, const float *i_high, double fraction,
				struct hl_ecu_window *ret)
{
	const struct hl_lid_grid *g = hl_lid_grid(lid);
	const size_t ns = (size_t)g->width * g->height;
	const int n = hl_lid_n_sources(lid);
	float *dense = malloc(sizeof(float) * ns);
	double *high = calloc(ns, sizeof(double));

	if (!dense || !high) {
		free(dense);
		free(high);
		return -1;
	}
	for (int k = 0; k < n; k++) {
		hl_lid_source_dense(lid, k, dense);
		for (size_t s = 0; s < ns; s++)
			high[s] += (double)i_high[k] * dense[s];
	}
	for (int k = 0; k < n; k++) {
		double h0 = INFINITY, h1 = -INFINITY, v0 = INFINITY, v1 = -INFINITY;

		hl_lid_source_dense(lid, k, dense);
		for (int y = 0; y < g->height; y++) {
			for (int x = 0; x < g->width; x++) {
				const double l = dense[(size_t)y * g->width + x];
				/* the float sum the library compares with, to the last bit */
				const double hs = (float)high[(size_t)y * g->width + x];
				const double h = g->h_first_deg +
						 x * (double)(g->h_last_deg - g->h_first_deg) /
							 (g->width - 1);
				const double v = g->v_last_deg -
						 y * (double)(g->v_last_deg - g->v_first_deg) /
							 (g->height - 1);

				if (!(l > 0.0 && l > fraction * hs))
					continue;
				h0 = fmin(h0, h);
				h1 = fmax(h1, h);
				v0 = fmin(v0, v);
				v1 = fmax(v1, v);
			}
		}
		ret[k] = (struct hl_ecu_window){ .empty = !(h1 >= h0),
						 .h0_deg = h1 >= h0 ? h0 : 0,
						 .h1_deg = h1 >= h0 ? h1 : 0,
						 .v0_deg = h1 >= h0 ? v0 : 0,
						 .v1_deg = h1 >= h0 ? v1 : 0 };
	}
	free(dense);
	free(high);
	return 0;
}

/*
 * A point at camera angles (h, v, type A, degrees) and range r from a camera at c with yaw 0 and
 * pitch cam_pitch_deg, seen from a lamp at l turned by yaw_deg (left) and then pitch_deg (up),
 * type A angles (degrees).
 */
static inline void naive_parallax_pitched(const double c[3], double cam_pitch_deg, double h_deg,
					  double v_deg, double r, const double l[3], double yaw_deg,
					  double pitch_deg, double *ret_h, double *ret_v)
{
	/* direction in the camera's level frame: forward, left, up */
	const double f0 = cos(v_deg * NAIVE_DEG) * cos(h_deg * NAIVE_DEG);
	const double left = -cos(v_deg * NAIVE_DEG) * sin(h_deg * NAIVE_DEG);
	const double up0 = sin(v_deg * NAIVE_DEG);
	/* pitched: forward and up rotate about the left axis */
	const double p = cam_pitch_deg * NAIVE_DEG;
	const double fwd = f0 * cos(p) - up0 * sin(p);
	const double up = f0 * sin(p) + up0 * cos(p);
	const double dx = c[0] + r * fwd - l[0], dy = c[1] + r * left - l[1],
		     dz = c[2] + r * up - l[2];
	/* into the lamp: undo its yaw about z, then its pitch about its left axis */
	const double y = yaw_deg * NAIVE_DEG, q = pitch_deg * NAIVE_DEG;
	const double lf = dx * cos(y) + dy * sin(y), ll = -dx * sin(y) + dy * cos(y);
	const double lf2 = lf * cos(q) + dz * sin(q), lu = -lf * sin(q) + dz * cos(q);

	*ret_h = atan2(-ll, lf2) / NAIVE_DEG;
	*ret_v = atan2(lu, hypot(ll, lf2)) / NAIVE_DEG;
}

/* The same for a level lamp. */
static inline void naive_parallax(const double c[3], double pitch_deg, double h_deg, double v_deg,
				  double r, const double l[3], double yaw_deg, double *ret_h,
				  double *ret_v)
{
	naive_parallax_pitched(c, pitch_deg, h_deg, v_deg, r, l, yaw_deg, 0.0, ret_h, ret_v);
}

#endif
