/* SPDX-License-Identifier: MIT */
#include "lamp/lid.h"
#include "lamp/lid_internal.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

struct hl_lid {
	struct hl_lid_grid grid;
	int n_sources;
	bool combined;
	struct hl_lid_box *boxes;
	float **data; /* per source, box-packed, NULL when the box is empty */
	float *peaks_cd;
	char **names;
};

int hl_lid_grid_check(const struct hl_lid_grid *g)
{
	if (g->width < 2 || g->height < 2 || g->width > 65536 || g->height > 65536)
		return -EINVAL;
	if (g->angles != HL_ANGLES_A && g->angles != HL_ANGLES_B)
		return -EINVAL;
	if (!isfinite(g->h_first_deg) || !isfinite(g->h_last_deg) || !isfinite(g->v_first_deg) ||
	    !isfinite(g->v_last_deg))
		return -EINVAL;
	if (!(g->h_first_deg < g->h_last_deg) || !(g->v_first_deg < g->v_last_deg))
		return -EINVAL;
	if (g->h_first_deg < -180.0f || g->h_last_deg > 180.0f || g->v_first_deg < -90.0f ||
	    g->v_last_deg > 90.0f)
		return -EINVAL;
	return 0;
}

int hl_lid_new(int n_sources, const struct hl_lid_grid *grid, bool combined, struct hl_lid **ret)
{
	struct hl_lid *lid;

	if (n_sources < 1 || n_sources > HL_LID_MAX_SOURCES || (combined && n_sources != 1))
		return -EINVAL;
	if (hl_lid_grid_check(grid) < 0)
		return -EINVAL;

	lid = calloc(1, sizeof(*lid));
	if (!lid)
		return -ENOMEM;
	lid->grid = *grid;
	lid->n_sources = n_sources;
	lid->combined = combined;
	lid->boxes = calloc(n_sources, sizeof(*lid->boxes));
	lid->data = calloc(n_sources, sizeof(*lid->data));
	lid->peaks_cd = calloc(n_sources, sizeof(*lid->peaks_cd));
	lid->names = calloc(n_sources, sizeof(*lid->names));
	if (!lid->boxes || !lid->data || !lid->peaks_cd || !lid->names) {
		hl_lid_free(lid);
		return -ENOMEM;
	}
	*ret = lid;
	return 0;
}

void hl_lid_free(struct hl_lid *lid)
{
	if (!lid)
		return;
	for (int k = 0; k < lid->n_sources; k++) {
		if (lid->data)
			free(lid->data[k]);
		if (lid->names)
			free(lid->names[k]);
	}
	free(lid->boxes);
	free(lid->data);
	free(lid->peaks_cd);
	free(lid->names);
	free(lid);
}

int hl_lid_set_source(struct hl_lid *lid, int k, const float *dense)
{
	const int w = lid->grid.width, h = lid->grid.height;
	struct hl_lid_box box = { w, h, 0, 0 };
	float peak = 0.0f, *packed = NULL;

	if (k < 0 || k >= lid->n_sources)
		return -EINVAL;
	for (int y = 0; y < h; y++) {
		for (int x = 0; x < w; x++) {
			float s = dense[(size_t)y * w + x];

			if (!isfinite(s) || s < 0.0f)
				return -EINVAL;
			if (s == 0.0f)
				continue;
			if (x < box.x0)
				box.x0 = x;
			if (x >= box.x1)
				box.x1 = x + 1;
			if (y < box.y0)
				box.y0 = y;
			if (y >= box.y1)
				box.y1 = y + 1;
			if (s > peak)
				peak = s;
		}
	}
	if (box.x1 == 0) {
		box = (struct hl_lid_box){ 0, 0, 0, 0 };
	} else {
		int bw = box.x1 - box.x0;

		packed = malloc(sizeof(float) * (size_t)bw * (box.y1 - box.y0));
		if (!packed)
			return -ENOMEM;
		for (int y = box.y0; y < box.y1; y++)
			memcpy(packed + (size_t)(y - box.y0) * bw, dense + (size_t)y * w + box.x0,
			       sizeof(float) * bw);
	}
	free(lid->data[k]);
	lid->data[k] = packed;
	lid->boxes[k] = box;
	lid->peaks_cd[k] = peak;
	return 0;
}

