/* SPDX-License-Identifier: MIT */
/*
 * The headlight pass on the CPU (docs/design.md §1, §4): every G-buffer point is lit by each lamp
 * with E = I(H, V) * cos(eps) / r^2 (lux), (H, V) the direction of the point in lamp space in
 * the lamp's angle system (type A or B, exact), I a bilinear lookup of the lamp's combined
 * distribution with samples at texel centres and zero outside the grid. Lamps add.
 *
 * Lamp poses are fixed and the G-buffer changes seldom or never, so hl_headlight_new()
 * computes per pixel and lamp what does not depend on the currents: the sample cell, the
 * bilinear weights and cos(eps) / r^2. A frame (hl_headlight_run) is then only the four
 * lookups, the weighting and the sum, over the pixels a lamp can reach.
 *
 * A frame is also available in bands of pixels (chunks) that several threads can light at
 * once: hl_headlight_run() is every chunk in turn.
 *
 * A moving scene (a new G-buffer each frame, render/renderer.h) switches the object once to
 * the moving layout (hl_headlight_make_moving), where every pixel has room for its terms; then
 * hl_headlight_update_chunk() recomputes the terms of the pixels that changed, chunk by chunk.
 * A still scene never pays for it: its terms stay packed, lit pixels only.
 *
 * Thread-safety: one thread builds, switches and frees the object (the G-buffer is read only
 * in _new and _update_chunk); hl_headlight_run_chunk() and hl_headlight_update_chunk() of
 * different chunks may run on several threads at once (a chunk is lit after its update, by
 * the same thread or after the threads have joined).
 */
#ifndef HL_RENDER_HEADLIGHT_H
#define HL_RENDER_HEADLIGHT_H

#include "world/camera.h"
#include "lamp/lid.h"
#include "render/scene.h"

#define HL_HEADLIGHT_MAX_LAMPS 2

struct hl_headlight;

/* A lamp as the pass sees it: where it is and the grid of its distributions. */
struct hl_headlight_lamp {
	struct hl_lamp_pose pose;
	struct hl_lid_grid grid;
};

/* 0, -EINVAL (n_lamps outside 1..2, bad grid), -ENOMEM. */
int hl_headlight_new(const struct hl_gbuffer *gb, int n_lamps,
		     const struct hl_headlight_lamp *lamps, struct hl_headlight **ret);
void hl_headlight_free(struct hl_headlight *h);

/*
 * Illuminance of every pixel (width * height floats, lux, row 0 at the top) from the lamps'
 * current distributions dense[k] (grid layout, cd); dense[k] NULL leaves lamp k dark.
 * Allocates nothing.
 */
void hl_headlight_run(const struct hl_headlight *h, const float *const *dense, float *ret_lux);

/* Bands a frame is split into; chunk c covers the pixels *ret_first .. + *ret_count - 1. */
size_t hl_headlight_chunks(const struct hl_headlight *h);
void hl_headlight_chunk_pixels(const struct hl_headlight *h, size_t c, size_t *ret_first,
			       size_t *ret_count);
/* hl_headlight_run() for the pixels of chunk c only (writes nothing else of ret_lux). */
void hl_headlight_run_chunk(const struct hl_headlight *h, const float *const *dense, size_t c,
			    float *ret_lux);

/*
 * The same for the pixels in the spans only (those some lamp can reach; in a moving scene also
 * those some lamp reached in an earlier G-buffer): the others keep what ret_lux holds, which
 * is the right value (zero) when the caller zeroed the buffer once, since no frame makes them
 * anything else. span(userdata, ret_lux, first, count), if not NULL, is called for each run of
 * lit pixels as soon as it is done, while it is still in the cache.
 */
typedef void (*hl_headlight_span_fn)(void *userdata, const float *lux, size_t first, size_t count);
void hl_headlight_run_chunk_lit(const struct hl_headlight *h, const float *const *dense, size_t c,
				float *ret_lux, hl_headlight_span_fn span, void *userdata);

/*
 * The moving layout: each pixel's terms at a place of its own (n_lamps x 12 bytes for every
 * pixel, where the still layout holds lit pixels only), each chunk's spans in room for the
 * most a chunk can have. The terms and spans made so far are kept. 0 (also when already
 * moving), -ENOMEM. Allocates: call it once, before the frames.
 */
int hl_headlight_make_moving(struct hl_headlight *h);

/*
 * Moving layout: recomputes from gb (the size of the object's) the terms of every pixel of
 * chunk c whose changed[i] (i the pixel's index in the image) is non-zero. A pixel some lamp
 * reaches now that none reached before joins the chunk's spans. A pixel no lamp reaches any
 * more stays in them with zero terms, so frames keep writing its zero (and pass it to the
 * span callback): a buffer that an earlier frame lit holds zero there again, and the pixels
 * outside the spans are still exactly those never lit since the object was made. Allocates
 * nothing.
 */
void hl_headlight_update_chunk(struct hl_headlight *h, const struct hl_gbuffer *gb, size_t c,
			       const uint8_t *changed);

/* Pixel-lamp pairs a lamp reaches (the work of one frame, without the zero terms above). */
size_t hl_headlight_work(const struct hl_headlight *h);

/*
 * What one lamp contributes at one point before its distribution is known: the bilinear taps
 * and the geometry. E = g * the bilinear lookup of cell's 2 x 2 samples with weights tx
 * (towards column + 1) and ty (towards row + 1), which hl_headlight_tap_lookup() computes.
 */
struct hl_headlight_tap {
	size_t cell; /* index of the cell's upper-left sample in the dense grid */
	double tx, ty; /* bilinear weights, 0..1 */
	double g; /* cos(eps) / r^2, 1/m^2 */
};

/*
 * The taps of lamp at point p with unit normal n (vehicle frame); false, with *ret zeroed, when
 * the lamp does not light the point (it faces away, or its direction is outside the grid).
 */
bool hl_headlight_tap(const struct hl_headlight_lamp *lamp, const double p[3], const double n[3],
		      struct hl_headlight_tap *ret);
/* g * I at the taps, in double precision, from dense (grid layout, width columns, cd). */
double hl_headlight_tap_lookup(const struct hl_headlight_tap *t, const float *dense, int width);

/*
 * The same quantity for one point, without any precomputation, in double precision: the
 * reference the fast paths are checked against. p, n in the vehicle frame (n unit).
 */
double hl_headlight_point(const struct hl_headlight_lamp *lamp, const float *dense,
			  const double p[3], const double n[3]);

#endif
