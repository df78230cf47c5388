/* SPDX-License-Identifier: MIT */
/*
 * The restbus (docs/ecu-inputs.md): hdlampd plays the rest of the car for the headlamp ECU. Its
 * own thread sends the input messages of a database mapped by can/inputs.h (by default the
 * shipped dbc/hd84_inputs.dbc) through SocketCAN: the vehicle state and the front camera's
 * object list of the scenario (daemon/loop/restbus_state.h), each message at its GenMsgCycleTime on
 * CLOCK_MONOTONIC absolute deadlines, with E2E counters and CRCs.
 *
 * Timing: the deadlines of a message with period P lie at scenario times k * P (the scenario
 * clock's origin t0_ns on CLOCK_MONOTONIC, the render thread's); the state sent at a deadline is
 * the scenario's at that deadline's time (held at 0 before the start and at duration_s after
 * the end), or, with a pose input that has had a message, the newest pose (the vehicle state
 * then from the ego's path at the pose's t_s). A wake-up later than a whole period sends once
 * for the newest passed deadline and counts the skipped ones as overruns. Every send's
 * lateness behind its deadline and, per message, the deviation of the interval between two
 * consecutive sends from the period (the TX period jitter) are measured.
 *
 * It never blocks rendering: nothing here is shared with the render thread; the counters are
 * copied under a priority-inheritance mutex held only for the copy. Frames are written without
 * blocking; a full queue (EAGAIN, ENOBUFS) and other TX errors are counted, an interface that
 * goes down is reopened with the CAN input's back-off, error frames give the bus state and
 * bus-off events, and a frame of one of its own IDs sent by another node is counted as foreign.
 *
 * Thread-safety: new, start, stop and free from the main thread; the counts, JSON and metrics
 * from any thread.
 */
#ifndef HL_DAEMON_LOOP_RESTBUS_H
#define HL_DAEMON_LOOP_RESTBUS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "can/inputs.h"
#include "can/socket.h"
#include "daemon/loop/loop_latency.h"
#include "daemon/loop/osi_input.h"
#include "daemon/loop/pose_input.h"
#include "daemon/core/prom.h"
#include "daemon/loop/restbus_state.h"
#include "world/scenario.h"

#define HL_RESTBUS_MAX_MESSAGES (1 + HL_INPUTS_MAX_OBJ_MESSAGES)
#define HL_RESTBUS_MAX_CYCLE_MS 1000 /* longest GenMsgCycleTime it sends at */

struct hl_restbus_config {
	const char *iface; /* SocketCAN interface */
	const char *dbc; /* the input database's path */
	const struct hl_scenario *sc; /* must outlive the restbus */
	struct hl_pose_input *pose; /* NULL: the scenario's paths only */
	struct hl_osi_input *osi; /* NULL: no live OSI world; else its newest state */
	struct hl_restbus_camera cam;
	enum hl_light_switch light_switch;
	bool adb_enable;
	int rt_priority; /* SCHED_FIFO of its thread; 0: normal scheduling */
	/* NULL, or told of every camera cycle (its consumer, daemon/loop/loop_latency.h) */
	struct hl_loop_latency *loop;
	FILE *log;
};

struct hl_restbus_message_counts {
	char name[64];
	uint32_t can_id;
	unsigned cycle_ms;
	uint64_t sent; /* frames */
	uint64_t failed; /* frames not sent: TX error, queue full, link down, unencodable */
	uint64_t intervals; /* jitter samples: consecutive deadlines both sent */
	double jitter_last_ms, jitter_max_ms, jitter_mean_abs_ms; /* interval - period */
	double late_last_ms, late_max_ms; /* send - deadline */
};

struct hl_restbus_counts {
	int64_t t0_ns; /* CLOCK_MONOTONIC of scenario time 0; 0 before the start */
	int n_messages;
	struct hl_restbus_message_counts msg[HL_RESTBUS_MAX_MESSAGES];
	uint64_t vehicle_cycles, camera_cycles; /* deadlines served */
	uint64_t overruns; /* deadlines skipped: woke a whole period late or more */
	uint64_t tx_full; /* EAGAIN / ENOBUFS: the interface's queue was full */
	uint64_t tx_errors; /* other send errors */
	uint64_t encode_errors; /* a value its signal cannot carry (frame not sent) */
	uint64_t link_down; /* frames due while the interface was down */
	uint64_t foreign_frames; /* one of our IDs sent by another node */
	uint64_t objects_sent; /* summed over camera cycles */
	/* road users not sent, summed over camera cycles: behind the camera's plane, beyond its
	 * range, outside its field of view, over the slots (restbus_state.h) */
	uint64_t unseen_behind, unseen_beyond_range, unseen_outside_fov, unseen_over_max;
	struct hl_can_socket_stats sock;
	bool have_cycle; /* the newest camera cycle below is set */
	double cycle_t_s; /* its scenario time */
	struct hl_camera_objects objects;
	struct hl_vehicle_state vehicle; /* the newest vehicle state sent */
};

struct hl_restbus;

/*
 * Loads and maps the database, checks the cycle times (1..HL_RESTBUS_MAX_CYCLE_MS, the same for
 * every objects message) and that the camera's field of view and range fit the box and distance
 * signals' ranges, makes the socket (not opened yet). 0, -EINVAL (err names the file, message, signal or
 * attribute), -errno.
 */
int hl_restbus_new(const struct hl_restbus_config *cfg, struct hl_restbus **ret, char *err,
		   size_t err_size);
/* Starts the thread (hl-restbus) with scenario time 0 at t0_ns (CLOCK_MONOTONIC). 0 or -errno. */
int hl_restbus_start(struct hl_restbus *rb, int64_t t0_ns);
void hl_restbus_stop(struct hl_restbus *rb);
void hl_restbus_free(struct hl_restbus *rb);

void hl_restbus_counts(struct hl_restbus *rb, struct hl_restbus_counts *ret);
/* ,"restbus":{...} */
void hl_restbus_status_json(struct hl_restbus *rb, FILE *f);
/* hdlamp_restbus_* */
void hl_restbus_metrics(struct hl_restbus *rb, struct hl_prom *p);

#endif
