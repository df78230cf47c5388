/* SPDX-License-Identifier: MIT */
#include "daemon/pipeline.h"

#include <assert.h>
#include <errno.h>
#include <malloc.h>
#include <math.h>
#include <poll.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/clock.h"
#include "daemon/core/glare_live.h"
#include "daemon/loop/osi_input.h"
#include "daemon/loop/world_feed.h"
#include "daemon/loop/pose_input.h"
#include "base/sched.h"
#include "render/compose.h"
#include "render/egl.h"
#include "render/renderer.h"
#include "render/view.h"
#include "render/workers.h"
#include "render/world_scene.h"
#include "daemon/core/sched_start.h"
#include "world/scenario_clock.h"

#define IDLE_WAKE_MS 100 /* longest wait without a snapshot, so stop and the watchdog are seen */
/*
 * Catch-up: while the render thread is at most this many snapshots behind the CAN thread, it
 * takes them in order, so a pass that ran late (a page fault, a busy host, a preempted vCPU)
 * costs latency but no lamp cycle; further behind, it takes the newest and counts the cycles
 * in between as not rendered. 8 snapshots: four ECU periods of two lamps, 80 ms at 50 Hz.
 * Never more than half the ring (hdlampd --ring-slots), which laps only beyond that.
 */
#define CATCH_UP_SNAPSHOTS 8u

/* The render time histogram's bucket bounds, ms (le; +Inf implied). */
/* Prometheus base units: seconds (1, 2, 5, 10, 20, 50, 100 ms) */
static const double render_s_bounds[] = { 0.001, 0.002, 0.005, 0.010, 0.020, 0.050, 0.100 };

struct hl_pipeline {
	struct hl_config cfg;
	hl_pipeline_frame_fn frame_fn; /* NULL: none */
	void *frame_ctx;
	struct hl_lid *lids[HL_FRAME_MAX_LAMPS];
	struct hl_source_scale *scales[HL_FRAME_MAX_LAMPS]; /* n_sources each */
	int n_lamps;
	struct hl_ring *ring;
	struct hl_frame_pool *pool;
	const struct hl_verdicts *verdicts; /* NULL: none */
	struct hl_verdict_records *records; /* their records over the run; NULL: none */
	struct hl_pipeline_hooks hooks;
	/* the moving scene (hl_pipeline_set_scene): NULL without a scenario */
	const struct hl_scenario *sc;
	struct hl_glare_live *glare;
	struct hl_pose_input *pose; /* NULL: no pose input */
	struct hl_osi_input *osi; /* NULL: no live OSI input */
	int64_t t_start_ns; /* CLOCK_MONOTONIC when the renderer was ready: a live bus's scenario clock */

	/* live settings, changed by reload under the lock */
	pthread_mutex_t lock;
	enum hl_failsafe failsafe;
	uint8_t *failsafe_dims[HL_FRAME_MAX_LAMPS];
	double exposure_ev;
	struct hl_pipeline_counts c;

	/* render thread's */
	struct hl_egl *egl;
	struct hl_scene scene;
	struct hl_camera cam;
	struct hl_gbuffer *gb;
	struct hl_renderer *r;
	struct hl_snapshot *snap;
	float *cur, *lux, *rgba;
	enum hl_view_kind view;
	struct hl_view_lux_opts lux_opts;
	char describe[256];
	uint64_t last_seq[HL_FRAME_MAX_LAMPS]; /* each lamp's cycle in the last frame rendered */
	/*
	 * THE world state of the frame being rendered (world/world.h): where the ego and every
	 * road user are and whose lamps are lit. scene_at() fills it at the start of render(),
	 * before the renderer runs; the glare, the header and /status read it. The renderer is to
	 * draw this same instant (the moving scene): pass &p->world to it where render() says.
	 */
	struct hl_world_state world;
	/* the moving scene's ray cast (a scenario): p->world into p->gb every frame; NULL: still */
	struct hl_world_scene *ws;
	struct hl_world_raster *raster; /* ws's frames into gb, remembering what each pixel was */
	struct hl_world_emitter emitters[HL_SCN_MAX_ACTORS * HL_SCN_MAX_LAMPS];
	enum hl_scene_source world_source;
	int64_t world_pose_rx_ns; /* world_source pose: when that message arrived */

