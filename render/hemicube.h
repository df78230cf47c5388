/* SPDX-License-Identifier: MIT */
/*
 * The sensor map of sensor-based lighting as a hemicube: a full front face of size x size
 * texels looking along the surface normal and four half side faces (size x size/2 texels
 * each), so the whole hemisphere is seen, down to grazing directions (the paper's single
 * 135° camera misses everything beyond 67.5° from the normal).
 *
 * Local frame: +z the surface normal, x and y tangent; the cube has half-width 1 at distance 1.
 * Each texel carries its centre direction (unit) and its exact projected solid angle
 * F = integral of cos(theta) d(omega) over the texel, in sr, from the closed forms of
 * Nusselt's analogue on a plane:
 *   front face z = 1:  integral of dx dy / (1 + x^2 + y^2)^2
 *   side face x = 1:   integral of z dy dz / (1 + y^2 + z^2)^2
 * The weights sum to pi over the hemicube, so sum F_ij L_ij is the irradiance E (lux) of a
 * surface that sees luminances L_ij (cd/m^2); a uniform sky of luminance L gives E = pi L,
 * and a diffuse surface of reflectance rho scatters L_s = rho E / pi.
 *
 * Thread-safety: read-only once made; any thread.
 */
#ifndef HL_RENDER_HEMICUBE_H
#define HL_RENDER_HEMICUBE_H

#include <stddef.h>

#define HL_HEMICUBE_MAX_SIZE 1024

struct hl_hemicube;

/* size: texels across the front face, even, 2..HL_HEMICUBE_MAX_SIZE. 0, -EINVAL, -ENOMEM. */
int hl_hemicube_new(int size, struct hl_hemicube **ret);
void hl_hemicube_free(struct hl_hemicube *h);

int hl_hemicube_size(const struct hl_hemicube *h);
/* Texels of all five faces: 3 size^2. */
size_t hl_hemicube_texels(const struct hl_hemicube *h);
/* Unit centre directions in the local frame, 3 floats per texel; owned by h. */
const float *hl_hemicube_dirs(const struct hl_hemicube *h);
/* Projected solid angle per texel (sr); owned by h; sums to pi. */
const double *hl_hemicube_weights(const struct hl_hemicube *h);

/*
 * Direction (local frame, not unit) of sub-sample (su, sv) of an s x s grid over texel i:
 * supersampling a texel splits its weight evenly over its sub-samples.
 */
void hl_hemicube_subdir(const struct hl_hemicube *h, size_t i, int su, int sv, int s,
			double ret[3]);
/* Upper bound of the angle from a texel's centre direction to any point of the texel, rad. */
double hl_hemicube_texel_radius(const struct hl_hemicube *h);

/*
 * Projected solid angle of the rectangle [x0, x1] x [y0, y1] of the front face (plane z = 1),
 * and of [y0, y1] x [z0, z1] of the side face x = 1 (z the height above the tangent plane).
 */
double hl_hemicube_front_patch(double x0, double x1, double y0, double y1);
double hl_hemicube_side_patch(double y0, double y1, double z0, double z1);

/*
 * An orthonormal tangent frame for unit normal n: ret_t, ret_b, n right-handed. The same n
 * always gives the same frame.
 */
void hl_hemicube_frame(const double n[3], double ret_t[3], double ret_b[3]);

#endif
