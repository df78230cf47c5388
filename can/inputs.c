/* SPDX-License-Identifier: MIT */
/*
 * The ECU's inputs on CAN (can/inputs.h): the map from a database's attributes to the vehicle
 * state and the camera's object list, their encoder, and the decoder with its camera-cycle rule.
 */
#include "can/inputs.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DEG (M_PI / 180.0)
#define KMH (1.0 / 3.6) /* m/s per km/h */

enum { VF_SPEED, VF_YAW, VF_STEER, VF_SWITCH, VF_ADB, VF_N };
static const char *const vf_name[VF_N] = { "speed", "yaw_rate", "steering", "light_switch",
					   "adb_enable" };

enum { OF_COUNT, OF_ID, OF_CLASS, OF_HL, OF_HR, OF_VB, OF_VT, OF_DIST, OF_CONF, OF_N };
static const char *const of_name[OF_N] = { "object_count", "id",       "class",
					   "h_left",	   "h_right",  "v_bottom",
					   "v_top",	   "distance", "confidence" };

struct obj_msg {
	const struct hl_dbc_signal *index, *alive, *crc;
	const struct hl_dbc_signal *field[OF_N][HL_INPUTS_MAX_OBJECTS]; /* per slot */
	bool has[OF_N];
	int slots; /* the slots index can name */
};

struct hl_inputs_map {
	const struct hl_dbc *db;
	int n; /* messages: vehicle, then the objects ones in cycle order */
	struct hl_inputs_message m[1 + HL_INPUTS_MAX_OBJ_MESSAGES];
	unsigned counter_max[1 + HL_INPUTS_MAX_OBJ_MESSAGES];
	const struct hl_dbc_signal *vsig[VF_N], *valive, *vcrc;
	int n_obj;
	struct obj_msg obj[HL_INPUTS_MAX_OBJ_MESSAGES]; /* obj[k] is m[1 + k] */
	int slots;
};

