/* SPDX-License-Identifier: MIT */
/*
 * The restbus as a node of the virtual bus (docs/sil.md): the rest of the car in virtual time.
 * The same messages as hdlampd's restbus (daemon/loop/restbus.h) from the same state
 * (daemon/loop/restbus_state.h): each message of the input database at its GenMsgCycleTime,
 * deadlines at scenario times k * P (virtual time 0 = scenario time 0), the scenario's state at
 * the deadline's time (held at duration_s after the end), alive counters and CRCs; the frames
 * go onto the bus at the deadline. A camera cycle's input time is when its last frame ended on
 * the bus, and the loop's judge (daemon/loop/loop_latency.h) is told of it then.
 *
 * Thread-safety: belongs to the thread that drives its bus.
 */
#ifndef HL_SIL_RESTBUS_NODE_H
#define HL_SIL_RESTBUS_NODE_H

#include <stdbool.h>
#include <stdint.h>

#include "can/inputs.h"
#include "can/vbus.h"
#include "daemon/loop/loop_latency.h"
#include "daemon/loop/restbus_state.h"
#include "world/scenario.h"

struct hl_restbus_node_config {
	const struct hl_scenario *sc;
	const struct hl_inputs_map *map;
	struct hl_restbus_camera cam;
	enum hl_light_switch light_switch;
	bool adb_enable;
	struct hl_loop_latency *loop; /* NULL: none */
};

struct hl_restbus_node_counts {
	uint64_t vehicle_cycles, camera_cycles;
	uint64_t frames_sent;
	uint64_t tx_full; /* refused by the bus: its queue was full */
	uint64_t encode_errors;
	uint64_t objects_sent;
};

struct hl_restbus_node;

/* 0, -EINVAL (a message without a cycle time), -ENOMEM. */
int hl_restbus_node_new(const struct hl_restbus_node_config *cfg, struct hl_vbus *bus,
			struct hl_restbus_node **ret);
void hl_restbus_node_free(struct hl_restbus_node *rb);
/* The next deadline. */
int64_t hl_restbus_node_next(const struct hl_restbus_node *rb);
/* Sends what is due at t (== the next deadline). */
void hl_restbus_node_run(struct hl_restbus_node *rb, int64_t t);
/* Every frame the bus delivered (the node's own among them: their end is the input time). */
void hl_restbus_node_delivered(struct hl_restbus_node *rb, const struct hl_vbus_frame *f);
/* The node's index on the bus. */
int hl_restbus_node_index(const struct hl_restbus_node *rb);
void hl_restbus_node_counts(const struct hl_restbus_node *rb, struct hl_restbus_node_counts *ret);

#endif
