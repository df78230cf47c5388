/* SPDX-License-Identifier: MIT */
/*
 * OSI messages to and from plain C through protobuf-c's code for world/osi.proto (generated in
 * the build tree; only this file includes it). Decoding unpacks with protobuf-c's default
 * allocator, copies what the frame holds and frees the unpacked tree before returning. Encoding
 * builds the message tree in a few arrays made for the call, packs it and frees them.
 */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "osi.pb-c.h"
#include "world/osi_msg.h"

#define NS_PER_S 1000000000LL

struct hl_osi_frame *hl_osi_frame_new(void)
{
	return calloc(1, sizeof(struct hl_osi_frame));
}

void hl_osi_frame_free(struct hl_osi_frame *f)
{
	free(f);
}

const char *hl_osi_kind_name(enum hl_osi_kind k)
{
	return k == HL_OSI_SENSOR_VIEW ? "sensor-view" : "ground-truth";
}

int hl_osi_kind_parse(const char *name, enum hl_osi_kind *ret)
{
	if (!name)
		return -EINVAL;
	if (strcmp(name, "ground-truth") == 0)
		*ret = HL_OSI_GROUND_TRUTH;
	else if (strcmp(name, "sensor-view") == 0)
		*ret = HL_OSI_SENSOR_VIEW;
	else
		return -EINVAL;
	return 0;
}

static void say(char *why, size_t why_size, const char *fmt, ...)
{
	va_list ap;

	if (!why || why_size == 0)
		return;
	va_start(ap, fmt);
	vsnprintf(why, why_size, fmt, ap);
	va_end(ap);
}

/* ---- decoding ---- */

static double num(protobuf_c_boolean has, double v)
{
	return has ? v : NAN;
}

static void vec(const Osi3__Vector3d *v, double out[3])
{
	out[0] = v ? num(v->has_x, v->x) : NAN;
	out[1] = v ? num(v->has_y, v->y) : NAN;
	out[2] = v ? num(v->has_z, v->z) : NAN;
}

static void object_from(const Osi3__MovingObject *m, struct hl_osi_object *o)
{
	const Osi3__BaseMoving *b = m->base_moving;
	const Osi3__Dimension3d *d = b ? b->dimension : NULL;
	const Osi3__Orientation3d *r = b ? b->orientation : NULL;
	const Osi3__MovingObject__VehicleClassification *c = m->vehicle_classification;
	const Osi3__MovingObject__VehicleClassification__LightState *l = c ? c->light_state : NULL;

	memset(o, 0, sizeof(*o));
	o->has_id = m->id != NULL;
	o->id = m->id && m->id->has_value ? m->id->value : 0;
	o->type = m->has_type ? (int)m->type : 0;
	o->has_classification = c != NULL;
	o->vehicle_type = c && c->has_type ? (int)c->type : 0;
	o->head_light = l && l->has_head_light ? (int)l->head_light : 0;
	o->high_beam = l && l->has_high_beam ? (int)l->high_beam : 0;
	o->brake_light = l && l->has_brake_light_state ? (int)l->brake_light_state : 0;
	o->tail_light = l && l->has_tail_light ? (int)l->tail_light : 0;
	o->dim_m[0] = d ? num(d->has_length, d->length) : NAN;
	o->dim_m[1] = d ? num(d->has_width, d->width) : NAN;
	o->dim_m[2] = d ? num(d->has_height, d->height) : NAN;
	vec(b ? b->position : NULL, o->pos_m);
	o->rpy_rad[0] = r ? num(r->has_roll, r->roll) : NAN;
	o->rpy_rad[1] = r ? num(r->has_pitch, r->pitch) : NAN;
	o->rpy_rad[2] = r ? num(r->has_yaw, r->yaw) : NAN;
	vec(b ? b->velocity : NULL, o->vel_mps);
}

static bool id_from(const Osi3__Identifier *id, uint64_t *ret)
{
	if (!id)
		return false;
	*ret = id->has_value ? id->value : 0;
	return true;
}

