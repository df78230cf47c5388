/* SPDX-License-Identifier: MIT */
#include "render/headlight.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "lamp/angles.h"

#define DEG (M_PI / 180.0)
#define WEIGHT_ONE 65535.0f /* bilinear weights are stored as 16-bit fractions */

/*
 * What a frame needs of one lamp at one pixel: 12 bytes. g = 0 when the lamp does not reach
 * the pixel (cell 0 is then read and multiplied by zero: cheaper than a branch).
 */
struct term {
	uint32_t cell; /* index of the cell's upper-left sample in the dense grid */
	uint16_t tx, ty; /* bilinear weights towards column + 1 and row + 1 */
	float g; /* cos(eps) / r^2, 1/m^2 */
};

/* A run of consecutive pixels that at least one lamp reaches. */
struct span {
	uint32_t first, count;
};

/*
 * A band of CHUNK_PIXELS pixels (the last one shorter), the unit a frame is split into for the
 * threads: its spans, which never cross a band's border, and where its terms start.
 */
struct chunk {
	size_t first_span, n_spans;
	size_t first_term;
	size_t work; /* pixel-lamp pairs with g > 0 */
};

/* A lamp's axes in the vehicle frame (hl_lamp_basis). */
struct basis {
	double x[3], y[3], z[3];
};

#define CHUNK_PIXELS 16384 /* 12.8 rows of 1280: ~60 chunks a frame, ~100 us each */
/* Moving layout: room for a chunk's spans (at most one per two pixels, an unlit one between). */
#define CHUNK_SPANS (CHUNK_PIXELS / 2)

struct hl_headlight {
	int width, height;
	int n_lamps;
	struct hl_headlight_lamp lamps[HL_HEADLIGHT_MAX_LAMPS];
	struct basis basis[HL_HEADLIGHT_MAX_LAMPS];
	struct span *spans;
	size_t n_spans;
	struct chunk *chunks;
	size_t n_chunks;
	/*
	 * Still layout: n_lamps per lit pixel, in pixel order, lamps interleaved, packed. Moving
	 * layout (hl_headlight_make_moving): n_lamps for every pixel, at n_lamps * its index;
	 * chunk c's spans at c * CHUNK_SPANS.
	 */
	struct term *terms;
	size_t n_lit; /* pixels in the spans (still layout) */
	bool moving;
	uint8_t *ever; /* moving layout: 1 for a pixel in the spans (lit now or before) */
};

/*
 * Continuous sample coordinates of direction d (lamp space) on grid g; false outside the
 * measured range, where the lookup is zero.
 */
static bool sample_coords(const struct hl_lid_grid *g, const double d[3], double *fx, double *fy)
{
	double h, v;

	hl_angles_from_dir(g->angles, d, &h, &v);
	*fx = (h / DEG - g->h_first_deg) * (g->width - 1) /
	      ((double)g->h_last_deg - g->h_first_deg);
	*fy = ((double)g->v_last_deg - v / DEG) * (g->height - 1) /
	      ((double)g->v_last_deg - g->v_first_deg);
	return *fx >= 0.0 && *fx <= g->width - 1 && *fy >= 0.0 && *fy <= g->height - 1;
}

/*
 * Lamp-space offset d of point p, and cos(eps) / r^2 for normal n (0 when facing away); b the
 * lamp's axes (hl_lamp_basis of its pose, made once per lamp).
 */
static double geometry(const struct hl_lamp_pose *pose, const struct basis *b, const double p[3],
		       const double n[3], double d[3])
{
	double w[3], r2, cos_eps;

	for (int i = 0; i < 3; i++)
		w[i] = p[i] - pose->pos_m[i];
	d[0] = w[0] * b->x[0] + w[1] * b->x[1] + w[2] * b->x[2];
	d[1] = w[0] * b->y[0] + w[1] * b->y[1] + w[2] * b->y[2];
	d[2] = w[0] * b->z[0] + w[1] * b->z[1] + w[2] * b->z[2];
	r2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
	if (!(r2 > 0.0))
		return 0.0;
	cos_eps = -(n[0] * w[0] + n[1] * w[1] + n[2] * w[2]) / sqrt(r2);
	return cos_eps > 0.0 ? cos_eps / r2 : 0.0;
}

