/* SPDX-License-Identifier: MIT */
/*
 * The headlamp ECU's inputs on CAN: vehicle state and the front camera's object list, as
 * dbc/hd84_inputs.dbc lays them out and as any database carrying the same DBC attributes does
 * (docs/ecu-inputs.md). The restbus (daemon/loop/restbus.c) encodes them, the reference virtual ECU
 * (`hdlamp ecu`) decodes them; a real ECU's own database maps onto them without code.
 *
 * Semantics come from DBC attributes, not from names:
 *   BO_ "HdlInput"  STRING  "vehicle" | "objects"       which struct the message fills
 *   BO_ "HdlE2E"    STRING  "P1 dataid=0x...." | "none"  as for the dimming frames (can/e2e.h)
 *   BO_ "GenMsgCycleTime" INT  the restbus's period, ms
 *   SG_ "HdlInputSignal" STRING  the field a signal carries, one of
 *       vehicle: "speed", "yaw_rate", "steering", "light_switch", "adb_enable"
 *       objects: "object_index" (the multiplexor: slot 0..7), "object_count" (objects in this
 *                cycle), "id", "class", "h_left", "h_right", "v_bottom", "v_top", "distance",
 *                "confidence"
 *       both:    "crc", "alive" (the E2E fields; their layout must match HdlE2E)
 *   Units are the DBC's: speed km/h, yaw rate deg/s, steering deg, angles deg, distance m,
 *   confidence 0..1. The codec converts to the SI/degree fields below.
 *
 * Angles (docs/design.md §4): H positive to the right, V positive up, seen from the camera; an
 * object's box is [h_left_deg, h_right_deg] x [v_bottom_deg, v_top_deg] with h_left < h_right.
 * Yaw rate and steering are positive to the left (counter-clockwise seen from above, ISO 8855).
 *
 * The object list may be spread over several messages with HdlInput "objects" (hd84_inputs.dbc:
 * HDI_CamObjInfo and HDI_CamObjBox, because one classic frame cannot hold an object), each
 * multiplexed by its own "object_index" signal; every other object field is given by exactly one
 * signal of one of them (for each slot: extended multiplexing or one signal per slot both map).
 *
 * The camera cycle (the rule hl_inputs_decode() applies; docs/ecu-inputs.md):
 *   - the sender sends, for each slot 0..count-1 in order, one frame of every objects message;
 *     with no object, slot 0 of each message that carries "object_count" (count 0) and nothing
 *     else; every frame of one cycle carries the same counter (the E2E counter, or the "alive"
 *     signal without E2E), one step on per cycle;
 *   - a receiver has a complete cycle when every objects message delivered every slot
 *     0..count-1 under one counter value, all with the same count; a frame with another counter
 *     starts the next cycle and the unfinished one is counted incomplete; a slot at or beyond
 *     count, a count that differs between frames of one cycle, or a slot delivered twice are
 *     counted (bad_values, duplicates) and end the cycle as incomplete;
 *   - the counter is checked once per cycle: a cycle whose counter repeats the last complete
 *     one is ignored (counter_repeated), skipped values are counted (counter_lost).
 * The vehicle message stands alone: each valid frame is a new state; a repeated counter drops
 * the frame (counter_repeated), a skip is counted (counter_lost) and the frame is taken.
 *
 * Thread-safety: a struct hl_inputs_map is immutable after hl_inputs_map_new(); encode may run
 * on any thread with its own output buffers. A struct hl_inputs_decoder belongs to one thread.
 */
#ifndef HL_CAN_INPUTS_H
#define HL_CAN_INPUTS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "can/e2e.h"
#include "dbc/database.h"

#define HL_INPUTS_MAX_OBJECTS 8 /* per camera cycle */

enum hl_light_switch {
	HL_SWITCH_OFF = 0,
	HL_SWITCH_AUTO = 1,
	HL_SWITCH_LOW = 2,
	HL_SWITCH_HIGH = 3,
};

enum hl_object_class {
	HL_OBJECT_OTHER = 0,
	HL_OBJECT_ONCOMING = 1,
	HL_OBJECT_PRECEDING = 2,
	HL_OBJECT_PEDESTRIAN = 3,
};

struct hl_vehicle_state {
	double speed_mps;
	double yaw_rate_rad_s; /* + left */
	double steering_rad; /* steering wheel angle, + left */
	enum hl_light_switch light_switch;
	bool adb_enable;
};

struct hl_camera_object {
	unsigned id; /* 1..255 while tracked; stays the same from cycle to cycle */
	enum hl_object_class cls;
	double h_left_deg, h_right_deg; /* horizontal angles of the box's edges, from the camera */
	double v_bottom_deg, v_top_deg;
	double distance_m;
	double confidence; /* 0..1 */
};

/* One camera cycle: n objects (0..HL_INPUTS_MAX_OBJECTS). */
struct hl_camera_objects {
	int n;
	struct hl_camera_object obj[HL_INPUTS_MAX_OBJECTS];
};

enum hl_inputs_kind {
	HL_INPUTS_VEHICLE = 1,
	HL_INPUTS_OBJECTS = 2,
};

/* One message of the map: what the restbus sends and how. */
struct hl_inputs_message {
	const struct hl_dbc_message *msg; /* owned by the database */
	enum hl_inputs_kind kind;
	unsigned cycle_ms; /* GenMsgCycleTime; 0 when the database gives none */
	struct hl_e2e_config e2e;
	bool fd; /* CAN FD: VFrameFormat *_FD or more than 8 bytes */
};

/* A frame to send: can_id with HL_DBC_EFF_FLAG for an extended ID (as CAN_EFF_FLAG). */
struct hl_inputs_frame {
	uint32_t can_id;
	uint8_t len;
	bool fd;
	uint8_t data[HL_DBC_MAX_PAYLOAD];
};

