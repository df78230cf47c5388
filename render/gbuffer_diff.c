/* SPDX-License-Identifier: MIT */
#include "render/gbuffer_diff.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

/* What the headlight pass reads of one pixel, as bits: 28 bytes. */
struct geo {
	uint32_t p[3]; /* position, m (vehicle frame) */
	uint32_t n[3]; /* unit normal */
	uint32_t hit; /* 1: some surface, 0: nothing (the sky) */
};

struct hl_gbuffer_diff {
	int width, height;
	struct geo *copy;
	uint8_t *changed;
};

static struct geo geo_of(const struct hl_gbuffer *gb, size_t i)
{
	struct geo g;

	memcpy(g.p, gb->pos + 4 * i, sizeof(g.p));
	memcpy(g.n, gb->nrm + 4 * i, sizeof(g.n));
	g.hit = gb->nrm[4 * i + 3] != (float)HL_SURF_NONE;
	return g;
}

int hl_gbuffer_diff_new(int width, int height, const struct hl_gbuffer *gb,
			struct hl_gbuffer_diff **ret)
{
	const size_t n = width > 0 && height > 0 ? (size_t)width * height : 0;
	struct hl_gbuffer_diff *d;

	if (!n || (gb && (gb->width != width || gb->height != height)))
		return -EINVAL;
	d = calloc(1, sizeof(*d));
	if (!d)
		return -ENOMEM;
	d->width = width;
	d->height = height;
	d->copy = malloc(sizeof(*d->copy) * n);
	d->changed = calloc(n, 1);
	if (!d->copy || !d->changed) {
		hl_gbuffer_diff_free(d);
		return -ENOMEM;
	}
	if (gb)
		hl_gbuffer_diff_band(d, gb, 0, n, true);
	memset(d->changed, 0, n);
	*ret = d;
	return 0;
}

void hl_gbuffer_diff_free(struct hl_gbuffer_diff *d)
{
	if (!d)
		return;
	free(d->copy);
	free(d->changed);
	free(d);
}

size_t hl_gbuffer_diff_band(struct hl_gbuffer_diff *d, const struct hl_gbuffer *gb, size_t first,
			    size_t count, bool all)
{
	size_t n_changed = 0;

	/*
	 * Reads 32 bytes of the G-buffer and 28 of the copy per pixel: bound by memory, so no
	 * calls and one well-predicted branch per pixel (most pixels keep their geometry).
	 */
	for (size_t i = first; i < first + count; i++) {
		const struct geo g = geo_of(gb, i);
		struct geo *old = &d->copy[i];
		const uint32_t moved = (g.p[0] ^ old->p[0]) | (g.p[1] ^ old->p[1]) |
				       (g.p[2] ^ old->p[2]) | (g.n[0] ^ old->n[0]) |
				       (g.n[1] ^ old->n[1]) | (g.n[2] ^ old->n[2]);
		const bool changed = all || g.hit != old->hit || (g.hit && moved != 0);

		d->changed[i] = changed;
		if (changed) {
			*old = g;
			n_changed++;
		}
	}
	return n_changed;
}

const uint8_t *hl_gbuffer_diff_flags(const struct hl_gbuffer_diff *d)
{
	return d->changed;
}
