/* SPDX-License-Identifier: MIT */
/* A suite run live: see daemon/core/suite_live.h. */
#include "daemon/core/suite_live.h"

#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "base/json_write.h"
#include "base/sched.h"
#include "verdict/suite_judge.h"
#include "verdict/suite_measure.h"

struct hl_suite_live {
	struct hl_suite_result *r;
	const struct hl_regulation *reg;
	pthread_mutex_t lock; /* PI: guards what follows */
	int current; /* the variant measured, -1 between them */
	const struct hl_suite_scenario *d;
	struct hl_suite_measure *m;
	uint64_t frames; /* measured, over every variant */
	double scene_t_s;
};

int hl_suite_live_new(struct hl_suite_result *r, const struct hl_regulation *reg,
		      struct hl_suite_live **ret)
{
	struct hl_suite_live *sl = calloc(1, sizeof(*sl));

	if (!sl)
		return -ENOMEM;
	if (hl_mutex_init_pi(&sl->lock) != 0) {
		free(sl);
		return -ENOMEM;
	}
	sl->r = r;
	sl->reg = reg;
	sl->current = -1;
	*ret = sl;
	return 0;
}

void hl_suite_live_free(struct hl_suite_live *sl)
{
	if (!sl)
		return;
	hl_suite_measure_free(sl->m);
	pthread_mutex_destroy(&sl->lock);
	free(sl);
}

int hl_suite_live_begin(struct hl_suite_live *sl, const struct hl_suite_scenario *d, int i)
{
	struct hl_suite_measure *m;
	int rc;

	if (i < 0 || i >= sl->r->n_variants)
		return -EINVAL;
	rc = hl_suite_measure_new(sl->r->suite, d, sl->reg, &sl->r->v[i], &m);
	if (rc < 0)
		return rc;
	pthread_mutex_lock(&sl->lock);
	hl_suite_measure_free(sl->m);
	sl->m = m;
	sl->d = d;
	sl->current = i;
	sl->scene_t_s = 0.0;
	pthread_mutex_unlock(&sl->lock);
	return 0;
}

int hl_suite_live_end(struct hl_suite_live *sl)
{
	int rc = 0;

	pthread_mutex_lock(&sl->lock);
	if (sl->m)
		rc = hl_suite_measure_finish(sl->m);
	hl_suite_measure_free(sl->m);
	sl->m = NULL;
	sl->current = -1;
	pthread_mutex_unlock(&sl->lock);
	return rc;
}

void hl_suite_live_frame(void *ctx, const struct hl_scenario *sc, const struct hl_world_state *w,
			 const struct hl_lid_grid *const grids[2], const float *const dist[2])
{
	struct hl_suite_live *sl = ctx;

	pthread_mutex_lock(&sl->lock);
	if (sl->m) {
		hl_suite_measure_frame(sl->m, sc, w, grids, dist);
		sl->frames++;
		sl->scene_t_s = w->t_s;
	}
	pthread_mutex_unlock(&sl->lock);
}

/* Variant i has run and is not the one running. */
static bool finished(const struct hl_suite_live *sl, int i)
{
	const struct hl_suite_variant *v = &sl->r->v[i];

	return i != sl->current && v->id[0] && v->n_frames > 0;
}

/* The limit of series s's photometer at range_m (NAN: none). */
static double limit_at(const struct hl_suite *s, const struct hl_suite_series *se, double range_m)
{
	int b;

	if (s->procedure != HL_SUITE_FMVSS108_ADB)
		return NAN;
	b = hl_suite_bin_of(s, se->role, range_m);
	return b < 0 ? NAN : s->bin[b].max_lx;
}

/* A case so far: its bin's maximum (as judged: rounded) against the limit. */
static const char *so_far(const struct hl_suite *s, const struct hl_suite_case *c)
{
	double value;

	if (c->n_samples == 0)
		return "not_reached";
	if (isnan(c->limit))
		return "reported";
	value = c->unit && !strcmp(c->unit, "lx") ? hl_suite_round(s, c->max_raw) : c->max_raw;
	return value > c->limit ? "failing" : "passing";
}

static void write_case(FILE *f, const struct hl_suite *s, const struct hl_suite_case *c)
{
	fputs("{\"name\":", f);
	hl_json_write_str(f, c->name);
	fputs(",\"photometer\":", f);
	hl_json_write_str(f, c->photometer);
	fputs(",\"from_m\":", f);
	hl_json_write_num(f, c->from_m, "%.1f");
	fputs(",\"to_m\":", f);
	hl_json_write_num(f, c->to_m, "%.1f");
	fprintf(f, ",\"samples\":%d,\"max\":", c->n_samples);
	hl_json_write_num(f, c->max_raw, "%.6g");
	fputs(",\"limit\":", f);
	hl_json_write_num(f, c->limit, "%.6g");
	fputs(",\"unit\":", f);
	hl_json_write_str(f, c->unit);
	fprintf(f, ",\"status\":\"%s\"}", so_far(s, c));
}

