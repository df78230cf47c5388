/* SPDX-License-Identifier: MIT */
/* The ECU's inputs decoded with the camera-cycle rule (can/inputs.h). */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "can/inputs_internal.h"

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
	const struct hl_inputs_obj_msg *om = &map->obj[k];
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
