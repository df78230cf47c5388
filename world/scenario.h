/* SPDX-License-Identifier: MIT */
/*
 * A scenario (docs/scenarios.md): a road of straight and arc segments (or one polyline) with
 * lanes and posts, the ego vehicle's path, speed, lamps and camera, other road users with paths,
 * bodies, lamps and eye points, and a duration. Read from JSON with jansson and checked strictly: an unknown key,
 * a wrong type, a value out of range, waypoints not strictly increasing in time or a road that
 * does not connect is refused with the file, line, column and key path.
 *
 * Frames (docs/design.md §4): world x, y horizontal and z up (metres), the road starting at
 * road.start heading road.start.heading_deg (0: along +x); a vehicle's or road user's own frame
 * is ISO 8855 (x forward, y left, z up) with its origin on the ground below the centre of its
 * front face. Headings in radians here, degrees in files. Road coordinates: s along the road's
 * centre line (m), lateral offset d positive to the left looking toward increasing s. Lanes are
 * numbered 1.. from the right edge; the ego drives toward increasing s (right-hand traffic).
 *
 * The road and the paths along it are world/road.h's; where everything is at a time, world/world.h's.
 *
 * Thread-safety: a scenario is built by one thread and read-only afterwards.
 */
#ifndef HL_WORLD_SCENARIO_H
#define HL_WORLD_SCENARIO_H

#include <stddef.h>

#include "world/camera.h"
#include "world/road.h"
#include "world/state.h"
#include "base/json_check.h"

#define HL_SCN_MAX_LAMPS 8 /* a road user's emitters */
#define HL_SCN_ID_MAX 48
#define HL_SCN_TEXT_MAX 256

enum hl_actor_kind {
	HL_ACTOR_CAR,
	HL_ACTOR_PEDESTRIAN,
	HL_ACTOR_CYCLIST,
	HL_ACTOR_TRUCK,
	HL_ACTOR_MOTORBIKE,
	HL_ACTOR_KINDS
};
enum hl_actor_role { HL_ROLE_ONCOMING, HL_ROLE_PRECEDING, HL_ROLE_CROSSING, HL_ROLE_ROADSIDE };
enum hl_emitter_kind { HL_EMITTER_HEADLAMP, HL_EMITTER_TAIL };

/* A road user's lamp seen as a point emitter: a headlamp shines forward, a tail lamp back. */
struct hl_emitter {
	enum hl_emitter_kind kind;
	double pos_m[3]; /* the road user's frame */
	double intensity_cd; /* toward the viewer, uniform over the half space it faces */
	double rgb[3]; /* linear colour, max component 1 */
};

struct hl_actor {
	char id[HL_SCN_ID_MAX];
	enum hl_actor_kind kind;
	enum hl_actor_role role;
	struct hl_path path;
	double size_m[3]; /* body box: length (behind the origin), width, height */
	double reflectance;
	int n_lamps;
	struct hl_emitter lamp[HL_SCN_MAX_LAMPS];
	double eye_m[3]; /* the driver's (a pedestrian's, a cyclist's) eye, its own frame */
	int line;
};

struct hl_ego {
	struct hl_path path; /* a lane path toward increasing s */
	struct hl_lamp_pose lamp[2]; /* left, right; vehicle frame */
	struct hl_camera camera; /* the driver's camera, vehicle frame (width/height 0) */
};

struct hl_world_track;

struct hl_scenario {
	char title[HL_SCN_TEXT_MAX];
	double duration_s;
	struct hl_road road;
	struct hl_ego ego;
	int n_actors;
	struct hl_actor actor[HL_SCN_MAX_ACTORS];
	/* A recording's poses (world/track.h, e.g. an OSI trace), owned; NULL: the paths'. */
	struct hl_world_track *track;
};

/*
 * Reads and checks one file. 0, -errno (cannot open), -EBADMSG (malformed JSON or a fault the
 * error names), -ENOMEM. *ret is the caller's, freed with hl_scenario_free(). err (may be
 * NULL) says where: file, line, column, key path, what was expected (hl_json_error_format()
 * writes it as "FILE:LINE:COL: KEY: MESSAGE").
 */
int hl_scenario_read(const char *path, struct hl_scenario **ret, struct hl_json_error *err);
/* The same from text; name stands for the file in the error. */
int hl_scenario_parse(const char *text, const char *name, struct hl_scenario **ret,
		      struct hl_json_error *err);
void hl_scenario_free(struct hl_scenario *sc);

/*
 * The shipped scenarios' directory: hl_share_dir("scenarios") (base/share_dir.h), e.g.
 * /usr/bin/hdlamp -> /usr/share/hdlamp/scenarios. 0 or -errno.
 */
int hl_scenario_default_dir(char *buf, size_t size);

const char *hl_actor_kind_name(enum hl_actor_kind kind);
/*
 * A road user of kind with the kind's defaults (docs/scenarios.md): body (size_m NULL: the
 * kind's), reflectance, eye point, lamps; path standing still at the origin.
 */
void hl_actor_init(struct hl_actor *a, const char *id, enum hl_actor_kind kind,
		   enum hl_actor_role role, const double size_m[3]);
const char *hl_actor_role_name(enum hl_actor_role role);

#endif