void hl_suite_live_status_json(struct hl_suite_live *sl, FILE *f)
{
	const struct hl_suite_result *r;

	if (!sl)
		return;
	r = sl->r;
	pthread_mutex_lock(&sl->lock);
	fputs(",\"suite\":{\"name\":", f);
	hl_json_write_str(f, r->suite->name);
	fputs(",\"title\":", f);
	hl_json_write_str(f, r->suite->title);
	fprintf(f, ",\"variants\":%d,\"frames\":%llu,\"current\":", r->n_variants,
		(unsigned long long)sl->frames);
	if (sl->current < 0) {
		fputs("null", f);
	} else {
		const struct hl_suite_variant *v = &r->v[sl->current];

		fprintf(f, "{\"index\":%d,\"id\":", sl->current);
		hl_json_write_str(f, v->id);
		fputs(",\"title\":", f);
		hl_json_write_str(f, v->title);
		fputs(",\"scene_t_s\":", f);
		hl_json_write_num(f, sl->scene_t_s, "%.3f");
		fputs(",\"photometers\":[", f);
		for (int i = 0; i < v->n_series; i++) {
			double range = NAN, lx = NAN;
			const bool have = sl->m && hl_suite_measure_last(sl->m, i, &range, &lx);

			fputs(i ? ",{\"id\":" : "{\"id\":", f);
			hl_json_write_str(f, v->series[i].label);
			fputs(",\"range_m\":", f);
			hl_json_write_num(f, have ? range : NAN, "%.2f");
			fputs(",\"lx\":", f);
			hl_json_write_num(f, have ? lx : NAN, "%.6g");
			fputs(",\"limit_lx\":", f);
			hl_json_write_num(f, have ? limit_at(r->suite, &v->series[i], range) : NAN,
					  "%.6g");
			fputs("}", f);
		}
		fputs("],\"bins\":[", f);
		for (int k = 0; k < v->n_cases; k++) {
			fputs(k ? "," : "", f);
			write_case(f, r->suite, &v->cases[k]);
		}
		fputs("]}", f);
	}
	fputs(",\"done\":[", f);
	for (int i = 0, first = 1; i < r->n_variants; i++) {
		const struct hl_suite_variant *v = &r->v[i];
		struct hl_suite_totals t;

		if (!finished(sl, i))
			continue;
		hl_suite_variant_totals(v, &t);
		fputs(first ? "{\"id\":" : ",{\"id\":", f);
		first = 0;
		hl_json_write_str(f, v->id);
		fprintf(f, ",\"frames\":%d,\"cases\":%d,\"judged\":%d,\"failed\":%d}", v->n_frames,
			t.cases, t.judged, t.failed + t.no_samples);
	}
	fputs("]}", f);
	pthread_mutex_unlock(&sl->lock);
}

void hl_suite_live_metrics(struct hl_suite_live *sl, struct hl_prom *p)
{
	const struct hl_suite_result *r;
	int done = 0, failed = 0;

	if (!sl)
		return;
	r = sl->r;
	pthread_mutex_lock(&sl->lock);
	for (int i = 0; i < r->n_variants; i++) {
		struct hl_suite_totals t;

		if (!finished(sl, i))
			continue;
		hl_suite_variant_totals(&r->v[i], &t);
		done++;
		failed += t.failed + t.no_samples;
	}
	hl_prom_family(p, "hdlamp_suite_frames_total", HL_PROM_COUNTER,
		       "frames the suite's photometers measured, over every variant");
	hl_prom_counter(p, "hdlamp_suite_frames_total", NULL, sl->frames);
	hl_prom_family(p, "hdlamp_suite_variants", HL_PROM_GAUGE, "the suite's variants");
	hl_prom_gauge(p, "hdlamp_suite_variants", NULL, r->n_variants);
	hl_prom_family(p, "hdlamp_suite_variants_done", HL_PROM_GAUGE, "variants finished");
	hl_prom_gauge(p, "hdlamp_suite_variants_done", NULL, done);
	hl_prom_family(p, "hdlamp_suite_cases_failed", HL_PROM_GAUGE,
		       "cases failed (or bins not reached) in the finished variants");
	hl_prom_gauge(p, "hdlamp_suite_cases_failed", NULL, failed);
	if (sl->current >= 0 && sl->m) {
		const struct hl_suite_variant *v = &r->v[sl->current];

		hl_prom_family(p, "hdlamp_suite_photometer_lux", HL_PROM_GAUGE,
			       "the newest frame's illuminance at each photometer of the variant");
		for (int i = 0; i < v->n_series; i++) {
			double range, lx;
			const char *labels[] = { "variant", v->id, "photometer", v->series[i].label,
						 NULL };

			if (hl_suite_measure_last(sl->m, i, &range, &lx))
				hl_prom_gauge(p, "hdlamp_suite_photometer_lux", labels, lx);
		}
		hl_prom_family(p, "hdlamp_suite_photometer_limit_lux", HL_PROM_GAUGE,
			       "the limit of the bin of each photometer's newest range (FMVSS)");
		for (int i = 0; i < v->n_series; i++) {
			double range, lx;
			const char *labels[] = { "variant", v->id, "photometer", v->series[i].label,
						 NULL };

			if (hl_suite_measure_last(sl->m, i, &range, &lx) &&
			    !isnan(limit_at(r->suite, &v->series[i], range)))
				hl_prom_gauge(p, "hdlamp_suite_photometer_limit_lux", labels,
					      limit_at(r->suite, &v->series[i], range));
		}
	}
	pthread_mutex_unlock(&sl->lock);
}
