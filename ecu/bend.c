/* SPDX-License-Identifier: MIT */
#include "ecu/bend.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define DEG (M_PI / 180.0)
#define ROW_V_TOL_DEG 0.5 /* a row's windows share their V extent within this */
#define ROW_W_RATIO 1.5 /* and their H widths within this factor */
#define ROW_MIN 3 /* sources in a row at least */

struct hl_ecu_rows {
	int n; /* sources */
	int n_rows;
	int *start; /* row i is order[start[i] .. start[i + 1]) */
	int *order; /* sources by row, then by H centre */
	double *centre_deg; /* H centre of each source's window, by source */
	int bend_left, bend_right; /* sources, -1: none */
};

void hl_ecu_bend_default(struct hl_ecu_bend_config *ret)
{
	*ret = (struct hl_ecu_bend_config){
		.preview_s = 2.0,
		.preview_min_m = 10.0,
		.preview_max_m = 60.0,
		.max_deg = 15.0,
		.min_speed_mps = 10.0 / 3.6,
	};
}

double hl_ecu_bend_swivel_deg(const struct hl_ecu_bend_config *c, double speed_mps,
			      double yaw_rate_rad_s)
{
	double d, s, a;

	if (!(speed_mps >= c->min_speed_mps) || speed_mps <= 0.0 || yaw_rate_rad_s == 0.0 ||
	    !isfinite(yaw_rate_rad_s))
		return 0.0;
	d = fmin(fmax(speed_mps * c->preview_s, c->preview_min_m), c->preview_max_m);
	s = fmin(1.0, d * fabs(yaw_rate_rad_s) / (2.0 * speed_mps));
	a = fmin(c->max_deg, asin(s) / DEG);
	return yaw_rate_rad_s > 0.0 ? a : -a;
}

static int by_centre(const void *a, const void *b, void *centre)
{
	const double ca = ((const double *)centre)[*(const int *)a];
	const double cb = ((const double *)centre)[*(const int *)b];

	return ca < cb ? -1 : ca > cb ? 1 : 0;
}

static bool same_row(const struct hl_ecu_window *a, const struct hl_ecu_window *b)
{
	const double wa = a->h1_deg - a->h0_deg, wb = b->h1_deg - b->h0_deg;

	return !a->empty && !b->empty && fabs(a->v0_deg - b->v0_deg) <= ROW_V_TOL_DEG &&
	       fabs(a->v1_deg - b->v1_deg) <= ROW_V_TOL_DEG && wa <= ROW_W_RATIO * wb &&
	       wb <= ROW_W_RATIO * wa;
}

int hl_ecu_rows_new(const struct hl_ecu_window *w, const char *const *names, int n,
		    struct hl_ecu_rows **ret)
{
	struct hl_ecu_rows *r = calloc(1, sizeof(*r));
	bool *used = calloc((size_t)n + 1, sizeof(bool));
	int *members = malloc(sizeof(int) * ((size_t)n + 1));
	int filled = 0;

	if (!r || !used || !members)
		goto err;
	r->n = n;
	r->start = malloc(sizeof(int) * ((size_t)n + 1));
	r->order = malloc(sizeof(int) * ((size_t)n + 1));
	r->centre_deg = malloc(sizeof(double) * ((size_t)n + 1));
	if (!r->start || !r->order || !r->centre_deg)
		goto err;
	r->bend_left = r->bend_right = -1;
	for (int k = 0; k < n; k++) {
		r->centre_deg[k] = (w[k].h0_deg + w[k].h1_deg) / 2;
		if (names && names[k] && strcmp(names[k], "bend_left") == 0)
			r->bend_left = k;
		if (names && names[k] && strcmp(names[k], "bend_right") == 0)
			r->bend_right = k;
	}
	for (int k = 0; k < n; k++) {
		int m = 0;

		if (used[k] || w[k].empty)
			continue;
		for (int j = k; j < n; j++)
			if (!used[j] && same_row(&w[k], &w[j]))
				members[m++] = j;
		if (m < ROW_MIN)
			continue;
		for (int i = 0; i < m; i++)
			used[members[i]] = true;
		qsort_r(members, (size_t)m, sizeof(int), by_centre, r->centre_deg);
		r->start[r->n_rows++] = filled;
		memcpy(r->order + filled, members, sizeof(int) * (size_t)m);
		filled += m;
	}
	r->start[r->n_rows] = filled;
	free(used);
	free(members);
	*ret = r;
	return 0;

err:
	free(used);
	free(members);
	hl_ecu_rows_free(r);
	return -ENOMEM;
}

void hl_ecu_rows_free(struct hl_ecu_rows *r)
{
	if (!r)
		return;
	free(r->start);
	free(r->order);
	free(r->centre_deg);
	free(r);
}

int hl_ecu_rows_count(const struct hl_ecu_rows *r)
{
	return r->n_rows;
}

const int *hl_ecu_rows_row(const struct hl_ecu_rows *r, int i, int *ret_n)
{
	*ret_n = r->start[i + 1] - r->start[i];
	return r->order + r->start[i];
}

/* The unturned row's value at H q: linear between the centres, the end values beyond. */
static float row_value(const struct hl_ecu_rows *r, const int *row, int m, const float *in,
		       double q)
{
	if (q <= r->centre_deg[row[0]])
		return in[row[0]];
	for (int i = 1; i < m; i++) {
		const double c0 = r->centre_deg[row[i - 1]], c1 = r->centre_deg[row[i]];

		if (q <= c1) {
			const double t = c1 > c0 ? (q - c0) / (c1 - c0) : 1.0;

			return (float)((1.0 - t) * in[row[i - 1]] + t * in[row[i]]);
		}
	}
	return in[row[m - 1]];
}

void hl_ecu_rows_turn(const struct hl_ecu_rows *r, const float *in, double swivel_deg,
		      double max_deg, float *out)
{
	memcpy(out, in, sizeof(float) * (size_t)r->n);
	if (swivel_deg == 0.0)
		return;
	for (int i = 0; i < r->n_rows; i++) {
		int m;
		const int *row = hl_ecu_rows_row(r, i, &m);

		/* a left swivel (positive) moves the pattern to negative H: source k shows what
		 * the unturned row has swivel degrees to its right */
		for (int j = 0; j < m; j++)
			out[row[j]] = row_value(r, row, m, in, r->centre_deg[row[j]] + swivel_deg);
	}
	{
		const int b = swivel_deg > 0.0 ? r->bend_left : r->bend_right;
		const float f = (float)fmin(1.0, fabs(swivel_deg) / max_deg);

		if (b >= 0 && f > out[b])
			out[b] = f;
	}
}
