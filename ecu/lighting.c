/* SPDX-License-Identifier: MIT */
#include "ecu/lighting.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

struct input {
	bool have;
	int64_t t_rx_ns;
	int e2e_run; /* E2E failures in a row */
};

struct lamp {
	const struct hl_lid *lid;
	struct hl_ecu_mount mount;
	int n;
	float *low, *high, *base, *out;
	struct hl_ecu_window *windows;
	struct hl_ecu_rows *rows;
};

struct hl_ecu {
	struct hl_ecu_config c;
	int n_lamps;
	struct lamp lamp[HL_ECU_MAX_LAMPS];
	struct input in[2]; /* by enum hl_ecu_input */
	struct hl_vehicle_state vehicle;
	struct hl_camera_objects objects;
};

void hl_ecu_config_default(struct hl_ecu_config *ret)
{
	*ret = (struct hl_ecu_config){
		.camera = { .pos_m = { -1.8, 0.0, 1.3 } },
		.window_fraction = HL_ECU_WINDOW_FRACTION,
		.margin_deg = 0.5,
		.margin_m = 0.2,
		.min_confidence = 0.5,
		.auto_high_mps = 40.0 / 3.6,
		.vehicle_timeout_ns = 60000000,
		.objects_timeout_ns = 60000000,
		.e2e_max_errors = 3,
		.bend = true,
	};
	hl_ecu_bend_default(&ret->bend_config);
}

const char *hl_ecu_mode_name(enum hl_ecu_mode mode)
{
	switch (mode) {
	case HL_ECU_OFF:
		return "off";
	case HL_ECU_LOW:
		return "low";
	case HL_ECU_HIGH:
		return "high";
	case HL_ECU_GLAREFREE:
		return "glarefree";
	}
	return "?";
}

const char *hl_ecu_beam_mode_name(enum hl_ecu_mode mode)
{
	return mode == HL_ECU_OFF ? "unset" : hl_ecu_mode_name(mode);
}

static int check_config(const struct hl_ecu_config *c, const char **what)
{
	const struct hl_ecu_bend_config *b = &c->bend_config;

	if (!(c->window_fraction > 0.0 && c->window_fraction < 1.0))
		*what = "window fraction: expected a number in (0, 1)";
	else if (!(c->margin_deg >= 0.0 && c->margin_deg <= 45.0))
		*what = "margin: expected degrees in [0, 45]";
	else if (!(c->margin_m >= 0.0 && c->margin_m <= 5.0))
		*what = "margin: expected metres in [0, 5]";
	else if (!(c->min_confidence >= 0.0 && c->min_confidence <= 1.0))
		*what = "minimum confidence: expected a number in [0, 1]";
	else if (!(c->auto_high_mps >= 0.0 && c->auto_high_mps <= 100.0))
		*what = "auto high beam speed: expected m/s in [0, 100]";
	else if (c->vehicle_timeout_ns <= 0 || c->objects_timeout_ns <= 0)
		*what = "timeout: expected a positive time";
	else if (c->e2e_max_errors < 1)
		*what = "E2E errors: expected at least 1";
	else if (!(b->preview_s > 0.0 && b->preview_min_m > 0.0 &&
		   b->preview_max_m >= b->preview_min_m && b->max_deg > 0.0 && b->max_deg <= 90.0 &&
		   b->min_speed_mps >= 0.0))
		*what = "bend: expected preview > 0, 0 < min <= max distance, max swivel in (0, 90]";
	else
		return 0;
	return -EINVAL;
}

static int lamp_init(struct lamp *l, const struct hl_ecu_lamp *in, double fraction,
		     const char **what)
{
	const char **names;
	int rc;

	l->lid = in->lid;
	l->mount = in->mount;
	l->n = hl_lid_n_sources(in->lid);
	if (hl_lid_is_combined(in->lid)) {
		*what = "lamp: a combined LID has no sources";
		return -EINVAL;
	}
	for (int k = 0; k < l->n; k++)
		if (!(in->low[k] >= 0.0f && in->low[k] <= 1.0f && in->high[k] >= 0.0f &&
		      in->high[k] <= 1.0f)) {
			*what = "beam: expected relative currents in [0, 1]";
			return -EINVAL;
		}
	l->low = malloc(sizeof(float) * (size_t)l->n);
	l->high = malloc(sizeof(float) * (size_t)l->n);
	l->base = malloc(sizeof(float) * (size_t)l->n);
	l->out = malloc(sizeof(float) * (size_t)l->n);
	l->windows = malloc(sizeof(*l->windows) * (size_t)l->n);
	names = malloc(sizeof(*names) * (size_t)l->n);
	if (!l->low || !l->high || !l->base || !l->out || !l->windows || !names) {
		free(names);
		return -ENOMEM;
	}
	memcpy(l->low, in->low, sizeof(float) * (size_t)l->n);
	memcpy(l->high, in->high, sizeof(float) * (size_t)l->n);
	memcpy(l->out, in->low, sizeof(float) * (size_t)l->n);
	rc = hl_ecu_windows(in->lid, l->high, fraction, l->windows);
	for (int k = 0; rc == 0 && k < l->n; k++)
		names[k] = hl_lid_name(in->lid, k);
	if (rc == 0)
		rc = hl_ecu_rows_new(l->windows, names, l->n, &l->rows);
	free(names);
	return rc;
}

