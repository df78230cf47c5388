/* SPDX-License-Identifier: MIT */
#include "render/gi.h"

#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "render/hemicube.h"

#define SAME_SURFACE_COS 0.9 /* normals within ~25° may share an interpolated tile */
#define PLANE_SLOPE 0.02 /* off-plane distance allowed per metre of separation */
#define PLANE_SLACK_M 0.005
#define FLOOR_FRACTION 1.0 /* threshold floor: the first level's mean, times this */
#define PROGRESS_MS 250.0

enum state { NONE, QUEUED, DONE };

struct cell {
	int x0, y0, x1, y1; /* corner pixels, inclusive */
};

struct batch {
	size_t first, count;
};

struct key {
	float n[3];
	uint32_t pix;
};

struct worker;

/* One level's sensors: shared by the workers. */
struct level {
	const struct hl_gi_config *cfg;
	const struct hl_hemicube *cube;
	struct hl_sensor_aa aa;
	const struct hl_gi_sensors *sensors;
	const struct hl_gbuffer *gb;
	const struct key *keys;
	const struct batch *batches;
	size_t n_batches;
	atomic_size_t next;
	atomic_size_t done;
	float *val;
	int rc; /* the batch function's failure; calling thread only */
	/* progress, calling thread only */
	size_t done_before, estimated;
	double last_report_ms;
};

struct worker {
	struct level *lv;
	bool main;
	pthread_t thread;
	float *scratch;
	double *p, *n, *e;
};

static double now_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

void hl_gi_config_default(struct hl_gi_config *ret)
{
	*ret = (struct hl_gi_config){
		.sensor_size = 32,
		.tile = 8,
		.dradiance = 1.0,
		.sigma_px = 1.0,
		.threads = 2,
		.batch = 64,
		.aa_samples = 4,
	};
}

static void *work(void *arg)
{
	struct worker *w = arg;
	struct level *lv = w->lv;

	for (;;) {
		const size_t b = atomic_fetch_add(&lv->next, 1);
		const struct batch *bt;
		double n[3];

		if (b >= lv->n_batches)
			break;
		bt = &lv->batches[b];
		for (int j = 0; j < 3; j++)
			n[j] = lv->keys[bt->first].n[j];
		for (size_t s = 0; s < bt->count; s++) {
			const struct key *k = &lv->keys[bt->first + s];
			const float *pos = lv->gb->pos + 4 * (size_t)k->pix;

			for (int j = 0; j < 3; j++) {
				w->p[3 * s + j] = pos[j];
				w->n[3 * s + j] = k->n[j];
			}
		}
		if (lv->sensors->fn) {
			hl_sensor_batch(lv->cube, lv->sensors->fn, lv->sensors->field, &lv->aa, n,
					bt->count, w->p, w->scratch, w->e);
		} else {
			/* Batch functions run on the calling thread only (no workers started). */
			const int rc = lv->sensors->batch(lv->sensors->userdata, bt->count, w->p,
							  w->n, w->e);

			if (rc < 0) {
				lv->rc = rc;
				break;
			}
		}
		for (size_t s = 0; s < bt->count; s++)
			lv->val[lv->keys[bt->first + s].pix] = (float)w->e[s];
		atomic_fetch_add(&lv->done, bt->count);
		if (w->main && lv->cfg->progress && now_ms() - lv->last_report_ms > PROGRESS_MS) {
			const size_t done = lv->done_before + atomic_load(&lv->done);

			lv->last_report_ms = now_ms();
			lv->cfg->progress(lv->cfg->userdata, done,
					  lv->estimated > done ? lv->estimated : done);
		}
	}
	return NULL;
}

static int cmp_key(const void *a, const void *b)
{
	const struct key *x = a, *y = b;
	const int c = memcmp(x->n, y->n, sizeof(x->n));

	if (c)
		return c;
	return (x->pix > y->pix) - (x->pix < y->pix);
}

