/* SPDX-License-Identifier: MIT */
/*
 * ASAM OSI messages (docs/osi.md): one serialized osi3::GroundTruth or osi3::SensorView decoded
 * into plain C, the few fields hdlamp reads, and the same encoded again (hdlamp scenario osi,
 * tests). The wire format is our own osi.proto (world/osi.proto): OSI 3.x's package, message
 * names and field numbers for the fields we use, so a message of any OSI producer decodes; the
 * fields we do not declare are skipped by protobuf's rules.
 *
 * Values are OSI's, unconverted: metres, radians, the world frame of the producer (x, y, z right
 * handed, z up), positions of the bounding box's centre. Enumerations keep OSI's numbers. Which
 * world state this makes is world/osi_world.h's.
 *
 * Thread-safety: a frame is one thread's; the functions are reentrant. hl_osi_decode() fills a
 * frame made by hl_osi_frame_new() and allocates only inside protobuf-c's unpacking (freed
 * before it returns).
 */
#ifndef HL_WORLD_OSI_MSG_H
#define HL_WORLD_OSI_MSG_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define HL_OSI_MAX_OBJECTS 256 /* moving objects in one message */
#define HL_OSI_MAX_BOUNDARIES 128 /* lane boundaries in one message */
#define HL_OSI_MAX_POINTS 16384 /* boundary points in one message, all boundaries */

/* The OSI release whose field numbers world/osi.proto follows; hl_osi_encode() writes it. */
#define HL_OSI_VERSION_MAJOR 3
#define HL_OSI_VERSION_MINOR 7
#define HL_OSI_VERSION_PATCH 0

/* Which message a buffer holds (the wire format does not say; the source does). */
enum hl_osi_kind { HL_OSI_GROUND_TRUTH, HL_OSI_SENSOR_VIEW };

/* osi3::MovingObject::Type (osi_object.proto), OSI's numbers. */
enum hl_osi_object_type {
	HL_OSI_TYPE_UNKNOWN = 0,
	HL_OSI_TYPE_OTHER = 1,
	HL_OSI_TYPE_VEHICLE = 2,
	HL_OSI_TYPE_PEDESTRIAN = 3,
	HL_OSI_TYPE_ANIMAL = 4,
};

/* osi3::MovingObject::VehicleClassification::Type, OSI's numbers (the ones we map). */
enum hl_osi_vehicle_type {
	HL_OSI_VEHICLE_UNKNOWN = 0,
	HL_OSI_VEHICLE_OTHER = 1,
	HL_OSI_VEHICLE_SMALL_CAR = 2,
	HL_OSI_VEHICLE_COMPACT_CAR = 3,
	HL_OSI_VEHICLE_MEDIUM_CAR = 4, /* OSI 3.7.0 also names it TYPE_CAR */
	HL_OSI_VEHICLE_LUXURY_CAR = 5,
	HL_OSI_VEHICLE_DELIVERY_VAN = 6,
	HL_OSI_VEHICLE_HEAVY_TRUCK = 7,
	HL_OSI_VEHICLE_SEMITRAILER = 8,
	HL_OSI_VEHICLE_TRAILER = 9,
	HL_OSI_VEHICLE_MOTORBIKE = 10,
	HL_OSI_VEHICLE_BICYCLE = 11,
	HL_OSI_VEHICLE_BUS = 12,
	HL_OSI_VEHICLE_TRAM = 13,
	HL_OSI_VEHICLE_TRAIN = 14,
	HL_OSI_VEHICLE_WHEELCHAIR = 15,
	/* 16 and above: later OSI versions' additions (3.7.0: 16 semitractor, 17 stand-up
	   scooter; more after it) */
};

/* osi3::MovingObject::VehicleClassification::LightState::GenericLightState. */
enum hl_osi_light {
	HL_OSI_LIGHT_UNKNOWN = 0,
	HL_OSI_LIGHT_OTHER = 1,
	HL_OSI_LIGHT_OFF = 2,
	HL_OSI_LIGHT_ON = 3,
	/* 4..: flashing states */
};

/* osi3::LaneBoundary::Classification::Type (osi_lane.proto), OSI's numbers. */
enum hl_osi_boundary_type {
	HL_OSI_BOUNDARY_UNKNOWN = 0,
	HL_OSI_BOUNDARY_OTHER = 1,
	HL_OSI_BOUNDARY_NO_LINE = 2,
	HL_OSI_BOUNDARY_SOLID_LINE = 3,
	HL_OSI_BOUNDARY_DASHED_LINE = 4,
	HL_OSI_BOUNDARY_BOTTS_DOTS = 5,
	HL_OSI_BOUNDARY_ROAD_EDGE = 6,
	HL_OSI_BOUNDARY_SNOW_EDGE = 7,
	HL_OSI_BOUNDARY_GRASS_EDGE = 8,
	HL_OSI_BOUNDARY_GRAVEL_EDGE = 9,
	HL_OSI_BOUNDARY_SOIL_EDGE = 10,
	HL_OSI_BOUNDARY_GUARD_RAIL = 11,
	HL_OSI_BOUNDARY_CURB = 12,
	HL_OSI_BOUNDARY_STRUCTURE = 13,
	HL_OSI_BOUNDARY_BARRIER = 14,
	HL_OSI_BOUNDARY_SOUND_BARRIER = 15,
};

