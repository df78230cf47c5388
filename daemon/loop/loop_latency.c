/* SPDX-License-Identifier: MIT */
/* The closed loop's latency and glare verdict: see daemon/loop/loop_latency.h. */
#include "daemon/loop/loop_latency.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "base/sched.h"
#include "base/json_write.h"

#define MS_NS 1e6

/* What the consumer needs of a published frame. */
struct frame_sum {
	uint64_t seq;
	double t_s;
	int64_t t_cycle_min_ns, t_cycle_max_ns; /* the lamps' cycles' completions */
	int64_t t_render_done_ns;
	uint32_t failed; /* bit i: road user i over its limit */
	int n_actors;
	float lux[HL_SCN_MAX_ACTORS];
};

/* The consumer's view of one road user. */
struct actor_state {
	bool visible;
	bool open; /* an enter event waits for its masking frame */
	struct hl_loop_event ev; /* the open enter event */
	double interval_glare_s;
	uint64_t interval_frames_over;
};

struct hl_loop_latency {
	struct hl_loop_latency_config cfg;
	int n_actors;

	/* the render thread -> consumer ring: the producer owns head, the consumer tail */
	struct frame_sum slot[HL_LOOP_FRAME_SLOTS];
	atomic_uint_fast64_t head, tail;
	atomic_uint_fast64_t dropped;

	/* the consumer's own */
	struct frame_sum pending[HL_LOOP_FRAME_SLOTS];
	int n_pending;
	struct actor_state a[HL_SCN_MAX_ACTORS];
	bool have_prev;
	double prev_t_s;
	uint32_t prev_over_view, prev_over_late, prev_over_any;
	bool finished;

	pthread_mutex_t lock; /* PI: guards c and events; the consumer holds it to update */
	struct hl_loop_counts c;
	struct hl_loop_event events[HL_LOOP_MAX_EVENTS];
	int n_events;
};

static const double latency_bounds_s[] = { 10,	20,  30,  40,  50,  60,	  80,	100,
					   120, 160, 200, 300, 500, 1000, 2000, 5000 };
static const char *const stage_names[3] = { "input", "mask", "frame" };

int hl_loop_latency_new(const struct hl_loop_latency_config *cfg, struct hl_loop_latency **ret)
{
	struct hl_loop_latency *ll;
	int rc;

	if (!(cfg->ecu_cycle_ms > 0) || !(cfg->reaction_ms > 0) || !cfg->sc)
		return -EINVAL;
	ll = calloc(1, sizeof(*ll));
	if (!ll)
		return -ENOMEM;
	ll->cfg = *cfg;
	ll->n_actors = cfg->sc->n_actors;
	ll->c.n_actors = ll->n_actors;
	atomic_init(&ll->head, 0);
	atomic_init(&ll->tail, 0);
	atomic_init(&ll->dropped, 0);
	for (int s = 0; s < 3; s++)
		hl_prom_histogram_init(
			&ll->c.latency_s[s], latency_bounds_s,
			(int)(sizeof(latency_bounds_s) / sizeof(latency_bounds_s[0])));
	rc = hl_mutex_init_pi(&ll->lock);
	if (rc < 0) {
		free(ll);
		return rc;
	}
	*ret = ll;
	return 0;
}

void hl_loop_latency_free(struct hl_loop_latency *ll)
{
	if (!ll)
		return;
	pthread_mutex_destroy(&ll->lock);
	free(ll);
}

double hl_loop_latency_reaction_ms(const struct hl_loop_latency *ll)
{
	return ll->cfg.reaction_ms;
}