/* The timestamp as int64 nanoseconds; false if they cannot hold it. */
static bool time_from(const Osi3__Timestamp *t, int64_t *ret)
{
	int64_t s = t->has_seconds ? t->seconds : 0, ns;

	if (__builtin_mul_overflow(s, NS_PER_S, &ns) ||
	    __builtin_add_overflow(ns, (int64_t)(t->has_nanos ? t->nanos : 0), &ns))
		return false;
	*ret = ns;
	return true;
}

/* The ground truth's objects and boundaries (g may be NULL: an empty world). */
static enum hl_osi_decode_result world_from(const Osi3__GroundTruth *g, struct hl_osi_frame *f,
					    char *why, size_t why_size)
{
	size_t points = 0;

	if (!g)
		return HL_OSI_DECODE_OK;
	if (g->n_moving_object > HL_OSI_MAX_OBJECTS) {
		say(why, why_size, "%zu moving objects, more than %d", g->n_moving_object,
		    HL_OSI_MAX_OBJECTS);
		return HL_OSI_DECODE_TOO_MANY;
	}
	if (g->n_lane_boundary > HL_OSI_MAX_BOUNDARIES) {
		say(why, why_size, "%zu lane boundaries, more than %d", g->n_lane_boundary,
		    HL_OSI_MAX_BOUNDARIES);
		return HL_OSI_DECODE_TOO_MANY;
	}
	for (size_t i = 0; i < g->n_lane_boundary; i++)
		points += g->lane_boundary[i]->n_boundary_line;
	if (points > HL_OSI_MAX_POINTS) {
		say(why, why_size, "%zu lane boundary points, more than %d", points,
		    HL_OSI_MAX_POINTS);
		return HL_OSI_DECODE_TOO_MANY;
	}
	for (size_t i = 0; i < g->n_moving_object; i++)
		object_from(g->moving_object[i], &f->object[f->n_objects++]);
	for (size_t i = 0; i < g->n_lane_boundary; i++) {
		const Osi3__LaneBoundary *lb = g->lane_boundary[i];
		struct hl_osi_boundary *b = &f->boundary[f->n_boundaries++];

		b->id = 0;
		id_from(lb->id, &b->id);
		b->type = lb->classification && lb->classification->has_type ?
				  (int)lb->classification->type :
				  0;
		b->first = f->n_points;
		b->n = (int)lb->n_boundary_line;
		for (size_t k = 0; k < lb->n_boundary_line; k++) {
			const Osi3__LaneBoundary__BoundaryPoint *p = lb->boundary_line[k];

			vec(p->position, f->point[f->n_points]);
			f->point_width_m[f->n_points] = num(p->has_width, p->width);
			f->n_points++;
		}
	}
	return HL_OSI_DECODE_OK;
}

static enum hl_osi_decode_result header_from(const Osi3__InterfaceVersion *v,
					     const Osi3__Timestamp *t, struct hl_osi_frame *f,
					     char *why, size_t why_size)
{
	if (v && !f->has_version) {
		f->has_version = true;
		f->version[0] = v->has_version_major ? v->version_major : 0;
		f->version[1] = v->has_version_minor ? v->version_minor : 0;
		f->version[2] = v->has_version_patch ? v->version_patch : 0;
	}
	if (t && !f->has_timestamp) {
		if (!time_from(t, &f->t_ns)) {
			say(why, why_size,
			    "timestamp %lld s %u ns does not fit in int64 nanoseconds",
			    (long long)t->seconds, (unsigned)t->nanos);
			return HL_OSI_DECODE_MALFORMED;
		}
		f->has_timestamp = true;
	}
	return HL_OSI_DECODE_OK;
}

static void reset(struct hl_osi_frame *f, enum hl_osi_kind kind)
{
	f->kind = kind;
	f->has_version = false;
	memset(f->version, 0, sizeof(f->version));
	f->has_timestamp = false;
	f->t_ns = 0;
	f->has_host = false;
	f->host_id = 0;
	f->n_objects = 0;
	f->n_boundaries = 0;
	f->n_points = 0;
}

enum hl_osi_decode_result hl_osi_decode(const uint8_t *buf, size_t len, enum hl_osi_kind kind,
					struct hl_osi_frame *ret, char *why, size_t why_size)
{
	enum hl_osi_decode_result r;