/* Sensors for the queued pixels; groups them by normal into batches. */
static int run_level(struct level *lv, struct worker *workers, int n_workers, struct key *keys,
		     size_t n, struct batch *batches, size_t *ret_batches)
{
	const int bmax = lv->cfg->batch;
	/* CPU batches share a normal; a batch function takes any mix, so only size cuts. */
	const bool by_normal = lv->sensors->fn != NULL;
	size_t nb = 0;
	int started = 0;

	if (!by_normal)
		n_workers = 1;
	qsort(keys, n, sizeof(*keys), cmp_key);
	for (size_t i = 0; i < n;) {
		size_t j = i + 1;

		while (j < n && j - i < (size_t)bmax &&
		       (!by_normal || memcmp(keys[j].n, keys[i].n, sizeof(keys[i].n)) == 0))
			j++;
		batches[nb++] = (struct batch){ i, j - i };
		i = j;
	}
	lv->keys = keys;
	lv->batches = batches;
	lv->n_batches = nb;
	atomic_store(&lv->next, 0);
	atomic_store(&lv->done, 0);
	lv->rc = 0;
	for (int t = 1; t < n_workers; t++) {
		workers[t].lv = lv;
		if (pthread_create(&workers[t].thread, NULL, work, &workers[t]) != 0)
			break;
		started++;
	}
	workers[0].lv = lv;
	work(&workers[0]);
	/* Threads that could not be started leave their batches to the calling thread. */
	for (int t = 1; t <= started; t++)
		pthread_join(workers[t].thread, NULL);
	*ret_batches = nb;
	return lv->rc;
}

static bool same_surface(const struct hl_gbuffer *gb, size_t a, size_t b)
{
	const float *na = gb->nrm + 4 * a, *nb = gb->nrm + 4 * b;
	const float *pa = gb->pos + 4 * a, *pb = gb->pos + 4 * b;
	double dot = 0.0, off = 0.0, dist2 = 0.0;

	if ((na[3] == (float)HL_SURF_NONE) != (nb[3] == (float)HL_SURF_NONE))
		return false;
	if (na[3] == (float)HL_SURF_NONE)
		return true;
	for (int i = 0; i < 3; i++) {
		dot += (double)na[i] * nb[i];
		off += (double)na[i] * (pb[i] - pa[i]);
		dist2 += ((double)pb[i] - pa[i]) * ((double)pb[i] - pa[i]);
	}
	return dot > SAME_SURFACE_COS && fabs(off) <= PLANE_SLOPE * sqrt(dist2) + PLANE_SLACK_M;
}

/* Whether a cell must be split: mixed surfaces, or corners differing by more than allowed. */
static bool must_refine(const struct hl_gbuffer *gb, const struct hl_gi_config *cfg,
			const float *val, const struct cell *c, double floor_lx)
{
	const int w = gb->width;
	const size_t corner[4] = { (size_t)c->y0 * w + c->x0, (size_t)c->y0 * w + c->x1,
				   (size_t)c->y1 * w + c->x0, (size_t)c->y1 * w + c->x1 };
	double lo = INFINITY, hi = -INFINITY, mean = 0.0;

	for (int y = c->y0; y <= c->y1; y++)
		for (int x = c->x0; x <= c->x1; x++)
			if (!same_surface(gb, corner[0], (size_t)y * w + x))
				return true;
	if (gb->nrm[4 * corner[0] + 3] == (float)HL_SURF_NONE)
		return false; /* all sky */
	for (int k = 0; k < 4; k++) {
		const double v = val[corner[k]];

		lo = v < lo ? v : lo;
		hi = v > hi ? v : hi;
		mean += v / 4;
	}
	return hi - lo > cfg->dradiance * (mean > floor_lx ? mean : floor_lx);
}

/*
 * Whether sensors that neighbouring cells placed on this cell's border (or inside it) disagree
 * with its bilinear interpolation by more than the refinement threshold: a glow that no corner
 * saw, found from the side.
 */