void hl_loop_latency_frame(struct hl_loop_latency *ll, const struct hl_frame *f)
{
	const uint64_t head = atomic_load_explicit(&ll->head, memory_order_relaxed);
	const uint64_t tail = atomic_load_explicit(&ll->tail, memory_order_acquire);
	struct frame_sum *s;
	int n_lamps = f->hdr.n_lamps ? f->hdr.n_lamps : 1;

	if (head - tail >= HL_LOOP_FRAME_SLOTS) {
		atomic_fetch_add_explicit(&ll->dropped, 1, memory_order_relaxed);
		return;
	}
	s = &ll->slot[head % HL_LOOP_FRAME_SLOTS];
	s->seq = f->hdr.seq;
	s->t_s = f->hdr.scene_t_s;
	s->t_cycle_min_ns = INT64_MAX;
	s->t_cycle_max_ns = INT64_MIN;
	for (int l = 0; l < n_lamps && l < HL_FRAME_MAX_LAMPS; l++) {
		const int64_t t = f->hdr.t_lamp_done_ns[l];

		s->t_cycle_min_ns = t < s->t_cycle_min_ns ? t : s->t_cycle_min_ns;
		s->t_cycle_max_ns = t > s->t_cycle_max_ns ? t : s->t_cycle_max_ns;
	}
	s->t_render_done_ns = f->hdr.t_render_done_ns;
	s->failed = f->hdr.glare_failed;
	s->n_actors = f->hdr.n_actors < ll->n_actors ? f->hdr.n_actors : ll->n_actors;
	for (int i = 0; i < s->n_actors; i++)
		s->lux[i] = (float)f->glare[i].illuminance_lx;
	atomic_store_explicit(&ll->head, head + 1, memory_order_release);
}

/* Consumer: moves what the render thread handed over into pending. */
static void take_frames(struct hl_loop_latency *ll)
{
	const uint64_t head = atomic_load_explicit(&ll->head, memory_order_acquire);
	uint64_t tail = atomic_load_explicit(&ll->tail, memory_order_relaxed);

	while (tail != head && ll->n_pending < HL_LOOP_FRAME_SLOTS) {
		ll->pending[ll->n_pending++] = ll->slot[tail % HL_LOOP_FRAME_SLOTS];
		tail++;
	}
	atomic_store_explicit(&ll->tail, tail, memory_order_release);
}

static double ms_between(int64_t a_ns, int64_t b_ns)
{
	return (double)(b_ns - a_ns) / MS_NS;
}

void hl_loop_event_json(const struct hl_loop_latency *ll, const struct hl_loop_event *e, FILE *f)
{
	const double cyc = ll->cfg.ecu_cycle_ms;
	const char *kind = e->enter ? "enter" : e->t_enter_ns ? "leave" : "end";

	fprintf(f, "{\"event\":\"%s\",\"actor\":\"%s\",\"index\":%d,\"t_enter_s\":%.6f", kind,
		ll->cfg.sc->actor[e->actor].id, e->actor, e->t_enter_s);
	if (e->t_enter_ns)
		fprintf(f, ",\"t_enter_ns\":%" PRId64 ",\"t_input_ns\":%" PRId64, e->t_enter_ns,
			e->t_input_ns);
	if (e->enter) {
		const double in = ms_between(e->t_enter_ns, e->t_input_ns);

		fprintf(f, ",\"masked\":%s", e->masked ? "true" : "false");
		if (e->masked) {
			const double mk = ms_between(e->t_enter_ns, e->t_mask_ns);
			const double fr = ms_between(e->t_enter_ns, e->t_frame_ns);

			fprintf(f,
				",\"t_mask_ns\":%" PRId64 ",\"t_frame_ns\":%" PRId64
				",\"frame_seq\":%" PRIu64 ",\"latency_ms\":{\"input\":%.3f,"
				"\"mask\":%.3f,\"frame\":%.3f},\"latency_cycles\":{\"input\":%.3f,"
				"\"mask\":%.3f,\"frame\":%.3f}",
				e->t_mask_ns, e->t_frame_ns, e->frame_seq, in, mk, fr, in / cyc,
				mk / cyc, fr / cyc);
		} else {
			fprintf(f,
				",\"latency_ms\":{\"input\":%.3f},\"latency_cycles\":{\"input\":%.3f}",
				in, in / cyc);
		}
	} else {
		if (e->t_enter_ns)
			fprintf(f, ",\"latency_ms\":{\"input\":%.3f}",
				ms_between(e->t_enter_ns, e->t_input_ns));
		fprintf(f, ",\"glare_s\":%.6f,\"frames_over\":%" PRIu64, e->glare_s,
			e->frames_over);
	}
	fputc('}', f);
}

