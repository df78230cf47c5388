/* SPDX-License-Identifier: MIT */
#include "import/gonio.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "lamp/angles.h"
#include "import/typec.h"

#define DEG (M_PI / 180.0)

struct hl_gonio {
	enum hl_gonio_system system;
	int n_planes, n_in;
	double *planes, *in;
	float *values; /* [plane][in] */
	float peak_cd;
	bool periodic; /* type C planes span exactly 360 degrees */
};

/* Plane and in-plane angle ranges of each system, degrees (see gonio.h). */
static const struct {
	double p_lo, p_hi, i_lo, i_hi;
} ranges[] = {
	[HL_GONIO_A] = { -180.0, 180.0, -90.0, 90.0 },
	[HL_GONIO_B] = { -90.0, 90.0, -180.0, 180.0 },
	[HL_GONIO_C] = { 0.0, 360.0, 0.0, 180.0 },
};

static bool increasing_in(const double *a, int n, double lo, double hi)
{
	for (int i = 0; i < n; i++) {
		if (!isfinite(a[i]) || a[i] < lo || a[i] > hi)
			return false;
		if (i > 0 && !(a[i] > a[i - 1]))
			return false;
	}
	return true;
}

int hl_gonio_new(enum hl_gonio_system system, int n_planes, const double *planes, int n_in,
		 const double *in, const float *values, struct hl_gonio **ret)
{
	const size_t n = (size_t)n_planes * (size_t)n_in;
	double p_lo, p_hi, i_lo, i_hi;
	struct hl_gonio *g;
	float peak = 0.0f;

	if (system != HL_GONIO_A && system != HL_GONIO_B && system != HL_GONIO_C)
		return -EINVAL;
	if (n_planes < 2 || n_in < 2)
		return -EINVAL;
	p_lo = ranges[system].p_lo;
	p_hi = ranges[system].p_hi;
	i_lo = ranges[system].i_lo;
	i_hi = ranges[system].i_hi;
	/* a periodic type C table may start anywhere in 0..360 and span up to 360 */
	if (system == HL_GONIO_C)
		p_hi = planes[0] + 360.0;
	if (!increasing_in(planes, n_planes, p_lo, p_hi) || !increasing_in(in, n_in, i_lo, i_hi))
		return -EINVAL;
	if (system == HL_GONIO_C && planes[0] >= 360.0)
		return -EINVAL;
	for (size_t k = 0; k < n; k++) {
		if (!isfinite(values[k]) || values[k] < 0.0f)
			return -EINVAL;
		if (values[k] > peak)
			peak = values[k];
	}
	g = calloc(1, sizeof(*g));
	if (!g)
		return -ENOMEM;
	g->planes = malloc(sizeof(double) * n_planes);
	g->in = malloc(sizeof(double) * n_in);
	g->values = malloc(sizeof(float) * n);
	if (!g->planes || !g->in || !g->values) {
		hl_gonio_free(g);
		return -ENOMEM;
	}
	memcpy(g->planes, planes, sizeof(double) * n_planes);
	memcpy(g->in, in, sizeof(double) * n_in);
	memcpy(g->values, values, sizeof(float) * n);
	g->system = system;
	g->n_planes = n_planes;
	g->n_in = n_in;
	g->peak_cd = peak;
	g->periodic = system == HL_GONIO_C && planes[n_planes - 1] - planes[0] == 360.0;
	*ret = g;
	return 0;
}

/* Builds a table from (angle, source plane) pairs: the expanded plane list of a symmetry. */
struct expansion {
	int n;
	double *angles;
	int *from;
};

static void push(struct expansion *e, double angle, int from)
{
	e->angles[e->n] = angle;
	e->from[e->n] = from;
	e->n++;
}

