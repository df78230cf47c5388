/* SPDX-License-Identifier: MIT */
/*
 * ASAM OSI ground truth as hdlamp's world (docs/osi.md, "Mapping"): a decoded message
 * (world/osi_msg.h) becomes a scenario (road, ego lamps and camera, the road users) and, message
 * by message, world states (world/world.h).
 *
 * - The host vehicle (host_vehicle_id) is the ego; every other moving object a road user, cast
 *   once into a slot of the scenario by its id: a live source casts the first message's objects
 *   (one that appears later is counted as new_object and left out), a trace the objects of all
 *   its messages. A road user missing from a message is not present in that state.
 * - Kinds: MovingObject.type PEDESTRIAN a pedestrian; VEHICLE by vehicle_classification.type:
 *   BICYCLE a cyclist, MOTORBIKE a motorbike, HEAVY_TRUCK, SEMITRAILER, TRAILER, BUS, TRAM,
 *   TRAIN and 16 (SEMITRACTOR) a truck, WHEELCHAIR a pedestrian, the cars, DELIVERY_VAN,
 *   UNKNOWN, OTHER and no classification a car; any other type (UNKNOWN, OTHER, ANIMAL) or
 *   vehicle type is counted as unknown_type and left out. Eye points and lamps are the kind's
 *   defaults (world/scenario.h); the body is the message's dimension.
 * - Lamps lit unless light_state.head_light is OFF (tail lamps go with them: OSI has no
 *   tail-lamp state of its own).
 * - Poses: OSI's position is the bounding box's centre, ours the ground below the front face's
 *   centre: origin = centre + (length / 2) along the yaw, z dropped (the ground is flat at z = 0;
 *   roll and pitch are ignored). heading = yaw, speed = |velocity| in the ground plane.
 * - The road from the first message's lane boundaries (world/osi_road.h); without any, the base
 *   scenario's road.
 * - Checks: a message without a host id or whose host is no moving object is no_host; a host
 *   with a NaN or absurd (|x| > 1e5 m, size <= 0 or > 100 m) value is bad_value; such an object
 *   is counted as object_bad_value and left out.
 *
 * Thread-safety: hl_osi_world_new() and _cast() from one thread; afterwards hl_osi_world_map()
 * is a pure function of read-only data (any thread) and allocates nothing.
 */
#ifndef HL_WORLD_OSI_WORLD_H
#define HL_WORLD_OSI_WORLD_H

#include <stddef.h>
#include <stdint.h>

#include "world/osi_msg.h"
#include "world/scenario.h"
#include "world/world.h"

#define HL_OSI_MAX_COORD_M 1e5 /* |x|, |y|, |z| of a sane position */
#define HL_OSI_MAX_SIZE_M 100.0 /* a body's length, width, height */
#define HL_OSI_MAX_JUMP_S 1.0 /* a step in time beyond this is counted as time_jump */

/* What became of a message, a datagram or an object: each counted by reason. */
enum hl_osi_reason {
	HL_OSI_OK,
	HL_OSI_MALFORMED, /* not a valid serialized message */
	HL_OSI_TOO_MANY, /* more objects, boundaries or points than we hold */
	HL_OSI_NO_HOST, /* no host_vehicle_id, or no moving object with it */
	HL_OSI_BAD_VALUE, /* the host's position, orientation or size NaN or absurd */
	HL_OSI_NO_TIMESTAMP, /* no timestamp */
	HL_OSI_NO_ROAD, /* live, before the road: no lane boundaries (and no base scenario) */
	HL_OSI_PAST, /* not after the last good message's timestamp: dropped */
	HL_OSI_TIME_JUMP, /* over HL_OSI_MAX_JUMP_S after the last: taken, counted */
	HL_OSI_TRUNCATED, /* a trace ends in the middle of a message */
	HL_OSI_BAD_FRAMING, /* a UDP part lost, repeated, out of order or with a bad header */
	HL_OSI_TOO_LARGE, /* a datagram or message over the limit */
	HL_OSI_UNKNOWN_TYPE, /* an object: a type we do not map; left out */
	HL_OSI_OBJECT_BAD_VALUE, /* an object with a NaN or absurd value; left out */
	HL_OSI_NEW_OBJECT, /* an object the live source did not cast; left out */
	HL_OSI_REASONS
};

/* "ok", "malformed", ...: the reason's label in /metrics, /status and logs. */
const char *hl_osi_reason_name(enum hl_osi_reason r);

struct hl_osi_world;

/*
 * The scenario of a source whose first good message is first: road, cast, ego lamps and camera
 * (from base if not NULL, else a scenario file's defaults). base's road serves when first has
 * no lane boundaries. 0, -EINVAL (no usable host: why says why), -ENOENT (no road: neither
 * lane boundaries nor base), -EBADMSG (lane boundaries that make no road: why), -ENOMEM.
 */
int hl_osi_world_new(const struct hl_osi_frame *first, const struct hl_scenario *base,
		     struct hl_osi_world **ret, char *why, size_t why_size);
void hl_osi_world_free(struct hl_osi_world *w);

/* Casts f's objects not cast yet (a trace's other messages); over the slots: counted. */
void hl_osi_world_cast(struct hl_osi_world *w, const struct hl_osi_frame *f,
		       uint64_t counts[HL_OSI_REASONS]);

/* The scenario (owned by w until taken: then the caller's, hl_scenario_free()). */
const struct hl_scenario *hl_osi_world_scenario(const struct hl_osi_world *w);
struct hl_scenario *hl_osi_world_take_scenario(struct hl_osi_world *w);

/*
 * f as the world state at scenario time t_s. Returns HL_OSI_OK, HL_OSI_NO_HOST or
 * HL_OSI_BAD_VALUE (then *ret is untouched and why says what); per-object reasons are added to
 * counts (may be NULL).
 */
enum hl_osi_reason hl_osi_world_map(const struct hl_osi_world *w, const struct hl_osi_frame *f,
				    double t_s, struct hl_world_state *ret,
				    uint64_t counts[HL_OSI_REASONS], char *why, size_t why_size);

/* The inverse for a writer: a body pose and size as OSI's centre position and yaw. */
void hl_osi_pose_to_centre(const struct hl_body_pose *pose, const double size_m[3],
			   double ret_pos_m[3], double *ret_yaw_rad);

#endif