/* hl_headlight_tap() with the lamp's axes made already. */
static bool tap_with(const struct hl_headlight_lamp *lamp, const struct basis *b, const double p[3],
		     const double n[3], struct hl_headlight_tap *ret)
{
	const struct hl_lid_grid *g = &lamp->grid;
	double d[3], fx, fy, geo;
	int x0, y0;

	*ret = (struct hl_headlight_tap){ 0 };
	geo = geometry(&lamp->pose, b, p, n, d);
	if (geo == 0.0 || !sample_coords(g, d, &fx, &fy))
		return false;
	x0 = fx > g->width - 2 ? g->width - 2 : (int)fx;
	y0 = fy > g->height - 2 ? g->height - 2 : (int)fy;
	*ret = (struct hl_headlight_tap){
		.cell = (size_t)y0 * g->width + x0,
		.tx = fx - x0,
		.ty = fy - y0,
		.g = geo,
	};
	return true;
}

/* The term of lamp k at one G-buffer entry; g = 0 when it does not light it. */
static struct term make_term(const struct hl_headlight *h, int k, const float *pf, const float *nf)
{
	const double p[3] = { pf[0], pf[1], pf[2] }, nn[3] = { nf[0], nf[1], nf[2] };
	struct hl_headlight_tap tap;

	if (nf[3] == (float)HL_SURF_NONE || !tap_with(&h->lamps[k], &h->basis[k], p, nn, &tap))
		return (struct term){ 0 };
	return (struct term){
		.cell = (uint32_t)tap.cell,
		.tx = (uint16_t)lrint(tap.tx * WEIGHT_ONE),
		.ty = (uint16_t)lrint(tap.ty * WEIGHT_ONE),
		.g = (float)tap.g,
	};
}

static int precompute(struct hl_headlight *h, const struct hl_gbuffer *gb)
{
	const size_t npix = (size_t)gb->width * gb->height;
	const int nl = h->n_lamps;
	size_t n_lit = 0, n_spans = 0;
	bool prev_lit = false;

	h->n_chunks = (npix + CHUNK_PIXELS - 1) / CHUNK_PIXELS;
	h->terms = malloc(sizeof(*h->terms) * nl * (npix ? npix : 1));
	/* a span needs an unlit pixel or a band border before it */
	h->spans = malloc(sizeof(*h->spans) * (npix / 2 + h->n_chunks + 1));
	h->chunks = calloc(h->n_chunks ? h->n_chunks : 1, sizeof(*h->chunks));
	if (!h->terms || !h->spans || !h->chunks)
		return -ENOMEM;
	for (size_t i = 0; i < npix; i++) {
		struct term t[HL_HEADLIGHT_MAX_LAMPS];
		bool lit = false;

		if (i % CHUNK_PIXELS == 0) {
			struct chunk *c = &h->chunks[i / CHUNK_PIXELS];

			if (i > 0)
				c[-1].n_spans = n_spans - c[-1].first_span;
			c->first_span = n_spans;
			c->first_term = n_lit * nl;
			prev_lit = false;
		}

		for (int k = 0; k < nl; k++) {
			t[k] = make_term(h, k, gb->pos + 4 * i, gb->nrm + 4 * i);
			lit |= t[k].g > 0.0f;
			h->chunks[i / CHUNK_PIXELS].work += t[k].g > 0.0f;
		}
		if (!lit) {
			prev_lit = false;
			continue;
		}
		if (!prev_lit)
			h->spans[n_spans++] = (struct span){ (uint32_t)i, 0 };
		h->spans[n_spans - 1].count++;
		memcpy(h->terms + n_lit * nl, t, sizeof(*t) * nl);
		n_lit++;
		prev_lit = true;
	}
	if (h->n_chunks)
		h->chunks[h->n_chunks - 1].n_spans =
			n_spans - h->chunks[h->n_chunks - 1].first_span;
	h->n_lit = n_lit;
	h->n_spans = n_spans;
	/* Shrinking cannot fail in practice; keep the larger block if it does. */
	{
		struct term *t = realloc(h->terms, sizeof(*t) * nl * (n_lit ? n_lit : 1));
		struct span *s = realloc(h->spans, sizeof(*s) * (n_spans ? n_spans : 1));

		h->terms = t ? t : h->terms;
		h->spans = s ? s : h->spans;
	}
	return 0;
}

