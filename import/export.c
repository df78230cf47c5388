/* SPDX-License-Identifier: MIT */
#include "import/export.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "import/resample.h"

#define DEDUPE_DEG 1e-7 /* angles closer than this are one angle */

/* A growing list of angles. */
struct list {
	double *a;
	int n, cap;
};

static int add(struct list *l, double x)
{
	if (l->n == l->cap) {
		int cap = l->cap ? l->cap * 2 : 256;
		double *b = realloc(l->a, sizeof(double) * cap);

		if (!b)
			return -ENOMEM;
		l->a = b;
		l->cap = cap;
	}
	l->a[l->n++] = x;
	return 0;
}

static int cmp_double(const void *x, const void *y)
{
	const double a = *(const double *)x, b = *(const double *)y;

	return a < b ? -1 : a > b;
}

static void sort_unique(struct list *l)
{
	int m = 0;

	qsort(l->a, l->n, sizeof(double), cmp_double);
	for (int i = 0; i < l->n; i++)
		if (m == 0 || l->a[i] - l->a[m - 1] > DEDUPE_DEG)
			l->a[m++] = l->a[i];
	l->n = m;
}

/*
 * One axis: fine angles origin + i * step over [lo, hi] (wrapped into [0, 360) when wrap),
 * clipped to [full_lo, full_hi], plus the coarse frame over [full_lo, full_hi] except where it
 * falls inside the fine region.
 */
static int axis(double lo, double hi, double step, double origin, double full_lo, double full_hi,
		bool wrap, struct list *out)
{
	struct list fine = { 0 };
	int rc = 0;

	if (lo <= hi) {
		const long i0 = (long)ceil((lo - origin) / step - 1e-9);
		const long i1 = (long)floor((hi - origin) / step + 1e-9);

		for (long i = i0; i <= i1 && rc == 0; i++) {
			double x = origin + (double)i * step;

			if (wrap && x < 0.0)
				x += 360.0;
			if (wrap && x >= 360.0)
				x -= 360.0;
			if (x >= full_lo - DEDUPE_DEG && x <= full_hi + DEDUPE_DEG)
				rc = add(&fine, fmin(fmax(x, full_lo), full_hi));
		}
		if (rc < 0)
			goto out;
		sort_unique(&fine);
	}
	for (int i = 0; i < fine.n && rc == 0; i++)
		rc = add(out, fine.a[i]);
	for (int m = 0; rc == 0; m++) {
		const double x = fmin(full_lo + m * HL_EXPORT_COARSE_DEG, full_hi);
		bool inside = false;

		/* inside the fine region: between two fine angles at most 1.5 steps apart */
		for (int i = 0; i + 1 < fine.n; i++) {
			if (fine.a[i] < x && x < fine.a[i + 1] &&
			    fine.a[i + 1] - fine.a[i] <= 1.5 * step) {
				inside = true;
				break;
			}
		}
		if (!inside)
			rc = add(out, x);
		if (x >= full_hi)
			break;
	}
	if (rc == 0)
		sort_unique(out);
out:
	free(fine.a);
	return rc;
}

/* Sample (col, row) of a dense grid; zero beyond the grid, as everywhere outside it. */
static double at(const struct hl_lid_grid *g, const float *dense, int col, int row)
{
	if (col < 0 || col >= g->width || row < 0 || row >= g->height)
		return 0.0;
	return dense[(size_t)row * g->width + col];
}

/* Catmull-Rom weights for the samples at -1, 0, 1, 2 around t in [0, 1]. */
static void cr_weights(double t, double w[4])
{
	const double t2 = t * t, t3 = t2 * t;

	w[0] = 0.5 * (-t3 + 2.0 * t2 - t);
	w[1] = 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0);
	w[2] = 0.5 * (-3.0 * t3 + 4.0 * t2 + t);
	w[3] = 0.5 * (t3 - t2);
}

