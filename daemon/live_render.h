/* SPDX-License-Identifier: MIT */
/*
 * The daemon's renderer and outputs (docs/design.md §2), with the renderer on: the frame pool,
 * the render thread (daemon/pipeline.h) with the lamps' fail-safe and DBC scales, the GPIO
 * strobe and trigger, the loop judge's subscription, the systemd watchdog, the capture queue,
 * the frame stream, the status and the HTTP server, made and logged in that order, started,
 * and stopped and freed in the order their readers need.
 *
 * Thread-safety: every function on hl_live_run's thread (the main thread's event loop); the
 * parts run their own threads (the render thread calls the watchdog hook, the HTTP server's
 * threads the status and capture callbacks) as their headers say.
 */
#ifndef HL_DAEMON_LIVE_RENDER_H
#define HL_DAEMON_LIVE_RENDER_H

#include <stdbool.h>

#include "can/assembler.h"
#include "daemon/core/can_input.h"
#include "daemon/live_ecu.h"
#include "daemon/core/config.h"
#include "daemon/core/glare_live.h"
#include "daemon/core/suite_live.h"
#include "daemon/core/ring.h"
#include "daemon/core/verdicts.h"
#include "daemon/loop/loop_latency.h"
#include "daemon/loop/osi_input.h"
#include "daemon/loop/pose_input.h"
#include "world/osi_replay.h"
#include "daemon/loop/restbus.h"
#include "daemon/pipeline.h"
#include "lamp/lid.h"
#include "world/scenario.h"

/* What the renderer and the outputs read; all the caller's, and must outlive the object. */
struct hl_live_render_parts {
	const char *input_name; /* the interface or the replayed log */
	const struct hl_assembler *a; /* the sources' DBC scales */
	int n_lamps;
	int n_sources; /* the most of any lamp */
	const char *const *lamp_names; /* n_lamps */
	struct hl_lid *const *lids; /* n_lamps */
	struct hl_ring *ring; /* the render thread consumes it */
	struct hl_can_input *in;
	const struct hl_verdicts *verdicts;
	/* the moving scene (NULL without a scenario, the pose input without pose.listen) */
	const struct hl_scenario *sc;
	struct hl_glare_live *glare;
	struct hl_pose_input *pose;
	struct hl_osi_input *osi; /* scene.world osi:udp: */
	const struct hl_osi_replay_report *osi_replay; /* scene.world osi:file: its counts */
	struct hl_restbus *restbus; /* NULL: none */
	struct hl_loop_latency *loop; /* NULL: none; published frames are handed to it */
	struct hl_live_ecu *ecu; /* NULL: none (an ECU outside); its part of /status */
	struct hl_suite_live *suite; /* NULL: none; measured on every frame, its part of /status */
};

struct hl_live_render;

/*
 * Makes and starts the renderer (cfg's render.*, lamps.failsafe, gpio.*,
 * HDLAMPD_DEBUG_STALL_RENDER_AFTER_FRAMES), then the outputs (capture.*, stream.*, http.*),
 * logging each. The pose input, the restbus and the CAN thread are the caller's to start. *ret
 * is the caller's. 0 or -errno, logged; on failure *ret_config_error says whether the
 * configuration is at fault (exit 2: the fault switch's value).
 */
int hl_live_render_new(const struct hl_config *cfg, const struct hl_live_render_parts *parts,
		       struct hl_live_render **ret, bool *ret_config_error);
/* Stops the outputs and the render thread and frees them. NULL: nothing. */
void hl_live_render_free(struct hl_live_render *r);

/* The render thread (counts, its scenario clock), owned by r. */
struct hl_pipeline *hl_live_render_pipeline(const struct hl_live_render *r);

/* The GPIO trigger line's fd to poll, -1 without gpio.chip. */
int hl_live_render_trigger_fd(const struct hl_live_render *r);
/* The trigger fd polled readable: its edges read; a capture queued when there were any. */
void hl_live_render_trigger(struct hl_live_render *r);
/* A capture queued (SIGUSR1); the queue logs what becomes of it. */
void hl_live_render_capture(struct hl_live_render *r);
/*
 * SIGHUP: next's lamps.failsafe and render.exposure_ev applied to the running renderer (the
 * CAN thread runs on, so no cycle is lost) and the status told; logged. A fail-safe preset that
 * does not load is logged and nothing is applied.
 */
void hl_live_render_reload(struct hl_live_render *r, const struct hl_config *next);
/*
 * Quiesces before the report, in this order: the pool closed, the HTTP server, the capture
 * queue (what was asked for is written and counted), the render thread, the restbus and the
 * pose input of the parts, the frame stream. The caller stops the CAN thread first.
 */
void hl_live_render_stop(struct hl_live_render *r);
/* The status as one JSON line on stdout (at exit). */
void hl_live_render_print_status(struct hl_live_render *r);

#endif
