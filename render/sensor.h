/* SPDX-License-Identifier: MIT */
/*
 * Sensors of sensor-based lighting: a sensor at point p with unit normal n renders what p sees
 * over its hemicube (render/hemicube.h) and returns the projected-solid-angle weighted sum of
 * the luminances, i.e. the irradiance E = sum F_ij L_ij in lux (sum F_ij = pi).
 *
 * What a sensor sees is a radiance field: a function giving the luminance (cd/m^2) along a
 * ray. hl_sensor_scene_radiance() is the directly lit scene: the nearest surface of the
 * scene's analytic geometry (hl_scene_cast) with its luminance rho E / pi, E from the
 * headlight pass at that point (hl_headlight_point, both lamps), and sky_cd_m2 where nothing
 * is hit. Other fields (a uniform sky, a test pattern) prove the sensor's normalisation.
 *
 * Batching: the sensors of a batch share one normal (all of a plane's pixels do), so the
 * hemicube's directions are turned into the world frame once per batch, not per sensor.
 *
 * Thread-safety: the fields are read-only; batches may run on several threads at once, each
 * with its own scratch.
 */
#ifndef HL_RENDER_SENSOR_H
#define HL_RENDER_SENSOR_H

#include <stddef.h>

#include "render/headlight.h"
#include "render/hemicube.h"
#include "render/scene.h"

/* Luminance (cd/m^2) seen from o along unit direction d. */
typedef double (*hl_radiance_fn)(const void *field, const double o[3], const double d[3]);

/* The directly lit scene as a radiance field. Everything pointed to must outlive its use. */
struct hl_sensor_scene {
	const struct hl_scene *scene;
	int n_lamps; /* 1 or 2 */
	struct hl_headlight_lamp lamps[HL_HEADLIGHT_MAX_LAMPS];
	const float *dense[HL_HEADLIGHT_MAX_LAMPS]; /* combined distributions, grid layout, cd */
	double sky_cd_m2; /* what rays that hit nothing see; 0 at night */
};

/* field: a struct hl_sensor_scene. */
double hl_sensor_scene_radiance(const void *field, const double o[3], const double d[3]);

/* Floats of scratch a batch needs: the world directions of the hemicube's texels. */
size_t hl_sensor_scratch_floats(const struct hl_hemicube *h);

/*
 * Anti-aliasing of thin objects: texels whose cone passes within a capsule's radius (plus the
 * texel's own angular size at that distance) are supersampled with samples x samples rays.
 */
struct hl_sensor_aa {
	const struct hl_capsule *thin;
	int n_thin;
	int samples; /* per texel side, >= 1 */
};

/* Offset of a sensor's eye from its surface point along the normal, m (no self-hits). */
#define HL_SENSOR_OFFSET_M 1e-3

/*
 * Irradiance (lux) at count points p (3 doubles each, on the surface) sharing unit normal n,
 * into ret_lx. aa: NULL for plain point sampling. scratch: hl_sensor_scratch_floats() floats.
 * Allocates nothing.
 */
void hl_sensor_batch(const struct hl_hemicube *h, hl_radiance_fn fn, const void *field,
		     const struct hl_sensor_aa *aa, const double n[3], size_t count,
		     const double *p, float *scratch, double *ret_lx);

#endif