int hl_ecu_new(const struct hl_ecu_config *c, const struct hl_ecu_lamp *lamps, int n_lamps,
	       struct hl_ecu **ret, const char **ret_what)
{
	const char *what = NULL;
	struct hl_ecu *e;
	int rc;

	if (n_lamps < 1 || n_lamps > HL_ECU_MAX_LAMPS) {
		what = "lamps: expected 1 to 8";
		rc = -EINVAL;
		goto err_what;
	}
	rc = check_config(c, &what);
	if (rc < 0)
		goto err_what;
	e = calloc(1, sizeof(*e));
	if (!e)
		return -ENOMEM;
	e->c = *c;
	e->n_lamps = n_lamps;
	for (int i = 0; i < n_lamps; i++) {
		rc = lamp_init(&e->lamp[i], &lamps[i], c->window_fraction, &what);
		if (rc < 0)
			goto err_free;
	}
	*ret = e;
	return 0;

err_free:
	hl_ecu_free(e);
err_what:
	if (ret_what)
		*ret_what = what;
	return rc;
}

void hl_ecu_free(struct hl_ecu *e)
{
	if (!e)
		return;
	for (int i = 0; i < HL_ECU_MAX_LAMPS; i++) {
		struct lamp *l = &e->lamp[i];

		free(l->low);
		free(l->high);
		free(l->base);
		free(l->out);
		free(l->windows);
		hl_ecu_rows_free(l->rows);
	}
	free(e);
}

void hl_ecu_vehicle(struct hl_ecu *e, const struct hl_vehicle_state *s, int64_t t_rx_ns)
{
	e->vehicle = *s;
	e->in[HL_ECU_INPUT_VEHICLE] = (struct input){ .have = true, .t_rx_ns = t_rx_ns };
}

void hl_ecu_objects(struct hl_ecu *e, const struct hl_camera_objects *o, int64_t t_rx_ns)
{
	e->objects = *o;
	if (e->objects.n < 0)
		e->objects.n = 0;
	if (e->objects.n > HL_INPUTS_MAX_OBJECTS)
		e->objects.n = HL_INPUTS_MAX_OBJECTS;
	e->in[HL_ECU_INPUT_OBJECTS] = (struct input){ .have = true, .t_rx_ns = t_rx_ns };
}

void hl_ecu_input_error(struct hl_ecu *e, enum hl_ecu_input in)
{
	e->in[in].e2e_run++;
}

static unsigned input_faults(const struct hl_ecu *e, enum hl_ecu_input in, int64_t now_ns)
{
	const struct input *i = &e->in[in];
	const int64_t timeout = in == HL_ECU_INPUT_VEHICLE ? e->c.vehicle_timeout_ns :
							     e->c.objects_timeout_ns;
	unsigned f = 0;

	if (!i->have || now_ns - i->t_rx_ns > timeout)
		f |= in == HL_ECU_INPUT_VEHICLE ? HL_ECU_FS_VEHICLE_MISSING :
						  HL_ECU_FS_OBJECTS_MISSING;
	if (i->e2e_run >= e->c.e2e_max_errors)
		f |= in == HL_ECU_INPUT_VEHICLE ? HL_ECU_FS_VEHICLE_E2E : HL_ECU_FS_OBJECTS_E2E;
	return f;
}

static bool object_valid(const struct hl_camera_object *o)
{
	return isfinite(o->h_left_deg) && isfinite(o->h_right_deg) && isfinite(o->v_bottom_deg) &&
	       isfinite(o->v_top_deg) && isfinite(o->distance_m) &&
	       o->h_left_deg <= o->h_right_deg && o->v_bottom_deg <= o->v_top_deg &&
	       o->distance_m > 0.0;
}

