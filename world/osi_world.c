/* SPDX-License-Identifier: MIT */
/* ASAM OSI ground truth as hdlamp's world: see world/osi_world.h. */
#include "world/osi_world.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "world/osi_road.h"

#define DEG (M_PI / 180.0)
#define LIVE_DURATION_S 3600.0 /* a live source's scenario: as long as a scenario may be */

/* A scenario with nothing but the file format's defaults: the ego's lamps and camera. */
static const char template_json[] =
	"{\"version\": 1, \"title\": \"ASAM OSI\", \"duration_s\": 1,"
	" \"road\": {\"segments\": [{\"kind\": \"straight\", \"length_m\": 100}]}}";

struct hl_osi_world {
	struct hl_scenario *sc;
	uint64_t host_id;
	uint64_t id[HL_SCN_MAX_ACTORS]; /* the OSI id of each cast road user */
};

static const char *const reason_names[HL_OSI_REASONS] = {
	[HL_OSI_OK] = "ok",
	[HL_OSI_MALFORMED] = "malformed",
	[HL_OSI_TOO_MANY] = "too_many",
	[HL_OSI_NO_HOST] = "no_host",
	[HL_OSI_BAD_VALUE] = "bad_value",
	[HL_OSI_NO_TIMESTAMP] = "no_timestamp",
	[HL_OSI_NO_ROAD] = "no_road",
	[HL_OSI_PAST] = "past",
	[HL_OSI_TIME_JUMP] = "time_jump",
	[HL_OSI_TRUNCATED] = "truncated",
	[HL_OSI_BAD_FRAMING] = "bad_framing",
	[HL_OSI_TOO_LARGE] = "too_large",
	[HL_OSI_UNKNOWN_TYPE] = "unknown_type",
	[HL_OSI_OBJECT_BAD_VALUE] = "object_bad_value",
	[HL_OSI_NEW_OBJECT] = "new_object",
};

const char *hl_osi_reason_name(enum hl_osi_reason r)
{
	return (unsigned)r < HL_OSI_REASONS ? reason_names[r] : "?";
}

static enum hl_osi_reason fail(enum hl_osi_reason r, char *why, size_t size, const char *fmt, ...)
{
	va_list ap;

	if (why && size) {
		va_start(ap, fmt);
		vsnprintf(why, size, fmt, ap);
		va_end(ap);
	}
	return r;
}

/* The kind of an object, or -1 for a type we do not map. */
static int kind_of(const struct hl_osi_object *o)
{
	if (o->type == HL_OSI_TYPE_PEDESTRIAN)
		return HL_ACTOR_PEDESTRIAN;
	if (o->type != HL_OSI_TYPE_VEHICLE)
		return -1;
	if (!o->has_classification)
		return HL_ACTOR_CAR;
	switch (o->vehicle_type) {
	case HL_OSI_VEHICLE_UNKNOWN:
	case HL_OSI_VEHICLE_OTHER:
	case HL_OSI_VEHICLE_SMALL_CAR:
	case HL_OSI_VEHICLE_COMPACT_CAR:
	case HL_OSI_VEHICLE_MEDIUM_CAR:
	case HL_OSI_VEHICLE_LUXURY_CAR:
	case HL_OSI_VEHICLE_DELIVERY_VAN:
		return HL_ACTOR_CAR;
	case HL_OSI_VEHICLE_HEAVY_TRUCK:
	case HL_OSI_VEHICLE_SEMITRAILER:
	case HL_OSI_VEHICLE_TRAILER:
	case HL_OSI_VEHICLE_BUS:
	case HL_OSI_VEHICLE_TRAM:
	case HL_OSI_VEHICLE_TRAIN:
	case 16: /* SEMITRACTOR */
		return HL_ACTOR_TRUCK;
	case HL_OSI_VEHICLE_MOTORBIKE:
		return HL_ACTOR_MOTORBIKE;
	case HL_OSI_VEHICLE_BICYCLE:
		return HL_ACTOR_CYCLIST;
	case HL_OSI_VEHICLE_WHEELCHAIR:
		return HL_ACTOR_PEDESTRIAN;
	default:
		return -1;
	}
}

static bool sane_coord(double v)
{
	return isfinite(v) && fabs(v) <= HL_OSI_MAX_COORD_M;
}