/* Consumer: keeps e (counted) and writes its line. */
static void emit(struct hl_loop_latency *ll, const struct hl_loop_event *e)
{
	pthread_mutex_lock(&ll->lock);
	ll->c.events++;
	if (ll->n_events < HL_LOOP_MAX_EVENTS)
		ll->events[ll->n_events++] = *e;
	else
		ll->c.events_not_kept++;
	if (e->enter && e->masked) {
		hl_prom_histogram_observe(&ll->c.latency_s[0],
					  ms_between(e->t_enter_ns, e->t_input_ns) / 1e3);
		hl_prom_histogram_observe(&ll->c.latency_s[1],
					  ms_between(e->t_enter_ns, e->t_mask_ns) / 1e3);
		hl_prom_histogram_observe(&ll->c.latency_s[2],
					  ms_between(e->t_enter_ns, e->t_frame_ns) / 1e3);
	} else if (e->enter) {
		ll->c.unmasked++;
	}
	pthread_mutex_unlock(&ll->lock);
	if (ll->cfg.events) {
		hl_loop_event_json(ll, e, ll->cfg.events);
		fputc('\n', ll->cfg.events);
		fflush(ll->cfg.events);
	}
}

/* Consumer: one frame under the camera state in force at its time. */
static void judge(struct hl_loop_latency *ll, const struct frame_sum *s)
{
	const double reaction_s = ll->cfg.reaction_ms / 1e3;
	uint32_t over_view = 0, over_late = 0;
	struct hl_loop_event done[HL_SCN_MAX_ACTORS];
	int n_done = 0;

	pthread_mutex_lock(&ll->lock);
	if (ll->have_prev) {
		const double dt = s->t_s > ll->prev_t_s ? s->t_s - ll->prev_t_s : 0.0;

		for (int i = 0; i < ll->n_actors; i++) {
			if (ll->prev_over_view & (1u << i)) {
				ll->c.actor[i].glare_s += dt;
				ll->a[i].interval_glare_s += dt;
			}
			if (ll->prev_over_late & (1u << i))
				ll->c.actor[i].glare_late_s += dt;
			if (ll->prev_over_any & (1u << i))
				ll->c.actor[i].glare_total_s += dt;
		}
	}
	for (int i = 0; i < s->n_actors; i++) {
		struct hl_loop_actor *ac = &ll->c.actor[i];
		struct actor_state *st = &ll->a[i];
		const bool over = s->failed & (1u << i);

		ac->max_lux = fmax(ac->max_lux, (double)s->lux[i]);
		if (over)
			ac->frames_over++;
		if (over && !st->visible) {
			ac->frames_over_unseen++;
		} else if (over) {
			over_view |= 1u << i;
			st->interval_frames_over++;
			if (s->t_s - st->ev.t_enter_s <= reaction_s + 1e-9) {
				ac->frames_over_in_reaction++;
			} else {
				ac->frames_over_late++;
				over_late |= 1u << i;
			}
		}
		/* the first frame under the limit showing cycles received after the input */
		if (st->visible && st->open && !over && s->t_cycle_min_ns > st->ev.t_input_ns) {
			st->ev.masked = true;
			st->ev.t_mask_ns = s->t_cycle_max_ns;
			st->ev.t_frame_ns = s->t_render_done_ns;
			st->ev.frame_seq = s->seq;
			st->open = false;
			done[n_done++] = st->ev;
		}
	}
	ll->have_prev = true;
	ll->prev_t_s = s->t_s;
	ll->prev_over_view = over_view;
	ll->prev_over_late = over_late;
	ll->prev_over_any = s->failed;
	ll->c.frames_judged++;
	pthread_mutex_unlock(&ll->lock);
	for (int k = 0; k < n_done; k++)
		emit(ll, &done[k]);
}