/*
 * One moving object. A field the message lacks is NAN (numbers) or 0 (OSI's UNKNOWN for
 * enumerations); has_* say whether a sub-message was there at all.
 */
struct hl_osi_object {
	uint64_t id; /* MovingObject.id.value */
	bool has_id;
	int type; /* enum hl_osi_object_type or another number of a later OSI */
	bool has_classification; /* vehicle_classification present */
	int vehicle_type; /* enum hl_osi_vehicle_type or another number */
	int head_light; /* light_state.head_light: enum hl_osi_light */
	int high_beam; /* light_state.high_beam */
	int brake_light; /* light_state.brake_light_state (OSI's BrakeLightState numbers) */
	int tail_light; /* light_state.tail_light, the rear position light: enum hl_osi_light
			   (OSI 3.8.0-rc1 on; 0 from an older producer) */
	double dim_m[3]; /* base.dimension: length, width, height */
	double pos_m[3]; /* base.position: the bounding box's centre */
	double rpy_rad[3]; /* base.orientation: roll, pitch, yaw */
	double vel_mps[3]; /* base.velocity */
};

/* One lane boundary: its points are frame->point[first .. first + n - 1]. */
struct hl_osi_boundary {
	uint64_t id;
	int type; /* classification.type: enum hl_osi_boundary_type or another number */
	int first, n;
};

struct hl_osi_frame {
	enum hl_osi_kind kind; /* what was decoded */
	bool has_version;
	unsigned version[3]; /* version: the sender's OSI major, minor, patch */
	bool has_timestamp;
	int64_t t_ns; /* timestamp: seconds * 1e9 + nanos (SensorView: its own, else the ground
			 truth's) */
	bool has_host;
	uint64_t host_id; /* GroundTruth.host_vehicle_id (SensorView: its own, else the ground
			     truth's) */
	int n_objects;
	struct hl_osi_object object[HL_OSI_MAX_OBJECTS];
	int n_boundaries;
	struct hl_osi_boundary boundary[HL_OSI_MAX_BOUNDARIES];
	int n_points;
	double point[HL_OSI_MAX_POINTS][3]; /* boundary_line[].position, metres */
	double point_width_m[HL_OSI_MAX_POINTS]; /* boundary_line[].width; NAN if absent */
};

/* What became of a buffer. */
enum hl_osi_decode_result {
	HL_OSI_DECODE_OK,
	HL_OSI_DECODE_MALFORMED, /* not a valid serialized message of the kind */
	HL_OSI_DECODE_TOO_MANY, /* more objects, boundaries or points than the limits above */
};

/* A frame (about 650 kB: make it once, reuse it); NULL without memory. */
struct hl_osi_frame *hl_osi_frame_new(void);
void hl_osi_frame_free(struct hl_osi_frame *f);

/*
 * Decodes buf (len bytes) as a message of kind into *ret (overwritten whole). why (may be
 * NULL) says what is wrong. Unknown fields are skipped; nothing is checked beyond the wire
 * format, the limits and a timestamp that int64 nanoseconds cannot hold (MALFORMED): NaN,
 * absurd values and a missing host are the world's to judge. A SensorView's objects and
 * boundaries are those of its global_ground_truth.
 */
enum hl_osi_decode_result hl_osi_decode(const uint8_t *buf, size_t len, enum hl_osi_kind kind,
					struct hl_osi_frame *ret, char *why, size_t why_size);

/*
 * Encodes f as a message of kind (f->kind is ignored) into a new buffer *ret_buf (the
 * caller's, free()) of *ret_len bytes. Writes the fields above that are set (not NAN, not 0
 * for the enumerations; the sub-messages of has_*), the interface version HL_OSI_VERSION_*
 * (f->version is ignored), and nothing else; a SensorView carries the timestamp, host and
 * version both itself and in its global_ground_truth. 0, -EINVAL (counts beyond the limits, a
 * boundary's points outside f->point) or -ENOMEM.
 */
int hl_osi_encode(const struct hl_osi_frame *f, enum hl_osi_kind kind, uint8_t **ret_buf,
		  size_t *ret_len);

/* "ground-truth" / "sensor-view"; from a name: 0, or -EINVAL. */
const char *hl_osi_kind_name(enum hl_osi_kind k);
int hl_osi_kind_parse(const char *name, enum hl_osi_kind *ret);

#endif