/* The most frames one camera cycle can take: every objects message for every slot. */
#define HL_INPUTS_MAX_OBJ_MESSAGES 4
#define HL_INPUTS_MAX_CYCLE_FRAMES (HL_INPUTS_MAX_OBJECTS * HL_INPUTS_MAX_OBJ_MESSAGES)

struct hl_inputs_map;

/*
 * Finds the input messages and signals of db by their attributes. The database must hold one
 * message with HdlInput "vehicle" carrying speed, yaw_rate, steering, light_switch and
 * adb_enable (unmultiplexed), and 1..4 messages with HdlInput "objects" which together carry
 * every object field for slots 0..n-1 (n = the slots the object_index signals can name, at
 * most 8); with HdlE2E P1/P5 a message's "crc" and "alive" signals must lie where the profile
 * puts them, without E2E an objects message needs an "alive" signal. Returns 0, -EINVAL (msg
 * names the message, signal and attribute at fault and what was expected), -ENOMEM. db must
 * outlive the map. msg (may be NULL) gets the reason.
 */
int hl_inputs_map_new(const struct hl_dbc *db, struct hl_inputs_map **ret, char *msg,
		      size_t msg_size);
void hl_inputs_map_free(struct hl_inputs_map *map);

int hl_inputs_map_n_messages(const struct hl_inputs_map *map);
/* Message i: the vehicle message first, then the objects messages in their cycle order. */
const struct hl_inputs_message *hl_inputs_map_message(const struct hl_inputs_map *map, int i);
/* Slots per camera cycle (1..HL_INPUTS_MAX_OBJECTS). */
int hl_inputs_map_slots(const struct hl_inputs_map *map);
/* The largest counter value of message i (14 for P1). */
unsigned hl_inputs_map_counter_max(const struct hl_inputs_map *map, int i);
/* The range [min, max] of an object field's signal in the DBC's unit (deg, m), e.g. for a
 * camera's field of view; field is an HdlInputSignal name. -ENOENT for an unknown field. */
int hl_inputs_map_range(const struct hl_inputs_map *map, const char *field, double *ret_min,
			double *ret_max);

/*
 * The signal carrying field (an HdlInputSignal name: a vehicle field, or an object field in
 * slot 0..slots-1; the slot is ignored for vehicle fields and for "object_count", which is
 * taken from slot 0), owned by the database; NULL for an unknown field or slot.
 */
const struct hl_dbc_signal *hl_inputs_map_signal(const struct hl_inputs_map *map, const char *field,
						 int slot);

/*
 * The vehicle state as one frame with the E2E counter (0..counter max) and CRC. 0, or -ERANGE
 * when a value does not fit its signal (the frame is then unusable), -EINVAL for a counter
 * above the maximum.
 */
int hl_inputs_encode_vehicle(const struct hl_inputs_map *map, const struct hl_vehicle_state *st,
			     unsigned counter, struct hl_inputs_frame *ret);
/*
 * One camera cycle as its frames in sending order (the rule above) into ret (room for
 * HL_INPUTS_MAX_CYCLE_FRAMES). Returns the number of frames, -E2BIG for more objects than
 * slots, -ERANGE when a value does not fit its signal, -EINVAL for a counter above the
 * maximum.
 */
int hl_inputs_encode_objects(const struct hl_inputs_map *map, const struct hl_camera_objects *o,
			     unsigned counter, struct hl_inputs_frame *ret);

/* What a decoder saw; every frame lands in exactly one of frames' outcomes. */
struct hl_inputs_counters {
	uint64_t frames; /* handed to hl_inputs_decode() */
	uint64_t unknown_id; /* not an input message: ignored */
	uint64_t short_frames; /* shorter than the message */
	uint64_t crc_errors; /* E2E CRC wrong */
	uint64_t counter_repeated; /* dropped: a repeated vehicle counter, a frame of a cycle
				    * already complete or already found incomplete */
	uint64_t counter_lost; /* counter values skipped (a sum of gaps) */
	uint64_t bad_values; /* a value no state can hold: a slot/class/switch out of range, ... */
	uint64_t duplicates; /* a slot of one message twice in one cycle */
	uint64_t vehicle_states; /* good vehicle frames */
	uint64_t object_frames; /* objects frames taken into a cycle */
	uint64_t cycles_complete;
	uint64_t cycles_incomplete; /* started and never completed */
};

struct hl_inputs_decoder;

/* A decoder of map (which must outlive it). 0 or -ENOMEM. */
int hl_inputs_decoder_new(const struct hl_inputs_map *map, struct hl_inputs_decoder **ret);
void hl_inputs_decoder_free(struct hl_inputs_decoder *d);
/*
 * Takes one received frame. Returns HL_INPUTS_VEHICLE with *ret_vehicle filled,
 * HL_INPUTS_OBJECTS with *ret_objects filled when the frame completed a camera cycle, 0 when it
 * was taken and nothing is complete yet, or a negative errno when it was refused (counted):
 * -ENOENT not an input message, -EMSGSIZE short, -EBADMSG CRC, -ESTALE repeated counter,
 * -ERANGE a bad value, -EEXIST a duplicate slot. Allocates nothing. The outputs are untouched
 * unless the return says so.
 */
int hl_inputs_decode(struct hl_inputs_decoder *d, uint32_t can_id, const uint8_t *data, size_t len,
		     struct hl_vehicle_state *ret_vehicle, struct hl_camera_objects *ret_objects);
const struct hl_inputs_counters *hl_inputs_decoder_counters(const struct hl_inputs_decoder *d);

const char *hl_object_class_name(enum hl_object_class cls);
const char *hl_light_switch_name(enum hl_light_switch sw);

#endif
