/* SPDX-License-Identifier: MIT */
/*
 * The live ASAM OSI input (docs/osi.md, "Live over UDP"; scene.world osi:udp:HOST:PORT): a
 * driving simulator sends one osi3::SensorView or osi3::GroundTruth per message, in datagrams
 * framed as esmini frames them (world/osi_udp_frame.h). The input's own thread reassembles,
 * decodes (world/osi_msg.h) and maps (world/osi_world.h) each message; a good one becomes the
 * newest world state, a bad one is counted by reason and changes nothing (logged at most once
 * per reason per second). The scenario (road, cast of road users) is made from the first usable
 * message: hl_osi_input_first() waits for it before the renderer starts.
 *
 * The last good state holds, its age reported; past scene.world_timeout_s without a good
 * message the world is "no world": the ego held where it was, no road users (nothing lit,
 * drawn, judged or reported to the ECU) until messages come again.
 *
 * Thread-safety: new, first, start, stop and free from the main thread. hl_osi_input_latest()
 * is the render thread's and the restbus's: it copies the newest state under a
 * priority-inheritance mutex that the input's thread holds only for that copy.
 * hl_osi_input_counts() and _port() from any thread.
 */
#ifndef HL_DAEMON_LOOP_OSI_INPUT_H
#define HL_DAEMON_LOOP_OSI_INPUT_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "world/osi_msg.h"
#include "world/osi_world.h"
#include "world/scenario.h"
#include "world/world.h"

struct hl_osi_input_counts {
	uint64_t reasons[HL_OSI_REASONS]; /* messages, datagrams and objects by reason */
	uint64_t datagrams; /* received */
	uint64_t socket_drops; /* datagrams the kernel dropped, full receive buffer (SO_RXQ_OVFL) */
	bool have; /* a good message arrived */
	int64_t t_last_ok_ns; /* CLOCK_MONOTONIC: when the newest good one arrived */
	double t_s; /* its timestamp (s): live, the scene's time is the simulator's */
	int objects; /* road users present in it */
};

struct hl_osi_input;

/*
 * An input on listen, "udp:HOST:PORT" (PORT 0: any free port, hl_osi_input_port()), reading
 * messages of kind; base (may be NULL, must outlive the input) lends the ego's lamps and camera
 * and a road; timeout_s turns a silent source into no world. Binds the socket. 0, -EINVAL,
 * -errno; err says why.
 */
int hl_osi_input_new(const char *listen, enum hl_osi_kind kind, const struct hl_scenario *base,
		     double timeout_s, FILE *log, struct hl_osi_input **ret, char *err,
		     size_t err_size);
/*
 * Waits up to wait_s for the first usable message and makes the scenario of it; messages
 * before it are counted by what they lack (no_host, no_road, ...). 0, or -ETIMEDOUT with err
 * saying what the last one lacked.
 */
int hl_osi_input_first(struct hl_osi_input *oi, double wait_s, char *err, size_t err_size);
/* The scenario (after hl_osi_input_first()), the input's: valid until hl_osi_input_free(). */
const struct hl_scenario *hl_osi_input_scenario(const struct hl_osi_input *oi);
/* Starts the input's thread (hl-osi, SCHED_OTHER). 0 or -errno. */
int hl_osi_input_start(struct hl_osi_input *oi);
void hl_osi_input_stop(struct hl_osi_input *oi);
void hl_osi_input_free(struct hl_osi_input *oi);

uint16_t hl_osi_input_port(const struct hl_osi_input *oi);
/*
 * The newest good message's state and arrival (CLOCK_MONOTONIC), or no world (no road user
 * present) when it is older than the timeout; false before the first.
 */
bool hl_osi_input_latest(struct hl_osi_input *oi, struct hl_world_state *ret, int64_t *ret_rx_ns);
void hl_osi_input_counts(struct hl_osi_input *oi, struct hl_osi_input_counts *ret);
/* The timeout (s) after which the world is none. */
double hl_osi_input_timeout_s(const struct hl_osi_input *oi);

#endif