static bool contradicted(const struct hl_gbuffer *gb, const struct hl_gi_config *cfg,
			 const uint8_t *state, const float *val, const struct cell *c,
			 double floor_lx)
{
	const int w = gb->width;
	const double v00 = val[(size_t)c->y0 * w + c->x0], v10 = val[(size_t)c->y0 * w + c->x1];
	const double v01 = val[(size_t)c->y1 * w + c->x0], v11 = val[(size_t)c->y1 * w + c->x1];
	const double sx = c->x1 > c->x0 ? c->x1 - c->x0 : 1, sy = c->y1 > c->y0 ? c->y1 - c->y0 : 1;
	const double mean = (v00 + v10 + v01 + v11) / 4;
	const double limit = cfg->dradiance * (mean > floor_lx ? mean : floor_lx);

	if (gb->nrm[4 * ((size_t)c->y0 * w + c->x0) + 3] == (float)HL_SURF_NONE)
		return false;
	for (int y = c->y0; y <= c->y1; y++)
		for (int x = c->x0; x <= c->x1; x++) {
			const size_t i = (size_t)y * w + x;
			const double fx = (x - c->x0) / sx, fy = (y - c->y0) / sy;
			double pred;

			if (state[i] != DONE)
				continue;
			pred = (1 - fy) * ((1 - fx) * v00 + fx * v10) +
			       fy * ((1 - fx) * v01 + fx * v11);
			if (fabs(val[i] - pred) > limit)
				return true;
		}
	return false;
}

static void split(const struct cell *cl, struct cell *out, size_t *n)
{
	const int xm = (cl->x0 + cl->x1) / 2, ym = (cl->y0 + cl->y1) / 2;
	const bool sx = cl->x1 - cl->x0 >= 2, sy = cl->y1 - cl->y0 >= 2;

	for (int j = 0; j < (sy ? 2 : 1); j++)
		for (int i = 0; i < (sx ? 2 : 1); i++)
			out[(*n)++] = (struct cell){
				i == 0 ? cl->x0 : xm,
				j == 0 ? cl->y0 : ym,
				(i == 1 || !sx) ? cl->x1 : xm,
				(j == 1 || !sy) ? cl->y1 : ym,
			};
}

/* Bilinear from the corners into the cell's pixels that have no sensor of their own. */
static void interpolate(const struct hl_gbuffer *gb, const uint8_t *state, float *val,
			const struct cell *c)
{
	const int w = gb->width;
	const double v00 = val[(size_t)c->y0 * w + c->x0], v10 = val[(size_t)c->y0 * w + c->x1];
	const double v01 = val[(size_t)c->y1 * w + c->x0], v11 = val[(size_t)c->y1 * w + c->x1];
	const double sx = c->x1 > c->x0 ? c->x1 - c->x0 : 1, sy = c->y1 > c->y0 ? c->y1 - c->y0 : 1;

	if (gb->nrm[4 * ((size_t)c->y0 * w + c->x0) + 3] == (float)HL_SURF_NONE)
		return;
	for (int y = c->y0; y <= c->y1; y++)
		for (int x = c->x0; x <= c->x1; x++) {
			const size_t i = (size_t)y * w + x;
			const double fx = (x - c->x0) / sx, fy = (y - c->y0) / sy;

			if (state[i] == DONE)
				continue;
			val[i] = (float)((1 - fy) * ((1 - fx) * v00 + fx * v10) +
					 fy * ((1 - fx) * v01 + fx * v11));
		}
}

static void queue_pixel(const struct hl_gbuffer *gb, uint8_t *state, struct key *keys, size_t *n,
			int x, int y)
{
	const size_t i = (size_t)y * gb->width + x;

	if (state[i] != NONE || gb->nrm[4 * i + 3] == (float)HL_SURF_NONE)
		return;
	state[i] = QUEUED;
	memcpy(keys[*n].n, gb->nrm + 4 * i, sizeof(keys[*n].n));
	keys[*n].pix = (uint32_t)i;
	++*n;
}

