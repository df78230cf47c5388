/* SPDX-License-Identifier: MIT */
/*
 * The daemon's status for other threads: the /status JSON (also printed at exit) and the
 * /metrics text, read from the input's, ring's, renderer's, pool's and outputs' own counters
 * and from the newest published frame (its verdicts and road KPIs, daemon/core/verdicts.h),
 * plus what only the main thread changes (the fail-safe mode a reload sets, the reload count),
 * which it keeps under its own lock.
 *
 * Thread-safety: hl_status_json and hl_status_metrics from any thread (the HTTP server's);
 * hl_status_reloaded from any thread; new and free from the main thread
 * while no other thread uses the status.
 */
#ifndef HL_DAEMON_STATUS_H
#define HL_DAEMON_STATUS_H

#include <stdbool.h>
#include <stddef.h>

#include "daemon/core/can_input.h"
#include "daemon/out/capture_queue.h"
#include "daemon/core/config.h"
#include "daemon/core/frame_pool.h"
#include "daemon/core/glare_live.h"
#include "daemon/core/suite_live.h"
#include "daemon/out/gpio.h"
#include "daemon/out/http.h"
#include "daemon/pipeline.h"
#include "daemon/loop/osi_input.h"
#include "daemon/loop/pose_input.h"
#include "world/osi_replay.h"
#include "daemon/loop/loop_latency.h"
#include "daemon/live_ecu.h"
#include "daemon/loop/restbus.h"
#include "daemon/core/ring.h"
#include "daemon/out/stream.h"
#include "daemon/core/verdicts.h"

/* What the status reads; every pointer must outlive it. NULL: that part is off (zeros). */
struct hl_status_sources {
	const char *input_name; /* the interface or the replayed log */
	int n_lamps;
	const char *const *lamp_names;
	struct hl_can_input *in;
	struct hl_ring *ring;
	struct hl_pipeline *pipe; /* NULL: the renderer is off */
	struct hl_frame_pool *pool;
	struct hl_stream *stream;
	struct hl_gpio *gpio;
	struct hl_capture_queue *captures;
	struct hl_http *http; /* its counters: "http" in the JSON, hdlamp_http_* in the metrics */
	const struct hl_verdicts *verdicts; /* with pipe and pool: the newest frame's verdicts */
	struct hl_glare_live *glare; /* with pool: the scenario's time and the newest frame's glare */
	struct hl_pose_input *pose; /* the pose input's counters and the newest pose's age */
	struct hl_osi_input *osi; /* the live OSI input's counters, the newest message's age */
	const struct hl_osi_replay_report *osi_replay; /* an OSI trace's counts */
	struct hl_restbus *restbus; /* "restbus" in the JSON, hdlamp_restbus_* in the metrics */
	struct hl_loop_latency *loop; /* "loop" in the JSON, hdlamp_loop_* in the metrics */
	struct hl_live_ecu *ecu; /* ecu.model: "ecu" in the JSON */
	struct hl_suite_live *suite; /* hdlampd --suite: "suite" in the JSON, hdlamp_suite_* */
};

struct hl_status;

/* failsafe: the running lamps.failsafe. 0, -EINVAL (no lamps), -ENOMEM. */
int hl_status_new(const struct hl_status_sources *src, enum hl_failsafe failsafe,
		  struct hl_status **ret);
void hl_status_free(struct hl_status *st);

/* A reload applied: its fail-safe mode is now the running one; counts the reload. */
void hl_status_reloaded(struct hl_status *st, enum hl_failsafe failsafe);

/* The status as one JSON object, NUL-terminated: its length, or -ENOBUFS, -errno. */
int hl_status_json(struct hl_status *st, char *buf, size_t size);
/* The counters as Prometheus text (daemon/core/prom.h): its length, or -ENOBUFS. */
int hl_status_metrics(struct hl_status *st, char *buf, size_t size);

#endif
