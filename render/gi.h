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
 * Sensors run on the CPU (render/sensor.h: a radiance field ray cast on cfg->threads
 * threads) or through a batch function such as render/gl_sensor.h's GLES sensors, which is
 * called on the calling thread only (the one that owns the GL context), cfg->batch sensors at a
 * time; either way the placement, interpolation and filter are the same code.
 *
 * Thread-safety: hl_gi_run() is called from one thread; it starts and joins its own workers
 * (CPU sensors only) and calls progress only from the calling thread.
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
	int batch; /* sensors per batch (CPU: sharing one normal; batch function: per call), >= 1 */
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
 * A batch of sensors evaluated at once: irradiance (lux) at count points p with unit normals n
 * (3 doubles each) into ret_lx. 0 or -errno (hl_gi_run returns it).
 */
typedef int (*hl_gi_batch_fn)(void *userdata, size_t count, const double *p, const double *n,
			      double *ret_lx);

/* Where sensors run: fn and field (CPU, hl_sensor_batch), or batch and userdata when fn is NULL. */
struct hl_gi_sensors {
	hl_radiance_fn fn;
	const void *field;
	hl_gi_batch_fn batch;
	void *userdata;
};

/*
 * Indirect illuminance (lux, width * height floats, row 0 at the top; 0 on the sky) of the
 * G-buffer's points. 0, -EINVAL (bad config, G-buffer smaller than 2 x 2), -ENOMEM, or what the
 * batch function returned. Threads that cannot be started leave their share to the calling
 * thread.
 */
int hl_gi_run_sensors(const struct hl_gi_config *cfg, const struct hl_gi_sensors *sensors,
		      const struct hl_gbuffer *gb, float *ret_indirect_lx,
		      struct hl_gi_stats *ret_stats);
/* The same with CPU sensors over the radiance field fn, field. */
int hl_gi_run(const struct hl_gi_config *cfg, hl_radiance_fn fn, const void *field,
	      const struct hl_gbuffer *gb, float *ret_indirect_lx, struct hl_gi_stats *ret_stats);

/*
 * Wall time per sensor (ms) of one batch of cfg->batch sensors (fewer if the G-buffer has
 * fewer surface pixels) spread evenly over the G-buffer's surface pixels, run as hl_gi_run
 * would run them (CPU: cfg->threads threads), after one untimed sensor (shader compilation,
 * first-touch costs). For choosing a backend. 0, -EINVAL (no surface pixel), -ENOMEM, or what
 * the batch function returned.
 */
int hl_gi_time_batch(const struct hl_gi_config *cfg, const struct hl_gi_sensors *sensors,
		     const struct hl_gbuffer *gb, double *ret_ms_per_sensor);

/*
 * The composition filter: Gaussian of sigma_px over the pixels of the same surface id as the
 * centre (radius 2 sigma); the sky stays 0. in and out must not overlap. 0, -EINVAL.
 */
int hl_gi_filter(const struct hl_gbuffer *gb, const float *in, double sigma_px, float *out);

#endif