	uint64_t stall_after_frames; /* test-only fault: hang after this many frames; 0: never */
	uint64_t catch_up; /* snapshots behind that are still taken in order (CATCH_UP_SNAPSHOTS) */

	pthread_t thread;
	bool started;
	atomic_int stop;
	/* start-up handshake */
	pthread_cond_t up;
	int start_rc; /* 1 while starting */
	char start_err[512];
};

int hl_pipeline_new(const struct hl_config *cfg, struct hl_lid *const lids[HL_FRAME_MAX_LAMPS],
		    int n_lamps, const struct hl_source_scale *const scales[HL_FRAME_MAX_LAMPS],
		    const uint8_t *const failsafe_dims[HL_FRAME_MAX_LAMPS], struct hl_ring *ring,
		    struct hl_frame_pool *pool, const struct hl_verdicts *verdicts,
		    const struct hl_pipeline_hooks *hooks, struct hl_pipeline **ret)
{
	struct hl_pipeline *p = calloc(1, sizeof(*p));
	int rc;

	if (!p)
		return -ENOMEM;
	p->cfg = *cfg;
	p->n_lamps = n_lamps;
	p->ring = ring;
	p->pool = pool;
	if (verdicts && hl_verdicts_n_results(verdicts) > hl_frame_pool_shape(pool)->n_results) {
		free(p);
		return -EINVAL; /* the pool's frames cannot hold the results */
	}
	p->verdicts = verdicts;
	if (hooks)
		p->hooks = *hooks;
	p->exposure_ev = cfg->exposure_ev;
	/* the fixed-rate mode shows the newest state at each tick: no catch-up */
	p->catch_up = cfg->rate_hz > 0 ? 0 : hl_ring_slots(ring) / 2;
	if (p->catch_up > CATCH_UP_SNAPSHOTS)
		p->catch_up = CATCH_UP_SNAPSHOTS;
	rc = hl_mutex_init_pi(&p->lock);
	if (rc < 0) {
		free(p);
		return rc;
	}
	pthread_cond_init(&p->up, NULL);
	atomic_init(&p->stop, 0);
	for (int l = 0; l < n_lamps; l++)
		p->lids[l] = lids[l];
	rc = hl_snapshot_new(ring, &p->snap);
	if (rc < 0)
		goto err;
	for (int l = 0; l < n_lamps; l++) {
		p->scales[l] = malloc(sizeof(*p->scales[l]) * p->snap->n_sources);
		if (!p->scales[l]) {
			rc = -ENOMEM;
			goto err;
		}
		memcpy(p->scales[l], scales[l], sizeof(*p->scales[l]) * p->snap->n_sources);
	}
	p->cur = calloc(p->snap->n_sources, sizeof(float));
	p->lux = calloc((size_t)cfg->width * cfg->height, sizeof(float));
	p->rgba = calloc((size_t)cfg->width * cfg->height * 4, sizeof(float));
	if (!p->cur || !p->lux || !p->rgba) {
		rc = -ENOMEM;
		goto err;
	}
	rc = hl_view_from_name(cfg->view);
	if (rc < 0 || rc == HL_VIEW_LID) {
		rc = -EINVAL;
		goto err;
	}
	p->view = rc;
	rc = hl_prom_histogram_init(&p->c.render_seconds, render_s_bounds,
				    (int)(sizeof(render_s_bounds) / sizeof(render_s_bounds[0])));
	assert(rc == 0);
	hl_view_lux_defaults(&p->lux_opts);
	hl_pipeline_set_failsafe(p, cfg->failsafe, failsafe_dims);
	*ret = p;
	return 0;
err:
	hl_pipeline_free(p);
	return rc;
}

void hl_pipeline_free(struct hl_pipeline *p)
{
	if (!p)
		return;
	hl_pipeline_stop(p);
	hl_snapshot_free(p->snap);
	free(p->cur);
	free(p->lux);
	free(p->rgba);
	for (int l = 0; l < HL_FRAME_MAX_LAMPS; l++) {
		free(p->scales[l]);
		free(p->failsafe_dims[l]);
	}
	pthread_cond_destroy(&p->up);
	pthread_mutex_destroy(&p->lock);
	free(p);
}