	reset(ret, kind);
	say(why, why_size, "ok");
	if (kind == HL_OSI_SENSOR_VIEW) {
		Osi3__SensorView *sv = osi3__sensor_view__unpack(NULL, len, buf);
		const Osi3__GroundTruth *g;

		if (!sv) {
			say(why, why_size,
			    "%zu bytes are not a serialized osi3.SensorView (protobuf-c could "
			    "not unpack them)",
			    len);
			return HL_OSI_DECODE_MALFORMED;
		}
		g = sv->global_ground_truth;
		/* The sensor view's own fields first, the ground truth's where it has none. */
		ret->has_host = id_from(sv->host_vehicle_id, &ret->host_id) ||
				(g && id_from(g->host_vehicle_id, &ret->host_id));
		r = header_from(sv->version, sv->timestamp, ret, why, why_size);
		if (r == HL_OSI_DECODE_OK && g)
			r = header_from(g->version, g->timestamp, ret, why, why_size);
		if (r == HL_OSI_DECODE_OK)
			r = world_from(g, ret, why, why_size);
		osi3__sensor_view__free_unpacked(sv, NULL);
	} else {
		Osi3__GroundTruth *g = osi3__ground_truth__unpack(NULL, len, buf);

		if (!g) {
			say(why, why_size,
			    "%zu bytes are not a serialized osi3.GroundTruth (protobuf-c could "
			    "not unpack them)",
			    len);
			return HL_OSI_DECODE_MALFORMED;
		}
		ret->has_host = id_from(g->host_vehicle_id, &ret->host_id);
		r = header_from(g->version, g->timestamp, ret, why, why_size);
		if (r == HL_OSI_DECODE_OK)
			r = world_from(g, ret, why, why_size);
		osi3__ground_truth__free_unpacked(g, NULL);
	}
	if (r != HL_OSI_DECODE_OK)
		reset(ret, kind);
	return r;
}

/* ---- encoding ---- */

/* Everything one call packs, made at once and freed at once. */
struct tree {
	Osi3__InterfaceVersion version;
	Osi3__Timestamp time;
	Osi3__Identifier host;
	Osi3__GroundTruth gt;
	Osi3__SensorView sv;

	Osi3__MovingObject *obj, **obj_p;
	Osi3__Identifier *obj_id;
	Osi3__BaseMoving *base;
	Osi3__Dimension3d *dim;
	Osi3__Vector3d *pos, *vel;
	Osi3__Orientation3d *rpy;
	Osi3__MovingObject__VehicleClassification *cls;
	Osi3__MovingObject__VehicleClassification__LightState *light;

	Osi3__LaneBoundary *lb, **lb_p;
	Osi3__Identifier *lb_id;
	Osi3__LaneBoundary__Classification *lb_cls;
	Osi3__LaneBoundary__BoundaryPoint *pt, **pt_p;
	Osi3__Vector3d *pt_pos;
};

static void tree_free(struct tree *t)
{
	free(t->obj);
	free(t->obj_p);
	free(t->obj_id);
	free(t->base);
	free(t->dim);
	free(t->pos);
	free(t->vel);
	free(t->rpy);
	free(t->cls);
	free(t->light);
	free(t->lb);
	free(t->lb_p);
	free(t->lb_id);
	free(t->lb_cls);
	free(t->pt);
	free(t->pt_p);
	free(t->pt_pos);
}

/* calloc of at least one element, so that NULL means no memory. */
#define ALLOC(p, n) ((p) = calloc((n) ? (size_t)(n) : 1, sizeof(*(p))))

static int tree_alloc(struct tree *t, int n_obj, int n_lb, int n_pt)
{
	if (!ALLOC(t->obj, n_obj) || !ALLOC(t->obj_p, n_obj) || !ALLOC(t->obj_id, n_obj) ||
	    !ALLOC(t->base, n_obj) || !ALLOC(t->dim, n_obj) || !ALLOC(t->pos, n_obj) ||
	    !ALLOC(t->vel, n_obj) || !ALLOC(t->rpy, n_obj) || !ALLOC(t->cls, n_obj) ||
	    !ALLOC(t->light, n_obj) || !ALLOC(t->lb, n_lb) || !ALLOC(t->lb_p, n_lb) ||
	    !ALLOC(t->lb_id, n_lb) || !ALLOC(t->lb_cls, n_lb) || !ALLOC(t->pt, n_pt) ||
	    !ALLOC(t->pt_p, n_pt) || !ALLOC(t->pt_pos, n_pt))
		return -ENOMEM;
	return 0;
}

