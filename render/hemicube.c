/* SPDX-License-Identifier: MIT */
#include "render/hemicube.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>

struct hl_hemicube {
	int size;
	size_t n;
	float *dirs;
	double *weights;
};

/*
 * Antiderivative of 1 / (1 + x^2 + y^2)^2 in x and y (odd in each): the corner form of the
 * differential-area-to-parallel-rectangle form factor times pi.
 */
static double front_corner(double x, double y)
{
	const double ax = sqrt(1.0 + x * x), ay = sqrt(1.0 + y * y);

	return 0.5 * (x / ax * atan(y / ax) + y / ay * atan(x / ay));
}

/* Antiderivative of z / (1 + y^2 + z^2)^2 in y and z. */
static double side_corner(double y, double z)
{
	const double a = sqrt(1.0 + z * z);

	return -0.5 * atan(y / a) / a;
}

double hl_hemicube_front_patch(double x0, double x1, double y0, double y1)
{
	return front_corner(x1, y1) - front_corner(x0, y1) - front_corner(x1, y0) +
	       front_corner(x0, y0);
}

double hl_hemicube_side_patch(double y0, double y1, double z0, double z1)
{
	return side_corner(y1, z1) - side_corner(y0, z1) - side_corner(y1, z0) +
	       side_corner(y0, z0);
}

static void put(struct hl_hemicube *h, size_t i, double x, double y, double z, double w)
{
	const double r = sqrt(x * x + y * y + z * z);

	h->dirs[3 * i + 0] = (float)(x / r);
	h->dirs[3 * i + 1] = (float)(y / r);
	h->dirs[3 * i + 2] = (float)(z / r);
	h->weights[i] = w;
}

int hl_hemicube_new(int size, struct hl_hemicube **ret)
{
	struct hl_hemicube *h;
	const double step = 2.0 / size;
	size_t i = 0;

	if (size < 2 || size > HL_HEMICUBE_MAX_SIZE || size % 2)
		return -EINVAL;
	h = calloc(1, sizeof(*h));
	if (!h)
		return -ENOMEM;
	h->size = size;
	h->n = 3 * (size_t)size * size;
	h->dirs = malloc(sizeof(float) * 3 * h->n);
	h->weights = malloc(sizeof(double) * h->n);
	if (!h->dirs || !h->weights) {
		hl_hemicube_free(h);
		return -ENOMEM;
	}
	/* Front face: texel (col, row) covers [-1 + col step, ...] in x and y. */
	for (int row = 0; row < size; row++)
		for (int col = 0; col < size; col++) {
			const double x0 = -1.0 + col * step, y0 = -1.0 + row * step;

			put(h, i++, x0 + step / 2, y0 + step / 2, 1.0,
			    hl_hemicube_front_patch(x0, x0 + step, y0, y0 + step));
		}
	/*
	 * Side faces x = +1, x = -1, y = +1, y = -1: u runs along the face in [-1, 1], the
	 * height z in [0, 1]; all four have the same weights by symmetry.
	 */
	for (int face = 0; face < 4; face++)
		for (int row = 0; row < size / 2; row++)
			for (int col = 0; col < size; col++) {
				const double u0 = -1.0 + col * step, z0 = row * step;
				const double u = u0 + step / 2, z = z0 + step / 2;
				const double w =
					hl_hemicube_side_patch(u0, u0 + step, z0, z0 + step);

				switch (face) {
				case 0:
					put(h, i++, 1.0, u, z, w);
					break;
				case 1:
					put(h, i++, -1.0, u, z, w);
					break;
				case 2:
					put(h, i++, u, 1.0, z, w);
					break;
				default:
					put(h, i++, u, -1.0, z, w);
					break;
				}
			}
	*ret = h;
	return 0;
}

void hl_hemicube_free(struct hl_hemicube *h)
{
	if (!h)
		return;
	free(h->dirs);
	free(h->weights);
	free(h);
}

int hl_hemicube_size(const struct hl_hemicube *h)
{
	return h->size;
}

size_t hl_hemicube_texels(const struct hl_hemicube *h)
{
	return h->n;
}

const float *hl_hemicube_dirs(const struct hl_hemicube *h)
{
	return h->dirs;
}

const double *hl_hemicube_weights(const struct hl_hemicube *h)
{
	return h->weights;
}

void hl_hemicube_subdir(const struct hl_hemicube *h, size_t i, int su, int sv, int s, double ret[3])
{
	const int n = h->size;
	const double step = 2.0 / n;
	const double fu = (su + 0.5) / s * step, fv = (sv + 0.5) / s * step;
	size_t j;
	double u, z;

	if (i < (size_t)n * n) {
		ret[0] = -1.0 + (double)(i % n) * step + fu;
		ret[1] = -1.0 + (double)(i / n) * step + fv;
		ret[2] = 1.0;
		return;
	}
	j = i - (size_t)n * n;
	u = -1.0 + (double)(j % n) * step + fu;
	z = (double)((j % ((size_t)n * n / 2)) / n) * step + fv;
	switch (j / ((size_t)n * n / 2)) {
	case 0:
		ret[0] = 1.0, ret[1] = u;
		break;
	case 1:
		ret[0] = -1.0, ret[1] = u;
		break;
	case 2:
		ret[0] = u, ret[1] = 1.0;
		break;
	default:
		ret[0] = u, ret[1] = -1.0;
		break;
	}
	ret[2] = z;
}

double hl_hemicube_texel_radius(const struct hl_hemicube *h)
{
	/* Half the texel diagonal, seen from at least unit distance. */
	return M_SQRT2 / h->size;
}

void hl_hemicube_frame(const double n[3], double t[3], double b[3])
{
	/* The world axis least aligned with n, crossed with n. */
	const double ax = fabs(n[0]), ay = fabs(n[1]), az = fabs(n[2]);
	double a[3] = { 0, 0, 0 }, len;

	if (ax <= ay && ax <= az)
		a[0] = 1.0;
	else if (ay <= az)
		a[1] = 1.0;
	else
		a[2] = 1.0;
	/* t = a x n, normalised; b = n x t. */
	t[0] = a[1] * n[2] - a[2] * n[1];
	t[1] = a[2] * n[0] - a[0] * n[2];
	t[2] = a[0] * n[1] - a[1] * n[0];
	len = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
	for (int i = 0; i < 3; i++)
		t[i] /= len;
	b[0] = n[1] * t[2] - n[2] * t[1];
	b[1] = n[2] * t[0] - n[0] * t[2];
	b[2] = n[0] * t[1] - n[1] * t[0];
}