void hl_pipeline_set_failsafe(struct hl_pipeline *p, enum hl_failsafe mode,
			      const uint8_t *const dims[HL_FRAME_MAX_LAMPS])
{
	pthread_mutex_lock(&p->lock);
	p->failsafe = mode;
	for (int l = 0; l < p->n_lamps; l++) {
		free(p->failsafe_dims[l]);
		p->failsafe_dims[l] = NULL;
		if (mode == HL_FAILSAFE_PRESET && dims && dims[l]) {
			p->failsafe_dims[l] = malloc(p->snap->n_sources);
			if (p->failsafe_dims[l])
				memcpy(p->failsafe_dims[l], dims[l], p->snap->n_sources);
		}
	}
	pthread_mutex_unlock(&p->lock);
}

void hl_pipeline_set_exposure(struct hl_pipeline *p, double ev)
{
	pthread_mutex_lock(&p->lock);
	p->exposure_ev = ev;
	pthread_mutex_unlock(&p->lock);
}

void hl_pipeline_counts(struct hl_pipeline *p, struct hl_pipeline_counts *ret)
{
	pthread_mutex_lock(&p->lock);
	*ret = p->c;
	pthread_mutex_unlock(&p->lock);
}

const char *hl_pipeline_describe(const struct hl_pipeline *p)
{
	return p->describe;
}

const struct hl_gbuffer *hl_pipeline_gbuffer(const struct hl_pipeline *p)
{
	return p->ws ? NULL : p->gb; /* a moving scene's changes every frame */
}

const struct hl_camera *hl_pipeline_camera(const struct hl_pipeline *p)
{
	return &p->cam;
}

/* Render-thread set-up: EGL, scene, G-buffer, renderer. */
/* The renderer's threads ray cast the moving scene band by band (hl_renderer_fill_fn). */
static void world_fill(void *userdata, struct hl_gbuffer *gb, size_t first, size_t count,
		       uint8_t *changed)
{
	const struct hl_pipeline *p = userdata;

	(void)gb; /* the raster's */
	hl_world_raster_pixels(p->raster, &p->world, first, count, changed);
}

