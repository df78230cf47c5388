/* SPDX-License-Identifier: MIT */
/* The verdict evaluator: requirement kinds planned once on a grid, weighted sums per frame. */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "lamp/angles.h"
#include "verdict/verdict.h"

#define DEG (M_PI / 180.0)
#define LINE_STEP_DEG 0.1 /* positions along a segment and a zone's edges */
#define ZONE_STEP_DEG 0.1 /* the lattice inside a zone (or half the receiver, if larger) */
#define SQUARE_Q 4 /* quadrature points per side of a square receiver */
#define CIRCLE_Q 8 /* lattice per side over a circular receiver's bounding square */
#define MAX_QUAD (CIRCLE_Q * CIRCLE_Q)
#define MAX_TAPS (4 * MAX_QUAD) /* before merging equal samples */

#define CHUNK_POS 64 /* positions per chunk of a segment or zone */
#define TILE 8 /* a zone's lattice in TILE x TILE tiles: compact chunks */
#define BOUNDS_KEPT 1024 /* chunk bounds kept on the stack during one requirement */

struct plan_req {
	uint32_t first_pos, n_pos;
	int n_outside;
	uint32_t first_chunk, n_chunks; /* segments and zones */
};

/*
 * Consecutive positions of a segment or zone and the union of the samples their receivers read
 * (the footprint). The receiver's mean is a weighted mean with weights summing to at most 1 of
 * non-negative samples, so no position of a chunk reads more than the footprint's largest
 * sample: a chunk whose bound cannot beat the highest value found so far is skipped.
 */
struct chunk {
	uint32_t first_pos, n_pos;
	uint32_t first_fp, n_fp; /* into fp_idx */
};

struct hl_verdict {
	const struct hl_regulation *reg;
	struct hl_lid_grid grid;
	struct hl_verdict_options opts;
	size_t n_samples;
	struct plan_req *req;
	/* positions: where (regulation frame, traffic applied) and their taps */
	uint32_t n_pos, cap_pos;
	float *pos_h, *pos_v;
	uint32_t *pos_tap; /* n_pos + 1 offsets into the taps */
	uint32_t n_taps, cap_taps;
	uint32_t *tap_idx;
	float *tap_w;
	struct chunk *chunks;
	uint32_t n_chunks, cap_chunks;
	uint32_t *fp_idx;
	uint32_t n_fp, cap_fp;
};

struct quad {
	int n;
	double dh[MAX_QUAD], dv[MAX_QUAD];
};

static void quadrature(enum hl_receiver_shape shape, double size, struct quad *q)
{
	q->n = 0;
	if (shape == HL_RECEIVER_SQUARE) {
		for (int i = 0; i < SQUARE_Q; i++)
			for (int j = 0; j < SQUARE_Q; j++) {
				q->dh[q->n] = ((j + 0.5) / SQUARE_Q - 0.5) * size;
				q->dv[q->n++] = ((i + 0.5) / SQUARE_Q - 0.5) * size;
			}
		return;
	}
	for (int i = 0; i < CIRCLE_Q; i++)
		for (int j = 0; j < CIRCLE_Q; j++) {
			const double x = ((j + 0.5) / CIRCLE_Q - 0.5),
				     y = ((i + 0.5) / CIRCLE_Q - 0.5);

			if (x * x + y * y <= 0.25) {
				q->dh[q->n] = x * size;
				q->dv[q->n++] = y * size;
			}
		}
}

/* Grid coordinates of a direction given in the regulation frame; false when outside. */
static bool to_grid(const struct hl_verdict *v, double h_deg, double v_deg, double *ret_fx,
		    double *ret_fy)
{
	const struct hl_lid_grid *g = &v->grid;
	double h = h_deg - v->opts.aim_h_deg, vv = v_deg - v->opts.aim_v_deg;

	if (v->reg->angles != g->angles) {
		double d[3], hr, vr;

		hl_angles_to_dir(v->reg->angles, h * DEG, vv * DEG, d);
		hl_angles_from_dir(g->angles, d, &hr, &vr);
		h = hr / DEG;
		vv = vr / DEG;
	}
	*ret_fx = (h - g->h_first_deg) * (g->width - 1) / (g->h_last_deg - g->h_first_deg);
	*ret_fy = (g->v_last_deg - vv) * (g->height - 1) / (g->v_last_deg - g->v_first_deg);
	return *ret_fx >= 0.0 && *ret_fx <= g->width - 1 && *ret_fy >= 0.0 &&
	       *ret_fy <= g->height - 1;
}

