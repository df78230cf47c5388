/* SPDX-License-Identifier: MIT */
/*
 * The render thread (docs/architecture.md) owns the EGL context and the renderer, takes the
 * next complete snapshot from the ring whenever the CAN thread pushes one (in order while it is
 * at most a few snapshots behind, so a late pass loses no cycle; the newest when further behind
 * or at a fixed rate),
 * applies each stale lamp's fail-safe (hold, dark or a preset), renders the scene, converts it
 * to the configured view in a frame from the pool and publishes it with its latency stamps.
 *
 * Thread-safety: new/start/stop/free and the live settings (set_failsafe, set_exposure) from
 * the main thread; counts (locked) and describe, gbuffer, camera (fixed once started) from any
 * thread; the rest runs on the render thread. The hook runs on the render thread and must not
 * block. Published frames reach the outputs through the pool's subscribers; the ring's
 * eventfd wakes the thread. The verdicts (daemon/core/verdicts.h) are read-only; the render thread
 * evaluates them into each frame before publishing it, so readers see a frame's results whole.
 */
#ifndef HL_DAEMON_PIPELINE_H
#define HL_DAEMON_PIPELINE_H

#include <stdint.h>

#include "daemon/core/config.h"
#include "daemon/core/frame_pool.h"
#include "daemon/core/prom.h"
#include "daemon/core/ring.h"
#include "daemon/core/verdict_records.h"
#include "daemon/core/verdicts.h"
#include "lamp/lid.h"
#include "world/scenario.h"
#include "render/scene.h"

struct hl_pipeline_hooks {
	void *userdata;
	void (*alive)(void *userdata); /* once per loop turn: the watchdog */
};

struct hl_pipeline_counts {
	uint64_t frames; /* rendered and published */
	uint64_t not_published; /* rendered, but every pool frame was held by readers */
	uint64_t failsafe_frames[HL_FRAME_MAX_LAMPS]; /* frames with the lamp's fail-safe active */
	/*
	 * Complete cycles of the lamp that no rendered frame showed: the lamp's cycle_seq moved on
	 * by more than one between two frames (the render thread was busy for two of its cycles),
	 * or cycles came before the first frame. Superseded ring snapshots are not lost cycles as
	 * long as the newer snapshot carries each lamp's next cycle: this counts what was lost.
	 */
	uint64_t cycles_not_rendered[HL_FRAME_MAX_LAMPS];
	double render_ms_last, render_ms_max;
	/* per verdict set (verdict.sets order): frames it was evaluated on, and failed on */
	uint64_t verdict_frames[HL_VERDICTS_MAX_SETS];
	uint64_t verdict_failed_frames[HL_VERDICTS_MAX_SETS];
	double verdict_ms_last, verdict_ms_max; /* the verdicts and road KPIs of one frame */
	struct hl_prom_histogram render_seconds; /* render time, s (bounds: hl_pipeline_new) */
};

/*
 * How a source's relative current and the raw value its DBC signal carries map onto each other:
 * i = raw * factor + offset (the signal's factor and offset), so the frame carries the raw
 * values the ECU sent, whatever the database's scale.
 */
struct hl_source_scale {
	double factor, offset;
};

struct hl_pipeline;

/*
 * scales: per lamp, n_sources entries (the ring's), copied. failsafe_dims: per lamp the preset's
 * raw values (n_sources each) for HL_FAILSAFE_PRESET, else NULL. lids must outlive the
 * pipeline. verdicts (NULL: none), whose results the pool's frames hold (the shape's
 * n_results), must outlive it too: every frame gets each set's results (the sets the frame's
 * beam mode selects, all without one) and the road KPIs in its header. 0, -errno.
 */
int hl_pipeline_new(const struct hl_config *cfg, struct hl_lid *const lids[HL_FRAME_MAX_LAMPS],
		    int n_lamps, const struct hl_source_scale *const scales[HL_FRAME_MAX_LAMPS],
		    const uint8_t *const failsafe_dims[HL_FRAME_MAX_LAMPS], struct hl_ring *ring,
		    struct hl_frame_pool *pool, const struct hl_verdicts *verdicts,
		    const struct hl_pipeline_hooks *hooks, struct hl_pipeline **ret);