static void queue_cell(const struct hl_gbuffer *gb, uint8_t *state, struct key *keys, size_t *n,
		       const struct cell *c)
{
	queue_pixel(gb, state, keys, n, c->x0, c->y0);
	queue_pixel(gb, state, keys, n, c->x1, c->y0);
	queue_pixel(gb, state, keys, n, c->x0, c->y1);
	queue_pixel(gb, state, keys, n, c->x1, c->y1);
}

static bool bad_config(const struct hl_gi_config *cfg)
{
	return cfg->sensor_size < 2 || cfg->sensor_size > HL_HEMICUBE_MAX_SIZE ||
	       cfg->sensor_size % 2 || cfg->tile < 1 || cfg->tile > 256 ||
	       (cfg->tile & (cfg->tile - 1)) || !(cfg->dradiance > 0.0) ||
	       !(cfg->sigma_px >= 0.0 && cfg->sigma_px <= 16.0) || cfg->threads < 1 ||
	       cfg->threads > HL_GI_MAX_THREADS || cfg->batch < 1 || cfg->aa_samples < 1 ||
	       cfg->aa_samples > 64 || cfg->n_thin < 0 || (cfg->n_thin && !cfg->thin);
}

static void workers_free(struct worker *workers, int n)
{
	for (int t = 0; t < n; t++) {
		free(workers[t].scratch);
		free(workers[t].p);
		free(workers[t].n);
		free(workers[t].e);
	}
}

static int workers_alloc(const struct hl_gi_config *cfg, const struct hl_hemicube *cube,
			 struct worker *workers)
{
	for (int t = 0; t < cfg->threads; t++) {
		workers[t].main = t == 0;
		workers[t].scratch = malloc(sizeof(float) * hl_sensor_scratch_floats(cube));
		workers[t].p = malloc(sizeof(double) * 3 * cfg->batch);
		workers[t].n = malloc(sizeof(double) * 3 * cfg->batch);
		workers[t].e = malloc(sizeof(double) * cfg->batch);
		if (!workers[t].scratch || !workers[t].p || !workers[t].n || !workers[t].e)
			return -ENOMEM;
	}
	return 0;
}

static bool bad_sensors(const struct hl_gi_sensors *s)
{
	return !s || (!s->fn && !s->batch);
}

int hl_gi_run(const struct hl_gi_config *cfg, hl_radiance_fn fn, const void *field,
	      const struct hl_gbuffer *gb, float *ret_indirect_lx, struct hl_gi_stats *ret_stats)
{
	const struct hl_gi_sensors sensors = { .fn = fn, .field = field };

	return hl_gi_run_sensors(cfg, &sensors, gb, ret_indirect_lx, ret_stats);
}

int hl_gi_time_batch(const struct hl_gi_config *cfg, const struct hl_gi_sensors *sensors,
		     const struct hl_gbuffer *gb, double *ret_ms_per_sensor)
{
	const size_t npix = (size_t)gb->width * gb->height;
	struct hl_hemicube *cube = NULL;
	struct worker workers[HL_GI_MAX_THREADS] = { 0 };
	struct level lv = { 0 };
	struct key *keys = NULL;
	struct batch *batches = NULL;
	size_t n_surface = 0, n = 0, nb, stride;
	double t0;
	int rc;

	if (bad_config(cfg) || bad_sensors(sensors))
		return -EINVAL;
	for (size_t i = 0; i < npix; i++)
		n_surface += gb->nrm[4 * i + 3] != (float)HL_SURF_NONE;
	if (n_surface == 0)
		return -EINVAL;
	rc = hl_hemicube_new(cfg->sensor_size, &cube);
	if (rc < 0)
		return rc;
	keys = malloc(sizeof(*keys) * (size_t)cfg->batch);
	batches = malloc(sizeof(*batches) * (size_t)cfg->batch);
	rc = -ENOMEM;
	if (!keys || !batches || workers_alloc(cfg, cube, workers) < 0)
		goto out;
	/* Every stride-th surface pixel. */
	stride = n_surface > (size_t)cfg->batch ? n_surface / cfg->batch : 1;
	for (size_t i = 0, k = 0; i < npix && n < (size_t)cfg->batch; i++) {
		if (gb->nrm[4 * i + 3] == (float)HL_SURF_NONE || k++ % stride)
			continue;
		memcpy(keys[n].n, gb->nrm + 4 * i, sizeof(keys[n].n));
		keys[n++].pix = (uint32_t)i;
	}
	lv = (struct level){ .cfg = cfg,
			     .cube = cube,
			     .sensors = sensors,
			     .gb = gb,
			     .aa = { cfg->thin, cfg->n_thin, cfg->aa_samples } };
	lv.val = calloc(npix, sizeof(float));
	if (!lv.val)
		goto out;
	/* Warm-up: one sensor, untimed. */
	rc = run_level(&lv, workers, cfg->threads, keys, 1, batches, &nb);
	if (rc < 0)
		goto out;
	t0 = now_ms();
	rc = run_level(&lv, workers, cfg->threads, keys, n, batches, &nb);
	if (rc == 0)
		*ret_ms_per_sensor = (now_ms() - t0) / n;
out:
	workers_free(workers, cfg->threads);
	free(lv.val);
	free(keys);
	free(batches);
	hl_hemicube_free(cube);
	return rc;
}

