/* SPDX-License-Identifier: MIT */
/*
 * Where each light source of a lamp lights (docs/ecu.md, "Source windows"): the lit window of
 * source k is the bounding box, in the lamp's own angles (H, V, degrees, its LID grid's angle
 * system), of the grid samples where k at full current gives more than a set fraction of the
 * full high beam's intensity there:
 *
 *     L_k(H, V) > fraction * L_high(H, V),   L_high = sum_j i_high_j * L_j
 *
 * with the box's edges at the centres of the outermost such samples. Where the high beam is
 * dark (L_high = 0) any light of k counts. A source that lights nowhere has an empty window.
 * The glare-free high beam switches a source off when its window overlaps an object; a
 * fraction of 5 % ignores the faint skirts a source shares with its neighbours, which add
 * nothing a driver would notice next to the high beam and would otherwise widen every dark
 * tunnel by a neighbour or two.
 *
 * Thread-safety: computed once at start; the result is plain data.
 */
#ifndef HL_ECU_WINDOWS_H
#define HL_ECU_WINDOWS_H

#include <stdbool.h>

#include "lamp/lid.h"

#define HL_ECU_WINDOW_FRACTION 0.05 /* default: 5 % of the high beam */

struct hl_ecu_window {
	bool empty; /* the source lights no sample by the rule: never masked */
	double h0_deg, h1_deg; /* h0 <= h1 */
	double v0_deg, v1_deg; /* v0 <= v1 */
};

/*
 * The windows of every source of lid into ret (hl_lid_n_sources(lid) entries). i_high is the
 * high beam (n_sources relative currents in [0, 1]); fraction in (0, 1). 0, -EINVAL (a combined
 * lid, a fraction or current out of range), -ENOMEM. Allocates a scratch grid.
 */
int hl_ecu_windows(const struct hl_lid *lid, const float *i_high, double fraction,
		   struct hl_ecu_window *ret);

/* Whether window w overlaps the box [h0, h1] x [v0, v1] (degrees, closed intervals). */
bool hl_ecu_window_overlaps(const struct hl_ecu_window *w, double h0_deg, double h1_deg,
			    double v0_deg, double v1_deg);

#endif
