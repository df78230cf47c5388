/* SPDX-License-Identifier: MIT */
/* The live glare of a scenario: see daemon/core/glare_live.h. */
#include "daemon/core/glare_live.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "base/sched.h"
#include "base/json_write.h"

/* One frame in the history: what /glare.json gives per frame. */
struct entry {
	uint64_t seq;
	double t_s;
	uint32_t failed; /* bit i: road user i over its limit */
	uint8_t source;
	float eye_lux_max;
	float lux[HL_SCN_MAX_ACTORS];
	float cd[HL_SCN_MAX_ACTORS]; /* half the pair's sum */
	float distance_m[HL_SCN_MAX_ACTORS];
};

struct hl_glare_live {
	const struct hl_scenario *sc;
	const struct hl_regulation *reg;
	struct hl_glare *plan;

	pthread_mutex_t lock; /* PI: the render thread stores under it; guards what follows */
	struct entry *history;
	size_t n_history, next, used; /* capacity; where the next goes; how many are kept */
	struct hl_glare_live_counts c;
};

int hl_glare_live_new(const struct hl_scenario *sc, const struct hl_regulation *reg,
		      const struct hl_lid_grid *const grids[2], int history,
		      struct hl_glare_live **ret)
{
	struct hl_glare_live *gl;
	int rc;

	if (history < 1)
		return -EINVAL;
	gl = calloc(1, sizeof(*gl));
	if (!gl)
		return -ENOMEM;
	gl->sc = sc;
	gl->reg = reg;
	gl->n_history = (size_t)history;
	gl->history = calloc(gl->n_history, sizeof(*gl->history));
	rc = gl->history ? hl_glare_new(sc, reg, grids, &gl->plan) : -ENOMEM;
	if (rc == 0)
		rc = hl_mutex_init_pi(&gl->lock);
	if (rc < 0) {
		hl_glare_free(gl->plan);
		free(gl->history);
		free(gl);
		return rc;
	}
	*ret = gl;
	return 0;
}

void hl_glare_live_free(struct hl_glare_live *gl)
{
	if (!gl)
		return;
	pthread_mutex_destroy(&gl->lock);
	hl_glare_free(gl->plan);
	free(gl->history);
	free(gl);
}

const struct hl_scenario *hl_glare_live_scenario(const struct hl_glare_live *gl)
{
	return gl->sc;
}

const struct hl_regulation *hl_glare_live_regulation(const struct hl_glare_live *gl)
{
	return gl->reg;
}

const char *hl_scene_source_name(enum hl_scene_source s)
{
	switch (s) {
	case HL_SCENE_CLOCK:
		return "clock";
	case HL_SCENE_LOG:
		return "log";
	case HL_SCENE_POSE:
		return "pose";
	case HL_SCENE_OSI:
		return "osi";
	default:
		return "none";
	}
}

void hl_glare_live_eval(struct hl_glare_live *gl, const struct hl_world_state *w,
			enum hl_scene_source source, const float *const dist[2], uint64_t seq,
			struct hl_frame *f)
{
	const int n = gl->sc->n_actors;
	struct entry *e;
	uint32_t failed = 0;
	double lux_max = 0.0;

	hl_glare_eval_world(gl->plan, w, dist, f->glare);
	for (int i = 0; i < n; i++) {
		if (!f->glare[i].pass)
			failed |= 1u << i;
		lux_max = fmax(lux_max, f->glare[i].illuminance_lx);
	}
	f->hdr.scene_t_s = w->t_s;
	f->hdr.scene_source = (uint8_t)source;
	f->hdr.n_actors = (uint8_t)n;
	f->hdr.glare_failed = failed;
	f->hdr.eye_lux_max = (float)lux_max;

	pthread_mutex_lock(&gl->lock);
	e = &gl->history[gl->next];
	e->seq = seq;
	e->t_s = w->t_s;
	e->failed = failed;
	e->source = (uint8_t)source;
	e->eye_lux_max = (float)lux_max;
	for (int i = 0; i < n; i++) {
		e->lux[i] = (float)f->glare[i].illuminance_lx;
		e->cd[i] = (float)f->glare[i].pair_half_cd;
		e->distance_m[i] = (float)f->glare[i].distance_m;
		if (failed & (1u << i))
			gl->c.fail_frames[i]++;
	}
	gl->next = (gl->next + 1) % gl->n_history;
	if (gl->used < gl->n_history)
		gl->used++;
	else
		gl->c.history_overwritten++;
	gl->c.frames++;
	pthread_mutex_unlock(&gl->lock);
}

void hl_glare_live_counts(struct hl_glare_live *gl, struct hl_glare_live_counts *ret)
{
	pthread_mutex_lock(&gl->lock);
	*ret = gl->c;
	pthread_mutex_unlock(&gl->lock);
}

