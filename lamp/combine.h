/* SPDX-License-Identifier: MIT */
/*
 * The reference combiner ("cookie combiner", docs/design.md §1): a lamp's distribution
 * L = sum_k i_k * L_k over its sources, in 32-bit floats, touching each source only over its
 * non-zero box (sparse). A combiner keeps the last intensities and updates incrementally: only
 * sources whose i_k changed are added as (i_new - i_old) * L_k. Float increments drift, so every
 * full_every-th update recomputes from scratch, which bounds the error (docs/rendering.md).
 *
 * Thread-safety: a combiner belongs to one thread; the lid it reads must outlive it.
 */
#ifndef HL_RENDER_COMBINE_H
#define HL_RENDER_COMBINE_H

#include "lamp/lid.h"

#define HL_COMBINE_FULL_EVERY 64 /* incremental updates between full recomputes */

struct hl_combiner;

/* full_every 0 means HL_COMBINE_FULL_EVERY. 0, -ENOMEM. Starts with all i_k = 0. */
int hl_combiner_new(const struct hl_lid *lid, unsigned full_every, struct hl_combiner **ret);
void hl_combiner_free(struct hl_combiner *c);

/*
 * Sets the relative currents i (n_sources values in [0, 1]). Returns the number of sources
 * that changed, or -EINVAL (nothing changed) for a value outside [0, 1] or not finite.
 * Allocates nothing.
 */
int hl_combiner_update(struct hl_combiner *c, const float *i);
/* Recomputes the whole distribution from the current intensities. */
void hl_combiner_recompute(struct hl_combiner *c);

/* The distribution (width * height floats, cd, grid of the lid); owned by the combiner. */
const float *hl_combiner_result(const struct hl_combiner *c);
/* The current intensities (n_sources floats); owned by the combiner. */
const float *hl_combiner_intensities(const struct hl_combiner *c);

/* Stateless sparse combine into out (width * height floats). i must be valid as above. */
void hl_combine_sparse(const struct hl_lid *lid, const float *i, float *out);

#endif
