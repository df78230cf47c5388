/* SPDX-License-Identifier: MIT */
#include "lamp/combine.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

struct hl_combiner {
	const struct hl_lid *lid;
	float *out;
	float *current;
	unsigned full_every;
	unsigned since_full;
};

/* out[box] += a * L_k over the box of source k. */
static void add_source(const struct hl_lid *lid, int k, float a, float *out)
{
	const int w = hl_lid_grid(lid)->width;
	struct hl_lid_box b;
	const float *src = hl_lid_source(lid, k, &b);
	const int bw = b.x1 - b.x0;

	if (!src || a == 0.0f)
		return;
	for (int y = b.y0; y < b.y1; y++) {
		float *restrict o = out + (size_t)y * w + b.x0;
		const float *restrict s = src + (size_t)(y - b.y0) * bw;

		for (int x = 0; x < bw; x++)
			o[x] += a * s[x];
	}
}

void hl_combine_sparse(const struct hl_lid *lid, const float *i, float *out)
{
	const struct hl_lid_grid *g = hl_lid_grid(lid);

	memset(out, 0, sizeof(float) * (size_t)g->width * g->height);
	for (int k = 0; k < hl_lid_n_sources(lid); k++)
		add_source(lid, k, i[k], out);
}

int hl_combiner_new(const struct hl_lid *lid, unsigned full_every, struct hl_combiner **ret)
{
	const struct hl_lid_grid *g = hl_lid_grid(lid);
	struct hl_combiner *c = calloc(1, sizeof(*c));

	if (!c)
		return -ENOMEM;
	c->lid = lid;
	c->full_every = full_every ? full_every : HL_COMBINE_FULL_EVERY;
	c->out = calloc((size_t)g->width * g->height, sizeof(float));
	c->current = calloc(hl_lid_n_sources(lid), sizeof(float));
	if (!c->out || !c->current) {
		hl_combiner_free(c);
		return -ENOMEM;
	}
	*ret = c;
	return 0;
}

void hl_combiner_free(struct hl_combiner *c)
{
	if (!c)
		return;
	free(c->out);
	free(c->current);
	free(c);
}

void hl_combiner_recompute(struct hl_combiner *c)
{
	hl_combine_sparse(c->lid, c->current, c->out);
	c->since_full = 0;
}

int hl_combiner_update(struct hl_combiner *c, const float *i)
{
	const int n = hl_lid_n_sources(c->lid);
	int changed = 0;

	for (int k = 0; k < n; k++) {
		if (!(i[k] >= 0.0f && i[k] <= 1.0f))
			return -EINVAL;
		changed += i[k] != c->current[k];
	}
	if (changed == 0)
		return 0;
	if (++c->since_full >= c->full_every) {
		memcpy(c->current, i, sizeof(float) * n);
		hl_combiner_recompute(c);
		return changed;
	}
	for (int k = 0; k < n; k++) {
		if (i[k] == c->current[k])
			continue;
		add_source(c->lid, k, i[k] - c->current[k], c->out);
		c->current[k] = i[k];
	}
	return changed;
}

const float *hl_combiner_result(const struct hl_combiner *c)
{
	return c->out;
}

const float *hl_combiner_intensities(const struct hl_combiner *c)
{
	return c->current;
}
