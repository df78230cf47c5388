/* SPDX-License-Identifier: MIT */
/*
 * The regulation aim's cut-off (verdict/verdict.h, hl_verdict_find_cutoff): the inflection point
 * of log I on a vertical scan, as R149 finds the cut-off's horizontal part.
 */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "lamp/angles.h"
#include "verdict/verdict.h"

#define SCAN_LO_DEG (-5.0) /* the cut-off scan, upward */
#define SCAN_HI_DEG 3.0
#define SCAN_STEP_DEG 0.05 /* R149 Annex: steps not exceeding 0.05° */
#define G_DELTA_DEG 0.1 /* G = log E(b) - log E(b + 0.1°) */
#define SCAN_FLOOR 1e-4 /* values below this share of the scan's peak count as this */

/*
 * The inflection point of log I on a vertical scan at h: the largest
 * G = log10 E(b) - log10 E(b + 0.1°), b every 0.05° upward, at b + 0.05° (the middle of the
 * steepest 0.1°), refined by a parabola through G's neighbours.
 */
static int scan(const struct hl_regulation *reg, const struct hl_lid_grid *grid, const float *dense,
		double h, double *ret_v, double *ret_g)
{
	enum { N = (int)((SCAN_HI_DEG - SCAN_LO_DEG) / SCAN_STEP_DEG) + 1 };
	const int d = (int)lround(G_DELTA_DEG / SCAN_STEP_DEG);
	double e[N], peak = 0.0, best = 0.0;
	int at = -1;

	const double half = reg->receiver_deg / 2;
	bool ok[N];

	/* only where the whole receiver is on the grid: beyond its edge the lookup is zero */
	for (int k = 0; k < N; k++) {
		const double v = SCAN_LO_DEG + k * SCAN_STEP_DEG;

		ok[k] = v - half >= grid->v_first_deg - 1e-6 && v + half <= grid->v_last_deg + 1e-6;
		e[k] = ok[k] ? hl_verdict_receiver_mean(grid, dense, reg->receiver,
							reg->receiver_deg, h, v) :
			       0.0;
		peak = fmax(peak, e[k]);
	}
	if (!(peak > 0.0))
		return -ENOENT;
	for (int k = 0; k < N; k++)
		e[k] = log10(fmax(e[k], peak * SCAN_FLOOR));
	for (int k = 0; k + d < N; k++)
		if (ok[k] && ok[k + d] && e[k] - e[k + d] > best) {
			best = e[k] - e[k + d];
			at = k;
		}
	if (at < 0)
		return -ENOENT;
	double off = 0.0;

	if (at > 0 && at + 1 + d < N && ok[at - 1] && ok[at + 1 + d]) {
		const double gm = e[at - 1] - e[at - 1 + d], gp = e[at + 1] - e[at + 1 + d];
		const double den = gm - 2 * best + gp;

		if (den < 0.0)
			off = fmax(-0.5, fmin(0.5, 0.5 * (gm - gp) / den));
	}
	*ret_v = SCAN_LO_DEG + (at + off) * SCAN_STEP_DEG + G_DELTA_DEG / 2;
	*ret_g = best;
	return 0;
}

int hl_verdict_find_cutoff(const struct hl_regulation *reg, const struct hl_lid_grid *grid,
			   const float *dense, enum hl_traffic traffic, struct hl_cutoff *ret)
{
	const double sign = traffic == HL_TRAFFIC_LEFT ? -1.0 : 1.0;
	const double hs[3] = { reg->aim_scan_h_deg, reg->aim_linearity_h_deg[0],
			       reg->aim_linearity_h_deg[1] };
	double g, lo = INFINITY, hi = -INFINITY;
	int rc;

	if (reg->aim != HL_REG_AIM_CUTOFF)
		return -EINVAL;
	for (int k = 0; k < 3; k++) {
		rc = scan(reg, grid, dense, sign * hs[k], &ret->v_lin_deg[k], &g);
		if (rc < 0)
			return rc;
		if (k == 0) {
			ret->v_deg = ret->v_lin_deg[0];
			ret->g = g;
		}
		lo = fmin(lo, ret->v_lin_deg[k]);
		hi = fmax(hi, ret->v_lin_deg[k]);
	}
	ret->linearity_deg = hi - lo;
	ret->sharp_ok = ret->g >= reg->aim_g_min && ret->g <= reg->aim_g_max;
	ret->linear_ok = ret->linearity_deg <= reg->aim_linearity_max_deg;
	return 0;
}