void hl_loop_latency_drain(struct hl_loop_latency *ll, double t_s)
{
	int k = 0;

	take_frames(ll);
	while (k < ll->n_pending && ll->pending[k].t_s < t_s)
		judge(ll, &ll->pending[k++]);
	if (k) {
		memmove(ll->pending, ll->pending + k, sizeof(ll->pending[0]) * (ll->n_pending - k));
		ll->n_pending -= k;
	}
	pthread_mutex_lock(&ll->lock);
	ll->c.frames_dropped = atomic_load_explicit(&ll->dropped, memory_order_relaxed);
	ll->c.frames_in = atomic_load_explicit(&ll->head, memory_order_acquire);
	pthread_mutex_unlock(&ll->lock);
}

/* Consumer: road user i's visible interval ends (a leave at a cycle, or the end: t_ns 0). */
static void close_interval(struct hl_loop_latency *ll, int i, double t_s, int64_t t_ns,
			   int64_t t_input_ns)
{
	struct actor_state *st = &ll->a[i];
	struct hl_loop_event e = {
		.actor = i, .t_enter_s = t_s, .t_enter_ns = t_ns, .t_input_ns = t_input_ns
	};

	if (st->open) { /* never masked while in view */
		st->open = false;
		emit(ll, &st->ev);
	}
	pthread_mutex_lock(&ll->lock);
	e.glare_s = st->interval_glare_s;
	e.frames_over = st->interval_frames_over;
	if (t_ns)
		ll->c.actor[i].leaves++;
	pthread_mutex_unlock(&ll->lock);
	/* the time after the last frame in view is not this interval's */
	ll->prev_over_view &= ~(1u << i);
	ll->prev_over_late &= ~(1u << i);
	st->visible = false;
	st->interval_glare_s = 0;
	st->interval_frames_over = 0;
	emit(ll, &e);
}

void hl_loop_latency_camera(struct hl_loop_latency *ll, int64_t deadline_ns, double t_s,
			    uint32_t visible, int64_t t_input_ns)
{
	hl_loop_latency_drain(ll, t_s);
	for (int i = 0; i < ll->n_actors; i++) {
		struct actor_state *st = &ll->a[i];
		const bool vis = visible & (1u << i);

		if (vis && !st->visible) {
			st->visible = true;
			st->open = true;
			st->interval_glare_s = 0;
			st->interval_frames_over = 0;
			st->ev = (struct hl_loop_event){ .actor = i,
							 .enter = true,
							 .t_enter_s = t_s,
							 .t_enter_ns = deadline_ns,
							 .t_input_ns = t_input_ns };
			pthread_mutex_lock(&ll->lock);
			ll->c.actor[i].entries++;
			pthread_mutex_unlock(&ll->lock);
		} else if (!vis && st->visible) {
			close_interval(ll, i, t_s, deadline_ns, t_input_ns);
		}
	}
	pthread_mutex_lock(&ll->lock);
	ll->c.camera_cycles++;
	pthread_mutex_unlock(&ll->lock);
}

void hl_loop_latency_finish(struct hl_loop_latency *ll)
{
	if (ll->finished)
		return;
	ll->finished = true;
	hl_loop_latency_drain(ll, INFINITY);
	for (int i = 0; i < ll->n_actors; i++)
		if (ll->a[i].visible)
			close_interval(ll, i, ll->have_prev ? ll->prev_t_s : 0.0, 0, 0);
}

void hl_loop_latency_counts(struct hl_loop_latency *ll, struct hl_loop_counts *ret)
{
	pthread_mutex_lock(&ll->lock);
	*ret = ll->c;
	pthread_mutex_unlock(&ll->lock);
}

bool hl_loop_latency_event(struct hl_loop_latency *ll, int k, struct hl_loop_event *ret)
{
	bool ok;

	pthread_mutex_lock(&ll->lock);
	ok = k >= 0 && k < ll->n_events;
	if (ok)
		*ret = ll->events[k];
	pthread_mutex_unlock(&ll->lock);
	return ok;
}