/*
 * The LID between its samples for export: separable Catmull-Rom (exact at the samples, smooth
 * between them, clamped at 0), zero outside the grid's range. Bilinear reconstruction would
 * carry the grid's kinks into a table in other angles, where they cost first-order accuracy
 * on the way back (docs/import.md, "Export").
 */
static double lid_lookup(const struct hl_lid_grid *g, const float *dense, double h, double v)
{
	double h0, h1, v0, v1, fx, fy, wx[4], wy[4], sum = 0.0;
	int x0, y0;

	hl_resample_grid_ends(g, &h0, &h1, &v0, &v1);
	fx = (h - h0) * (g->width - 1) / (h1 - h0);
	fy = (v1 - v) * (g->height - 1) / (v1 - v0);
	/* a table angle on a sample is exactly on it, not a rounding error beside it */
	if (fabs(fx - round(fx)) < 1e-9)
		fx = round(fx);
	if (fabs(fy - round(fy)) < 1e-9)
		fy = round(fy);
	if (!(fx >= 0.0 && fx <= g->width - 1 && fy >= 0.0 && fy <= g->height - 1))
		return 0.0;
	x0 = fx < g->width - 2 ? (int)fx : g->width - 2;
	y0 = fy < g->height - 2 ? (int)fy : g->height - 2;
	cr_weights(fx - x0, wx);
	cr_weights(fy - y0, wy);
	for (int j = 0; j < 4; j++) {
		double row = 0.0;

		for (int i = 0; i < 4; i++)
			row += wx[i] * at(g, dense, x0 - 1 + i, y0 - 1 + j);
		sum += wy[j] * row;
	}
	return sum > 0.0 ? sum : 0.0;
}

/* The LID at every (planes[i], in[j]) of a table: values[i * in->n + j]. */
static void sample_table(const struct hl_lid_grid *g, const float *dense,
			 enum hl_gonio_system system, enum hl_gonio_system own,
			 const struct list *planes, const struct list *in, float *values)
{
	for (int i = 0; i < planes->n; i++) {
		for (int j = 0; j < in->n; j++) {
			double h = planes->a[i], v = in->a[j], d[3];

			if (system != own) {
				hl_gonio_angles_to_dir(system, planes->a[i], in->a[j], d);
				hl_gonio_angles_from_dir(own, d, &h, &v);
			}
			values[(size_t)i * in->n + j] = (float)lid_lookup(g, dense, h, v);
		}
	}
}

/*
 * Refines one axis of a sampled table where the distribution curves along it: linear
 * interpolation over an interval of length h misses by about h^2 / 8 * |f''|; f'' comes from
 * the table's own divided differences. An interval is cut into n equal parts so that this
 * stays below REFINE_TOL of the value there (or of floor_cd, if larger); n <= REFINE_MAX.
 * along_planes: the axis is the plane angles (rows of values), else the in-plane angles.
 */
#define REFINE_TOL 0.001
#define REFINE_MAX 16

static int refine_axis(const struct list *axis, const struct list *other, struct list *out,
		       const float *values, bool along_planes, double floor_cd)
{
	const int n = axis->n;
	double *curv = calloc(n, sizeof(double));
	int rc = 0;

	if (!curv)
		return -ENOMEM;
	for (int i = 1; i + 1 < n; i++) {
		const double h0 = axis->a[i] - axis->a[i - 1], h1 = axis->a[i + 1] - axis->a[i];

		for (int j = 0; j < other->n; j++) {
			const size_t at0 = along_planes ? (size_t)(i - 1) * other->n + j :
							  (size_t)j * n + (i - 1);
			const size_t stride = along_planes ? (size_t)other->n : 1;
			const double f0 = values[at0], f1 = values[at0 + stride];
			const double f2 = values[at0 + 2 * stride];
			const double d2 = 2.0 * ((f2 - f1) / h1 - (f1 - f0) / h0) / (h0 + h1);

			curv[i] = fmax(curv[i], fabs(d2) / fmax(fmax(f1, floor_cd), 1e-30));
		}
	}
	for (int i = 0; i + 1 < n && rc == 0; i++) {
		const double a = axis->a[i], b = axis->a[i + 1], h = b - a;
		/* relative error of linear interpolation over h */
		const double err = h * h / 8.0 * fmax(curv[i], curv[i + 1]);
		int parts = (int)ceil(sqrt(err / REFINE_TOL));

		if (parts > REFINE_MAX)
			parts = REFINE_MAX;
		for (int m = 0; m < (parts > 1 ? parts : 1) && rc == 0; m++)
			rc = add(out, a + h * m / (parts > 1 ? parts : 1));
	}
	if (rc == 0)
		rc = add(out, axis->a[n - 1]);
	free(curv);
	return rc;
}

