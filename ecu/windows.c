/* SPDX-License-Identifier: MIT */
#include "ecu/windows.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>

#include "lamp/combine.h"

int hl_ecu_windows(const struct hl_lid *lid, const float *i_high, double fraction,
		   struct hl_ecu_window *ret)
{
	const struct hl_lid_grid *g = hl_lid_grid(lid);
	const int n = hl_lid_n_sources(lid);
	float *high;

	if (hl_lid_is_combined(lid) || !(fraction > 0.0 && fraction < 1.0))
		return -EINVAL;
	for (int k = 0; k < n; k++)
		if (!(i_high[k] >= 0.0f && i_high[k] <= 1.0f))
			return -EINVAL;
	high = malloc(sizeof(float) * (size_t)g->width * g->height);
	if (!high)
		return -ENOMEM;
	hl_combine_sparse(lid, i_high, high);
	for (int k = 0; k < n; k++) {
		struct hl_lid_box b;
		const float *s = hl_lid_source(lid, k, &b);
		const int bw = b.x1 - b.x0;
		int x_min = g->width, x_max = -1, y_min = g->height, y_max = -1;

		for (int y = b.y0; s && y < b.y1; y++) {
			for (int x = b.x0; x < b.x1; x++) {
				const float l = s[(size_t)(y - b.y0) * bw + (x - b.x0)];

				if (!(l > 0.0f) ||
				    !((double)l > fraction * high[(size_t)y * g->width + x]))
					continue;
				if (x < x_min)
					x_min = x;
				if (x > x_max)
					x_max = x;
				if (y < y_min)
					y_min = y;
				if (y > y_max)
					y_max = y;
			}
		}
		if (x_max < 0) {
			ret[k] = (struct hl_ecu_window){ .empty = true };
			continue;
		}
		/* row 0 is the highest V */
		ret[k] = (struct hl_ecu_window){
			.h0_deg = hl_lid_grid_h_deg(g, x_min),
			.h1_deg = hl_lid_grid_h_deg(g, x_max),
			.v0_deg = hl_lid_grid_v_deg(g, y_max),
			.v1_deg = hl_lid_grid_v_deg(g, y_min),
		};
	}
	free(high);
	return 0;
}

bool hl_ecu_window_overlaps(const struct hl_ecu_window *w, double h0_deg, double h1_deg,
			    double v0_deg, double v1_deg)
{
	return !w->empty && w->h0_deg <= h1_deg && h0_deg <= w->h1_deg && w->v0_deg <= v1_deg &&
	       v0_deg <= w->v1_deg;
}