bool hl_loop_latency_strict(const struct hl_loop_latency *ll)
{
	return !ll->cfg.camera;
}

static bool actor_passed(const struct hl_loop_latency *ll, const struct hl_loop_actor *a)
{
	return ll->cfg.camera ? a->frames_over_late == 0 : a->frames_over == 0;
}

bool hl_loop_latency_passed(struct hl_loop_latency *ll)
{
	struct hl_loop_counts c;

	hl_loop_latency_counts(ll, &c);
	for (int i = 0; i < c.n_actors; i++)
		if (!actor_passed(ll, &c.actor[i]))
			return false;
	return true;
}

/* Percentile p (0..1) of the masked enter events' stage latency (ms); NAN without one. */
static double percentile(struct hl_loop_latency *ll, int stage, double p)
{
	double v[HL_LOOP_MAX_EVENTS];
	int n = 0;
	struct hl_loop_event e;

	for (int k = 0; hl_loop_latency_event(ll, k, &e); k++) {
		const int64_t t[3] = { e.t_input_ns, e.t_mask_ns, e.t_frame_ns };
		double x;
		int j;

		if (!e.enter || !e.masked)
			continue;
		x = ms_between(e.t_enter_ns, t[stage]);
		for (j = n; j > 0 && v[j - 1] > x; j--)
			v[j] = v[j - 1];
		v[j] = x;
		n++;
	}
	if (!n)
		return NAN;
	return v[(int)ceil(p * n) - 1 < 0 ? 0 : (int)ceil(p * n) - 1];
}

static void summary_json(struct hl_loop_latency *ll, const struct hl_loop_counts *c, FILE *f)
{
	fprintf(f,
		"\"camera\":%s,\"ecu_cycle_ms\":%.6g,\"reaction_ms\":%.6g,\"frames_in\":%" PRIu64
		",\"frames_dropped\":%" PRIu64 ",\"frames_judged\":%" PRIu64
		",\"camera_cycles\":%" PRIu64 ",\"events\":%" PRIu64 ",\"events_not_kept\":%" PRIu64
		",\"unmasked\":%" PRIu64 ",\"latency_ms\":{",
		ll->cfg.camera ? "true" : "false", ll->cfg.ecu_cycle_ms, ll->cfg.reaction_ms,
		c->frames_in, c->frames_dropped, c->frames_judged, c->camera_cycles, c->events,
		c->events_not_kept, c->unmasked);
	for (int s = 0; s < 3; s++) {
		fprintf(f, "%s\"%s\":{\"n\":%" PRIu64 ",\"p50\":", s ? "," : "", stage_names[s],
			c->latency_s[s].count);
		hl_json_write_num(f, percentile(ll, s, 0.5), "%.3f");
		fputs(",\"p99\":", f);
		hl_json_write_num(f, percentile(ll, s, 0.99), "%.3f");
		fputs(",\"max\":", f);
		hl_json_write_num(f, percentile(ll, s, 1.0), "%.3f");
		fputc('}', f);
	}
	fprintf(f, "},\"passed\":%s,\"actors\":[", hl_loop_latency_passed(ll) ? "true" : "false");
	for (int i = 0; i < c->n_actors; i++) {
		const struct hl_loop_actor *a = &c->actor[i];

		fprintf(f,
			"%s{\"id\":\"%s\",\"max_lux\":%.7g,\"frames_over\":%" PRIu64
			",\"frames_over_in_reaction\":%" PRIu64 ",\"frames_over_late\":%" PRIu64
			",\"frames_over_unseen\":%" PRIu64
			",\"glare_s\":%.6f,\"glare_late_s\":%.6f,\"glare_total_s\":%.6f,"
			"\"entries\":%" PRIu64 ",\"leaves\":%" PRIu64 ",\"passed\":%s}",
			i ? "," : "", ll->cfg.sc->actor[i].id, a->max_lux, a->frames_over,
			a->frames_over_in_reaction, a->frames_over_late, a->frames_over_unseen,
			a->glare_s, a->glare_late_s, a->glare_total_s, a->entries, a->leaves,
			actor_passed(ll, a) ? "true" : "false");
	}
	fputc(']', f);
}