int hl_export_sample(const struct hl_lid *lid, int k, enum hl_gonio_system system, double step_deg,
		     struct hl_gonio **ret)
{
	const struct hl_lid_grid *g = hl_lid_grid(lid);
	const enum hl_gonio_system own = g->angles == HL_ANGLES_A ? HL_GONIO_A : HL_GONIO_B;
	double gh0, gh1, gv0, gv1, dh, dv;
	double p_lo = INFINITY, p_hi = -INFINITY, q_lo = INFINITY, q_hi = -INFINITY;
	double full_p_lo, full_p_hi, full_q_lo, full_q_hi, margin, p_origin = 0, q_origin = 0;
	struct list planes = { 0 }, in = { 0 }, new_planes = { 0 }, new_in = { 0 };
	struct hl_lid_box box;
	float *dense = NULL, *values = NULL;
	int rc;

	if (k < 0 || k >= hl_lid_n_sources(lid))
		return -EINVAL;
	hl_resample_grid_ends(g, &gh0, &gh1, &gv0, &gv1);
	dh = (gh1 - gh0) / (g->width - 1);
	dv = (gv1 - gv0) / (g->height - 1);
	if (system != HL_GONIO_A && system != HL_GONIO_B && system != HL_GONIO_C)
		return -EINVAL;
	if (step_deg <= 0.0) {
		step_deg = fmin(dh, dv);
		if (system != own)
			step_deg /= 4.0;
	}
	if (!isfinite(step_deg) || step_deg < 1e-3 || step_deg > 10.0)
		return -EINVAL;
	if (system == own && fabs(step_deg - dh) < 1e-6 * dh && fabs(step_deg - dv) < 1e-6 * dv) {
		p_origin = gh0;
		q_origin = gv0;
	}
	if (system == HL_GONIO_C) {
		full_p_lo = 0.0;
		full_p_hi = 360.0;
		full_q_lo = 0.0;
		full_q_hi = 180.0;
	} else {
		full_p_lo = full_q_lo = -90.0;
		full_p_hi = full_q_hi = 90.0;
	}

	dense = malloc(sizeof(float) * (size_t)g->width * g->height);
	if (!dense)
		return -ENOMEM;
	hl_lid_source_dense(lid, k, dense);

