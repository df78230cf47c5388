/* SPDX-License-Identifier: MIT */
/*
 * The pose input (docs/live-scenario.md, "Pose input"): an external driving simulator sends where the
 * ego vehicle and the scenario's road users are, one JSON object per UDP datagram:
 *
 *   {"t_s": 12.5, "ego": {"x_m": 0, "y_m": -1.75, "heading_deg": 0},
 *    "actors": [{"id": "oncoming", "x_m": 80, "y_m": 1.75, "heading_deg": 180,
 *                "lamps": true}]}
 *
 * t_s and ego are required; actors is optional and names road users of the scenario by id
 * (lamps optional, default true). A road user the message does not name is where the
 * scenario's path puts it at t_s. Each message is parsed and checked whole on the input's own
 * thread; a good one becomes the newest world state (world/world.h), a bad one is counted by
 * reason (the first HL_POSE_LOGGED of each logged) and changes nothing. Nothing is fatal.
 *
 * Thread-safety: new, start, stop and free from the main thread. hl_pose_input_latest() is the
 * render thread's: it copies the newest state under a priority-inheritance mutex that the
 * input's thread holds only for that copy. hl_pose_input_counts() and hl_pose_input_port()
 * from any thread. hl_pose_parse() is a pure function (any thread).
 */
#ifndef HL_DAEMON_LOOP_POSE_INPUT_H
#define HL_DAEMON_LOOP_POSE_INPUT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "world/scenario.h"
#include "world/world.h"

#define HL_POSE_MAX_DATAGRAM 16384 /* bytes; a longer datagram is counted as too_large */
#define HL_POSE_LOGGED 5 /* bad messages logged per reason; the rest only counted */

/* What became of a datagram. */
enum hl_pose_result {
	HL_POSE_OK,
	HL_POSE_MALFORMED, /* not JSON, or not one object */
	HL_POSE_INVALID, /* JSON, but a key missing, unknown, of the wrong type or out of range */
	HL_POSE_UNKNOWN_ACTOR, /* an id that is not one of the scenario's road users */
	HL_POSE_TOO_LARGE, /* over HL_POSE_MAX_DATAGRAM bytes */
	HL_POSE_N,
};

struct hl_pose_counts {
	uint64_t messages[HL_POSE_N]; /* by result */
	bool have; /* a good message arrived */
	int64_t t_last_ok_ns; /* CLOCK_MONOTONIC: when the newest good one arrived */
	double t_s; /* its scenario time */
};

struct hl_pose_input;

/* "ok", "malformed", ...: the result's label in /metrics and /status. */
const char *hl_pose_result_name(enum hl_pose_result r);

/*
 * Parses one message for scenario sc into *ret (a whole world state: road users the message
 * does not name from sc's paths at its t_s). why (may be NULL) says what is wrong, naming the
 * key. Returns its result; *ret is only written for HL_POSE_OK.
 */
enum hl_pose_result hl_pose_parse(const struct hl_scenario *sc, const char *buf, size_t len,
				  struct hl_world_state *ret, char *why, size_t why_size);

/*
 * An input on listen, "udp:HOST:PORT" (PORT 0: any free port, hl_pose_input_port()), for sc
 * (which must outlive it); bad messages are logged to log. Binds the socket. 0, -EINVAL,
 * -errno (cannot bind); err says why.
 */
int hl_pose_input_new(const char *listen, const struct hl_scenario *sc, FILE *log,
		      struct hl_pose_input **ret, char *err, size_t err_size);
/* Starts the input's thread (hl-pose, SCHED_OTHER). 0 or -errno. */
int hl_pose_input_start(struct hl_pose_input *pi);
void hl_pose_input_stop(struct hl_pose_input *pi);
void hl_pose_input_free(struct hl_pose_input *pi);

uint16_t hl_pose_input_port(const struct hl_pose_input *pi);
/* The newest good message's state and arrival (CLOCK_MONOTONIC); false before the first. */
bool hl_pose_input_latest(struct hl_pose_input *pi, struct hl_world_state *ret, int64_t *ret_rx_ns);
void hl_pose_input_counts(struct hl_pose_input *pi, struct hl_pose_counts *ret);

#endif
