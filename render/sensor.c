/* SPDX-License-Identifier: MIT */
#include "render/sensor.h"

#include <math.h>
#include <stdbool.h>

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

/*
 * Whether the ray o + t d (t > 0, d unit) passes within r + t tan(alpha) of the segment a-b:
 * the closest points of the two lines, clamped to the segment and the ray.
 */
static bool near_capsule(const struct hl_capsule *c, double tan_alpha, const double o[3],
			 const double d[3])
{
	double ab[3], ao[3], q[3], ab2 = 0.0, abd = 0.0, abo = 0.0, dao = 0.0, den, s, t,
				   dist2 = 0.0;

	for (int i = 0; i < 3; i++) {
		ab[i] = c->b[i] - c->a[i];
		ao[i] = o[i] - c->a[i];
		ab2 += ab[i] * ab[i];
		abd += ab[i] * d[i];
		abo += ab[i] * ao[i];
		dao += d[i] * ao[i];
	}
	/* Minimise |a + s ab - o - t d| over s, t (d unit). */
	den = ab2 - abd * abd;
	s = den > 1e-12 ? (abo - abd * dao) / den : 0.0;
	s = s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s);
	t = 0.0;
	for (int i = 0; i < 3; i++)
		t += (c->a[i] + s * ab[i] - o[i]) * d[i];
	if (t <= 0.0)
		return false;
	s = (t * abd - abo) / ab2;
	s = s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s);
	for (int i = 0; i < 3; i++) {
		q[i] = c->a[i] + s * ab[i] - o[i] - t * d[i];
		dist2 += q[i] * q[i];
	}
	{
		const double reach = c->r_m + t * tan_alpha;

		return dist2 < reach * reach;
	}
}

/* A capsule as seen from a sensor: the cone around it, widened by the texel's cone. */
struct cone {
	const struct hl_capsule *c;
	double dir[3]; /* unit, to the segment's midpoint */
	double cos_reach; /* rays with d . dir below this cannot come near */
};

static void add_cone(struct cone *k, const struct hl_capsule *c, const double o[3], double alpha)
{
	double m[3], dist = 0.0, half = 0.0, beta;

	for (int i = 0; i < 3; i++) {
		m[i] = (c->a[i] + c->b[i]) / 2 - o[i];
		dist += m[i] * m[i];
		half += (c->b[i] - c->a[i]) * (c->b[i] - c->a[i]);
	}
	dist = sqrt(dist);
	half = sqrt(half) / 2 + c->r_m;
	k->c = c;
	/* Inside the bounding sphere or close to it: every direction may pass near. */
	if (dist <= half * 1.01) {
		k->dir[0] = k->dir[1] = k->dir[2] = 0.0;
		k->cos_reach = -2.0;
		return;
	}
	for (int i = 0; i < 3; i++)
		k->dir[i] = m[i] / dist;
	beta = asin(half / dist) + alpha;
	k->cos_reach = beta >= M_PI ? -2.0 : cos(beta);
}

void hl_sensor_batch(const struct hl_hemicube *h, hl_radiance_fn fn, const void *field,
		     const struct hl_sensor_aa *aa, const double n[3], size_t count,
		     const double *p, float *scratch, double *ret_lx)
{
	const size_t nt = hl_hemicube_texels(h);
	const float *local = hl_hemicube_dirs(h);
	const double *w = hl_hemicube_weights(h);
	/* The texel's cone, widened by half a sub-sample spacing and a margin. */
	const double alpha = 1.5 * hl_hemicube_texel_radius(h), tan_alpha = tan(alpha);
	const int ss = aa && aa->n_thin > 0 && aa->samples > 1 ? aa->samples : 1;
	const double inv_ss2 = 1.0 / (ss * ss);
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
		struct cone near[HL_SCENE_MAX_THIN];
		int n_near = 0;
		double e = 0.0;

		/* Thin objects above the sensor's tangent plane. */
		for (int k = 0; ss > 1 && k < aa->n_thin && n_near < HL_SCENE_MAX_THIN; k++) {
			const struct hl_capsule *c = &aa->thin[k];
			double ha = 0.0, hb = 0.0;

			for (int j = 0; j < 3; j++) {
				ha += (c->a[j] - o[j]) * n[j];
				hb += (c->b[j] - o[j]) * n[j];
			}
			if (ha > -c->r_m || hb > -c->r_m)
				add_cone(&near[n_near++], c, o, alpha);
		}
		for (size_t i = 0; i < nt; i++) {
			const double d[3] = { scratch[3 * i], scratch[3 * i + 1],
					      scratch[3 * i + 2] };
			bool fine = false;

			for (int k = 0; k < n_near && !fine; k++)
				fine = d[0] * near[k].dir[0] + d[1] * near[k].dir[1] +
						       d[2] * near[k].dir[2] >=
					       near[k].cos_reach &&
				       near_capsule(near[k].c, tan_alpha, o, d);
			if (!fine) {
				e += w[i] * fn(field, o, d);
				continue;
			}
			{
				double l = 0.0;

				for (int sv = 0; sv < ss; sv++)
					for (int su = 0; su < ss; su++) {
						double ld[3], wd[3], len;

						hl_hemicube_subdir(h, i, su, sv, ss, ld);
						len = sqrt(ld[0] * ld[0] + ld[1] * ld[1] +
							   ld[2] * ld[2]);
						for (int j = 0; j < 3; j++)
							wd[j] = (ld[0] * t[j] + ld[1] * b[j] +
								 ld[2] * n[j]) /
								len;
						l += fn(field, o, wd);
					}
				e += w[i] * l * inv_ss2;
			}
		}
		ret_lx[s] = e;
	}
}