/* Whether an object's pose and size are usable; what is wrong into why. */
static bool sane(const struct hl_osi_object *o, char *why, size_t size)
{
	static const char *const axis[3] = { "x", "y", "z" };
	static const char *const dim[3] = { "length", "width", "height" };

	for (int k = 0; k < 3; k++) {
		if (!sane_coord(o->pos_m[k])) {
			fail(HL_OSI_BAD_VALUE, why, size,
			     "object %" PRIu64 ": base.position.%s %g: expected a number within "
			     "+-%g m",
			     o->id, axis[k], o->pos_m[k], HL_OSI_MAX_COORD_M);
			return false;
		}
		if (!(o->dim_m[k] > 0.0 && o->dim_m[k] <= HL_OSI_MAX_SIZE_M)) {
			fail(HL_OSI_BAD_VALUE, why, size,
			     "object %" PRIu64 ": base.dimension.%s %g: expected 0 < %s <= %g m",
			     o->id, dim[k], o->dim_m[k], dim[k], HL_OSI_MAX_SIZE_M);
			return false;
		}
	}
	if (!isfinite(o->rpy_rad[2])) {
		fail(HL_OSI_BAD_VALUE, why, size,
		     "object %" PRIu64 ": base.orientation.yaw %g: expected a number (rad)", o->id,
		     o->rpy_rad[2]);
		return false;
	}
	return true;
}

static void pose_of(const struct hl_osi_object *o, struct hl_body_pose *ret)
{
	const double yaw = remainder(o->rpy_rad[2], 2 * M_PI), half = o->dim_m[0] / 2;
	const double vx = isfinite(o->vel_mps[0]) ? o->vel_mps[0] : 0.0;
	const double vy = isfinite(o->vel_mps[1]) ? o->vel_mps[1] : 0.0;

	*ret = (struct hl_body_pose){ .pos_m = { o->pos_m[0] + half * cos(yaw),
						 o->pos_m[1] + half * sin(yaw), 0.0 },
				      .heading_rad = yaw,
				      .s_m = NAN,
				      .speed_mps = hypot(vx, vy) };
}

void hl_osi_pose_to_centre(const struct hl_body_pose *pose, const double size_m[3],
			   double ret_pos_m[3], double *ret_yaw_rad)
{
	const double half = size_m[0] / 2;

	ret_pos_m[0] = pose->pos_m[0] - half * cos(pose->heading_rad);
	ret_pos_m[1] = pose->pos_m[1] - half * sin(pose->heading_rad);
	ret_pos_m[2] = pose->pos_m[2] + size_m[2] / 2;
	*ret_yaw_rad = pose->heading_rad;
}

static const struct hl_osi_object *find(const struct hl_osi_frame *f, uint64_t id)
{
	for (int i = 0; i < f->n_objects; i++)
		if (f->object[i].has_id && f->object[i].id == id)
			return &f->object[i];
	return NULL;
}

static int slot_of(const struct hl_osi_world *w, uint64_t id)
{
	for (int i = 0; i < w->sc->n_actors; i++)
		if (w->id[i] == id)
			return i;
	return -1;
}

/* The host of f, checked. */
static enum hl_osi_reason host_of(const struct hl_osi_frame *f, const struct hl_osi_object **ret,
				  char *why, size_t size)
{
	const struct hl_osi_object *h;

	if (!f->has_host)
		return fail(HL_OSI_NO_HOST, why, size,
			    "no host_vehicle_id: expected the ego vehicle's id");
	h = find(f, f->host_id);
	if (!h)
		return fail(HL_OSI_NO_HOST, why, size,
			    "host_vehicle_id %" PRIu64 " is none of the %d moving objects",
			    f->host_id, f->n_objects);
	if (!sane(h, why, size))
		return HL_OSI_BAD_VALUE;
	*ret = h;
	return HL_OSI_OK;
}

static enum hl_actor_role role_of(int kind, const struct hl_osi_object *o,
				  const struct hl_osi_object *host)
{
	const double c = cos(o->rpy_rad[2] - host->rpy_rad[2]);

	if (kind == HL_ACTOR_PEDESTRIAN)
		return HL_ROLE_ROADSIDE;
	if (c <= -cos(45 * DEG))
		return HL_ROLE_ONCOMING;
	if (c >= cos(45 * DEG))
		return HL_ROLE_PRECEDING;
	return HL_ROLE_CROSSING;
}

static void cast(struct hl_osi_world *w, const struct hl_osi_frame *f,
		 const struct hl_osi_object *host, uint64_t counts[HL_OSI_REASONS])
{
	struct hl_scenario *sc = w->sc;

	for (int i = 0; i < f->n_objects; i++) {
		const struct hl_osi_object *o = &f->object[i];
		char id[HL_SCN_ID_MAX];
		int kind;

		if (!o->has_id || o->id == w->host_id || slot_of(w, o->id) >= 0)
			continue;
		kind = kind_of(o);
		if (kind < 0 || !sane(o, NULL, 0))
			continue; /* counted by hl_osi_world_map() in every message it is in */
		if (sc->n_actors == HL_SCN_MAX_ACTORS) {
			if (counts)
				counts[HL_OSI_NEW_OBJECT]++;
			continue;
		}
		snprintf(id, sizeof(id), "osi-%" PRIu64, o->id);
		hl_actor_init(&sc->actor[sc->n_actors], id, (enum hl_actor_kind)kind,
			      role_of(kind, o, host), o->dim_m);
		w->id[sc->n_actors++] = o->id;
	}
}