static int setup(struct hl_pipeline *p)
{
	struct hl_egl_error eerr = { "" };
	struct hl_renderer_config rc_cfg = { 0 };
	struct hl_lamp_pose poses[HL_FRAME_MAX_LAMPS];
	int kind, rc;

	rc = hl_egl_new(&p->egl, &eerr);
	if (rc < 0) {
		snprintf(p->start_err, sizeof(p->start_err), "no EGL/GLES context: %s", eerr.msg);
		return rc;
	}
	kind = hl_scene_from_name(p->cfg.scene);
	if (kind < 0) {
		snprintf(p->start_err, sizeof(p->start_err), "render.scene '%s': unknown scene",
			 p->cfg.scene);
		return -EINVAL;
	}
	hl_lamp_pose_default(0, &poses[0]);
	hl_lamp_pose_default(1, &poses[1]);
	hl_scene_init(&p->scene, kind, poses);
	hl_scene_default_camera(&p->scene, p->cfg.width, p->cfg.height, &p->cam);
	if (p->sc) {
		/*
		 * The moving scene: the driver's camera and the ego lamps, fixed in the ego frame
		 * the G-buffer is cast in (render/world_scene.h); render.scene does not apply.
		 */
		p->cam = p->sc->ego.camera;
		p->cam.width = p->cfg.width;
		p->cam.height = p->cfg.height;
		memcpy(poses, p->sc->ego.lamp, sizeof(poses));
		rc_cfg.moving = true;
		rc_cfg.fill_only = true; /* the raster says what changed (render/world_scene.h) */
		hl_world_at(p->sc, 0.0, &p->world);
		rc = hl_world_scene_new(p->sc, &p->ws);
		if (rc == 0)
			rc = hl_gbuffer_new(p->cfg.width, p->cfg.height, &p->gb);
		if (rc == 0)
			rc = hl_world_scene_render(p->ws, &p->world, &p->cam, p->gb);
		if (rc == 0)
			rc = hl_world_raster_new(p->ws, &p->cam, p->gb, &p->raster);
	} else {
		rc = hl_gbuffer_new(p->cfg.width, p->cfg.height, &p->gb);
		if (rc == 0)
			rc = hl_scene_render(&p->scene, &p->cam, p->gb);
	}
	if (rc < 0) {
		snprintf(p->start_err, sizeof(p->start_err), "scene '%s': %s",
			 p->sc ? "scenario" : p->cfg.scene, strerror(-rc));
		return rc;
	}
	rc_cfg.n_lamps = p->n_lamps;
	rc_cfg.lids[0] = p->lids[0];
	rc_cfg.lids[1] = p->n_lamps > 1 ? p->lids[1] : NULL;
	memcpy(rc_cfg.poses, poses, sizeof(poses));
	rc_cfg.combine = hl_backend_from_name(p->cfg.combine);
	rc_cfg.headlight = hl_backend_from_name(p->cfg.headlight);
	rc_cfg.egl = p->egl;
	rc_cfg.threads = p->cfg.render_threads;
	if (rc_cfg.threads == 0) {
		const long cpus = sysconf(_SC_NPROCESSORS_ONLN);

		rc_cfg.threads = cpus < 1		       ? 1 :
				 cpus > HL_WORKERS_MAX_THREADS ? HL_WORKERS_MAX_THREADS :
								 (int)cpus;
	}
	rc = hl_renderer_new(&rc_cfg, p->gb, &p->r);
	if (rc < 0) {
		snprintf(p->start_err, sizeof(p->start_err), "cannot set up the renderer: %s",
			 strerror(-rc));
		return rc;
	}
	snprintf(p->describe, sizeof(p->describe),
		 "EGL %s, %s; combine on %s, headlight pass on %s, %d threads",
		 hl_egl_platform(p->egl), hl_egl_renderer(p->egl),
		 hl_backend_name(hl_renderer_combine_backend(p->r)),
		 hl_backend_name(hl_renderer_headlight_backend(p->r)), rc_cfg.threads);
	/*
	 * Both stages on the CPU (what auto picks on llvmpipe): the context has no more work, but
	 * llvmpipe keeps what the auto choice's GLES candidates allocated (~90 MB at 1280x720)
	 * until it goes. glibc keeps freed heap for reuse; hand that back too.
	 */
	if (hl_renderer_combine_backend(p->r) == HL_BACKEND_CPU &&
	    hl_renderer_headlight_backend(p->r) == HL_BACKEND_CPU) {
		hl_egl_free(p->egl);
		p->egl = NULL;
	}
	malloc_trim(0);
	if (p->ws) {
		/*
		 * A warm-up frame of the scene at time 0 with the lamps dark, before the first
		 * cycle: the raster, the renderer's buffers and its threads' caches are touched
		 * here. Without it the first cycle's frame took 73 ms at 1280x720 (tools/bench
		 * e2e_moving), three ECU periods, and the stream skipped the frames behind it.
		 */
		hl_renderer_set_gbuffer_fill(p->r, p->gb, world_fill, p);
		hl_renderer_frame(p->r, p->lux);
	}
	return 0;
}

static void teardown(struct hl_pipeline *p)
{
	hl_renderer_free(p->r);
	p->r = NULL;
	hl_gbuffer_free(p->gb);
	p->gb = NULL;
	hl_world_raster_free(p->raster);
	hl_world_scene_free(p->ws);
	p->ws = NULL;
	hl_egl_free(p->egl);
	p->egl = NULL;
}

/* evaluated, failed: the frame's verdict set masks; verdict_ms < 0: no verdicts ran */
static void record_time(struct hl_pipeline *p, double ms, bool published, uint32_t flags,
			uint32_t evaluated, uint32_t failed, double verdict_ms)
{
	pthread_mutex_lock(&p->lock);
	p->c.render_ms_last = ms;
	for (int i = 0; i < HL_VERDICTS_MAX_SETS; i++) {
		if (!(evaluated & (1u << i)))
			continue;
		p->c.verdict_frames[i]++;
		if (failed & (1u << i))
			p->c.verdict_failed_frames[i]++;
	}
	if (verdict_ms >= 0.0) {
		p->c.verdict_ms_last = verdict_ms;
		if (verdict_ms > p->c.verdict_ms_max)
			p->c.verdict_ms_max = verdict_ms;
	}
	if (ms > p->c.render_ms_max)
		p->c.render_ms_max = ms;
	hl_prom_histogram_observe(&p->c.render_seconds, ms / 1000.0);
	if (published)
		p->c.frames++;
	else
		p->c.not_published++;
	for (int l = 0; l < HL_FRAME_MAX_LAMPS; l++)
		if (flags & HL_FRAME_FAILSAFE(l))
			p->c.failsafe_frames[l]++;
	pthread_mutex_unlock(&p->lock);
}