/* Sets *v and *has from x unless x is NAN; true if it did. */
static bool put(double x, double *v, protobuf_c_boolean *has)
{
	*has = !isnan(x);
	if (*has)
		*v = x;
	return *has;
}

/* v from x[3]; NULL if all three are NAN. */
static Osi3__Vector3d *put_vec(const double x[3], Osi3__Vector3d *v)
{
	bool any;

	osi3__vector3d__init(v);
	any = put(x[0], &v->x, &v->has_x);
	any |= put(x[1], &v->y, &v->has_y);
	any |= put(x[2], &v->z, &v->has_z);
	return any ? v : NULL;
}

static void object_to(const struct hl_osi_object *o, struct tree *t, int i)
{
	Osi3__MovingObject *m = &t->obj[i];
	Osi3__BaseMoving *b = &t->base[i];
	Osi3__Dimension3d *d = &t->dim[i];
	Osi3__Orientation3d *r = &t->rpy[i];
	bool any;

	osi3__moving_object__init(m);
	if (o->has_id) {
		osi3__identifier__init(&t->obj_id[i]);
		t->obj_id[i].has_value = 1;
		t->obj_id[i].value = o->id;
		m->id = &t->obj_id[i];
	}
	m->has_type = o->type != 0;
	m->type = (Osi3__MovingObject__Type)o->type;

	osi3__base_moving__init(b);
	osi3__dimension3d__init(d);
	any = put(o->dim_m[0], &d->length, &d->has_length);
	any |= put(o->dim_m[1], &d->width, &d->has_width);
	any |= put(o->dim_m[2], &d->height, &d->has_height);
	b->dimension = any ? d : NULL;
	b->position = put_vec(o->pos_m, &t->pos[i]);
	osi3__orientation3d__init(r);
	any = put(o->rpy_rad[0], &r->roll, &r->has_roll);
	any |= put(o->rpy_rad[1], &r->pitch, &r->has_pitch);
	any |= put(o->rpy_rad[2], &r->yaw, &r->has_yaw);
	b->orientation = any ? r : NULL;
	b->velocity = put_vec(o->vel_mps, &t->vel[i]);
	if (b->dimension || b->position || b->orientation || b->velocity)
		m->base_moving = b;

	if (o->has_classification) {
		Osi3__MovingObject__VehicleClassification *c = &t->cls[i];
		Osi3__MovingObject__VehicleClassification__LightState *l = &t->light[i];

		osi3__moving_object__vehicle_classification__init(c);
		c->has_type = o->vehicle_type != 0;
		c->type = (Osi3__MovingObject__VehicleClassification__Type)o->vehicle_type;
		osi3__moving_object__vehicle_classification__light_state__init(l);
		l->has_head_light = o->head_light != 0;
		l->head_light = o->head_light;
		l->has_high_beam = o->high_beam != 0;
		l->high_beam = o->high_beam;
		l->has_brake_light_state = o->brake_light != 0;
		l->brake_light_state = o->brake_light;
		l->has_tail_light = o->tail_light != 0;
		l->tail_light = o->tail_light;
		if (l->has_head_light || l->has_high_beam || l->has_brake_light_state ||
		    l->has_tail_light)
			c->light_state = l;
		m->vehicle_classification = c;
	}
	t->obj_p[i] = m;
}

