/* SPDX-License-Identifier: MIT */
#include "render/headlight.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "render/angles.h"

#define DEG (M_PI / 180.0)
#define WEIGHT_ONE 65535.0f /* bilinear weights are stored as 16-bit fractions */

/* One pixel lit by one lamp: 16 bytes, so a 1280 x 720 frame of two lamps reads ~30 MB. */
struct entry {
	uint32_t pixel; /* row * width + col */
	uint32_t cell; /* index of the cell's upper-left sample in the dense grid */
	uint16_t tx, ty; /* bilinear weights towards col + 1 and row + 1 */
	float g; /* cos(eps) / r^2, 1/m^2 */
};

struct lamp_terms {
	struct hl_headlight_lamp lamp;
	struct entry *entries;
	size_t n;
};

struct hl_headlight {
	int width, height;
	int n_lamps;
	struct lamp_terms lamps[HL_HEADLIGHT_MAX_LAMPS];
};

/*
 * Continuous sample coordinates of direction d (lamp space) on grid g; false outside the
 * measured range, where the lookup is zero.
 */
static bool sample_coords(const struct hl_lid_grid *g, const double d[3], double *fx, double *fy)
{
	double h, v;

	hl_angles_from_dir(g->angles, d, &h, &v);
	*fx = (h / DEG - g->h_first_deg) * (g->width - 1) /
	      ((double)g->h_last_deg - g->h_first_deg);
	*fy = ((double)g->v_last_deg - v / DEG) * (g->height - 1) /
	      ((double)g->v_last_deg - g->v_first_deg);
	return *fx >= 0.0 && *fx <= g->width - 1 && *fy >= 0.0 && *fy <= g->height - 1;
}

/* Lamp-space offset d of point p, distance squared and cos(eps) for normal n. */
static double geometry(const struct hl_lamp_pose *pose, const double p[3], const double n[3],
		       double d[3])
{
	double x[3], y[3], z[3], w[3], r2, cos_eps;

	hl_lamp_basis(pose, x, y, z);
	for (int i = 0; i < 3; i++)
		w[i] = p[i] - pose->pos_m[i];
	d[0] = w[0] * x[0] + w[1] * x[1] + w[2] * x[2];
	d[1] = w[0] * y[0] + w[1] * y[1] + w[2] * y[2];
	d[2] = w[0] * z[0] + w[1] * z[1] + w[2] * z[2];
	r2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
	if (!(r2 > 0.0))
		return 0.0;
	cos_eps = -(n[0] * w[0] + n[1] * w[1] + n[2] * w[2]) / sqrt(r2);
	return cos_eps > 0.0 ? cos_eps / r2 : 0.0;
}

static int precompute(const struct hl_gbuffer *gb, struct lamp_terms *lt)
{
	const struct hl_lid_grid *g = &lt->lamp.grid;
	const size_t npix = (size_t)gb->width * gb->height;
	struct entry *e;
	size_t n = 0;

	e = malloc(sizeof(*e) * (npix ? npix : 1));
	if (!e)
		return -ENOMEM;
	for (size_t i = 0; i < npix; i++) {
		const float *pf = gb->pos + 4 * i, *nf = gb->nrm + 4 * i;
		const double p[3] = { pf[0], pf[1], pf[2] }, nn[3] = { nf[0], nf[1], nf[2] };
		double d[3], fx, fy, geo;
		int x0, y0;

		if (nf[3] == (float)HL_SURF_NONE)
			continue;
		geo = geometry(&lt->lamp.pose, p, nn, d);
		if (geo == 0.0 || !sample_coords(g, d, &fx, &fy))
			continue;
		x0 = (int)fx;
		y0 = (int)fy;
		if (x0 > g->width - 2)
			x0 = g->width - 2;
		if (y0 > g->height - 2)
			y0 = g->height - 2;
		e[n++] = (struct entry){
			.pixel = (uint32_t)i,
			.cell = (uint32_t)((size_t)y0 * g->width + x0),
			.tx = (uint16_t)lrint((fx - x0) * WEIGHT_ONE),
			.ty = (uint16_t)lrint((fy - y0) * WEIGHT_ONE),
			.g = (float)geo,
		};
	}
	lt->entries = n ? realloc(e, sizeof(*e) * n) : e;
	if (!lt->entries)
		lt->entries = e;
	lt->n = n;
	return 0;
}

int hl_headlight_new(const struct hl_gbuffer *gb, int n_lamps,
		     const struct hl_headlight_lamp *lamps, struct hl_headlight **ret)
{
	struct hl_headlight *h;
	int rc;

	if (n_lamps < 1 || n_lamps > HL_HEADLIGHT_MAX_LAMPS)
		return -EINVAL;
	for (int k = 0; k < n_lamps; k++)
		if (hl_lid_grid_check(&lamps[k].grid) < 0)
			return -EINVAL;
	h = calloc(1, sizeof(*h));
	if (!h)
		return -ENOMEM;
	h->width = gb->width;
	h->height = gb->height;
	h->n_lamps = n_lamps;
	for (int k = 0; k < n_lamps; k++) {
		h->lamps[k].lamp = lamps[k];
		rc = precompute(gb, &h->lamps[k]);
		if (rc < 0) {
			hl_headlight_free(h);
			return rc;
		}
	}
	*ret = h;
	return 0;
}

void hl_headlight_free(struct hl_headlight *h)
{
	if (!h)
		return;
	for (int k = 0; k < h->n_lamps; k++)
		free(h->lamps[k].entries);
	free(h);
}

static void add_lamp(const struct lamp_terms *lt, const float *restrict dense, float *restrict lux)
{
	const size_t w = (size_t)lt->lamp.grid.width;
	const float scale = 1.0f / WEIGHT_ONE;

	for (size_t i = 0; i < lt->n; i++) {
		const struct entry *e = &lt->entries[i];
		const float *s = dense + e->cell;
		const float tx = e->tx * scale, ty = e->ty * scale;
		const float top = s[0] + tx * (s[1] - s[0]);
		const float bottom = s[w] + tx * (s[w + 1] - s[w]);

		lux[e->pixel] += e->g * (top + ty * (bottom - top));
	}
}

void hl_headlight_run(const struct hl_headlight *h, const float *const *dense, float *lux)
{
	memset(lux, 0, sizeof(float) * (size_t)h->width * h->height);
	for (int k = 0; k < h->n_lamps; k++)
		if (dense[k])
			add_lamp(&h->lamps[k], dense[k], lux);
}

size_t hl_headlight_work(const struct hl_headlight *h)
{
	size_t n = 0;

	for (int k = 0; k < h->n_lamps; k++)
		n += h->lamps[k].n;
	return n;
}

double hl_headlight_point(const struct hl_headlight_lamp *lamp, const float *dense,
			  const double p[3], const double n[3])
{
	const struct hl_lid_grid *g = &lamp->grid;
	double d[3], fx, fy, geo, tx, ty;
	int x0, y0;

	geo = geometry(&lamp->pose, p, n, d);
	if (geo == 0.0 || !sample_coords(g, d, &fx, &fy))
		return 0.0;
	x0 = fx > g->width - 2 ? g->width - 2 : (int)fx;
	y0 = fy > g->height - 2 ? g->height - 2 : (int)fy;
	tx = fx - x0;
	ty = fy - y0;
	{
		const float *s = dense + (size_t)y0 * g->width + x0;
		const double top = s[0] * (1 - tx) + s[1] * tx;
		const double bottom = s[g->width] * (1 - tx) + s[g->width + 1] * tx;

		return geo * (top * (1 - ty) + bottom * ty);
	}
}