static int build(enum hl_gonio_system system, const struct expansion *e, int n_in, const double *in,
		 const float *values, struct hl_gonio **ret)
{
	float *v = malloc(sizeof(float) * (size_t)e->n * n_in);
	int rc;

	if (!v)
		return -ENOMEM;
	for (int i = 0; i < e->n; i++)
		memcpy(v + (size_t)i * n_in, values + (size_t)e->from[i] * n_in,
		       sizeof(float) * n_in);
	rc = hl_gonio_new(system, e->n, e->angles, n_in, in, v, ret);
	free(v);
	return rc;
}

int hl_gonio_new_c(enum hl_gonio_csym sym, int n_planes, const double *p, int n_in,
		   const double *in, const float *values, struct hl_gonio **ret)
{
	struct expansion e = { 0, NULL, NULL };
	const int last = n_planes - 1;
	int rc = -EINVAL;

	if (n_planes < 1)
		return -EINVAL;
	e.angles = malloc(sizeof(double) * (4 * (size_t)n_planes + 2));
	e.from = malloc(sizeof(int) * (4 * (size_t)n_planes + 2));
	if (!e.angles || !e.from) {
		rc = -ENOMEM;
		goto out;
	}
	switch (sym) {
	case HL_GONIO_CSYM_ROTATIONAL:
		if (n_planes != 1)
			goto out;
		push(&e, 0.0, 0);
		push(&e, 360.0, 0);
		break;
	case HL_GONIO_CSYM_QUADRANT:
		if (p[0] != 0.0 || p[last] != 90.0)
			goto out;
		for (int i = 0; i <= last; i++)
			push(&e, p[i], i); /* 0..90 */
		for (int i = last - 1; i >= 0; i--)
			push(&e, 180.0 - p[i], i); /* 90..180 */
		for (int i = 1; i <= last; i++)
			push(&e, 180.0 + p[i], i); /* 180..270 */
		for (int i = last - 1; i >= 0; i--)
			push(&e, 360.0 - p[i], i); /* 270..360 */
		break;
	case HL_GONIO_CSYM_C0_C180:
		if (p[0] != 0.0 || p[last] != 180.0)
			goto out;
		for (int i = 0; i <= last; i++)
			push(&e, p[i], i);
		for (int i = last - 1; i >= 0; i--)
			push(&e, 360.0 - p[i], i);
		break;
	case HL_GONIO_CSYM_C90_C270:
		/* I(C) = I(180 - C): the planes 90..270 and their mirror 270..450 */
		if (p[0] != 90.0 || p[last] != 270.0)
			goto out;
		for (int i = 0; i <= last; i++)
			push(&e, p[i], i);
		/* 270..450; 450 closes the circle (it is 90), so the table is periodic */
		for (int i = last - 1; i >= 0; i--)
			push(&e, 540.0 - p[i], i);
		break;
	case HL_GONIO_CSYM_NONE:
		if (n_planes < 2 || p[0] != 0.0 || !(p[last] > 180.0) || p[last] > 360.0)
			goto out;
		for (int i = 0; i <= last; i++)
			push(&e, p[i], i);
		if (p[last] < 360.0)
			push(&e, 360.0, 0);
		break;
	default:
		goto out;
	}
	rc = build(HL_GONIO_C, &e, n_in, in, values, ret);
out:
	free(e.angles);
	free(e.from);
	return rc;
}

int hl_gonio_new_lateral(enum hl_gonio_system system, int n_planes, const double *p, int n_in,
			 const double *in, const float *values, struct hl_gonio **ret)
{
	struct expansion e = { 0, NULL, NULL };
	int rc;

	if (system == HL_GONIO_C || n_planes < 2 || p[0] != 0.0)
		return -EINVAL;
	e.angles = malloc(sizeof(double) * 2 * (size_t)n_planes);
	e.from = malloc(sizeof(int) * 2 * (size_t)n_planes);
	if (!e.angles || !e.from) {
		rc = -ENOMEM;
		goto out;
	}
	for (int i = n_planes - 1; i >= 1; i--)
		push(&e, -p[i], i);
	for (int i = 0; i < n_planes; i++)
		push(&e, p[i], i);
	rc = build(system, &e, n_in, in, values, ret);
out:
	free(e.angles);
	free(e.from);
	return rc;
}

