/* SPDX-License-Identifier: MIT */
/*
 * The verdict's H-V isocandela diagram (docs/verdicts.md): the distribution as it was evaluated
 * (aim and traffic applied) around the set's test points, isocandela lines at fixed levels over
 * a dimmed log colour map, and every requirement drawn where it is measured — points, segments,
 * zones, the points of sums, Imax — green when it passes, red with its value and limit when it
 * fails. Written as an RGB PNG.
 */
#ifndef HL_RENDER_VERDICT_PLOT_H
#define HL_RENDER_VERDICT_PLOT_H

#include "verdict/verdict.h"

/*
 * dense: the distribution on grid (cd) as mounted; results: reg->n_requirements results of
 * hl_verdict_eval() with the same opts. 0, -ENOMEM, -EIO, -errno.
 */
int hl_plot_verdict_png(const struct hl_lid_grid *grid, const float *dense,
			const struct hl_regulation *reg, const struct hl_verdict_options *opts,
			const struct hl_req_result *results, const char *title, const char *path);

#endif