	/* the lit region in the table's angles (C signed, so a region around C = 0 is one) */
	hl_lid_source(lid, k, &box);
	for (int row = box.y0; row < box.y1; row++) {
		for (int col = box.x0; col < box.x1; col++) {
			double p, q;

			if (dense[(size_t)row * g->width + col] == 0.0f)
				continue;
			hl_resample_sample_angles(g, col, row, system, &p, &q);
			if (system == HL_GONIO_C && p > 180.0)
				p -= 360.0;
			p_lo = fmin(p_lo, p);
			p_hi = fmax(p_hi, p);
			q_lo = fmin(q_lo, q);
			q_hi = fmax(q_hi, q);
		}
	}
	margin = 2.0 * fmax(dh, dv) + 2.0 * step_deg;
	if (system == HL_GONIO_A) { /* type A may look beyond +-90 in H */
		full_p_lo = fmin(full_p_lo, fmax(p_lo - margin, -180.0));
		full_p_hi = fmax(full_p_hi, fmin(p_hi + margin, 180.0));
	}
	if (system == HL_GONIO_B) { /* and type B beyond +-90 in V */
		full_q_lo = fmin(full_q_lo, fmax(q_lo - margin, -180.0));
		full_q_hi = fmax(full_q_hi, fmin(q_hi + margin, 180.0));
	}
	rc = axis(p_lo - margin, p_hi + margin, step_deg, p_origin, full_p_lo, full_p_hi,
		  system == HL_GONIO_C, &planes);
	if (rc == 0)
		rc = axis(q_lo - margin, q_hi + margin, step_deg, q_origin, full_q_lo, full_q_hi,
			  false, &in);
	if (rc < 0)
		goto out;
	/*
	 * In a system whose directions are not the grid's (B for an A grid; A or C for a B grid)
	 * the table is refined where the distribution curves, so that interpolating it bilinearly
	 * stays within REFINE_TOL: sharp edges get finer angles, smooth light does not.
	 */
	if (system != own && !(system == HL_GONIO_C && own == HL_GONIO_A)) {
		const double floor_cd = 0.01 * hl_lid_peak_cd(lid, k);

		if ((long)planes.n * in.n > HL_EXPORT_MAX_VALUES) {
			rc = -EFBIG;
			goto out;
		}
		values = malloc(sizeof(float) * (size_t)planes.n * in.n);
		if (!values) {
			rc = -ENOMEM;
			goto out;
		}
		sample_table(g, dense, system, own, &planes, &in, values);
		/* both axes from the same base table; then swap the refined lists in */
		rc = refine_axis(&planes, &in, &new_planes, values, true, floor_cd);
		if (rc == 0)
			rc = refine_axis(&in, &planes, &new_in, values, false, floor_cd);
		free(values);
		values = NULL;
		if (rc < 0)
			goto out;
		free(planes.a);
		free(in.a);
		planes = new_planes;
		in = new_in;
		new_planes.a = new_in.a = NULL;
	}
	/* what the readers take back (ies.c, csv.c): at most 100000 angles, 16 Mi values */
	if (planes.n > HL_EXPORT_MAX_ANGLES || in.n > HL_EXPORT_MAX_ANGLES ||
	    (long)planes.n * in.n > HL_EXPORT_MAX_VALUES) {
		rc = -EFBIG;
		goto out;
	}
	values = malloc(sizeof(float) * (size_t)planes.n * in.n);
	if (!values) {
		rc = -ENOMEM;
		goto out;
	}
	sample_table(g, dense, system, own, &planes, &in, values);
	rc = hl_gonio_new(system, planes.n, planes.a, in.n, in.a, values, ret);
out:
	free(dense);
	free(values);
	free(planes.a);
	free(in.a);
	free(new_planes.a);
	free(new_in.a);
	return rc;
}

/* Numbers, at most per_line to a line. */
static void numbers_d(FILE *f, const double *a, int n, int per_line)
{
	for (int i = 0; i < n; i++)
		fprintf(f, "%.10g%s", a[i], (i + 1) % per_line == 0 || i + 1 == n ? "\n" : " ");
}

static void numbers_f(FILE *f, const float *a, int n, int per_line)
{
	for (int i = 0; i < n; i++)
		fprintf(f, "%.9g%s", (double)a[i],
			(i + 1) % per_line == 0 || i + 1 == n ? "\n" : " ");
}

/* A keyword value on one line of at most 256 characters, no line breaks. */
static void keyword(FILE *f, const char *key, const char *value)
{
	char clean[200];
	size_t j = 0;

	for (size_t i = 0; value[i] && j + 1 < sizeof(clean); i++)
		clean[j++] = (value[i] == '\n' || value[i] == '\r') ? ' ' : value[i];
	clean[j] = '\0';
	fprintf(f, "[%s] %s\n", key, clean);
}

