/* SPDX-License-Identifier: MIT */
/*
 * Which pixels of a moving scene's G-buffer changed for the headlight pass since the frame
 * before. The pass depends on a pixel's position and normal and on whether it hit anything
 * (render/headlight.h: the terms of each lamp), never on its albedo or on which surface it
 * hit: the ground's markings and albedo slide under the ego vehicle every frame without
 * changing a term. So the object keeps, per pixel, the position, the normal and a hit flag as
 * last lit, and compares them bit for bit (identical bits give identical terms, on the CPU and
 * in GLES): a pixel changed when it hits something now and did not before or the reverse, or
 * when it hits something in both and its position or normal differ. Two pixels that hit
 * nothing are equal whatever their position holds.
 *
 * Thread-safety: hl_gbuffer_diff_band() of disjoint pixel ranges may run on several threads
 * at once (each writes only its own pixels' copy and flags); the rest from one thread.
 */
#ifndef HL_RENDER_GBUFFER_DIFF_H
#define HL_RENDER_GBUFFER_DIFF_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "render/scene.h"

struct hl_gbuffer_diff;

/*
 * For a width x height G-buffer. With gb (same size), it is the copy to compare against;
 * without, nothing is known yet and the first comparison of each pixel must pass all = true.
 * 0, -EINVAL (a size <= 0 or gb of another size), -ENOMEM.
 */
int hl_gbuffer_diff_new(int width, int height, const struct hl_gbuffer *gb,
			struct hl_gbuffer_diff **ret);
void hl_gbuffer_diff_free(struct hl_gbuffer_diff *d);

/*
 * Compares pixels first .. first + count - 1 of gb (same size as d) with the copy: sets each
 * pixel's changed flag (1 or 0), takes the changed pixels into the copy, and returns how many
 * changed. all: every pixel counts as changed (and is copied). Allocates nothing.
 */
size_t hl_gbuffer_diff_band(struct hl_gbuffer_diff *d, const struct hl_gbuffer *gb, size_t first,
			    size_t count, bool all);

/* The changed flags of the last comparison, one byte per pixel (0 or 1), row 0 at the top. */
const uint8_t *hl_gbuffer_diff_flags(const struct hl_gbuffer_diff *d);

#endif
