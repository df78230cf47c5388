/* SPDX-License-Identifier: MIT */
#include "render/gbuffer_diff.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

/*
 * The copy, per pixel, as the G-buffer holds it (bits): position xyz with the hit flag in the
 * fourth lane (1: some surface, 0: nothing), normal xyz (the fourth lane unused). 32 bytes a
 * pixel in the G-buffer's own layout, so that the comparison is a few 16-byte operations.
 */
typedef uint32_t v4u __attribute__((vector_size(16)));

struct hl_gbuffer_diff {
	int width, height;
	v4u *pos, *nrm;
	uint8_t *changed;
};

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
	d->pos = aligned_alloc(sizeof(v4u), sizeof(v4u) * n);
	d->nrm = aligned_alloc(sizeof(v4u), sizeof(v4u) * n);
	d->changed = calloc(n, 1);
	if (!d->pos || !d->nrm || !d->changed) {
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
	free(d->pos);
	free(d->nrm);
	free(d->changed);
	free(d);
}

size_t hl_gbuffer_diff_band(struct hl_gbuffer_diff *d, const struct hl_gbuffer *gb, size_t first,
			    size_t count, bool all)
{
	const v4u xyz = { ~0u, ~0u, ~0u, 0 };
	size_t n_changed = 0;

	/*
	 * Bound by memory (32 bytes of the G-buffer and 32 of the copy per pixel): first the
	 * flags alone, straight-line 16-byte operations with no stores but the flag; then the
	 * few changed pixels into the copy.
	 */
	if (all) { /* the copy may hold nothing yet: not read */
		memset(d->changed + first, 1, count);
		n_changed = count;
	}
	for (size_t i = first; !all && i < first + count; i++) {
		v4u p, n;
		uint32_t hit, moved;
		v4u x;

		memcpy(&p, gb->pos + 4 * i, sizeof(p));
		memcpy(&n, gb->nrm + 4 * i, sizeof(n));
		x = ((p ^ d->pos[i]) | (n ^ d->nrm[i])) & xyz;
		moved = x[0] | x[1] | x[2];
		hit = gb->nrm[4 * i + 3] != (float)HL_SURF_NONE;
		d->changed[i] = (hit != d->pos[i][3]) | (hit & (moved != 0));
		n_changed += d->changed[i];
	}
	for (size_t i = first; n_changed && i < first + count; i++) {
		if (!d->changed[i])
			continue;
		memcpy(&d->pos[i], gb->pos + 4 * i, sizeof(v4u));
		memcpy(&d->nrm[i], gb->nrm + 4 * i, sizeof(v4u));
		d->pos[i][3] = gb->nrm[4 * i + 3] != (float)HL_SURF_NONE;
	}
	return n_changed;
}

const uint8_t *hl_gbuffer_diff_flags(const struct hl_gbuffer_diff *d)
{
	return d->changed;
}