void hl_glare_live_status_json(struct hl_glare_live *gl, const struct hl_frame *f,
			       double pose_age_s, FILE *out)
{
	const struct hl_scenario *sc = gl->sc;
	struct hl_glare_live_counts c;

	hl_glare_live_counts(gl, &c);
	fputs(",\"scene\":{\"title\":", out);
	hl_json_write_str(out, sc->title);
	fprintf(out, ",\"duration_s\":%.6g,\"glare_set\":", sc->duration_s);
	hl_json_write_str(out, gl->reg->id);
	fprintf(out, ",\"frames\":%" PRIu64 ",\"history_overwritten\":%" PRIu64, c.frames,
		c.history_overwritten);
	if (f)
		fprintf(out, ",\"seq\":%" PRIu64 ",\"t_s\":%.9g,\"source\":\"%s\"", f->hdr.seq,
			f->hdr.scene_t_s,
			hl_scene_source_name((enum hl_scene_source)f->hdr.scene_source));
	if (pose_age_s >= 0.0)
		fprintf(out, ",\"pose_age_s\":%.3f", pose_age_s);
	fputs("},\"glare\":[", out);
	for (int i = 0; f && i < sc->n_actors && i < f->hdr.n_actors; i++) {
		const struct hl_glare_result *r = &f->glare[i];

		fprintf(out, "%s{\"id\":", i ? "," : "");
		hl_json_write_str(out, sc->actor[i].id);
		if (!r->present) { /* not in the world (a recording's road user that left) */
			fprintf(out, ",\"kind\":\"%s\",\"role\":\"%s\",\"present\":false}",
				hl_actor_kind_name(sc->actor[i].kind),
				hl_actor_role_name(sc->actor[i].role));
			continue;
		}
		fprintf(out,
			",\"kind\":\"%s\",\"role\":\"%s\",\"distance_m\":%.9g,\"eye_lux\":%.9g,"
			"\"cd\":{\"left\":%.9g,\"right\":%.9g,\"pair_half\":%.9g},\"present\":true,"
			"\"limit_cd\":",
			hl_actor_kind_name(sc->actor[i].kind),
			hl_actor_role_name(sc->actor[i].role), r->distance_m, r->illuminance_lx,
			r->intensity_cd[0], r->intensity_cd[1], r->pair_half_cd);
		hl_json_write_num(out, r->limit.max_cd, "%.9g");
		fputs(",\"limit_distance_m\":", out);
		hl_json_write_num(out, r->limit.table_distance_m, "%.9g");
		fprintf(out, ",\"pass\":%s,\"fail_frames\":%" PRIu64 "}",
			r->pass ? "true" : "false", c.fail_frames[i]);
	}
	fputc(']', out);
}

void hl_glare_live_metrics(struct hl_glare_live *gl, const struct hl_frame *f, struct hl_prom *p)
{
	const struct hl_scenario *sc = gl->sc;
	const int n = f ? (sc->n_actors < f->hdr.n_actors ? sc->n_actors : f->hdr.n_actors) : 0;
	struct hl_glare_live_counts c;
	int n_limits = 0;

	hl_glare_live_counts(gl, &c);
	hl_prom_family(p, "hdlamp_glare_frames_total", HL_PROM_COUNTER,
		       "Frames whose glare at the road users' eyes was evaluated.");
	hl_prom_counter(p, "hdlamp_glare_frames_total", NULL, c.frames);
	hl_prom_family(p, "hdlamp_glare_history_overwritten_total", HL_PROM_COUNTER,
		       "Frames the bounded /glare.json history dropped to make room.");
	hl_prom_counter(p, "hdlamp_glare_history_overwritten_total", NULL, c.history_overwritten);
	if (sc->n_actors)
		hl_prom_family(p, "hdlamp_glare_fail_frames_total", HL_PROM_COUNTER,
			       "Frames a road user's glare was over its limit.");
	for (int i = 0; i < sc->n_actors; i++)
		hl_prom_counter(p, "hdlamp_glare_fail_frames_total",
				(const char *const[]){ "actor", sc->actor[i].id, NULL },
				c.fail_frames[i]);
	if (!f)
		return; /* no frame yet: no per-frame samples, and no family without samples */
	hl_prom_family(p, "hdlamp_scene_time_seconds", HL_PROM_GAUGE,
		       "Scenario time of the newest frame (s).");
	hl_prom_gauge(p, "hdlamp_scene_time_seconds", NULL, f->hdr.scene_t_s);
	if (!n)
		return;
	hl_prom_family(p, "hdlamp_glare_lux", HL_PROM_GAUGE,
		       "Illuminance at the road user's eye, both lamps, newest frame (lux).");
	for (int i = 0; i < n; i++)
		hl_prom_gauge(p, "hdlamp_glare_lux",
			      (const char *const[]){ "actor", sc->actor[i].id, NULL },
			      f->glare[i].illuminance_lx);
	hl_prom_family(
		p, "hdlamp_glare_cd", HL_PROM_GAUGE,
		"Intensity toward the road user's eye, half the pair's sum, newest frame (cd).");
	for (int i = 0; i < n; i++)
		hl_prom_gauge(p, "hdlamp_glare_cd",
			      (const char *const[]){ "actor", sc->actor[i].id, NULL },
			      f->glare[i].pair_half_cd);
	for (int i = 0; i < n; i++)
		n_limits += isfinite(f->glare[i].limit.max_cd);
	if (n_limits)
		hl_prom_family(p, "hdlamp_glare_limit_cd", HL_PROM_GAUGE,
			       "The glare limit that applies to the road user now (cd, half the "
			       "pair's sum); none for a class without one.");
	for (int i = 0; i < n; i++)
		if (isfinite(f->glare[i].limit.max_cd))
			hl_prom_gauge(p, "hdlamp_glare_limit_cd",
				      (const char *const[]){ "actor", sc->actor[i].id, NULL },
				      f->glare[i].limit.max_cd);
	hl_prom_family(
		p, "hdlamp_glare_distance_meters", HL_PROM_GAUGE,
		"Horizontal distance from the ego lamps' midpoint to the road user's eye (m).");
	for (int i = 0; i < n; i++)
		hl_prom_gauge(p, "hdlamp_glare_distance_meters",
			      (const char *const[]){ "actor", sc->actor[i].id, NULL },
			      f->glare[i].distance_m);
}

