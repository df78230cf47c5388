/* SPDX-License-Identifier: MIT */
/*
 * The headlamp ECU's inputs on CAN: vehicle state and the front camera's object list, as
 * dbc/hd84_inputs.dbc lays them out and as any database carrying the same DBC attributes does
 * (docs/ecu-inputs.md). The restbus (daemon/restbus.c) encodes them, the reference virtual ECU
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
 * Angles (DESIGN.md §4): H positive to the right, V positive up, seen from the camera; an
 * object's box is [h_left_deg, h_right_deg] x [v_bottom_deg, v_top_deg] with h_left < h_right.
 * Yaw rate and steering are positive to the left (counter-clockwise seen from above, ISO 8855).
 *
 * Thread-safety: a struct hl_inputs_map is immutable after hl_inputs_map_new(); encode and
 * decode may run on any thread with their own output buffers.
 */
#ifndef HL_CAN_INPUTS_H
#define HL_CAN_INPUTS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

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

#endif