int hl_headlight_new(const struct hl_gbuffer *gb, int n_lamps,
		     const struct hl_headlight_lamp *lamps, struct hl_headlight **ret)
{
	struct hl_headlight *h;
	int rc;

	if (n_lamps < 1 || n_lamps > HL_HEADLIGHT_MAX_LAMPS)
		return -EINVAL;
	for (int k = 0; k < n_lamps; k++)
		if (hl_lid_grid_check(&lamps[k].grid) < 0)
			return -EINVAL;
	h = calloc(1, sizeof(*h));
	if (!h)
		return -ENOMEM;
	h->width = gb->width;
	h->height = gb->height;
	h->n_lamps = n_lamps;
	memcpy(h->lamps, lamps, sizeof(*lamps) * n_lamps);
	for (int k = 0; k < n_lamps; k++)
		hl_lamp_basis(&lamps[k].pose, h->basis[k].x, h->basis[k].y, h->basis[k].z);
	rc = precompute(h, gb);
	if (rc < 0) {
		hl_headlight_free(h);
		return rc;
	}
	*ret = h;
	return 0;
}

void hl_headlight_free(struct hl_headlight *h)
{
	if (!h)
		return;
	free(h->terms);
	free(h->spans);
	free(h->chunks);
	free(h->ever);
	free(h);
}

int hl_headlight_make_moving(struct hl_headlight *h)
{
	const size_t npix = (size_t)h->width * h->height, nl = (size_t)h->n_lamps;
	struct term *terms;
	struct span *spans;
	uint8_t *ever;

	if (h->moving)
		return 0;
	terms = calloc(npix ? npix * nl : 1, sizeof(*terms));
	spans = malloc(sizeof(*spans) * (h->n_chunks ? h->n_chunks * CHUNK_SPANS : 1));
	ever = calloc(npix ? npix : 1, 1);
	if (!terms || !spans || !ever) {
		free(terms);
		free(spans);
		free(ever);
		return -ENOMEM;
	}
	/* Each lit pixel's terms to its own place, each chunk's spans to its own room. */
	for (size_t c = 0; c < h->n_chunks; c++) {
		struct chunk *ch = &h->chunks[c];
		const struct term *t = h->terms + ch->first_term;

		for (size_t s = 0; s < ch->n_spans; s++) {
			const struct span sp = h->spans[ch->first_span + s];

			memcpy(terms + sp.first * nl, t, sizeof(*t) * nl * sp.count);
			t += nl * sp.count;
			memset(ever + sp.first, 1, sp.count);
			spans[c * CHUNK_SPANS + s] = sp;
		}
		ch->first_span = c * CHUNK_SPANS;
		ch->first_term = c * CHUNK_PIXELS * nl;
	}
	free(h->terms);
	free(h->spans);
	h->terms = terms;
	h->spans = spans;
	h->ever = ever;
	h->moving = true;
	return 0;
}

/* Moving layout: chunk c's spans again from the pixels in them (h->ever). */
static void chunk_spans(struct hl_headlight *h, size_t c, size_t first, size_t count)
{
	struct chunk *ch = &h->chunks[c];
	struct span *sp = h->spans + ch->first_span;
	size_t n = 0;
	bool prev = false;

	for (size_t i = first; i < first + count; i++) {
		if (!h->ever[i]) {
			prev = false;
			continue;
		}
		if (!prev)
			sp[n++] = (struct span){ (uint32_t)i, 0 };
		sp[n - 1].count++;
		prev = true;
	}
	ch->n_spans = n;
}

void hl_headlight_update_chunk(struct hl_headlight *h, const struct hl_gbuffer *gb, size_t c,
			       const uint8_t *changed)
{
	const int nl = h->n_lamps;
	struct chunk *ch = &h->chunks[c];
	size_t first, count;
	bool grew = false;

	hl_headlight_chunk_pixels(h, c, &first, &count);
	for (size_t i = first; i < first + count; i++) {
		struct term *t = h->terms + i * nl;
		bool lit = false;

		if (!changed[i])
			continue;
		for (int k = 0; k < nl; k++) {
			ch->work -= t[k].g > 0.0f;
			t[k] = make_term(h, k, gb->pos + 4 * i, gb->nrm + 4 * i);
			ch->work += t[k].g > 0.0f;
			lit |= t[k].g > 0.0f;
		}
		/* A pixel that goes dark keeps its place with zero terms: frames write its zero. */
		if (lit && !h->ever[i]) {
			h->ever[i] = 1;
			grew = true;
		}
	}
	if (grew)
		chunk_spans(h, c, first, count);
}

static inline float lookup(const struct term *t, const float *restrict s0, size_t w)
{
	const float scale = 1.0f / WEIGHT_ONE;
	const float *s = s0 + t->cell;
	const float tx = t->tx * scale, ty = t->ty * scale;
	const float top = s[0] + tx * (s[1] - s[0]);
	const float bottom = s[w] + tx * (s[w + 1] - s[w]);

	return t->g * (top + ty * (bottom - top));
}