/* The raw value a signal of this scale carries for relative current i (nearest step). */
static uint8_t raw_of(const struct hl_source_scale *s, float i)
{
	const long r = lround(((double)i - s->offset) / s->factor);

	return r < 0 ? 0 : r > UINT8_MAX ? UINT8_MAX : (uint8_t)r;
}

/*
 * The frame's verdicts and road KPIs from its distributions, into the frame (before it is
 * published, so every reader sees them with the frame): the sets of the beam mode the mode
 * lamp's cycle carries (all without one). Returns the time taken, ms.
 */
static double check(struct hl_pipeline *p, struct hl_frame *f, const struct hl_verdict_peak *peaks)
{
	const int64_t t0 = hl_clock_monotonic_ns();
	const float *dist[HL_FRAME_MAX_LAMPS] = { f->dist[0], p->n_lamps > 1 ? f->dist[1] : NULL };
	const int ml = hl_verdicts_mode_lamp(p->verdicts);
	struct hl_road_kpi road;

	f->beam_mode = ml >= 0 && (p->snap->lamps[ml].status & HL_LAMP_VALID) ?
			       p->snap->lamps[ml].mode :
			       -1;
	f->hdr.sets_evaluated = hl_verdicts_active(p->verdicts, f->beam_mode);
	f->hdr.sets_failed =
		hl_verdicts_eval_peaks(p->verdicts, f->hdr.sets_evaluated, dist, peaks, f->results);
	hl_verdicts_road(p->verdicts, dist, &road);
	hl_verdicts_road_to_header(&road, &f->hdr);
	return (double)(hl_clock_monotonic_ns() - t0) / 1e6;
}

/*
 * The frame's instant into p->world (daemon/loop/world_feed.h): a live input's newest, else the
 * scenario clock: with a replay the log's time of the newest lamp cycle since the start of its
 * pass (so a recorded drive and its scenario stay in step, and each --loop pass starts the
 * scenario again), on a live bus CLOCK_MONOTONIC since the renderer was ready, held at 0 before
 * the start and at duration_s past the end.
 */
static void scene_at(struct hl_pipeline *p, const struct hl_snapshot *s, int newest)
{
	const struct hl_world_feed feed = { p->sc, p->pose, p->osi };
	const struct hl_lamp_snapshot *ls = &s->lamps[newest];
	double t_s = 0.0;

	if (p->sc && p->cfg.replay[0] && (ls->status & HL_LAMP_VALID))
		t_s = hl_scenario_clock_at(p->sc, s->t_pass_ns, ls->t_complete_ns);
	else if (p->sc && !p->cfg.replay[0])
		t_s = hl_scenario_clock_at(p->sc, p->t_start_ns, hl_clock_monotonic_ns());
	p->world_source = hl_world_feed_at(&feed, t_s,
					   p->cfg.replay[0] ? HL_SCENE_LOG : HL_SCENE_CLOCK,
					   &p->world, &p->world_pose_rx_ns);
}

_Static_assert(HL_FRAME_MAX_GLOW >= HL_SCN_MAX_ACTORS * HL_SCN_MAX_LAMPS,
	       "a frame records the glow of every road user's lamp");

