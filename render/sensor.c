/* SPDX-License-Identifier: MIT */
#include "render/sensor.h"

#include <math.h>

double hl_sensor_scene_radiance(const void *field, const double o[3], const double d[3])
{
	const struct hl_sensor_scene *s = field;
	float pos[4], nrm[4];
	double p[3], n[3], e = 0.0;

	if (hl_scene_cast(s->scene, o, d, pos, nrm) == HL_SURF_NONE)
		return s->sky_cd_m2;
	for (int i = 0; i < 3; i++) {
		p[i] = pos[i];
		n[i] = nrm[i];
	}
	for (int k = 0; k < s->n_lamps; k++)
		if (s->dense[k])
			e += hl_headlight_point(&s->lamps[k], s->dense[k], p, n);
	return pos[3] * e * M_1_PI;
}

size_t hl_sensor_scratch_floats(const struct hl_hemicube *h)
{
	return 3 * hl_hemicube_texels(h);
}

void hl_sensor_batch(const struct hl_hemicube *h, hl_radiance_fn fn, const void *field,
		     const double n[3], size_t count, const double *p, float *scratch,
		     double *ret_lx)
{
	const size_t nt = hl_hemicube_texels(h);
	const float *local = hl_hemicube_dirs(h);
	const double *w = hl_hemicube_weights(h);
	double t[3], b[3];

	/* Once per batch: the texel directions in the world frame. */
	hl_hemicube_frame(n, t, b);
	for (size_t i = 0; i < nt; i++) {
		const double x = local[3 * i], y = local[3 * i + 1], z = local[3 * i + 2];

		for (int j = 0; j < 3; j++)
			scratch[3 * i + j] = (float)(x * t[j] + y * b[j] + z * n[j]);
	}
	for (size_t s = 0; s < count; s++) {
		const double o[3] = { p[3 * s] + HL_SENSOR_OFFSET_M * n[0],
				      p[3 * s + 1] + HL_SENSOR_OFFSET_M * n[1],
				      p[3 * s + 2] + HL_SENSOR_OFFSET_M * n[2] };
		double e = 0.0;

		for (size_t i = 0; i < nt; i++) {
			const double d[3] = { scratch[3 * i], scratch[3 * i + 1],
					      scratch[3 * i + 2] };

			e += w[i] * fn(field, o, d);
		}
		ret_lx[s] = e;
	}
}
