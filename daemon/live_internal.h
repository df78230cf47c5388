/* SPDX-License-Identifier: MIT */
/*
 * The daemon's wiring (daemon/live.c) shared with the setup of its parts in other files
 * (daemon/live_setup.c: the verdicts, the scenario with its glare and pose input, the
 * loop's latency, the restbus). Only hl_live_run's thread touches a struct live.
 */
#ifndef HL_DAEMON_LIVE_INTERNAL_H
#define HL_DAEMON_LIVE_INTERNAL_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "can/assembler.h"
#include "daemon/core/can_input.h"
#include "daemon/out/capture_queue.h"
#include "daemon/core/config.h"
#include "daemon/core/decode_report.h"
#include "daemon/core/frame_pool.h"
#include "daemon/core/glare_live.h"
#include "daemon/out/gpio.h"
#include "daemon/out/http.h"
#include "daemon/loop/loop_latency.h"
#include "daemon/live.h"
#include "daemon/pipeline.h"
#include "daemon/loop/pose_input.h"
#include "daemon/loop/restbus.h"
#include "daemon/core/ring.h"
#include "daemon/status.h"
#include "daemon/out/stream.h"
#include "daemon/core/verdicts.h"
#include "verdict/regulation.h"
#include "render/frame_exr.h"
#include "world/scenario.h"

struct live {
	struct hl_config cfg;
	const struct hl_live_args *args;
	const char *input_name; /* the interface or the replayed log */
	struct hl_dbc *db;
	struct hl_assembler *a;
	const char *lamp_names[HL_RING_MAX_LAMPS]; /* the assembler's */
	int n_lamps;
	struct hl_ring *ring;
	struct hl_can_input *in;
	/* decode-only: this thread is the ring's consumer */
	struct hl_snapshot *snap;
	struct hl_decode_seen seen;
	/* the renderer and the outputs (NULL when decode-only) */
	struct hl_lid *lids[HL_FRAME_MAX_LAMPS];
	struct hl_frame_pool *pool;
	struct hl_pipeline *pipe;
	struct hl_stream *stream;
	struct hl_gpio *gpio;
	struct hl_status *status;
	struct hl_verdicts *verdicts; /* the regulation sets and road KPIs per frame */
	/* the moving scene (scene.scenario): its glare per frame, poses from a simulator */
	struct hl_scenario *sc;
	struct hl_regulation *glare_reg;
	struct hl_glare_live *glare;
	struct hl_pose_input *pose;
	struct hl_restbus *restbus; /* restbus.interface: the ECU's inputs from the scenario */
	/* the loop's latency and glare verdict (a scenario with a restbus or a report) */
	struct hl_loop_latency *loop;
	FILE *loop_events; /* loop.events when a file */
	bool config_error; /* setup failed on the configuration: exit 2 */
	struct hl_http *http;
	struct hl_capture_queue *captures; /* the one capture writer */
	struct hl_frame_exr_info exr_info; /* camera and lamp poses for /frame.exr */
	uint64_t watchdog_us; /* ping interval, 0 without a watchdog */
	int64_t watchdog_last_ns; /* render thread's */
};

/* "hdlampd: " and the message on stderr, one line. */
void hl_live_log(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* The live verdicts (verdict.*). 0 or -errno; lv->config_error on a configuration fault. */
int hl_live_setup_verdicts(struct live *lv);
/* The scenario (scene.*), its glare, the pose input (pose.listen). As above. */
int hl_live_setup_scene(struct live *lv);
/* The loop's latency and glare verdict (loop.*). As above. */
int hl_live_setup_loop(struct live *lv);
/* The restbus (restbus.*). As above. */
int hl_live_setup_restbus(struct live *lv);

#endif