static int fail(char *msg, size_t size, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int fail(char *msg, size_t size, const char *fmt, ...)
{
	va_list ap;

	if (msg && size > 0) {
		va_start(ap, fmt);
		vsnprintf(msg, size, fmt, ap);
		va_end(ap);
	}
	return -EINVAL;
}

static int field_of(const char *const *names, int n, const char *s)
{
	for (int i = 0; i < n; i++)
		if (strcmp(names[i], s) == 0)
			return i;
	return -1;
}

static const char *join(const char *const *names, int n, char *buf, size_t size)
{
	size_t off = 0;

	buf[0] = '\0';
	for (int i = 0; i < n && off < size; i++)
		off += (size_t)snprintf(buf + off, size - off, "%s%s", i ? ", " : "", names[i]);
	return buf;
}

/* The E2E fields must sit where the profile reads them. */
static int check_e2e_layout(const struct hl_inputs_message *im, const struct hl_dbc_signal *crc,
			    const struct hl_dbc_signal *alive, char *msg, size_t size)
{
	int crc_len, alive_start, alive_len;

	if (im->e2e.profile == HL_E2E_NONE)
		return 0;
	crc_len = im->e2e.profile == HL_E2E_P1 ? 8 : 16;
	alive_start = im->e2e.profile == HL_E2E_P1 ? 8 : 16;
	alive_len = im->e2e.profile == HL_E2E_P1 ? 4 : 8;
	if ((size_t)im->msg->size < hl_e2e_min_len(im->e2e.profile))
		return fail(msg, size, "message '%s': %d bytes are too short for HdlE2E %s",
			    im->msg->name, im->msg->size, hl_e2e_profile_name(im->e2e.profile));
	if (!crc || crc->start_bit != 0 || crc->length != crc_len || crc->order != HL_DBC_INTEL)
		return fail(msg, size,
			    "message '%s': HdlE2E %s needs a signal with HdlInputSignal \"crc\" at "
			    "0|%d@1, found %s%s",
			    im->msg->name, hl_e2e_profile_name(im->e2e.profile), crc_len,
			    crc ? "'" : "none", crc ? crc->name : "");
	if (!alive || alive->start_bit != alive_start || alive->length != alive_len ||
	    alive->order != HL_DBC_INTEL)
		return fail(msg, size,
			    "message '%s': HdlE2E %s needs a signal with HdlInputSignal \"alive\" "
			    "at %d|%d@1, found %s%s",
			    im->msg->name, hl_e2e_profile_name(im->e2e.profile), alive_start,
			    alive_len, alive ? "'" : "none", alive ? alive->name : "");
	return 0;
}

static int read_message(const struct hl_dbc *db, const struct hl_dbc_message *m,
			enum hl_inputs_kind kind, struct hl_inputs_message *ret, char *msg,
			size_t size)
{
	struct hl_dbc_attr_value v;

	*ret = (struct hl_inputs_message){ .msg = m, .kind = kind };
	if (hl_dbc_message_attr(db, m, "GenMsgCycleTime", &v) >= 0 && v.type != HL_DBC_ATTR_STRING)
		ret->cycle_ms = v.i > 0 ? (unsigned)v.i : 0;
	if (hl_dbc_message_attr(db, m, "HdlE2E", &v) >= 0) {
		if (v.type != HL_DBC_ATTR_STRING || !v.s || hl_e2e_config_parse(v.s, &ret->e2e) < 0)
			return fail(msg, size,
				    "message '%s': HdlE2E \"%s\": expected \"P1 dataid=0x....\", "
				    "\"P5 dataid=0x....\" or \"none\"",
				    m->name, v.s ? v.s : "");
	}
	ret->fd = m->size > 8 || (hl_dbc_message_attr(db, m, "VFrameFormat", &v) >= 0 &&
				  v.type == HL_DBC_ATTR_ENUM && v.s && strstr(v.s, "_FD"));
	return 0;
}

/* The signal's HdlInputSignal, or NULL when it has none. */
static const char *signal_field(const struct hl_dbc *db, const struct hl_dbc_message *m,
				const struct hl_dbc_signal *s)
{
	struct hl_dbc_attr_value v;

	if (hl_dbc_signal_attr(db, m, s, "HdlInputSignal", &v) < 0 ||
	    v.type != HL_DBC_ATTR_STRING || !v.s || !v.s[0])
		return NULL;
	return v.s;
}

static int map_vehicle(struct hl_inputs_map *map, char *msg, size_t size)
{
	const struct hl_dbc_message *m = map->m[0].msg;
	char names[128];

	for (int i = 0; i < m->n_signals; i++) {
		const struct hl_dbc_signal *s = &m->signals[i];
		const char *f = signal_field(map->db, m, s);
		const struct hl_dbc_signal **slot;
		int fi;

		if (!f)
			continue;
		fi = field_of(vf_name, VF_N, f);
		if (fi >= 0)
			slot = &map->vsig[fi];
		else if (strcmp(f, "crc") == 0)
			slot = &map->vcrc;
		else if (strcmp(f, "alive") == 0)
			slot = &map->valive;
		else
			return fail(msg, size,
				    "message '%s' signal '%s': HdlInputSignal \"%s\" is no vehicle "
				    "field (expected %s, crc or alive)",
				    m->name, s->name, f, join(vf_name, VF_N, names, sizeof(names)));
		if (*slot)
			return fail(msg, size,
				    "message '%s': HdlInputSignal \"%s\" on both '%s' and '%s'",
				    m->name, f, (*slot)->name, s->name);
		if (s->mux_parent >= 0 || s->is_multiplexor || s->unusable)
			return fail(msg, size,
				    "message '%s' signal '%s': a vehicle signal must be plain (not "
				    "multiplexed, inside the message)",
				    m->name, s->name);
		*slot = s;
	}
	for (int f = 0; f < VF_N; f++)
		if (!map->vsig[f])
			return fail(msg, size,
				    "message '%s' (HdlInput \"vehicle\"): no signal with "
				    "HdlInputSignal \"%s\"",
				    m->name, vf_name[f]);
	return check_e2e_layout(&map->m[0], map->vcrc, map->valive, msg, size);
}

static int index_slots(const struct hl_dbc_signal *s)
{
	int n = s->length >= 3 ? HL_INPUTS_MAX_OBJECTS : 1 << s->length;

	if (s->max > s->min && s->factor > 0) {
		double top = floor((s->max - s->offset) / s->factor + 0.5) + 1;

		if (top < n)
			n = top < 1 ? 0 : (int)top;
	}
	return n;
}

static int map_objects_message(struct hl_inputs_map *map, int k, char *msg, size_t size)
{
	const struct hl_dbc_message *m = map->m[1 + k].msg;
	struct obj_msg *om = &map->obj[k];
	uint8_t data[HL_DBC_MAX_PAYLOAD + 8];
	char names[160];

	for (int i = 0; i < m->n_signals; i++) {
		const struct hl_dbc_signal *s = &m->signals[i];
		const char *f = signal_field(map->db, m, s);

		if (!f)
			continue;
		if (strcmp(f, "object_index") == 0 || strcmp(f, "crc") == 0 ||
		    strcmp(f, "alive") == 0) {
			const struct hl_dbc_signal **slot = f[0] == 'o' ? &om->index :
							    f[0] == 'c' ? &om->crc :
									  &om->alive;

			if (*slot)
				return fail(msg, size,
					    "message '%s': HdlInputSignal \"%s\" on both '%s' and "
					    "'%s'",
					    m->name, f, (*slot)->name, s->name);
			if (s->mux_parent >= 0 || s->unusable || (f[0] == 'o') != s->is_multiplexor)
				return fail(msg, size,
					    "message '%s' signal '%s': \"%s\" must be %s", m->name,
					    s->name, f,
					    f[0] == 'o' ? "the message's multiplexor (M)" :
							  "a plain signal (not multiplexed)");
			*slot = s;
			continue;
		}
		if (field_of(of_name, OF_N, f) < 0)
			return fail(msg, size,
				    "message '%s' signal '%s': HdlInputSignal \"%s\" is no object "
				    "field (expected object_index, %s, crc or alive)",
				    m->name, s->name, f, join(of_name, OF_N, names, sizeof(names)));
	}
	if (!om->index)
		return fail(msg, size,
			    "message '%s' (HdlInput \"objects\"): no multiplexor with "
			    "HdlInputSignal \"object_index\"",
			    m->name);
	om->slots = index_slots(om->index);
	if (om->slots < 1)
		return fail(msg, size, "message '%s' signal '%s': object_index names no slot",
			    m->name, om->index->name);
	for (int i = 0; i < m->n_signals; i++) {
		const struct hl_dbc_signal *s = &m->signals[i];
		const char *f = signal_field(map->db, m, s);
		int fi = f ? field_of(of_name, OF_N, f) : -1;

		if (fi < 0)
			continue;
		if (s->unusable || s->is_multiplexor ||
		    (s->mux_parent >= 0 && &m->signals[s->mux_parent] != om->index))
			return fail(msg, size,
				    "message '%s' signal '%s': an object field must be multiplexed "
				    "by '%s' (object_index) or by nothing",
				    m->name, s->name, om->index->name);
		for (int slot = 0; slot < om->slots; slot++) {
			memset(data, 0, sizeof(data));
			hl_dbc_signal_set_raw(om->index, (uint64_t)slot, data, (size_t)m->size);
			if (!hl_dbc_signal_present(m, s, data, (size_t)m->size))
				continue;
			if (om->field[fi][slot])
				return fail(
					msg, size,
					"message '%s': HdlInputSignal \"%s\" of slot %d on both "
					"'%s' and '%s'",
					m->name, f, slot, om->field[fi][slot]->name, s->name);
			om->field[fi][slot] = s;
			om->has[fi] = true;
		}
	}
	if (map->m[1 + k].e2e.profile == HL_E2E_NONE && !om->alive)
		return fail(msg, size,
			    "message '%s' (HdlInput \"objects\", no E2E): no signal with "
			    "HdlInputSignal \"alive\" to tell the camera cycles apart",
			    m->name);
	return check_e2e_layout(&map->m[1 + k], om->crc, om->alive, msg, size);
}

static int map_objects(struct hl_inputs_map *map, char *msg, size_t size)
{
	char names[200];
	size_t off = 0;

	map->slots = HL_INPUTS_MAX_OBJECTS;
	for (int k = 0; k < map->n_obj; k++) {
		int rc = map_objects_message(map, k, msg, size);

		if (rc < 0)
			return rc;
		if (map->obj[k].slots < map->slots)
			map->slots = map->obj[k].slots;
		off += (size_t)snprintf(names + off, sizeof(names) - off, "%s%s", k ? ", " : "",
					map->m[1 + k].msg->name);
		if (off >= sizeof(names))
			off = sizeof(names) - 1;
	}
	for (int f = 0; f < OF_N; f++) {
		int owner = -1;

		for (int k = 0; k < map->n_obj; k++) {
			if (!map->obj[k].has[f])
				continue;
			if (owner >= 0)
				return fail(msg, size,
					    "HdlInputSignal \"%s\" in two objects messages: '%s' "
					    "and '%s'",
					    of_name[f], map->m[1 + owner].msg->name,
					    map->m[1 + k].msg->name);
			owner = k;
		}
		if (owner < 0)
			return fail(msg, size,
				    "no signal with HdlInputSignal \"%s\" in the objects messages "
				    "(%s)",
				    of_name[f], names);
		for (int slot = 0; slot < map->slots; slot++)
			if (!map->obj[owner].field[f][slot])
				return fail(
					msg, size,
					"message '%s': HdlInputSignal \"%s\" is missing in slot "
					"%d",
					map->m[1 + owner].msg->name, of_name[f], slot);
	}
	return 0;
}

/* The message carrying object_count goes first in a cycle: a receiver learns the count early. */
static void order_objects(struct hl_inputs_map *map)
{
	for (int k = 1; k < map->n_obj; k++) {
		if (!map->obj[k].has[OF_COUNT])
			continue;
		struct obj_msg om = map->obj[k];
		struct hl_inputs_message im = map->m[1 + k];

		memmove(&map->obj[1], &map->obj[0], (size_t)k * sizeof(map->obj[0]));
		memmove(&map->m[2], &map->m[1], (size_t)k * sizeof(map->m[0]));
		map->obj[0] = om;
		map->m[1] = im;
		break;
	}
}

int hl_inputs_map_new(const struct hl_dbc *db, struct hl_inputs_map **ret, char *msg,
		      size_t msg_size)
{
	struct hl_inputs_map *map;
	bool defined = false;
	int rc;

	map = calloc(1, sizeof(*map));
	if (!map)
		return -ENOMEM;
	map->db = db;
	map->n = 1;
	for (int i = 0; i < hl_dbc_n_messages(db); i++) {
		const struct hl_dbc_message *m = hl_dbc_message(db, i);
		struct hl_dbc_attr_value v;
		struct hl_inputs_message *im;

		if (m->independent || hl_dbc_message_attr(db, m, "HdlInput", &v) < 0)
			continue;
		defined = true;
		if (v.type != HL_DBC_ATTR_STRING || !v.s || !v.s[0])
			continue;
		if (strcmp(v.s, "vehicle") == 0) {
			if (map->m[0].msg) {
				rc = fail(msg, msg_size,
					  "HdlInput \"vehicle\" on two messages: '%s' and '%s'",
					  map->m[0].msg->name, m->name);
				goto err_free;
			}
			im = &map->m[0];
			rc = read_message(db, m, HL_INPUTS_VEHICLE, im, msg, msg_size);
		} else if (strcmp(v.s, "objects") == 0) {
			if (map->n_obj == HL_INPUTS_MAX_OBJ_MESSAGES) {
				rc = fail(msg, msg_size,
					  "message '%s': more than %d messages with HdlInput "
					  "\"objects\"",
					  m->name, HL_INPUTS_MAX_OBJ_MESSAGES);
				goto err_free;
			}
			im = &map->m[1 + map->n_obj++];
			rc = read_message(db, m, HL_INPUTS_OBJECTS, im, msg, msg_size);
		} else {
			rc = fail(
				msg, msg_size,
				"message '%s': HdlInput \"%s\": expected \"vehicle\" or \"objects\"",
				m->name, v.s);
		}
		if (rc < 0)
			goto err_free;
	}
	if (!defined) {
		rc = fail(
			msg, msg_size,
			"no message has the attribute HdlInput (expected BA_DEF_ BO_ \"HdlInput\" "
			"STRING and BA_ \"HdlInput\" BO_ <id> \"vehicle\" / \"objects\")");
		goto err_free;
	}
	if (!map->m[0].msg) {
		rc = fail(msg, msg_size, "no message with HdlInput \"vehicle\"");
		goto err_free;
	}
	if (map->n_obj == 0) {
		rc = fail(msg, msg_size, "no message with HdlInput \"objects\"");
		goto err_free;
	}
	map->n = 1 + map->n_obj;
	rc = map_vehicle(map, msg, msg_size);
	if (rc == 0)
		rc = map_objects(map, msg, msg_size);
	if (rc < 0)
		goto err_free;
	order_objects(map);
	for (int i = 0; i < map->n; i++) {
		const struct hl_dbc_signal *alive = i == 0 ? map->valive : map->obj[i - 1].alive;

		if (map->m[i].e2e.profile != HL_E2E_NONE)
			map->counter_max[i] = hl_e2e_counter_max(map->m[i].e2e.profile);
		else if (alive)
			map->counter_max[i] = alive->length >= 32 ? UINT32_MAX :
								    (1u << alive->length) - 1;
	}
	*ret = map;
	return 0;

err_free:
	free(map);
	return rc;
}

void hl_inputs_map_free(struct hl_inputs_map *map)
{
	free(map);
}

int hl_inputs_map_n_messages(const struct hl_inputs_map *map)
{
	return map->n;
}

const struct hl_inputs_message *hl_inputs_map_message(const struct hl_inputs_map *map, int i)
{
	return i >= 0 && i < map->n ? &map->m[i] : NULL;
}

int hl_inputs_map_slots(const struct hl_inputs_map *map)
{
	return map->slots;
}

unsigned hl_inputs_map_counter_max(const struct hl_inputs_map *map, int i)
{
	return i >= 0 && i < map->n ? map->counter_max[i] : 0;
}

static const struct hl_dbc_signal *object_signal(const struct hl_inputs_map *map, int f, int slot)
{
	for (int k = 0; k < map->n_obj; k++)
		if (map->obj[k].has[f])
			return map->obj[k].field[f][slot];
	return NULL;
}

int hl_inputs_map_range(const struct hl_inputs_map *map, const char *field, double *ret_min,
			double *ret_max)
{
	int f = field_of(of_name, OF_N, field);
	const struct hl_dbc_signal *s;

	if (f < 0) {
		f = field_of(vf_name, VF_N, field);
		if (f < 0)
			return -ENOENT;
		s = map->vsig[f];
	} else {
		s = object_signal(map, f, 0);
	}
	*ret_min = s->min;
	*ret_max = s->max;
	return 0;
}

/* --- encode --- */

static void frame_init(const struct hl_inputs_message *im, struct hl_inputs_frame *f)
{
	memset(f, 0, sizeof(*f));
	f->can_id = im->msg->can_id;
	f->len = (uint8_t)im->msg->size;
	f->fd = im->fd;
}

static int frame_seal(const struct hl_inputs_message *im, const struct hl_dbc_signal *alive,
		      unsigned counter, struct hl_inputs_frame *f)
{
	if (im->e2e.profile != HL_E2E_NONE)
		return hl_e2e_protect(&im->e2e, f->data, f->len, counter);
	if (alive)
		return hl_dbc_signal_set_raw(alive, counter, f->data, f->len);
	return 0;
}

int hl_inputs_encode_vehicle(const struct hl_inputs_map *map, const struct hl_vehicle_state *st,
			     unsigned counter, struct hl_inputs_frame *ret)
{
	const struct hl_inputs_message *im = &map->m[0];
	double v[VF_N];
	int rc;

	if (counter > map->counter_max[0])
		return -EINVAL;
	v[VF_SPEED] = st->speed_mps / KMH;
	v[VF_YAW] = st->yaw_rate_rad_s / DEG;
	v[VF_STEER] = st->steering_rad / DEG;
	v[VF_SWITCH] = (double)st->light_switch;
	v[VF_ADB] = st->adb_enable ? 1 : 0;
	frame_init(im, ret);
	for (int f = 0; f < VF_N; f++) {
		rc = hl_dbc_signal_encode(map->vsig[f], v[f], ret->data, ret->len);
		if (rc < 0)
			return rc;
	}
	return frame_seal(im, map->valive, counter, ret);
}

static void object_values(const struct hl_camera_objects *o, int slot, double v[OF_N])
{
	const struct hl_camera_object *ob = &o->obj[slot];

	v[OF_COUNT] = o->n;
	v[OF_ID] = ob->id;
	v[OF_CLASS] = (double)ob->cls;
	v[OF_HL] = ob->h_left_deg;
	v[OF_HR] = ob->h_right_deg;
	v[OF_VB] = ob->v_bottom_deg;
	v[OF_VT] = ob->v_top_deg;
	v[OF_DIST] = ob->distance_m;
	v[OF_CONF] = ob->confidence;
}

int hl_inputs_encode_objects(const struct hl_inputs_map *map, const struct hl_camera_objects *o,
			     unsigned counter, struct hl_inputs_frame *ret)
{
	int n = 0, rc;

	if (o->n < 0 || o->n > map->slots)
		return -E2BIG;
	for (int k = 0; k < map->n_obj; k++)
		if (counter > map->counter_max[1 + k])
			return -EINVAL;
	for (int slot = 0; slot < (o->n ? o->n : 1); slot++) {
		double v[OF_N];

		object_values(o, slot, v);
		for (int k = 0; k < map->n_obj; k++) {
			const struct obj_msg *om = &map->obj[k];
			struct hl_inputs_frame *f = &ret[n];

			if (o->n == 0 && !om->has[OF_COUNT])
				continue;
			frame_init(&map->m[1 + k], f);
			rc = hl_dbc_signal_set_raw(om->index, (uint64_t)slot, f->data, f->len);
			for (int fi = 0; rc == 0 && fi < OF_N; fi++) {
				if (!om->has[fi] || (o->n == 0 && fi != OF_COUNT))
					continue;
				rc = hl_dbc_signal_encode(om->field[fi][slot], v[fi], f->data,
							  f->len);
			}
			if (rc == 0)
				rc = frame_seal(&map->m[1 + k], om->alive, counter, f);
			if (rc < 0)
				return rc;
			n++;
		}
	}
	return n;
}

/* --- decode --- */

enum cycle_state { CYCLE_IDLE, CYCLE_OPEN, CYCLE_DEAD };

struct hl_inputs_decoder {
	const struct hl_inputs_map *map;
	struct hl_inputs_counters c;
	bool veh_seen;
	unsigned veh_counter;
	enum cycle_state state;
	unsigned cyc_counter; /* of the open or dead cycle */
	int cyc_count; /* -1 until a frame carries it */
	uint16_t mask[HL_INPUTS_MAX_OBJ_MESSAGES]; /* slots delivered, per message */
	bool cyc_seen; /* a cycle was started before: cyc_counter is its counter */
	bool done_seen;
	unsigned done_counter; /* of the last complete cycle */
	struct hl_camera_objects stage;
};

int hl_inputs_decoder_new(const struct hl_inputs_map *map, struct hl_inputs_decoder **ret)
{
	struct hl_inputs_decoder *d = calloc(1, sizeof(*d));

	if (!d)
		return -ENOMEM;
	d->map = map;
	d->cyc_count = -1;
	*ret = d;
	return 0;
}

void hl_inputs_decoder_free(struct hl_inputs_decoder *d)
{
	free(d);
}

const struct hl_inputs_counters *hl_inputs_decoder_counters(const struct hl_inputs_decoder *d)
{
	return &d->c;
}

static double phys(const struct hl_dbc_signal *s, const uint8_t *data, size_t len)
{
	uint64_t raw = 0;

	hl_dbc_signal_get_raw(s, data, len, &raw);
	return hl_dbc_signal_phys(s, raw);
}

/* A whole number in [lo, hi], or -1. */
static int whole(double v, int lo, int hi)
{
	if (!isfinite(v) || v != floor(v) || v < lo || v > hi)
		return -1;
	return (int)v;
}

static int decode_vehicle(struct hl_inputs_decoder *d, const uint8_t *data, size_t len,
			  bool have_counter, unsigned counter, struct hl_vehicle_state *ret)
{
	const struct hl_inputs_map *map = d->map;
	struct hl_vehicle_state st;
	double v[VF_N];
	int sw, adb;

	if (have_counter) {
		if (d->veh_seen) {
			unsigned lost = 0;
			int rc = hl_e2e_counter_check(map->counter_max[0], d->veh_counter, counter,
						      &lost);

			if (rc == HL_E2E_COUNTER_REPEATED) {
				d->c.counter_repeated++;
				return -ESTALE;
			}
			d->c.counter_lost += lost;
		}
		d->veh_seen = true;
		d->veh_counter = counter;
	}
	for (int f = 0; f < VF_N; f++)
		v[f] = phys(map->vsig[f], data, len);
	sw = whole(v[VF_SWITCH], HL_SWITCH_OFF, HL_SWITCH_HIGH);
	adb = whole(v[VF_ADB], 0, 1);
	if (sw < 0 || adb < 0 || !isfinite(v[VF_SPEED]) || !isfinite(v[VF_YAW]) ||
	    !isfinite(v[VF_STEER])) {
		d->c.bad_values++;
		return -ERANGE;
	}
	st.speed_mps = v[VF_SPEED] * KMH;
	st.yaw_rate_rad_s = v[VF_YAW] * DEG;
	st.steering_rad = v[VF_STEER] * DEG;
	st.light_switch = (enum hl_light_switch)sw;
	st.adb_enable = adb == 1;
	*ret = st;
	d->c.vehicle_states++;
	return HL_INPUTS_VEHICLE;
}

static void cycle_open(struct hl_inputs_decoder *d, int k_max, unsigned counter)
{
	if (d->cyc_seen) {
		unsigned lost = 0;

		hl_e2e_counter_check(d->map->counter_max[k_max], d->cyc_counter, counter, &lost);
		d->c.counter_lost += lost;
	}
	d->state = CYCLE_OPEN;
	d->cyc_seen = true;
	d->cyc_counter = counter;
	d->cyc_count = -1;
	memset(d->mask, 0, sizeof(d->mask));
	memset(&d->stage, 0, sizeof(d->stage));
}

/* Ends the open cycle as incomplete because of this frame. */
static int cycle_kill(struct hl_inputs_decoder *d, uint64_t *counter, int rc)
{
	(*counter)++;
	d->c.cycles_incomplete++;
	d->state = CYCLE_DEAD;
	return rc;
}

static bool object_ok(const struct hl_camera_object *o)
{
	return isfinite(o->h_left_deg) && isfinite(o->h_right_deg) && isfinite(o->v_bottom_deg) &&
	       isfinite(o->v_top_deg) && o->h_left_deg <= o->h_right_deg &&
	       o->v_bottom_deg <= o->v_top_deg && isfinite(o->distance_m) && o->distance_m >= 0 &&
	       o->confidence >= 0 && o->confidence <= 1;
}

/* The cycle's state once every frame arrived: 1 complete, 0 not yet, -ERANGE malformed. */
static int cycle_check(const struct hl_inputs_decoder *d)
{
	const struct hl_inputs_map *map = d->map;
	uint16_t want;

	if (d->cyc_count < 0)
		return 0;
	if (d->cyc_count == 0) {
		for (int k = 0; k < map->n_obj; k++)
			if (d->mask[k] & ~(map->obj[k].has[OF_COUNT] ? 1u : 0u))
				return -ERANGE;
		return 1;
	}
	want = (uint16_t)((1u << d->cyc_count) - 1);
	for (int k = 0; k < map->n_obj; k++) {
		if (d->mask[k] & ~want)
			return -ERANGE;
		if (d->mask[k] != want)
			return 0;
	}
	return 1;
}

static int decode_objects(struct hl_inputs_decoder *d, int k, const uint8_t *data, size_t len,
			  unsigned counter, struct hl_camera_objects *ret)
{
	const struct hl_inputs_map *map = d->map;
	const struct obj_msg *om = &map->obj[k];
	double v[OF_N] = { 0 };
	struct hl_camera_object *o;
	int slot, rc;

	if (d->state != CYCLE_IDLE && counter != d->cyc_counter) {
		if (d->state == CYCLE_OPEN)
			d->c.cycles_incomplete++;
		d->state = CYCLE_IDLE;
	}
	if (d->state == CYCLE_DEAD) {
		d->c.counter_repeated++;
		return -ESTALE;
	}
	if (d->state == CYCLE_IDLE) {
		if (d->done_seen && counter == d->done_counter) {
			d->c.counter_repeated++;
			return -ESTALE;
		}
		cycle_open(d, 1 + k, counter);
	}
	slot = whole(phys(om->index, data, len), 0, om->slots - 1);
	if (slot < 0 || slot >= map->slots)
		return cycle_kill(d, &d->c.bad_values, -ERANGE);
	if (d->mask[k] & (1u << slot))
		return cycle_kill(d, &d->c.duplicates, -EEXIST);
	for (int f = 0; f < OF_N; f++)
		if (om->has[f])
			v[f] = phys(om->field[f][slot], data, len);
	if (om->has[OF_COUNT]) {
		int n = whole(v[OF_COUNT], 0, map->slots);

		if (n < 0 || (d->cyc_count >= 0 && n != d->cyc_count))
			return cycle_kill(d, &d->c.bad_values, -ERANGE);
		d->cyc_count = n;
	}
	if ((om->has[OF_ID] && whole(v[OF_ID], 0, 255) < 0) ||
	    (om->has[OF_CLASS] && whole(v[OF_CLASS], HL_OBJECT_OTHER, HL_OBJECT_PEDESTRIAN) < 0))
		return cycle_kill(d, &d->c.bad_values, -ERANGE);
	o = &d->stage.obj[slot];
	if (om->has[OF_ID])
		o->id = (unsigned)v[OF_ID];
	if (om->has[OF_CLASS])
		o->cls = (enum hl_object_class)whole(v[OF_CLASS], 0, 3);
	if (om->has[OF_HL])
		o->h_left_deg = v[OF_HL];
	if (om->has[OF_HR])
		o->h_right_deg = v[OF_HR];
	if (om->has[OF_VB])
		o->v_bottom_deg = v[OF_VB];
	if (om->has[OF_VT])
		o->v_top_deg = v[OF_VT];
	if (om->has[OF_DIST])
		o->distance_m = v[OF_DIST];
	if (om->has[OF_CONF])
		o->confidence = v[OF_CONF];
	d->mask[k] |= (uint16_t)(1u << slot);
	rc = cycle_check(d);
	if (rc < 0)
		return cycle_kill(d, &d->c.bad_values, rc);
	if (rc == 0) {
		d->c.object_frames++;
		return 0;
	}
	d->stage.n = d->cyc_count;
	for (int i = 0; i < d->stage.n; i++)
		if (!object_ok(&d->stage.obj[i]))
			return cycle_kill(d, &d->c.bad_values, -ERANGE);
	d->c.object_frames++;
	d->c.cycles_complete++;
	d->state = CYCLE_IDLE;
	d->done_seen = true;
	d->done_counter = counter;
	*ret = d->stage;
	return HL_INPUTS_OBJECTS;
}

int hl_inputs_decode(struct hl_inputs_decoder *d, uint32_t can_id, const uint8_t *data, size_t len,
		     struct hl_vehicle_state *ret_vehicle, struct hl_camera_objects *ret_objects)
{
	const struct hl_inputs_map *map = d->map;
	const struct hl_inputs_message *im = NULL;
	const struct hl_dbc_signal *alive;
	unsigned counter = 0;
	bool have_counter;
	int i;

	d->c.frames++;
	for (i = 0; i < map->n; i++)
		if (map->m[i].msg->can_id == can_id) {
			im = &map->m[i];
			break;
		}
	if (!im) {
		d->c.unknown_id++;
		return -ENOENT;
	}
	if (len < (size_t)im->msg->size) {
		d->c.short_frames++;
		return -EMSGSIZE;
	}
	alive = i == 0 ? map->valive : map->obj[i - 1].alive;
	have_counter = true;
	if (im->e2e.profile != HL_E2E_NONE) {
		if (hl_e2e_check(&im->e2e, data, len) < 0) {
			d->c.crc_errors++;
			return -EBADMSG;
		}
		counter = hl_e2e_counter(&im->e2e, data);
		if (counter > map->counter_max[i]) {
			d->c.bad_values++;
			return -ERANGE;
		}
	} else if (alive) {
		uint64_t raw = 0;

		hl_dbc_signal_get_raw(alive, data, len, &raw);
		counter = (unsigned)raw;
	} else {
		have_counter = false;
	}
	if (i == 0)
		return decode_vehicle(d, data, len, have_counter, counter, ret_vehicle);
	return decode_objects(d, i - 1, data, len, counter, ret_objects);
}

const char *hl_object_class_name(enum hl_object_class cls)
{
	switch (cls) {
	case HL_OBJECT_ONCOMING:
		return "oncoming";
	case HL_OBJECT_PRECEDING:
		return "preceding";
	case HL_OBJECT_PEDESTRIAN:
		return "pedestrian";
	default:
		return "other";
	}
}

const char *hl_light_switch_name(enum hl_light_switch sw)
{
	switch (sw) {
	case HL_SWITCH_OFF:
		return "off";
	case HL_SWITCH_AUTO:
		return "auto";
	case HL_SWITCH_LOW:
		return "low";
	default:
		return "high";
	}
}