static void boundary_to(const struct hl_osi_frame *f, int i, struct tree *t)
{
	const struct hl_osi_boundary *b = &f->boundary[i];
	Osi3__LaneBoundary *lb = &t->lb[i];

	osi3__lane_boundary__init(lb);
	osi3__identifier__init(&t->lb_id[i]);
	t->lb_id[i].has_value = 1;
	t->lb_id[i].value = b->id;
	lb->id = &t->lb_id[i];
	if (b->type != 0) {
		osi3__lane_boundary__classification__init(&t->lb_cls[i]);
		t->lb_cls[i].has_type = 1;
		t->lb_cls[i].type = (Osi3__LaneBoundary__Classification__Type)b->type;
		lb->classification = &t->lb_cls[i];
	}
	lb->n_boundary_line = (size_t)b->n;
	lb->boundary_line = &t->pt_p[b->first];
	for (int k = b->first; k < b->first + b->n; k++) {
		Osi3__LaneBoundary__BoundaryPoint *p = &t->pt[k];

		osi3__lane_boundary__boundary_point__init(p);
		p->position = put_vec(f->point[k], &t->pt_pos[k]);
		put(f->point_width_m[k], &p->width, &p->has_width);
		t->pt_p[k] = p;
	}
	t->lb_p[i] = lb;
}

static bool frame_fits(const struct hl_osi_frame *f)
{
	if (f->n_objects < 0 || f->n_objects > HL_OSI_MAX_OBJECTS || f->n_boundaries < 0 ||
	    f->n_boundaries > HL_OSI_MAX_BOUNDARIES || f->n_points < 0 ||
	    f->n_points > HL_OSI_MAX_POINTS)
		return false;
	for (int i = 0; i < f->n_boundaries; i++) {
		const struct hl_osi_boundary *b = &f->boundary[i];

		if (b->first < 0 || b->n < 0 || b->first > f->n_points ||
		    b->n > f->n_points - b->first)
			return false;
	}
	return true;
}

int hl_osi_encode(const struct hl_osi_frame *f, enum hl_osi_kind kind, uint8_t **ret_buf,
		  size_t *ret_len)
{
	struct tree t = { 0 };
	const ProtobufCMessage *top;
	uint8_t *buf;
	size_t len;
	int r;

	if (!frame_fits(f))
		return -EINVAL;
	r = tree_alloc(&t, f->n_objects, f->n_boundaries, f->n_points);
	if (r < 0)
		goto out;

	osi3__interface_version__init(&t.version);
	t.version.has_version_major = t.version.has_version_minor = 1;
	t.version.has_version_patch = 1;
	t.version.version_major = HL_OSI_VERSION_MAJOR;
	t.version.version_minor = HL_OSI_VERSION_MINOR;
	t.version.version_patch = HL_OSI_VERSION_PATCH;
	osi3__timestamp__init(&t.time);
	if (f->has_timestamp) {
		/* Floor division: nanos stays in [0, 1e9) for times before zero too. */
		int64_t s = f->t_ns / NS_PER_S, ns = f->t_ns % NS_PER_S;

		if (ns < 0) {
			s -= 1;
			ns += NS_PER_S;
		}
		t.time.has_seconds = t.time.has_nanos = 1;
		t.time.seconds = s;
		t.time.nanos = (uint32_t)ns;
	}
	osi3__identifier__init(&t.host);
	t.host.has_value = 1;
	t.host.value = f->host_id;

	osi3__ground_truth__init(&t.gt);
	t.gt.version = &t.version;
	t.gt.timestamp = f->has_timestamp ? &t.time : NULL;
	t.gt.host_vehicle_id = f->has_host ? &t.host : NULL;
	for (int i = 0; i < f->n_objects; i++)
		object_to(&f->object[i], &t, i);
	t.gt.n_moving_object = (size_t)f->n_objects;
	t.gt.moving_object = t.obj_p;
	for (int i = 0; i < f->n_boundaries; i++)
		boundary_to(f, i, &t);
	t.gt.n_lane_boundary = (size_t)f->n_boundaries;
	t.gt.lane_boundary = t.lb_p;
	top = &t.gt.base;
	if (kind == HL_OSI_SENSOR_VIEW) {
		osi3__sensor_view__init(&t.sv);
		t.sv.version = &t.version;
		t.sv.timestamp = t.gt.timestamp;
		t.sv.host_vehicle_id = t.gt.host_vehicle_id;
		t.sv.global_ground_truth = &t.gt;
		top = &t.sv.base;
	}

	len = protobuf_c_message_get_packed_size(top);
	buf = malloc(len ? len : 1);
	if (!buf) {
		r = -ENOMEM;
		goto out;
	}
	protobuf_c_message_pack(top, buf);
	*ret_buf = buf;
	*ret_len = len;
out:
	tree_free(&t);
	return r;
}
