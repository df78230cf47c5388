/* SPDX-License-Identifier: MIT */
#include "import/resample.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static double nominal(float f)
{
	char buf[32];

	for (int digits = 1; digits <= 9; digits++) {
		snprintf(buf, sizeof(buf), "%.*g", digits, (double)f);
		if (strtof(buf, NULL) == f)
			return strtod(buf, NULL);
	}
	return f;
}

void hl_resample_grid_ends(const struct hl_lid_grid *g, double *ret_h_first, double *ret_h_last,
			   double *ret_v_first, double *ret_v_last)
{
	*ret_h_first = nominal(g->h_first_deg);
	*ret_h_last = nominal(g->h_last_deg);
	*ret_v_first = nominal(g->v_first_deg);
	*ret_v_last = nominal(g->v_last_deg);
}

static double grid_h(const struct hl_lid_grid *g, int col)
{
	double h0, h1, v0, v1;

	hl_resample_grid_ends(g, &h0, &h1, &v0, &v1);
	return h0 + (double)col * (h1 - h0) / (g->width - 1);
}

static double grid_v(const struct hl_lid_grid *g, int row)
{
	double h0, h1, v0, v1;

	hl_resample_grid_ends(g, &h0, &h1, &v0, &v1);
	return v1 - (double)row * (v1 - v0) / (g->height - 1);
}

void hl_resample_sample_angles(const struct hl_lid_grid *grid, int col, int row,
			       enum hl_gonio_system system, double *ret_plane_deg,
			       double *ret_in_deg)
{
	const enum hl_gonio_system own = grid->angles == HL_ANGLES_A ? HL_GONIO_A : HL_GONIO_B;
	const double h = grid_h(grid, col), v = grid_v(grid, row);
	double d[3];

	if (system == own) {
		/* same system: no round trip through trigonometry */
		*ret_plane_deg = h;
		*ret_in_deg = v;
		return;
	}
	hl_gonio_angles_to_dir(own, h, v, d);
	hl_gonio_angles_from_dir(system, d, ret_plane_deg, ret_in_deg);
}

void hl_resample(const struct hl_gonio *g, const struct hl_lid_grid *grid, float *dense)
{
	const enum hl_gonio_system system = hl_gonio_system(g);
	const enum hl_gonio_system own = grid->angles == HL_ANGLES_A ? HL_GONIO_A : HL_GONIO_B;
	double h0, h1, v0, v1;

	hl_resample_grid_ends(grid, &h0, &h1, &v0, &v1);
	for (int row = 0; row < grid->height; row++) {
		const double v = v1 - (double)row * (v1 - v0) / (grid->height - 1);

		for (int col = 0; col < grid->width; col++) {
			double p = h0 + (double)col * (h1 - h0) / (grid->width - 1), q = v, d[3];

			if (system != own) {
				hl_gonio_angles_to_dir(own, p, q, d);
				hl_gonio_angles_from_dir(system, d, &p, &q);
			}
			dense[(size_t)row * grid->width + col] = (float)hl_gonio_lookup(g, p, q);
		}
	}
}