/* One frame from the snapshot in p->snap. */
static void render(struct hl_pipeline *p)
{
	struct hl_frame *f = hl_frame_pool_acquire(p->pool);
	const struct hl_snapshot *s = p->snap;
	const int64_t t0 = hl_clock_monotonic_ns();
	uint32_t flags = 0;
	enum hl_failsafe mode;
	double ev, verdict_ms = -1.0;
	struct hl_verdict_peak peaks[HL_FRAME_MAX_LAMPS];
	uint32_t evaluated = 0, failed = 0;
	int newest = 0;

	/* the newest cycle: the one completed last (on the input's clock, which never goes back) */
	for (int l = 1; l < p->n_lamps; l++)
		if (s->lamps[l].t_complete_ns > s->lamps[newest].t_complete_ns)
			newest = l;
	scene_at(p, s, newest); /* p->world: the instant this frame shows */
	pthread_mutex_lock(&p->lock);
	mode = p->failsafe;
	ev = p->exposure_ev;
	for (int l = 0; l < p->n_lamps; l++) {
		const float *in = s->i + (size_t)l * s->n_sources;
		/* a lamp with no valid cycle yet counts as stale: there is nothing to show */
		const bool stale = (s->lamps[l].status & HL_LAMP_STALE) ||
				   !(s->lamps[l].status & HL_LAMP_VALID);

		for (int k = 0; k < s->n_sources; k++) {
			const struct hl_source_scale *sc = &p->scales[l][k];
			float v = in[k];
			uint8_t raw;

			if (stale && mode == HL_FAILSAFE_PRESET && p->failsafe_dims[l]) {
				raw = p->failsafe_dims[l][k];
				v = (float)(raw * sc->factor + sc->offset);
			} else {
				if (stale && mode == HL_FAILSAFE_DARK)
					v = 0.0f;
				raw = raw_of(sc, v);
			}
			p->cur[k] = v;
			if (f)
				f->dims[l][k] = raw;
		}
		if (stale)
			flags |= HL_FRAME_STALE(l) | HL_FRAME_FAILSAFE(l);
		hl_renderer_set_currents(p->r, l, p->cur);
		if (s->lamps[l].cycle_seq > p->last_seq[l] + 1)
			p->c.cycles_not_rendered[l] += s->lamps[l].cycle_seq - p->last_seq[l] - 1;
		p->last_seq[l] = s->lamps[l].cycle_seq;
	}
	pthread_mutex_unlock(&p->lock);
	if (p->ws) {
		/* the moving scene at the frame's instant: only what changed is lit anew */
		hl_renderer_set_gbuffer_fill(p->r, p->gb, world_fill, p);
	}
	if (f && p->view == HL_VIEW_DISPLAY) {
		/* tone-mapped band by band while the band's illuminance is in the cache */
		struct hl_compose_display j = { p->gb, ev, f->pixels };

		if (p->ws) { /* the road users' lamps of the frame this buffer last held */
			hl_compose_clear_boxes(f->pixels, p->cfg.width, f->glow, f->n_glow);
			f->n_glow = 0;
		}
		hl_renderer_frame_pixels(p->r, f->lux, hl_compose_display_band, &j);
		if (p->ws)
			f->n_glow = hl_compose_emitters(
				p->ws, &p->world, &p->cam, ev, p->emitters,
				(int)(sizeof(p->emitters) / sizeof(p->emitters[0])), f->pixels,
				f->glow, HL_FRAME_MAX_GLOW);
	} else {
		hl_renderer_frame(p->r, f ? f->lux : p->lux);
	}
	if (f) {
		switch (p->view) {
		case HL_VIEW_LUX:
			hl_view_lux(p->gb, f->lux, &p->lux_opts, f->pixels);
			break;
		case HL_VIEW_HDR:
			hl_compose_hdr(p->gb, f->lux, p->rgba, (uint16_t *)f->pixels);
			break;
		default: /* display: done with the frame */
			break;
		}
		for (int l = 0; l < p->n_lamps; l++) {
			const struct hl_lid_grid *g = hl_renderer_grid(p->r, l);

			/* with verdicts, the copy also finds each lamp's peak (Imax) */
			if (p->verdicts)
				hl_verdict_copy_peak(f->dist[l], hl_renderer_distribution(p->r, l),
						     (size_t)g->width * g->height, &peaks[l]);
			else
				memcpy(f->dist[l], hl_renderer_distribution(p->r, l),
				       sizeof(float) * (size_t)g->width * g->height);
			f->hdr.cycle_seq[l] = s->lamps[l].cycle_seq;
			f->hdr.t_lamp_done_ns[l] = s->lamps[l].t_complete_mono_ns;
			f->hdr.counter[l] = s->lamps[l].counter;
		}
		f->hdr.scene_source = HL_SCENE_NONE;
		f->hdr.n_actors = 0;
		f->hdr.glare_failed = 0;
		f->hdr.eye_lux_max = 0.0f;
		f->hdr.scene_t_s = 0.0;
		if (p->glare) {
			const float *dist[2] = { f->dist[0], f->dist[1] };

			/* the pool numbers published frames from 1; this one is next */
			hl_glare_live_eval(p->glare, &p->world, p->world_source, dist,
					   p->c.frames + 1, f);
			f->t_pose_rx_ns = p->world_pose_rx_ns;
			if (p->frame_fn) {
				const struct hl_lid_grid *grids[2] = { hl_renderer_grid(p->r, 0),
								       hl_renderer_grid(p->r, 1) };

				p->frame_fn(p->frame_ctx, p->sc, &p->world, grids, dist);
			}
		}
		if (p->verdicts) {
			verdict_ms = check(p, f, peaks);
			evaluated = f->hdr.sets_evaluated;
			failed = f->hdr.sets_failed;
		}
		f->hdr.flags = flags;
		f->hdr.t_cycle_rx_ns = s->lamps[newest].t_rx_first_ns;
		f->hdr.t_cycle_done_ns = s->t_push_ns;
		f->hdr.t_render_start_ns = t0;
		f->hdr.t_render_done_ns = hl_clock_monotonic_ns();
		f->hdr.t_sent_ns = 0;
		if (p->verdicts && p->records)
			hl_verdict_records_add(p->records, f); /* now and so far, per set */
		hl_frame_pool_publish(p->pool, f); /* and the pool wakes its subscribers */
	}
	record_time(p, (double)(hl_clock_monotonic_ns() - t0) / 1e6, f != NULL, flags, evaluated,
		    failed, verdict_ms);
}