size_t hl_headlight_chunks(const struct hl_headlight *h)
{
	return h->n_chunks;
}

void hl_headlight_chunk_pixels(const struct hl_headlight *h, size_t c, size_t *ret_first,
			       size_t *ret_count)
{
	const size_t npix = (size_t)h->width * h->height;
	const size_t first = c * CHUNK_PIXELS;

	*ret_first = first;
	*ret_count = npix - first < CHUNK_PIXELS ? npix - first : CHUNK_PIXELS;
}

/* The illuminance of span sp into lux, from its terms at t; returns the terms after it. */
static const struct term *light_span(const struct hl_headlight *h, const float *const *dense,
				     struct span sp, const struct term *t, float *lux)
{
	const float *d0 = dense[0], *d1 = h->n_lamps > 1 ? dense[1] : NULL;
	const size_t w0 = (size_t)h->lamps[0].grid.width;
	const size_t w1 = h->n_lamps > 1 ? (size_t)h->lamps[1].grid.width : 0;
	float *restrict out = lux + sp.first;

	if (h->n_lamps == 1) {
		for (uint32_t j = 0; j < sp.count; j++, t++)
			out[j] = d0 ? lookup(t, d0, w0) : 0.0f;
	} else {
		for (uint32_t j = 0; j < sp.count; j++, t += 2)
			out[j] = (d0 ? lookup(&t[0], d0, w0) : 0.0f) +
				 (d1 ? lookup(&t[1], d1, w1) : 0.0f);
	}
	return t;
}

void hl_headlight_run_chunk(const struct hl_headlight *h, const float *const *dense, size_t c,
			    float *lux)
{
	const struct chunk *ch = &h->chunks[c];
	const struct term *t = h->terms + ch->first_term;
	size_t first, count, prev_end;

	hl_headlight_chunk_pixels(h, c, &first, &count);
	prev_end = first;
	for (size_t s = ch->first_span; s < ch->first_span + ch->n_spans; s++) {
		/* Pixels between spans no lamp reaches. */
		memset(lux + prev_end, 0, sizeof(float) * (h->spans[s].first - prev_end));
		prev_end = (size_t)h->spans[s].first + h->spans[s].count;
		if (h->moving)
			t = h->terms + (size_t)h->spans[s].first * h->n_lamps;
		t = light_span(h, dense, h->spans[s], t, lux);
	}
	memset(lux + prev_end, 0, sizeof(float) * (first + count - prev_end));
}

void hl_headlight_run_chunk_lit(const struct hl_headlight *h, const float *const *dense, size_t c,
				float *lux, hl_headlight_span_fn span, void *userdata)
{
	const struct chunk *ch = &h->chunks[c];
	const struct term *t = h->terms + ch->first_term;

	for (size_t s = ch->first_span; s < ch->first_span + ch->n_spans; s++) {
		if (h->moving)
			t = h->terms + (size_t)h->spans[s].first * h->n_lamps;
		t = light_span(h, dense, h->spans[s], t, lux);
		if (span)
			span(userdata, lux, h->spans[s].first, h->spans[s].count);
	}
}

void hl_headlight_run(const struct hl_headlight *h, const float *const *dense, float *lux)
{
	for (size_t c = 0; c < h->n_chunks; c++)
		hl_headlight_run_chunk(h, dense, c, lux);
}

size_t hl_headlight_work(const struct hl_headlight *h)
{
	size_t work = 0;

	for (size_t c = 0; c < h->n_chunks; c++)
		work += h->chunks[c].work;
	return work;
}

bool hl_headlight_tap(const struct hl_headlight_lamp *lamp, const double p[3], const double n[3],
		      struct hl_headlight_tap *ret)
{
	struct basis b;

	hl_lamp_basis(&lamp->pose, b.x, b.y, b.z);
	return tap_with(lamp, &b, p, n, ret);
}

double hl_headlight_tap_lookup(const struct hl_headlight_tap *t, const float *dense, int width)
{
	const float *s = dense + t->cell;
	const double top = s[0] * (1 - t->tx) + s[1] * t->tx;
	const double bottom = s[width] * (1 - t->tx) + s[width + 1] * t->tx;

	return t->g * (top * (1 - t->ty) + bottom * t->ty);
}

double hl_headlight_point(const struct hl_headlight_lamp *lamp, const float *dense,
			  const double p[3], const double n[3])
{
	struct hl_headlight_tap t;

	if (!hl_headlight_tap(lamp, p, n, &t))
		return 0.0;
	return hl_headlight_tap_lookup(&t, dense, lamp->grid.width);
}