void hl_gonio_free(struct hl_gonio *g)
{
	if (!g)
		return;
	free(g->planes);
	free(g->in);
	free(g->values);
	free(g);
}

enum hl_gonio_system hl_gonio_system(const struct hl_gonio *g)
{
	return g->system;
}

int hl_gonio_n_planes(const struct hl_gonio *g)
{
	return g->n_planes;
}

int hl_gonio_n_in(const struct hl_gonio *g)
{
	return g->n_in;
}

const double *hl_gonio_planes(const struct hl_gonio *g)
{
	return g->planes;
}

const double *hl_gonio_in(const struct hl_gonio *g)
{
	return g->in;
}

const float *hl_gonio_values(const struct hl_gonio *g)
{
	return g->values;
}

float hl_gonio_peak_cd(const struct hl_gonio *g)
{
	return g->peak_cd;
}

/*
 * Interval of x in the increasing array a[0..n): index i with a[i] <= x <= a[i + 1] and the
 * fraction t in [0, 1]. False outside [a[0], a[n - 1]].
 */
static bool locate(const double *a, int n, double x, int *ret_i, double *ret_t)
{
	int lo = 0, hi = n - 1;

	if (!(x >= a[0] && x <= a[n - 1]))
		return false;
	while (hi - lo > 1) {
		int mid = lo + (hi - lo) / 2;

		if (a[mid] <= x)
			lo = mid;
		else
			hi = mid;
	}
	*ret_i = lo;
	*ret_t = (x - a[lo]) / (a[lo + 1] - a[lo]);
	return true;
}

double hl_gonio_lookup(const struct hl_gonio *g, double p, double q)
{
	int i, j;
	double s, t;
	const float *r0, *r1;

	if (g->system == HL_GONIO_C) {
		/* C is an azimuth: bring it into [planes[0], planes[0] + 360) */
		p = fmod(p - g->planes[0], 360.0);
		if (p < 0.0)
			p += 360.0;
		p += g->planes[0];
	}
	if (!locate(g->planes, g->n_planes, p, &i, &s) || !locate(g->in, g->n_in, q, &j, &t))
		return 0.0;
	r0 = g->values + (size_t)i * g->n_in;
	r1 = r0 + g->n_in;
	return (1.0 - s) * ((1.0 - t) * r0[j] + t * r0[j + 1]) +
	       s * ((1.0 - t) * r1[j] + t * r1[j + 1]);
}

void hl_gonio_angles_from_dir(enum hl_gonio_system system, const double d[3], double *ret_plane_deg,
			      double *ret_in_deg)
{
	double a, b;

	if (system == HL_GONIO_C) {
		hl_typec_from_dir(d, &a, &b);
	} else {
		hl_angles_from_dir(system == HL_GONIO_A ? HL_ANGLES_A : HL_ANGLES_B, d, &a, &b);
	}
	*ret_plane_deg = a / DEG;
	*ret_in_deg = b / DEG;
}

void hl_gonio_angles_to_dir(enum hl_gonio_system system, double plane_deg, double in_deg,
			    double ret_d[3])
{
	if (system == HL_GONIO_C)
		hl_typec_to_dir(plane_deg * DEG, in_deg * DEG, ret_d);
	else
		hl_angles_to_dir(system == HL_GONIO_A ? HL_ANGLES_A : HL_ANGLES_B, plane_deg * DEG,
				 in_deg * DEG, ret_d);
}

double hl_gonio_lookup_dir(const struct hl_gonio *g, const double d[3])
{
	double p, q;

	hl_gonio_angles_from_dir(g->system, d, &p, &q);
	return hl_gonio_lookup(g, p, q);
}

char hl_gonio_system_letter(enum hl_gonio_system system)
{
	return system == HL_GONIO_A ? 'A' : system == HL_GONIO_B ? 'B' : 'C';
}
