/* SPDX-License-Identifier: MIT */
/*
 * The ECU's inputs on CAN (can/inputs.h): the map from a database's attributes to the vehicle
 * state and the camera's object list, and their encoder (the decoder: can/inputs_decoder.c).
 */
#include "can/inputs.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "can/inputs_internal.h"

static const char *const vf_name[VF_N] = { "speed", "yaw_rate", "steering", "light_switch",
					   "adb_enable" };
static const char *const of_name[OF_N] = { "object_count", "id",       "class",
					   "h_left",	   "h_right",  "v_bottom",
					   "v_top",	   "distance", "confidence" };

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
	struct hl_inputs_obj_msg *om = &map->obj[k];
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
		struct hl_inputs_obj_msg om = map->obj[k];
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

const struct hl_dbc_signal *hl_inputs_map_signal(const struct hl_inputs_map *map, const char *field,
						 int slot)
{
	int f = field_of(vf_name, VF_N, field);

	if (f >= 0)
		return map->vsig[f];
	f = field_of(of_name, OF_N, field);
	if (f == OF_COUNT)
		slot = 0;
	if (f < 0 || slot < 0 || slot >= map->slots)
		return NULL;
	return object_signal(map, f, slot);
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
			const struct hl_inputs_obj_msg *om = &map->obj[k];
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
