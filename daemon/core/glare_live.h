/* SPDX-License-Identifier: MIT */
/*
 * The live glare of a scenario (docs/live-scenario.md, "Scenario and glare"): the render thread
 * evaluates verdict/glare.h on every frame from the frame's world state and its lamps'
 * distributions, into the frame (its glare results and header fields) and into a bounded
 * history of the last N frames (scene.glare_history) that GET /glare.json gives out; the
 * frames each road user failed are counted. The /status and /metrics parts are written from a
 * published frame (the newest), so a reader sees one frame's glare whole.
 *
 * Thread-safety: new and free from the main thread while no other thread uses it;
 * hl_glare_live_eval() from the render thread only; hl_glare_live_json(), _status_json(),
 * _metrics() and _counts() from any thread. The history and the counters are under a
 * priority-inheritance mutex that the render thread holds only to store one entry.
 */
#ifndef HL_DAEMON_CORE_GLARE_LIVE_H
#define HL_DAEMON_CORE_GLARE_LIVE_H

#include <stdint.h>
#include <stdio.h>

#include "daemon/core/frame.h"
#include "daemon/core/prom.h"
#include "lamp/lid.h"
#include "verdict/regulation.h"
#include "verdict/glare.h"
#include "world/scenario.h"
#include "world/world.h"

struct hl_glare_live_counts {
	uint64_t frames; /* frames evaluated */
	uint64_t fail_frames[HL_SCN_MAX_ACTORS]; /* per road user: frames over its limit */
	uint64_t history_overwritten; /* entries the bounded history dropped (it wrapped) */
};

struct hl_glare_live;

/*
 * For scenario sc under regulation set reg (both must outlive it) and two lamps on grids[0]
 * (left), grids[1] (right); history: frames /glare.json keeps (>= 1). 0, -EINVAL (reg is not
 * a glare table: verdict/glare.h), -E2BIG, -ENOMEM.
 */
int hl_glare_live_new(const struct hl_scenario *sc, const struct hl_regulation *reg,
		      const struct hl_lid_grid *const grids[2], int history,
		      struct hl_glare_live **ret);
void hl_glare_live_free(struct hl_glare_live *gl);

const struct hl_scenario *hl_glare_live_scenario(const struct hl_glare_live *gl);
const struct hl_regulation *hl_glare_live_regulation(const struct hl_glare_live *gl);

/*
 * Render thread: the glare of world w (source: where its time came from) under the lamps'
 * distributions dist[0], dist[1] into frame f (f->glare, and the header's scene_t_s,
 * scene_source, n_actors, glare_failed, eye_lux_max), stored in the history under seq (the
 * frame's sequence number: published frames, from 1). Allocates nothing.
 */
void hl_glare_live_eval(struct hl_glare_live *gl, const struct hl_world_state *w,
			enum hl_scene_source source, const float *const dist[2], uint64_t seq,
			struct hl_frame *f);

void hl_glare_live_counts(struct hl_glare_live *gl, struct hl_glare_live_counts *ret);

/* "clock", "log", "pose" (and "none"). */
const char *hl_scene_source_name(enum hl_scene_source s);

/*
 * The /status part for frame f (NULL: none published yet): "scene":{...},"glare":[...]
 * with a leading comma. pose_age_s >= 0: the newest pose's age, written as the scene's
 * pose_age_s.
 */
void hl_glare_live_status_json(struct hl_glare_live *gl, const struct hl_frame *f,
			       double pose_age_s, FILE *out);
/* The /metrics families (hdlamp_glare_*, hdlamp_scene_time_seconds) for frame f (may be NULL). */
void hl_glare_live_metrics(struct hl_glare_live *gl, const struct hl_frame *f, struct hl_prom *p);
/*
 * GET /glare.json: the history, oldest first, as one JSON object NUL-terminated in buf. Its
 * length, -ENOBUFS (too small), -errno.
 */
int hl_glare_live_json(struct hl_glare_live *gl, char *buf, size_t size);

#endif