/* One array of per-road-user values of an entry. */
static void json_floats(FILE *f, const char *name, const float *v, int n)
{
	fprintf(f, ",\"%s\":[", name);
	for (int i = 0; i < n; i++)
		if (isfinite(v[i]))
			fprintf(f, "%s%.7g", i ? "," : "", (double)v[i]);
		else
			fprintf(f, "%snull", i ? "," : ""); /* not in the world then */
	fputc(']', f);
}

int hl_glare_live_json(struct hl_glare_live *gl, char *buf, size_t size)
{
	const struct hl_scenario *sc = gl->sc;
	struct hl_glare_live_counts c;
	struct entry *copy;
	size_t used, first;
	FILE *f;
	long n;

	/* copied out under the lock, written outside it: the render thread never waits long */
	copy = malloc(sizeof(*copy) * gl->n_history);
	if (!copy)
		return -ENOMEM;
	pthread_mutex_lock(&gl->lock);
	used = gl->used;
	first = (gl->next + gl->n_history - used) % gl->n_history;
	for (size_t k = 0; k < used; k++)
		copy[k] = gl->history[(first + k) % gl->n_history];
	c = gl->c;
	pthread_mutex_unlock(&gl->lock);

	f = fmemopen(buf, size, "w");
	if (!f) {
		free(copy);
		return -errno;
	}
	fprintf(f,
		"{\"history_frames\":%zu,\"frames_kept\":%zu,\"frames\":%" PRIu64
		",\"history_overwritten\":%" PRIu64 ",\"glare_set\":",
		gl->n_history, used, c.frames, c.history_overwritten);
	hl_json_write_str(f, gl->reg->id);
	fputs(",\"actors\":[", f);
	for (int i = 0; i < sc->n_actors; i++) {
		fprintf(f, "%s{\"id\":", i ? "," : "");
		hl_json_write_str(f, sc->actor[i].id);
		fprintf(f, ",\"kind\":\"%s\",\"role\":\"%s\"}",
			hl_actor_kind_name(sc->actor[i].kind),
			hl_actor_role_name(sc->actor[i].role));
	}
	fputs("],\"history\":[", f);
	for (size_t k = 0; k < used; k++) {
		const struct entry *e = &copy[k];

		fprintf(f,
			"%s{\"seq\":%" PRIu64 ",\"t_s\":%.9g,\"source\":\"%s\",\"failed\":%" PRIu32
			",\"eye_lux_max\":%.7g",
			k ? "," : "", e->seq, e->t_s,
			hl_scene_source_name((enum hl_scene_source)e->source), e->failed,
			(double)e->eye_lux_max);
		json_floats(f, "lux", e->lux, sc->n_actors);
		json_floats(f, "cd", e->cd, sc->n_actors);
		json_floats(f, "distance_m", e->distance_m, sc->n_actors);
		fputc('}', f);
	}
	fputs("]}", f);
	n = ftell(f);
	fclose(f);
	free(copy);
	/* n bytes and the NUL fit in size; a longer text stops at size */
	return n >= (long)size ? -ENOBUFS : (int)n;
}