/*
 * True while one lamp's cycle is new since the last frame and another lamp, live (valid, not
 * stale), has not completed its cycle of the same ECU period yet: the ECU sends both lamps'
 * frames within a millisecond or two, so one frame for both halves the work and shows the
 * whole ECU cycle at once.
 */
static bool other_lamp_due(const struct hl_pipeline *p)
{
	bool advanced = false, lagging = false;

	for (int l = 0; l < p->n_lamps; l++) {
		const struct hl_lamp_snapshot *ls = &p->snap->lamps[l];

		if (ls->cycle_seq != p->last_seq[l])
			advanced = true;
		else if ((ls->status & HL_LAMP_VALID) && !(ls->status & HL_LAMP_STALE))
			lagging = true;
	}
	return advanced && lagging;
}

/*
 * The next snapshot into p->snap: in order while at most catch_up behind (every cycle shown),
 * else the newest (the ones skipped counted as superseded, their cycles as not rendered). The
 * fixed-rate mode shows the newest state at each tick: catch_up 0. False: nothing new.
 */
static bool take(struct hl_pipeline *p)
{
	const uint64_t pending = hl_ring_pending(p->ring);

	if (pending == 0)
		return false;
	if (pending <= p->catch_up)
		return hl_ring_pop(p->ring, p->snap);
	return hl_ring_take_newest(p->ring, p->snap);
}

/*
 * Waits up to coalesce_ns for the other lamp's cycle (render.coalesce_ms); a snapshot already
 * in the ring is taken without waiting, whatever the time.
 */
static void coalesce(struct hl_pipeline *p, int64_t coalesce_ns)
{
	const int64_t until = hl_clock_monotonic_ns() + coalesce_ns;

	while (other_lamp_due(p) && !atomic_load(&p->stop)) {
		if (hl_ring_pending(p->ring) == 0) {
			const int64_t left = until - hl_clock_monotonic_ns();
			struct pollfd pfd = { .fd = hl_ring_wake_fd(p->ring), .events = POLLIN };
			struct timespec ts = { left / 1000000000, left % 1000000000 };

			if (left <= 0)
				break;
			if (ppoll(&pfd, 1, &ts, NULL) > 0)
				hl_ring_wait(p->ring, 0); /* reset */
		}
		take(p);
	}
}

/*
 * The test-only fault (hl_pipeline_debug_stall): the render loop stops turning, so the alive
 * hook (the watchdog) stops too, until the pipeline is stopped.
 */
static void stall(struct hl_pipeline *p)
{
	while (!atomic_load(&p->stop))
		hl_clock_sleep_until_ns(hl_clock_monotonic_ns() + IDLE_WAKE_MS * 1000000ll, NULL);
}

