/* SPDX-License-Identifier: MIT */
/*
 * Sensors of sensor-based lighting in GLES (the CPU version: render/sensor.h): the scene's
 * triangles (render/scene_mesh.h) are rasterised into the hemicubes of a batch of sensors at
 * once, then a reduction pass weights each sensor's texels with their projected solid angles
 * and sums them; only one float per sensor is read back.
 *
 *   atlas       one tile per sensor, size x 3 size texels (times the supersampling): the front
 *               face, then the four half side faces, the layout and weights of
 *               render/hemicube.h; tiles in rows of a multisampled R32F texture
 *   one draw    per batch: instanced, instance = (sensor, face), the sensor's eye and frame
 *               from a texture, each face clipped to its rectangle by clip distances
 *               (EXT_clip_cull_distance); reversed float depth (EXT_clip_control)
 *   shading     fragment = rho E / pi, E from both lamps as the live headlight pass computes
 *               it (shaders/sensor_scene.frag.glsl), from the lamps' combined distributions
 *               uploaded as R32F textures; the sky is sky_cd_m2 (0 at night)
 *   thin posts  multisampling (msaa samples per texel, coverage-weighted, lit at the centroid)
 *               and optional supersampling (each texel as ss x ss sub-texels, their own exact
 *               weights), so a 12 cm post is not caught or missed by chance
 *   reduction   one fragment per sensor sums its tile (shaders/sensor_reduce.frag.glsl)
 *
 * Thread-safety: the thread that owns the current GL context.
 */
#ifndef HL_RENDER_GL_SENSOR_H
#define HL_RENDER_GL_SENSOR_H

#include <stddef.h>

#include "render/egl.h"
#include "render/headlight.h"
#include "render/scene_mesh.h"

struct hl_gl_sensor;

struct hl_gl_sensor_config {
	int size; /* hemicube front face texels across, even, 2..HL_HEMICUBE_MAX_SIZE */
	int supersample; /* sub-texels per texel side, >= 1 */
	int msaa; /* samples per (sub-)texel: 1, or a count the driver offers for R32F */
	int batch; /* sensors per draw, >= 1 */
	double sky_cd_m2; /* luminance where nothing is hit */
};

/*
 * The configuration that gives at least aa x aa samples per texel (the CPU sensors' aa x aa
 * rays near thin objects): aa 1 none; otherwise 4 multisamples (when the driver offers them)
 * on ceil(aa / 2) x ceil(aa / 2) sub-texels. Sky black.
 */
void hl_gl_sensor_config_for(const struct hl_egl *egl, int size, int aa, int batch,
			     struct hl_gl_sensor_config *ret);

/*
 * Uploads the mesh; lamps as the headlight pass takes them (1 or 2). The context must offer
 * float targets, EXT_clip_cull_distance and EXT_clip_control. 0, -EINVAL, -ENOTSUP (a missing
 * extension or sample count; log names it), -ENOMEM, -EIO (log says what).
 */
int hl_gl_sensor_new(const struct hl_egl *egl, const struct hl_scene_mesh *mesh, int n_lamps,
		     const struct hl_headlight_lamp *lamps, const struct hl_gl_sensor_config *cfg,
		     struct hl_gl_sensor **ret, char *log, size_t log_size);
void hl_gl_sensor_free(struct hl_gl_sensor *s);

/* Lamp k's combined distribution (grid layout, cd). 0 or -EIO. */
int hl_gl_sensor_upload(struct hl_gl_sensor *s, int k, const float *dense);

/*
 * Irradiance (lux) at count points p (3 doubles each) with unit normals n (3 doubles each) into
 * ret_lx, in draws of at most cfg->batch sensors; each eye sits HL_SENSOR_OFFSET_M above its
 * point. Allocates nothing. 0 or -EIO.
 */
int hl_gl_sensor_run(struct hl_gl_sensor *s, size_t count, const double *p, const double *n,
		     double *ret_lx);
/* The same as an hl_gi_batch_fn (render/gi.h): userdata is the struct hl_gl_sensor. */
int hl_gl_sensor_gi_batch(void *userdata, size_t count, const double *p, const double *n,
			  double *ret_lx);

#endif