int hl_lid_set_name(struct hl_lid *lid, int k, const char *name)
{
	char *copy = NULL;

	if (k < 0 || k >= lid->n_sources)
		return -EINVAL;
	if (name) {
		if (strchr(name, '\n'))
			return -EINVAL;
		copy = strdup(name);
		if (!copy)
			return -ENOMEM;
	}
	free(lid->names[k]);
	lid->names[k] = copy;
	return 0;
}

const struct hl_lid_grid *hl_lid_grid(const struct hl_lid *lid)
{
	return &lid->grid;
}

int hl_lid_n_sources(const struct hl_lid *lid)
{
	return lid->n_sources;
}

bool hl_lid_is_combined(const struct hl_lid *lid)
{
	return lid->combined;
}

const char *hl_lid_name(const struct hl_lid *lid, int k)
{
	return (k >= 0 && k < lid->n_sources) ? lid->names[k] : NULL;
}

const float *hl_lid_source(const struct hl_lid *lid, int k, struct hl_lid_box *ret_box)
{
	*ret_box = lid->boxes[k];
	return lid->data[k];
}

float hl_lid_peak_cd(const struct hl_lid *lid, int k)
{
	return lid->peaks_cd[k];
}

void hl_lid_source_dense(const struct hl_lid *lid, int k, float *out)
{
	const int w = lid->grid.width;
	const struct hl_lid_box *b = &lid->boxes[k];
	const int bw = b->x1 - b->x0;

	memset(out, 0, sizeof(float) * (size_t)w * lid->grid.height);
	for (int y = b->y0; y < b->y1; y++)
		memcpy(out + (size_t)y * w + b->x0, lid->data[k] + (size_t)(y - b->y0) * bw,
		       sizeof(float) * bw);
}

float hl_lid_grid_h_deg(const struct hl_lid_grid *g, int col)
{
	return g->h_first_deg + (float)col * (g->h_last_deg - g->h_first_deg) / (g->width - 1);
}

float hl_lid_grid_v_deg(const struct hl_lid_grid *g, int row)
{
	return g->v_last_deg - (float)row * (g->v_last_deg - g->v_first_deg) / (g->height - 1);
}

bool hl_lid_grid_equal(const struct hl_lid_grid *a, const struct hl_lid_grid *b)
{
	return a->width == b->width && a->height == b->height && a->angles == b->angles &&
	       a->h_first_deg == b->h_first_deg && a->h_last_deg == b->h_last_deg &&
	       a->v_first_deg == b->v_first_deg && a->v_last_deg == b->v_last_deg;
}

float hl_lid_grid_lookup(const struct hl_lid_grid *g, const float *dense, float h_deg, float v_deg)
{
	/* Continuous sample coordinates: column 0 at h_first, row 0 at v_last. */
	const float fx =
		(h_deg - g->h_first_deg) * (g->width - 1) / (g->h_last_deg - g->h_first_deg);
	const float fy =
		(g->v_last_deg - v_deg) * (g->height - 1) / (g->v_last_deg - g->v_first_deg);
	int x0, y0;
	float tx, ty, s00, s01, s10, s11;

	if (!(fx >= 0.0f && fx <= (float)(g->width - 1) && fy >= 0.0f &&
	      fy <= (float)(g->height - 1)))
		return 0.0f;
	x0 = (int)fx;
	y0 = (int)fy;
	if (x0 > g->width - 2)
		x0 = g->width - 2;
	if (y0 > g->height - 2)
		y0 = g->height - 2;
	tx = fx - (float)x0;
	ty = fy - (float)y0;
	s00 = dense[(size_t)y0 * g->width + x0];
	s01 = dense[(size_t)y0 * g->width + x0 + 1];
	s10 = dense[(size_t)(y0 + 1) * g->width + x0];
	s11 = dense[(size_t)(y0 + 1) * g->width + x0 + 1];
	return (s00 * (1.0f - tx) + s01 * tx) * (1.0f - ty) + (s10 * (1.0f - tx) + s11 * tx) * ty;
}

void hl_lid_adopt_source(struct hl_lid *lid, int k, const struct hl_lid_box *box, float *packed)
{
	const size_t n = (size_t)(box->x1 - box->x0) * (box->y1 - box->y0);
	float peak = 0.0f;

	for (size_t i = 0; i < n; i++)
		if (packed[i] > peak)
			peak = packed[i];
	free(lid->data[k]);
	lid->data[k] = n ? packed : NULL;
	if (!n)
		free(packed);
	lid->boxes[k] = n ? *box : (struct hl_lid_box){ 0, 0, 0, 0 };
	lid->peaks_cd[k] = peak;
}