static void *thread_main(void *arg)
{
	struct hl_pipeline *p = arg;
	const int64_t period_ns = p->cfg.rate_hz > 0 ? (int64_t)(1e9 / p->cfg.rate_hz) : 0;
	const int64_t coalesce_ns = (int64_t)(p->cfg.coalesce_ms * 1e6);
	int64_t next_ns = hl_clock_monotonic_ns();
	uint64_t rendered = 0;
	bool have = false;
	int rc;

	/* before setup: the helpers the renderer creates inherit the policy */
	pthread_setname_np(pthread_self(), "hl-render");
	hl_sched_start_thread("render", p->cfg.rt_priority, stderr);
	rc = setup(p);
	/* scenario time 0 on a live bus: the renderer is ready (its setup takes seconds in a slow
	 * VM, which would otherwise pass before the first frame); published by the lock below */
	p->t_start_ns = hl_clock_monotonic_ns();

	pthread_mutex_lock(&p->lock);
	p->start_rc = rc;
	pthread_cond_broadcast(&p->up);
	pthread_mutex_unlock(&p->lock);
	if (rc < 0) {
		teardown(p);
		return NULL;
	}
	while (!atomic_load(&p->stop)) {
		int timeout_ms = IDLE_WAKE_MS;
		bool fresh;

		if (p->hooks.alive)
			p->hooks.alive(p->hooks.userdata);
		if (period_ns) {
			const int64_t now = hl_clock_monotonic_ns();

			timeout_ms = next_ns > now ? (int)((next_ns - now) / 1000000) : 0;
		}
		/* snapshots left from a catch-up are taken at once (and the wake-up reset) */
		hl_ring_wait(p->ring, hl_ring_pending(p->ring) > 0 ? 0 : timeout_ms);
		fresh = take(p);
		have |= fresh;
		if (!have)
			continue;
		if (period_ns) {
			if (hl_clock_monotonic_ns() < next_ns)
				continue;
			next_ns += period_ns;
			render(p);
		} else if (fresh) {
			if (coalesce_ns > 0)
				coalesce(p, coalesce_ns);
			render(p);
		} else {
			continue;
		}
		if (++rendered == p->stall_after_frames)
			stall(p);
	}
	teardown(p);
	return NULL;
}

void hl_pipeline_set_records(struct hl_pipeline *p, struct hl_verdict_records *records)
{
	p->records = records;
}

struct hl_verdict_records *hl_pipeline_records(const struct hl_pipeline *p)
{
	return p->records;
}

void hl_pipeline_set_frame_hook(struct hl_pipeline *p, hl_pipeline_frame_fn fn, void *ctx)
{
	p->frame_fn = fn;
	p->frame_ctx = ctx;
}

void hl_pipeline_set_scene(struct hl_pipeline *p, const struct hl_scenario *sc,
			   struct hl_glare_live *glare, struct hl_pose_input *pose)
{
	p->sc = sc;
	p->glare = glare;
	p->pose = pose;
}

void hl_pipeline_set_osi(struct hl_pipeline *p, struct hl_osi_input *osi)
{
	p->osi = osi;
}

int64_t hl_pipeline_scene_t0_ns(const struct hl_pipeline *p)
{
	return p->t_start_ns;
}

void hl_pipeline_debug_stall(struct hl_pipeline *p, uint64_t after_frames)
{
	p->stall_after_frames = after_frames;
}

int hl_pipeline_start(struct hl_pipeline *p, char *err, size_t err_size)
{
	int rc;

	p->start_rc = 1;
	rc = pthread_create(&p->thread, NULL, thread_main, p);
	if (rc) {
		snprintf(err, err_size, "cannot start the render thread: %s", strerror(rc));
		return -rc;
	}
	p->started = true;
	pthread_mutex_lock(&p->lock);
	while (p->start_rc == 1)
		pthread_cond_wait(&p->up, &p->lock);
	rc = p->start_rc;
	pthread_mutex_unlock(&p->lock);
	if (rc < 0) {
		snprintf(err, err_size, "%s", p->start_err);
		hl_pipeline_stop(p);
	}
	return rc;
}

void hl_pipeline_stop(struct hl_pipeline *p)
{
	if (!p->started)
		return;
	atomic_store(&p->stop, 1);
	pthread_join(p->thread, NULL);
	p->started = false;
}