int hl_osi_world_new(const struct hl_osi_frame *first, const struct hl_scenario *base,
		     struct hl_osi_world **ret, char *why, size_t why_size)
{
	const struct hl_osi_object *host = NULL;
	struct hl_body_pose ego;
	struct hl_osi_world *w;
	int rc;

	if (host_of(first, &host, why, why_size) != HL_OSI_OK)
		return -EINVAL;
	if (!first->n_boundaries && !base) {
		fail(HL_OSI_OK, why, why_size,
		     "no lane boundaries in the first message and no scenario for the road: "
		     "expected GroundTruth.lane_boundary, or a --scenario");
		return -ENOENT;
	}
	w = calloc(1, sizeof(*w));
	if (!w)
		return -ENOMEM;
	if (base) {
		w->sc = malloc(sizeof(*w->sc));
		if (!w->sc) {
			rc = -ENOMEM;
			goto err_free;
		}
		*w->sc = *base;
		w->sc->track = NULL;
	} else {
		rc = hl_scenario_parse(template_json, "(OSI template)", &w->sc, NULL);
		if (rc < 0)
			goto err_free;
	}
	snprintf(w->sc->title, sizeof(w->sc->title), "ASAM OSI");
	w->sc->duration_s = LIVE_DURATION_S;
	w->sc->n_actors = 0;
	w->host_id = host->id;
	pose_of(host, &ego);
	if (first->n_boundaries) {
		rc = hl_osi_road(first, ego.pos_m[0], ego.pos_m[1], ego.heading_rad, &w->sc->road,
				 why, why_size);
		if (rc < 0) {
			rc = rc == -ENOMEM ? rc : -EBADMSG;
			goto err_free;
		}
	}
	w->sc->ego.path = (struct hl_path){ .kind = HL_PATH_WAYPOINTS, .n_waypoints = 1 };
	w->sc->ego.path.speed.n = 1;
	hl_speed_layout(&w->sc->ego.path.speed);
	hl_waypoints_layout(&w->sc->ego.path, 0.0);
	cast(w, first, host, NULL);
	*ret = w;
	return 0;
err_free:
	hl_osi_world_free(w);
	return rc;
}

void hl_osi_world_free(struct hl_osi_world *w)
{
	if (!w)
		return;
	hl_scenario_free(w->sc);
	free(w);
}

void hl_osi_world_cast(struct hl_osi_world *w, const struct hl_osi_frame *f,
		       uint64_t counts[HL_OSI_REASONS])
{
	const struct hl_osi_object *host = NULL;

	if (host_of(f, &host, NULL, 0) == HL_OSI_OK && host->id == w->host_id)
		cast(w, f, host, counts);
}

const struct hl_scenario *hl_osi_world_scenario(const struct hl_osi_world *w)
{
	return w->sc;
}

struct hl_scenario *hl_osi_world_take_scenario(struct hl_osi_world *w)
{
	struct hl_scenario *sc = w->sc;

	w->sc = NULL;
	return sc;
}

enum hl_osi_reason hl_osi_world_map(const struct hl_osi_world *w, const struct hl_osi_frame *f,
				    double t_s, struct hl_world_state *ret,
				    uint64_t counts[HL_OSI_REASONS], char *why, size_t why_size)
{
	const struct hl_scenario *sc = w->sc;
	const struct hl_osi_object *host = NULL;
	enum hl_osi_reason r = host_of(f, &host, why, why_size);
	struct hl_world_state st = { .t_s = t_s, .n_actors = sc->n_actors };

	if (r != HL_OSI_OK)
		return r;
	if (host->id != w->host_id)
		return fail(HL_OSI_NO_HOST, why, why_size,
			    "host_vehicle_id %" PRIu64 ": the source's ego is %" PRIu64, host->id,
			    w->host_id);
	pose_of(host, &st.ego);
	for (int i = 0; i < f->n_objects; i++) {
		const struct hl_osi_object *o = &f->object[i];
		int k;

		if (o == host)
			continue;
		if (!o->has_id || kind_of(o) < 0) {
			if (counts)
				counts[HL_OSI_UNKNOWN_TYPE]++;
			continue;
		}
		if (!sane(o, NULL, 0)) {
			if (counts)
				counts[HL_OSI_OBJECT_BAD_VALUE]++;
			continue;
		}
		k = slot_of(w, o->id);
		if (k < 0) {
			if (counts)
				counts[HL_OSI_NEW_OBJECT]++;
			continue;
		}
		pose_of(o, &st.actor[k]);
		st.present |= 1u << k;
		if (!(o->has_classification && o->head_light == HL_OSI_LIGHT_OFF))
			st.lamps_on |= 1u << k;
	}
	/* Road users not in this message: where they were cast, absent. */
	for (int k = 0; k < sc->n_actors; k++)
		if (!(st.present >> k & 1u))
			st.actor[k] = (struct hl_body_pose){ .s_m = NAN };
	*ret = st;
	return HL_OSI_OK;
}
