/* SPDX-License-Identifier: MIT */
#include "tools/import/resample.h"

#include <math.h>

static double grid_h(const struct hl_lid_grid *g, int col)
{
	return g->h_first_deg +
	       (double)col * ((double)g->h_last_deg - g->h_first_deg) / (g->width - 1);
}

static double grid_v(const struct hl_lid_grid *g, int row)
{
	return g->v_last_deg -
	       (double)row * ((double)g->v_last_deg - g->v_first_deg) / (g->height - 1);
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

	for (int row = 0; row < grid->height; row++) {
		for (int col = 0; col < grid->width; col++) {
			double p, q;

			hl_resample_sample_angles(grid, col, row, system, &p, &q);
			dense[(size_t)row * grid->width + col] = (float)hl_gonio_lookup(g, p, q);
		}
	}
}