static int grow(void **p, size_t elem, uint32_t *cap, uint32_t need)
{
	void *t;
	uint32_t c = *cap ? *cap : 1024;

	if (need <= *cap)
		return 0;
	while (c < need)
		c *= 2;
	t = realloc(*p, (size_t)c * elem);
	if (!t)
		return -ENOMEM;
	*p = t;
	return 0;
}

/* Room for need positions (and need + 1 tap offsets). */
static int reserve_pos(struct hl_verdict *v, uint32_t need)
{
	uint32_t c = v->cap_pos ? v->cap_pos : 1024;
	void *h, *vv, *t;

	if (need <= v->cap_pos)
		return 0;
	while (c < need)
		c *= 2;
	h = realloc(v->pos_h, (size_t)c * sizeof(float));
	if (h)
		v->pos_h = h;
	vv = realloc(v->pos_v, (size_t)c * sizeof(float));
	if (vv)
		v->pos_v = vv;
	t = realloc(v->pos_tap, ((size_t)c + 1) * sizeof(uint32_t));
	if (t)
		v->pos_tap = t;
	if (!h || !vv || !t)
		return -ENOMEM;
	v->cap_pos = c;
	return 0;
}

static int reserve_taps(struct hl_verdict *v, uint32_t need)
{
	uint32_t cap = v->cap_taps;

	if (grow((void **)&v->tap_idx, sizeof(uint32_t), &cap, need) < 0)
		return -ENOMEM;
	cap = v->cap_taps;
	if (grow((void **)&v->tap_w, sizeof(float), &cap, need) < 0)
		return -ENOMEM;
	v->cap_taps = cap;
	return 0;
}

/*
 * Adds the position (h, v): the receiver's quadrature, each point's bilinear taps as
 * hl_lid_grid_lookup() weighs them, equal samples merged. Returns 1 added, 0 outside the grid,
 * -ENOMEM.
 */
static int add_position(struct hl_verdict *v, const struct quad *q, double h, double vv)
{
	const struct hl_lid_grid *g = &v->grid;
	uint32_t idx[MAX_TAPS];
	float w[MAX_TAPS];
	int n = 0;
	double fx, fy;

	if (!to_grid(v, h, vv, &fx, &fy))
		return 0;
	for (int k = 0; k < q->n; k++) {
		int x0, y0;
		double tx, ty;
		const double qw = 1.0 / q->n;

		if (!to_grid(v, h + q->dh[k], vv + q->dv[k], &fx, &fy))
			continue; /* zero there, as the lookup is */
		x0 = (int)fx;
		y0 = (int)fy;
		if (x0 > g->width - 2)
			x0 = g->width - 2;
		if (y0 > g->height - 2)
			y0 = g->height - 2;
		tx = fx - x0;
		ty = fy - y0;
		const uint32_t i00 = (uint32_t)y0 * g->width + x0;
		const uint32_t ti[4] = { i00, i00 + 1, i00 + g->width, i00 + g->width + 1 };
		const double tw[4] = { (1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty };

		for (int t = 0; t < 4; t++) {
			int m;

			if (tw[t] == 0.0)
				continue;
			for (m = 0; m < n && idx[m] != ti[t]; m++)
				;
			if (m == n) {
				idx[n] = ti[t];
				w[n++] = 0.0f;
			}
			w[m] += (float)(tw[t] * qw);
		}
	}
	if (reserve_pos(v, v->n_pos + 1) < 0 || reserve_taps(v, v->n_taps + n) < 0)
		return -ENOMEM;
	memcpy(v->tap_idx + v->n_taps, idx, n * sizeof(*idx));
	memcpy(v->tap_w + v->n_taps, w, n * sizeof(*w));
	v->pos_h[v->n_pos] = (float)h;
	v->pos_v[v->n_pos] = (float)vv;
	v->pos_tap[v->n_pos] = v->n_taps;
	v->n_taps += n;
	v->n_pos++;
	v->pos_tap[v->n_pos] = v->n_taps;
	return 1;
}

/* Counts a position outside the grid, or adds it. */
static int position(struct hl_verdict *v, struct plan_req *pr, const struct quad *q, double h,
		    double vv)
{
	const int rc = add_position(v, q, h, vv);

	if (rc < 0)
		return rc;
	if (rc == 0)
		pr->n_outside++;
	else
		pr->n_pos++;
	return 0;
}

/* A file's angle pair in the evaluated frame: traffic mirrored, open ends at the grid's edges. */
static void resolve(const struct hl_verdict *v, const double p[2], double ret[2])
{
	const struct hl_lid_grid *g = &v->grid;
	const double inset = v->reg->receiver_deg / 2;
	double h = p[0];

	if (v->opts.traffic == HL_TRAFFIC_LEFT)
		h = h == HL_REG_OPEN_LEFT  ? HL_REG_OPEN_RIGHT :
		    h == HL_REG_OPEN_RIGHT ? HL_REG_OPEN_LEFT :
					     -h;
	ret[0] = h == HL_REG_OPEN_LEFT	? g->h_first_deg + v->opts.aim_h_deg + inset :
		 h == HL_REG_OPEN_RIGHT ? g->h_last_deg + v->opts.aim_h_deg - inset :
					  h;
	ret[1] = p[1] == HL_REG_OPEN_DOWN ? g->v_first_deg + v->opts.aim_v_deg + inset :
		 p[1] == HL_REG_OPEN_UP	  ? g->v_last_deg + v->opts.aim_v_deg - inset :
					    p[1];
}

static int plan_line(struct hl_verdict *v, struct plan_req *pr, const struct quad *q,
		     const double a[2], const double b[2])
{
	const double len = hypot(b[0] - a[0], b[1] - a[1]);
	const int n = (int)ceil(len / LINE_STEP_DEG - 1e-9) + 1;

	for (int k = 0; k < n; k++) {
		const double t = n > 1 ? (double)k / (n - 1) : 0.0;
		const int rc =
			position(v, pr, q, a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]));

		if (rc < 0)
			return rc;
	}
	return 0;
}