void hl_loop_latency_status_json(struct hl_loop_latency *ll, FILE *f)
{
	struct hl_loop_counts c;
	struct hl_loop_event e;
	int last = -1;

	hl_loop_latency_counts(ll, &c);
	fputs(",\"loop\":{", f);
	summary_json(ll, &c, f);
	for (int k = 0; hl_loop_latency_event(ll, k, &e); k++)
		if (e.enter)
			last = k;
	if (last >= 0 && hl_loop_latency_event(ll, last, &e)) {
		fputs(",\"last_enter\":", f);
		hl_loop_event_json(ll, &e, f);
	}
	fputc('}', f);
}

void hl_loop_latency_report_json(struct hl_loop_latency *ll, FILE *f)
{
	struct hl_loop_counts c;
	struct hl_loop_event e;

	hl_loop_latency_counts(ll, &c);
	fputs("\"loop\":{", f);
	summary_json(ll, &c, f);
	fputs(",\"event_list\":[", f);
	for (int k = 0; hl_loop_latency_event(ll, k, &e); k++) {
		if (k)
			fputc(',', f);
		hl_loop_event_json(ll, &e, f);
	}
	fputs("]}", f);
}

void hl_loop_latency_metrics(struct hl_loop_latency *ll, struct hl_prom *p)
{
	struct hl_loop_counts c;

	hl_loop_latency_counts(ll, &c);
	hl_prom_family(p, "hdlamp_loop_latency_seconds", HL_PROM_HISTOGRAM,
		       "Closed-loop latency per road user entering the camera's view, from the "
		       "camera cycle that first carried it to the stage (s).");
	for (int s = 0; s < 3; s++)
		hl_prom_histogram(p, "hdlamp_loop_latency_seconds",
				  (const char *const[]){ "stage", stage_names[s], NULL },
				  &c.latency_s[s]);
	hl_prom_family(p, "hdlamp_loop_events_total", HL_PROM_COUNTER,
		       "Road users entering or leaving the camera's view (and open at the end).");
	hl_prom_counter(p, "hdlamp_loop_events_total", NULL, c.events);
	hl_prom_family(p, "hdlamp_loop_unmasked_total", HL_PROM_COUNTER,
		       "Entries no frame masked before the road user left or the run ended.");
	hl_prom_counter(p, "hdlamp_loop_unmasked_total", NULL, c.unmasked);
	hl_prom_family(p, "hdlamp_loop_frames_dropped_total", HL_PROM_COUNTER,
		       "Frames not judged because the hand-over ring was full.");
	hl_prom_counter(p, "hdlamp_loop_frames_dropped_total", NULL, c.frames_dropped);
	if (!c.n_actors)
		return;
	hl_prom_family(p, "hdlamp_loop_glare_late_frames_total", HL_PROM_COUNTER,
		       "Frames a road user in the camera's view was over its glare limit after the "
		       "reaction time (violations).");
	for (int i = 0; i < c.n_actors; i++)
		hl_prom_counter(p, "hdlamp_loop_glare_late_frames_total",
				(const char *const[]){ "actor", ll->cfg.sc->actor[i].id, NULL },
				c.actor[i].frames_over_late);
	hl_prom_family(
		p, "hdlamp_loop_glare_seconds", HL_PROM_GAUGE,
		"Scenario time a road user in the camera's view was over its glare limit (s).");
	for (int i = 0; i < c.n_actors; i++)
		hl_prom_gauge(p, "hdlamp_loop_glare_seconds",
			      (const char *const[]){ "actor", ll->cfg.sc->actor[i].id, NULL },
			      c.actor[i].glare_s);
}