/* Marks the relevant objects in rel (by index); counts the others in st. */
static int relevant_objects(const struct hl_ecu *e, bool *rel, struct hl_ecu_status *st)
{
	int n = 0;

	for (int i = 0; i < e->objects.n; i++) {
		const struct hl_camera_object *o = &e->objects.obj[i];
		const bool cls = o->cls == HL_OBJECT_ONCOMING || o->cls == HL_OBJECT_PRECEDING ||
				 o->cls == HL_OBJECT_PEDESTRIAN;

		rel[i] = false;
		if (!object_valid(o))
			st->invalid++;
		else if (!cls || !(o->confidence >= e->c.min_confidence) ||
			 (e->c.faults & HL_ECU_FAULT_IGNORE_OBJECTS))
			st->ignored++;
		else
			rel[i] = true, n++;
	}
	return n;
}

static int mask_lamp(const struct hl_ecu *e, const struct lamp *l, const bool *rel)
{
	const enum hl_angles sys = hl_lid_grid(l->lid)->angles;
	const double m = e->c.margin_deg;
	int masked = 0;

	for (int i = 0; i < e->objects.n; i++) {
		const struct hl_camera_object *o = &e->objects.obj[i];
		struct hl_ecu_box b;
		double mh;

		if (!rel[i])
			continue;
		hl_ecu_box_to_lamp(&e->c.camera, &l->mount, sys, o->h_left_deg, o->h_right_deg,
				   o->v_bottom_deg, o->v_top_deg, o->distance_m, &b);
		mh = m + atan(e->c.margin_m / o->distance_m) * (180.0 / M_PI);
		for (int k = 0; k < l->n; k++) {
			if (l->out[k] == 0.0f ||
			    !hl_ecu_window_overlaps(&l->windows[k], b.h0_deg - mh, b.h1_deg + mh,
						    b.v0_deg - m, b.v1_deg + m))
				continue;
			l->out[k] = 0.0f;
			masked++;
		}
	}
	return masked;
}

void hl_ecu_step(struct hl_ecu *e, int64_t now_ns, struct hl_ecu_status *ret)
{
	const struct hl_vehicle_state *v = &e->vehicle;
	bool rel[HL_INPUTS_MAX_OBJECTS];
	enum hl_ecu_mode mode;

	memset(ret, 0, sizeof(*ret));
	if (!(e->c.faults & HL_ECU_FAULT_NO_FAILSAFE) || !e->in[0].have || !e->in[1].have)
		ret->failsafe = input_faults(e, HL_ECU_INPUT_VEHICLE, now_ns) |
				input_faults(e, HL_ECU_INPUT_OBJECTS, now_ns);
	if (ret->failsafe) {
		ret->mode = HL_ECU_LOW;
		for (int i = 0; i < e->n_lamps; i++)
			memcpy(e->lamp[i].out, e->lamp[i].low,
			       sizeof(float) * (size_t)e->lamp[i].n);
		return;
	}
	ret->objects = relevant_objects(e, rel, ret);
	switch (v->light_switch) {
	case HL_SWITCH_OFF:
		mode = HL_ECU_OFF;
		break;
	case HL_SWITCH_HIGH:
		mode = v->adb_enable ? HL_ECU_GLAREFREE : HL_ECU_HIGH;
		break;
	case HL_SWITCH_AUTO:
		if (!(v->speed_mps >= e->c.auto_high_mps))
			mode = HL_ECU_LOW;
		else if (v->adb_enable)
			mode = HL_ECU_GLAREFREE;
		else
			mode = ret->objects > 0 ? HL_ECU_LOW : HL_ECU_HIGH;
		break;
	case HL_SWITCH_LOW:
	default:
		mode = HL_ECU_LOW;
		break;
	}
	ret->mode = mode;
	if (mode != HL_ECU_OFF && e->c.bend)
		ret->swivel_deg =
			hl_ecu_bend_swivel_deg(&e->c.bend_config, v->speed_mps, v->yaw_rate_rad_s);
	for (int i = 0; i < e->n_lamps; i++) {
		struct lamp *l = &e->lamp[i];

		if (mode == HL_ECU_OFF) {
			memset(l->out, 0, sizeof(float) * (size_t)l->n);
			continue;
		}
		memcpy(l->base, mode == HL_ECU_LOW ? l->low : l->high,
		       sizeof(float) * (size_t)l->n);
		hl_ecu_rows_turn(l->rows, l->base, ret->swivel_deg, e->c.bend_config.max_deg,
				 l->out);
		if (mode == HL_ECU_GLAREFREE)
			ret->masked[i] = mask_lamp(e, l, rel);
	}
}

const float *hl_ecu_output(const struct hl_ecu *e, int lamp)
{
	return e->lamp[lamp].out;
}

const struct hl_ecu_window *hl_ecu_windows_of(const struct hl_ecu *e, int lamp)
{
	return e->lamp[lamp].windows;
}

const struct hl_ecu_rows *hl_ecu_rows_of(const struct hl_ecu *e, int lamp)
{
	return e->lamp[lamp].rows;
}