/* Inside or on the polygon (even-odd rule, edges within 1e-9° count as inside). */
static bool in_polygon(const double (*pts)[2], int n, double x, double y)
{
	bool in = false;

	for (int i = 0, j = n - 1; i < n; j = i++) {
		const double xi = pts[i][0], yi = pts[i][1], xj = pts[j][0], yj = pts[j][1];
		const double cross = (xj - xi) * (y - yi) - (yj - yi) * (x - xi);

		if (fabs(cross) < 1e-9 && x >= fmin(xi, xj) - 1e-9 && x <= fmax(xi, xj) + 1e-9 &&
		    y >= fmin(yi, yj) - 1e-9 && y <= fmax(yi, yj) + 1e-9)
			return true;
		if ((yi > y) != (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi)
			in = !in;
	}
	return in;
}

static int plan_zone(struct hl_verdict *v, struct plan_req *pr, const struct quad *q,
		     const struct hl_requirement *r)
{
	const double step = fmax(ZONE_STEP_DEG, v->reg->receiver_deg / 2);
	double pts[HL_REG_MAX_VERTICES][2], lo[2] = { 1e9, 1e9 }, hi[2] = { -1e9, -1e9 };
	int rc;

	for (int k = 0; k < r->n_pts; k++) {
		resolve(v, r->pts[k], pts[k]);
		for (int a = 0; a < 2; a++) {
			lo[a] = fmin(lo[a], pts[k][a]);
			hi[a] = fmax(hi[a], pts[k][a]);
		}
	}
	const long y0 = lround(ceil(lo[1] / step - 1e-9)), y1 = lround(floor(hi[1] / step + 1e-9));
	const long x0 = lround(ceil(lo[0] / step - 1e-9)), x1 = lround(floor(hi[0] / step + 1e-9));

	/* the lattice tile by tile, so that consecutive positions are neighbours (chunks) */
	for (long ty = y0; ty <= y1; ty += TILE)
		for (long tx = x0; tx <= x1; tx += TILE)
			for (long iy = ty; iy < ty + TILE && iy <= y1; iy++)
				for (long ix = tx; ix < tx + TILE && ix <= x1; ix++) {
					const double x = ix * step, y = iy * step;

					if (!in_polygon((const double(*)[2])pts, r->n_pts, x, y))
						continue;
					rc = position(v, pr, q, x, y);
					if (rc < 0)
						return rc;
				}
	for (int k = 0; k < r->n_pts; k++) {
		rc = plan_line(v, pr, q, pts[k], pts[(k + 1) % r->n_pts]);
		if (rc < 0)
			return rc;
	}
	return 0;
}

static int cmp_u32(const void *a, const void *b)
{
	const uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;

	return (x > y) - (x < y);
}

/* Cuts a segment's or zone's positions into chunks with their footprints. */
static int plan_chunks(struct hl_verdict *v, struct plan_req *pr)
{
	uint32_t tmp[CHUNK_POS * MAX_TAPS];

	pr->first_chunk = v->n_chunks;
	for (uint32_t p0 = pr->first_pos; p0 < pr->first_pos + pr->n_pos; p0 += CHUNK_POS) {
		const uint32_t end = p0 + CHUNK_POS < pr->first_pos + pr->n_pos ?
					     p0 + CHUNK_POS :
					     pr->first_pos + pr->n_pos;
		const uint32_t t0 = v->pos_tap[p0], t1 = v->pos_tap[end];
		uint32_t n = 0;
		struct chunk *c;

		for (uint32_t t = t0; t < t1; t++)
			tmp[n++] = v->tap_idx[t];
		qsort(tmp, n, sizeof(*tmp), cmp_u32);
		{
			uint32_t u = 0;

			for (uint32_t k = 0; k < n; k++)
				if (!u || tmp[u - 1] != tmp[k])
					tmp[u++] = tmp[k];
			n = u;
		}
		if (v->n_chunks == v->cap_chunks) {
			const uint32_t cap = v->cap_chunks ? 2 * v->cap_chunks : 64;
			void *t = realloc(v->chunks, cap * sizeof(*v->chunks));

			if (!t)
				return -ENOMEM;
			v->chunks = t;
			v->cap_chunks = cap;
		}
		if (v->n_fp + n > v->cap_fp) {
			uint32_t cap = v->cap_fp ? v->cap_fp : 4096;
			void *t;

			while (cap < v->n_fp + n)
				cap *= 2;
			t = realloc(v->fp_idx, (size_t)cap * sizeof(*v->fp_idx));
			if (!t)
				return -ENOMEM;
			v->fp_idx = t;
			v->cap_fp = cap;
		}
		memcpy(v->fp_idx + v->n_fp, tmp, n * sizeof(*tmp));
		c = &v->chunks[v->n_chunks++];
		*c = (struct chunk){ p0, end - p0, v->n_fp, n };
		v->n_fp += n;
	}
	pr->n_chunks = v->n_chunks - pr->first_chunk;
	return 0;
}

static int plan(struct hl_verdict *v)
{
	struct quad q;

	quadrature(v->reg->receiver, v->reg->receiver_deg, &q);
	if (reserve_pos(v, 1) < 0)
		return -ENOMEM;
	v->pos_tap[0] = 0;
	for (int i = 0; i < v->reg->n_requirements; i++) {
		const struct hl_requirement *r = &v->reg->req[i];
		struct plan_req *pr = &v->req[i];
		double a[2], b[2];
		int rc = 0;

		pr->first_pos = v->n_pos;
		switch (r->kind) {
		case HL_REQ_POINT:
		case HL_REQ_SUM:
			for (int k = 0; k < r->n_pts && rc >= 0; k++) {
				resolve(v, r->pts[k], a);
				rc = position(v, pr, &q, a[0], a[1]);
			}
			break;
		case HL_REQ_SEGMENT:
			resolve(v, r->pts[0], a);
			resolve(v, r->pts[1], b);
			rc = plan_line(v, pr, &q, a, b);
			break;
		case HL_REQ_ZONE:
			rc = plan_zone(v, pr, &q, r);
			break;
		case HL_REQ_IMAX:
			break;
		}
		if (rc >= 0 && (r->kind == HL_REQ_SEGMENT || r->kind == HL_REQ_ZONE))
			rc = plan_chunks(v, pr);
		if (rc < 0)
			return rc;
	}
	return 0;
}

int hl_verdict_new(const struct hl_regulation *reg, const struct hl_lid_grid *grid,
		   const struct hl_verdict_options *opts, struct hl_verdict **ret)
{
	struct hl_verdict *v;
	int rc;

	if (hl_lid_grid_check(grid) < 0 || !isfinite(opts->aim_h_deg) ||
	    !isfinite(opts->aim_v_deg) || fabs(opts->aim_h_deg) > 45.0 ||
	    fabs(opts->aim_v_deg) > 45.0 ||
	    (opts->traffic != HL_TRAFFIC_RIGHT && opts->traffic != HL_TRAFFIC_LEFT))
		return -EINVAL;
	v = calloc(1, sizeof(*v));
	if (!v)
		return -ENOMEM;
	v->reg = reg;
	v->grid = *grid;
	v->opts = *opts;
	v->n_samples = (size_t)grid->width * grid->height;
	v->req = calloc(reg->n_requirements ? reg->n_requirements : 1, sizeof(*v->req));
	rc = v->req ? plan(v) : -ENOMEM;
	if (rc < 0) {
		hl_verdict_free(v);
		return rc;
	}
	*ret = v;
	return 0;
}

void hl_verdict_free(struct hl_verdict *v)
{
	if (!v)
		return;
	free(v->req);
	free(v->pos_h);
	free(v->pos_v);
	free(v->pos_tap);
	free(v->tap_idx);
	free(v->tap_w);
	free(v->chunks);
	free(v->fp_idx);
	free(v);
}

const struct hl_regulation *hl_verdict_regulation(const struct hl_verdict *v)
{
	return v->reg;
}

static double value_at(const struct hl_verdict *v, uint32_t p, const float *a, const float *b)
{
	float s = 0.0f;

	if (b) {
		for (uint32_t t = v->pos_tap[p]; t < v->pos_tap[p + 1]; t++)
			s += v->tap_w[t] * (a[v->tap_idx[t]] + b[v->tap_idx[t]]);
		return 0.5 * s;
	}
	for (uint32_t t = v->pos_tap[p]; t < v->pos_tap[p + 1]; t++)
		s += v->tap_w[t] * a[v->tap_idx[t]];
	return s;
}

/*
 * The largest of n floats (0 if all are below), in 8 independent lanes: a compare-and-select
 * the compiler turns into packed max instructions at -O2, where fmaxf (NaN rules) stays a
 * scalar call per sample. The distributions hold no NaN, so the result is fmaxf's.
 */
bool hl_verdict_needs_peak(const struct hl_verdict *v)
{
	for (int i = 0; i < v->reg->n_requirements; i++)
		if (v->reg->req[i].kind == HL_REQ_IMAX)
			return true;
	return false;
}

static void imax(const struct hl_verdict *v, const struct hl_verdict_peak *p,
		 struct hl_req_result *r)
{
	r->value_cd = p->value_cd;
	r->at_h_deg =
		hl_lid_grid_h_deg(&v->grid, (int)(p->index % v->grid.width)) + v->opts.aim_h_deg;
	r->at_v_deg =
		hl_lid_grid_v_deg(&v->grid, (int)(p->index / v->grid.width)) + v->opts.aim_v_deg;
}

static double limit_cd(const struct hl_req_limit *l, const struct hl_req_result *done)
{
	if (!l->set)
		return NAN;
	return l->of < 0 ? l->cd : l->factor * done[l->of].value_cd;
}

/* The largest sample of a chunk's footprint: no position of the chunk reads more. */
static double chunk_bound(const struct hl_verdict *v, const struct chunk *c, const float *a,
			  const float *b)
{
	const uint32_t *idx = v->fp_idx + c->first_fp;
	float m = 0.0f;

	if (b) {
		for (uint32_t k = 0; k < c->n_fp; k++)
			m = a[idx[k]] + b[idx[k]] > m ? a[idx[k]] + b[idx[k]] : m;
		return 0.5 * m;
	}
	for (uint32_t k = 0; k < c->n_fp; k++)
		m = a[idx[k]] > m ? a[idx[k]] : m;
	return m;
}

/*
 * The highest receiver mean over a segment's or zone's positions: the chunk with the highest
 * bound first, then every chunk whose bound could beat what was found. The same value as
 * visiting every position; among equal values the position may be another one.
 */
static double chunk_max(const struct hl_verdict *v, const struct plan_req *pr, const float *a,
			const float *b, uint32_t *ret_at)
{
	const struct chunk *cs = v->chunks + pr->first_chunk;
	double best = -INFINITY, top = -INFINITY;
	uint32_t first = 0, at = pr->first_pos;

	float bounds[BOUNDS_KEPT]; /* the first chunks' bounds, not computed twice */

	for (uint32_t c = 0; c < pr->n_chunks; c++) {
		const double bound = chunk_bound(v, &cs[c], a, b);

		if (c < BOUNDS_KEPT)
			bounds[c] = (float)bound;
		if (bound > top) {
			top = bound;
			first = c;
		}
	}
	for (uint32_t k = 0; k <= pr->n_chunks; k++) {
		/* k == 0: the most promising chunk; then the others in order */
		const uint32_t c = k == 0 ? first : k - 1;

		if (k > 0 &&
		    (c == first ||
		     (c < BOUNDS_KEPT ? (double)bounds[c] : chunk_bound(v, &cs[c], a, b)) <= best))
			continue;
		for (uint32_t p = cs[c].first_pos; p < cs[c].first_pos + cs[c].n_pos; p++) {
			const double x = value_at(v, p, a, b);

			if (x > best) {
				best = x;
				at = p;
			}
		}
	}
	*ret_at = at;
	return best;
}

static double margin_min(double value, double min)
{
	return (value - min) / fmax(min, 1.0);
}

static double margin_max(double value, double max)
{
	return (max - value) / fmax(max, 1.0);
}

bool hl_verdict_eval(const struct hl_verdict *v, const float *a, const float *b,
		     struct hl_req_result *ret)
{
	return hl_verdict_eval_peak(v, a, b, NULL, ret);
}

bool hl_verdict_eval_peak(const struct hl_verdict *v, const float *a, const float *b,
			  const struct hl_verdict_peak *peak, struct hl_req_result *ret)
{
	struct hl_verdict_peak own;
	bool all = true;

	for (int i = 0; i < v->reg->n_requirements; i++) {
		const struct hl_requirement *req = &v->reg->req[i];
		const struct plan_req *pr = &v->req[i];
		struct hl_req_result *r = &ret[i];
		const bool has_min = req->min.set, has_max = req->max.set;

		r->n_outside = pr->n_outside;
		r->min_cd = limit_cd(&req->min, ret);
		r->max_cd = limit_cd(&req->max, ret);
		r->value_cd = NAN;
		r->at_h_deg = r->at_v_deg = NAN;
		if (req->kind == HL_REQ_IMAX) {
			if (!peak) {
				hl_verdict_peak(v->n_samples, a, b, &own);
				peak = &own;
			}
			imax(v, peak, r);
		} else if (req->kind == HL_REQ_POINT || req->kind == HL_REQ_SUM) {
			if (!pr->n_outside) {
				double s = 0.0;

				for (uint32_t k = 0; k < pr->n_pos; k++)
					s += value_at(v, pr->first_pos + k, a, b);
				r->value_cd = s;
				r->at_h_deg = v->pos_h[pr->first_pos];
				r->at_v_deg = v->pos_v[pr->first_pos];
			}
		} else if (pr->n_pos && has_max && !has_min) {
			uint32_t at;

			r->value_cd = chunk_max(v, pr, a, b, &at);
			r->at_h_deg = v->pos_h[at];
			r->at_v_deg = v->pos_v[at];
		} else if (pr->n_pos) {
			double lo = INFINITY, hi = -INFINITY;
			uint32_t at_lo = pr->first_pos, at_hi = pr->first_pos;

			for (uint32_t p = pr->first_pos; p < pr->first_pos + pr->n_pos; p++) {
				const double x = value_at(v, p, a, b);

				if (x < lo) {
					lo = x;
					at_lo = p;
				}
				if (x > hi) {
					hi = x;
					at_hi = p;
				}
			}
			/* the deciding extreme: the one nearer to failing its limit */
			bool use_lo = has_min && !has_max;

			if (has_min && has_max)
				use_lo = margin_min(lo, r->min_cd) < margin_max(hi, r->max_cd);
			r->value_cd = use_lo ? lo : hi;
			r->at_h_deg = v->pos_h[use_lo ? at_lo : at_hi];
			r->at_v_deg = v->pos_v[use_lo ? at_lo : at_hi];
		}
		double m = INFINITY;

		if (has_min)
			m = fmin(m, margin_min(r->value_cd, r->min_cd));
		if (has_max)
			m = fmin(m, margin_max(r->value_cd, r->max_cd));
		r->margin = isnan(r->value_cd) || isnan(m) ? NAN : m;
		r->pass = isfinite(r->margin) && r->margin >= 0.0;
		all = all && r->pass;
	}
	return all;
}

double hl_verdict_receiver_mean(const struct hl_lid_grid *grid, const float *dense,
				enum hl_receiver_shape shape, double size_deg, double h_deg,
				double v_deg)
{
	struct quad q;
	double s = 0.0;

	quadrature(shape, size_deg, &q);
	for (int k = 0; k < q.n; k++)
		s += hl_lid_grid_lookup(grid, dense, (float)(h_deg + q.dh[k]),
					(float)(v_deg + q.dv[k]));
	return s / q.n;
}