void hl_pipeline_free(struct hl_pipeline *p);

struct hl_glare_live;
struct hl_pose_input;
struct hl_osi_input;

/*
 * Before hl_pipeline_start: the records (daemon/core/verdict_records.h) the render thread feeds
 * with every frame whose verdicts ran; NULL: none. The caller owns them and frees them after
 * the pipeline.
 */
void hl_pipeline_set_records(struct hl_pipeline *p, struct hl_verdict_records *records);
/* The records set before the start, NULL for none. */
struct hl_verdict_records *hl_pipeline_records(const struct hl_pipeline *p);
/*
 * Before start: the moving scene. sc (NULL: none) sets each frame's world state (the scenario
 * clock: the replayed log's time, or CLOCK_MONOTONIC since start live; or pose's newest
 * message when pose is not NULL and one has come); glare (needs two lamps) evaluates it on
 * every published frame. All must outlive the pipeline.
 */
void hl_pipeline_set_scene(struct hl_pipeline *p, const struct hl_scenario *sc,
			   struct hl_glare_live *glare, struct hl_pose_input *pose);
/* Before start, after set_scene: the world from the live OSI input (scene.world osi:udp:). */
void hl_pipeline_set_osi(struct hl_pipeline *p, struct hl_osi_input *osi);

struct hl_lid_grid;
struct hl_world_state;
/* Called on the render thread for every published frame of a moving scene with two lamps. */
typedef void (*hl_pipeline_frame_fn)(void *ctx, const struct hl_scenario *sc,
				     const struct hl_world_state *w,
				     const struct hl_lid_grid *const grids[2],
				     const float *const dist[2]);
/*
 * Before start, after hl_pipeline_set_scene: fn(ctx, ...) with each published frame's world
 * state and its lamps' distributions, after its glare (a suite's photometers,
 * daemon/core/suite_live.h). It must take microseconds, not milliseconds.
 */
void hl_pipeline_set_frame_hook(struct hl_pipeline *p, hl_pipeline_frame_fn fn, void *ctx);

/*
 * Test-only fault, before start: after after_frames frames the render thread hangs (stops
 * rendering and calling the alive hook) until stopped, as a stuck renderer would; the systemd
 * watchdog then kills the daemon (HDLAMPD_DEBUG_STALL_RENDER_AFTER_FRAMES, docs/daemon.md).
 * 0: never (the default).
 */
/* CLOCK_MONOTONIC of scenario time 0 on a live bus: when the render thread had its renderer
 * ready (valid after hl_pipeline_start; any thread). The restbus's scenario clock. */
int64_t hl_pipeline_scene_t0_ns(const struct hl_pipeline *p);
void hl_pipeline_debug_stall(struct hl_pipeline *p, uint64_t after_frames);

/*
 * Starts the render thread (named hl-render, at SCHED_FIFO cfg->rt_priority when that is > 0,
 * base/sched.h) and waits until it has an EGL context and a renderer (or failed:
 * then err says why). 0, -errno.
 */
int hl_pipeline_start(struct hl_pipeline *p, char *err, size_t err_size);
void hl_pipeline_stop(struct hl_pipeline *p);

/* The renderer's description ("EGL surfaceless, llvmpipe ...; combine cpu, headlight cpu"). */
const char *hl_pipeline_describe(const struct hl_pipeline *p);
/*
 * The static G-buffer (valid between start and stop; read-only); NULL with a scenario, whose
 * moving G-buffer the render thread rewrites every frame.
 */
const struct hl_gbuffer *hl_pipeline_gbuffer(const struct hl_pipeline *p);
const struct hl_camera *hl_pipeline_camera(const struct hl_pipeline *p);
/* Live settings a reload may change. */
void hl_pipeline_set_failsafe(struct hl_pipeline *p, enum hl_failsafe mode,
			      const uint8_t *const dims[HL_FRAME_MAX_LAMPS]);
void hl_pipeline_set_exposure(struct hl_pipeline *p, double ev);
void hl_pipeline_counts(struct hl_pipeline *p, struct hl_pipeline_counts *ret);

#endif
