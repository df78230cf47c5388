/* SPDX-License-Identifier: MIT */
/*
 * Offline global illumination of the headlamp light by sensor-based lighting: the indirect
 * illuminance (one bounce) of every visible G-buffer point.
 *
 *   placement   one sensor (render/sensor.h) per tile corner, tiles of dt x dt pixels; a tile
 *               is split into four where its corners differ by more than dradiance (relative
 *               to their mean, or to the mean of the first level's sensors where that is
 *               larger, so that faint regions do not draw sensors) or where its
 *               pixels do not all lie on one smooth surface (normal within 25°, coplanar) or
 *               mix sky and surface; down to single pixels. When no tile is left to split,
 *               accepted tiles are checked against the sensors their refined neighbours put on
 *               their border and split if those disagree with the interpolation by more than
 *               the same threshold (a glow no corner saw). Pixels of accepted tiles are
 *               interpolated bilinearly from the tile's corners. tile 1 = a sensor per pixel.
 *   sensor map  a hemicube (render/hemicube.h); texels near the scene's thin objects (the
 *               road's posts) supersampled, or a sensor catches or misses a post by chance
 *               and the indirect light of the road shows moiré.
 *   batching    the sensors of a level are grouped by normal into batches (shared world
 *               directions) and the batches spread over threads.
 *   composition a Gaussian of sigma_px pixels over the samples of the same surface id only.
 *
 * The result is illuminance (lux) like the direct pass's, so total = direct + indirect and a
 * view shows albedo (direct + indirect) / pi.
 *
 * Thread-safety: hl_gi_run() is called from one thread; it starts and joins its own workers
 * and calls progress only from the calling thread.
 */
#ifndef HL_RENDER_GI_H
#define HL_RENDER_GI_H

#include <stddef.h>

#include "render/scene.h"
#include "render/sensor.h"

#define HL_GI_MAX_THREADS 64

struct hl_gi_config {
	int sensor_size; /* hemicube front face texels across (even) */
	int tile; /* dt: power of two, 1..256 */
	double dradiance; /* relative threshold of refinement, > 0 */
	double sigma_px; /* composition Gaussian, 0 = none */
	int threads; /* 1..HL_GI_MAX_THREADS */
	int batch; /* sensors per batch, >= 1 */
	int aa_samples; /* supersampling of texels near thin objects, per side; 1 = none */
	const struct hl_capsule *thin; /* the scene's thin objects (hl_scene_thin_objects) */
	int n_thin;
	/* Called now and then with sensors done and the current estimate of the total. */
	void (*progress)(void *userdata, size_t done, size_t estimated);
	void *userdata;
};

struct hl_gi_stats {
	size_t sensors; /* sensors rendered */
	size_t surface_pixels; /* pixels that hit a surface: the sensors of one per pixel */
	size_t batches;
	int levels; /* passes of sensors run: refinement levels and re-checks (1: none refined) */
	double sensor_ms; /* wall time inside the sensor batches */
	double total_ms; /* wall time of hl_gi_run */
};

/* sensor_size 32, tile 8, dradiance 1, sigma_px 1, 2 threads, batch 64, aa 4, no thin
 * objects, no progress. */
void hl_gi_config_default(struct hl_gi_config *ret);

/*
 * Indirect illuminance (lux, width * height floats, row 0 at the top; 0 on the sky) of the
 * G-buffer's points in field. 0, -EINVAL (bad config, G-buffer smaller than 2 x 2), -ENOMEM.
 * Threads that cannot be started leave their share to the calling thread.
 */
int hl_gi_run(const struct hl_gi_config *cfg, hl_radiance_fn fn, const void *field,
	      const struct hl_gbuffer *gb, float *ret_indirect_lx, struct hl_gi_stats *ret_stats);

/*
 * The composition filter: Gaussian of sigma_px over the pixels of the same surface id as the
 * centre (radius 2 sigma); the sky stays 0. in and out must not overlap. 0, -EINVAL.
 */
int hl_gi_filter(const struct hl_gbuffer *gb, const float *in, double sigma_px, float *out);

#endif