/* The stream's write error as -errno (ENOSPC on a full disk), -EIO when it kept none. */
static int finish(FILE *f)
{
	errno = 0;
	if (fflush(f) == 0 && !ferror(f))
		return 0;
	return errno ? -errno : -EIO;
}

int hl_export_ies(const struct hl_gonio *g, const struct hl_export_meta *meta, FILE *f)
{
	const enum hl_gonio_system s = hl_gonio_system(g);
	const int n_p = hl_gonio_n_planes(g), n_q = hl_gonio_n_in(g);
	const int type = s == HL_GONIO_C ? 1 : s == HL_GONIO_B ? 2 : 3;

	fprintf(f, "IES:LM-63-2019\n");
	keyword(f, "TEST", "hdlamp lid export");
	keyword(f, "TESTLAB", "hdlamp (resampled LID, not a measurement)");
	keyword(f, "ISSUEDATE", meta && meta->issue_date ? meta->issue_date : "unknown");
	keyword(f, "MANUFAC", "hdlamp");
	if (meta && meta->name)
		keyword(f, "LUMCAT", meta->name);
	if (meta && meta->origin)
		keyword(f, "LUMINAIRE", meta->origin);
	if (s == HL_GONIO_C)
		keyword(f, "_HDLAMP_ANGLES",
			"type C, gamma from the nadir, C0 forward (+z), C90 left (-x)");
	else
		keyword(f, "_HDLAMP_ANGLES",
			s == HL_GONIO_A ? "type A, H positive right, V positive up" :
					  "type B, H positive right, V positive up");
	fprintf(f, "TILT=NONE\n");
	/* one lamp, absolute photometry, multiplier 1, metres, no luminous opening */
	fprintf(f, "1 -1 1 %d %d %d 2 0 0 0\n", n_q, n_p, type);
	fprintf(f, "1 1 0\n");
	numbers_d(f, hl_gonio_in(g), n_q, 10);
	numbers_d(f, hl_gonio_planes(g), n_p, 10);
	for (int i = 0; i < n_p; i++)
		numbers_f(f, hl_gonio_values(g) + (size_t)i * n_q, n_q, 10);
	return finish(f);
	return 0;
}

int hl_export_csv(const struct hl_gonio *g, const struct hl_export_meta *meta, FILE *f)
{
	const enum hl_gonio_system s = hl_gonio_system(g);
	const int n_p = hl_gonio_n_planes(g), n_q = hl_gonio_n_in(g);
	const double *p = hl_gonio_planes(g), *q = hl_gonio_in(g);
	const float *v = hl_gonio_values(g);

	fputs("# hdlamp lid export", f);
	if (meta && meta->name) {
		/* one comment line: a line break in the name would start a data row */
		fputs(" of ", f);
		for (const char *c = meta->name; *c; c++)
			fputc(*c == '\n' || *c == '\r' ? ' ' : *c, f);
	}
	fputs(": luminous intensity in cd\n", f);
	if (s == HL_GONIO_C)
		fprintf(f, "# type C: columns C (deg, C0 forward, C90 left), rows gamma (deg, "
			   "0 = nadir)\n");
	else
		fprintf(f,
			"# type %c: columns H (deg, positive right), rows V (deg, positive "
			"up)\n",
			hl_gonio_system_letter(s));
	fputc(hl_gonio_system_letter(s), f);
	for (int i = 0; i < n_p; i++)
		fprintf(f, ",%.10g", p[i]);
	fputc('\n', f);
	for (int j = n_q - 1; j >= 0; j--) {
		fprintf(f, "%.10g", q[j]);
		for (int i = 0; i < n_p; i++)
			fprintf(f, ",%.9g", (double)v[(size_t)i * n_q + j]);
		fputc('\n', f);
	}
	return finish(f);
	return 0;
}