int hl_gi_run_sensors(const struct hl_gi_config *cfg, const struct hl_gi_sensors *sensors,
		      const struct hl_gbuffer *gb, float *ret_indirect_lx,
		      struct hl_gi_stats *ret_stats)
{
	const int w = gb->width, h = gb->height;
	const size_t npix = (size_t)w * h;
	const double t_start = now_ms();
	struct hl_gi_stats st = { 0 };
	struct hl_hemicube *cube = NULL;
	struct worker workers[HL_GI_MAX_THREADS] = { 0 };
	struct level lv = { 0 };
	uint8_t *state = NULL;
	float *val = NULL;
	struct key *keys = NULL;
	struct batch *batches = NULL;
	struct cell *cells = NULL, *next = NULL, *acc = NULL;
	size_t n_cells = 0, n_acc = 0, max_cells, queued_total = 0;
	double floor_lx = 0.0, refine_frac = 0.25;
	int rc;

	if (bad_config(cfg) || bad_sensors(sensors) || w < 2 || h < 2)
		return -EINVAL;
	rc = hl_hemicube_new(cfg->sensor_size, &cube);
	if (rc < 0)
		return rc;
	/* A cell splits into at most four; cells never overlap by more than an edge. */
	max_cells = 4 * (npix + 4);
	state = calloc(npix, 1);
	val = calloc(npix, sizeof(float));
	keys = malloc(sizeof(*keys) * npix);
	batches = malloc(sizeof(*batches) * npix);
	cells = malloc(sizeof(*cells) * max_cells);
	next = malloc(sizeof(*next) * max_cells);
	acc = malloc(sizeof(*acc) * max_cells);
	rc = -ENOMEM;
	if (!state || !val || !keys || !batches || !cells || !next || !acc ||
	    workers_alloc(cfg, cube, workers) < 0)
		goto out;
	for (size_t i = 0; i < npix; i++)
		st.surface_pixels += gb->nrm[4 * i + 3] != (float)HL_SURF_NONE;
	lv = (struct level){ .cfg = cfg,
			     .cube = cube,
			     .sensors = sensors,
			     .gb = gb,
			     .val = val,
			     .aa = { cfg->thin, cfg->n_thin, cfg->aa_samples },
			     .last_report_ms = now_ms() };

	for (int y = 0; y < h - 1; y += cfg->tile)
		for (int x = 0; x < w - 1; x += cfg->tile)
			cells[n_cells++] =
				(struct cell){ x, y, x + cfg->tile < w ? x + cfg->tile : w - 1,
					       y + cfg->tile < h ? y + cfg->tile : h - 1 };
	for (;;) {
		size_t n_queued = 0, n_next = 0, nb = 0;
		double t0;

		if (n_cells == 0) {
			/* Accepted cells that later sensors on their border contradict are split. */
			size_t keep = 0;

			for (size_t a = 0; a < n_acc; a++) {
				if (contradicted(gb, cfg, state, val, &acc[a], floor_lx))
					split(&acc[a], cells, &n_cells);
				else
					acc[keep++] = acc[a];
			}
			n_acc = keep;
			if (n_cells == 0)
				break;
		}

		for (size_t c = 0; c < n_cells; c++)
			queue_cell(gb, state, keys, &n_queued, &cells[c]);
		queued_total += n_queued;
		lv.done_before = st.sensors;
		lv.estimated = queued_total + (size_t)(refine_frac * 5 * n_cells);
		if (lv.estimated > st.surface_pixels)
			lv.estimated = st.surface_pixels;
		t0 = now_ms();
		rc = run_level(&lv, workers, cfg->threads, keys, n_queued, batches, &nb);
		st.sensor_ms += now_ms() - t0;
		if (rc < 0)
			goto out;
		st.sensors += n_queued;
		st.batches += nb;
		st.levels++;
		for (size_t k = 0; k < n_queued; k++)
			state[keys[k].pix] = DONE;
		if (st.levels == 1 && n_queued) {
			double sum = 0.0;

			for (size_t k = 0; k < n_queued; k++)
				sum += val[keys[k].pix];
			floor_lx = FLOOR_FRACTION * sum / n_queued;
		}
		for (size_t c = 0; c < n_cells; c++) {
			const struct cell *cl = &cells[c];

			if (cl->x1 - cl->x0 < 2 && cl->y1 - cl->y0 < 2)
				continue; /* every pixel is a corner */
			if (!must_refine(gb, cfg, val, cl, floor_lx))
				acc[n_acc++] = *cl;
			else
				split(cl, next, &n_next);
		}
		refine_frac = n_cells ? (double)n_next / (4.0 * n_cells) : 0.0;
		{
			struct cell *tmp = cells;

			cells = next;
			next = tmp;
			n_cells = n_next;
		}
	}
	for (size_t a = 0; a < n_acc; a++)
		interpolate(gb, state, val, &acc[a]);
	if (cfg->progress)
		cfg->progress(cfg->userdata, st.sensors, st.sensors);
	if (cfg->sigma_px > 0.0)
		rc = hl_gi_filter(gb, val, cfg->sigma_px, ret_indirect_lx);
	else
		memcpy(ret_indirect_lx, val, sizeof(float) * npix);
	st.total_ms = now_ms() - t_start;
	if (ret_stats)
		*ret_stats = st;
out:
	workers_free(workers, cfg->threads);
	free(state);
	free(val);
	free(keys);
	free(batches);
	free(cells);
	free(next);
	free(acc);
	hl_hemicube_free(cube);
	return rc;
}

int hl_gi_filter(const struct hl_gbuffer *gb, const float *in, double sigma_px, float *out)
{
	const int w = gb->width, h = gb->height;
	const int r = (int)ceil(2.0 * sigma_px);
	float kernel[2 * 32 + 1];

	if (!(sigma_px > 0.0) || r > 32)
		return -EINVAL;
	for (int k = -r; k <= r; k++)
		kernel[k + r] = (float)exp(-0.5 * k * k / (sigma_px * sigma_px));
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			const size_t i = (size_t)y * w + x;
			const float id = gb->nrm[4 * i + 3];
			double sum = 0.0, wsum = 0.0;

			if (id == (float)HL_SURF_NONE) {
				out[i] = 0.0f;
				continue;
			}
			for (int dy = -r; dy <= r; dy++) {
				const int yy = y + dy;

				if (yy < 0 || yy >= h)
					continue;
				for (int dx = -r; dx <= r; dx++) {
					const int xx = x + dx;
					const size_t j = (size_t)yy * w + xx;
					double k;

					if (xx < 0 || xx >= w || gb->nrm[4 * j + 3] != id)
						continue;
					k = (double)kernel[dy + r] * kernel[dx + r];
					sum += k * in[j];
					wsum += k;
				}
			}
			out[i] = (float)(sum / wsum);
		}
	return 0;
}
