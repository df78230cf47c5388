/* SPDX-License-Identifier: MIT */
/*
 * The ECU's named Real inputs and outputs (ecu/io.h). The input vector is laid out as
 *   the vehicle fields (speed, yaw_rate, steering, light_switch, adb_enable),
 *   the object count,
 *   per object field (id, class, h_left, h_right, v_bottom, v_top, distance, confidence) its
 *   slots 0..slots-1,
 *   COM_VehicleRxTime, COM_ObjectsRxTime, COM_VehicleE2EErrors, COM_ObjectsE2EErrors;
 * the outputs are every lamp's sources, lamp by lamp.
 */
#include "ecu/io.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/*
 * The unit conversions of the input database's decoder (can/inputs_decoder.c): the host side
 * divides by them, the model side multiplies like the decoder does.
 */
#define DEG (M_PI / 180.0) /* rad per deg */
#define KMH (1.0 / 3.6) /* m/s per km/h */
#define NS_PER_S 1e9

#define NAME_MAX_LEN 255 /* of an input or output name */
#define MAX_ERRORS_PER_STEP 65535 /* E2E errors fed to the ECU by one apply */

enum { IN_SPEED, IN_YAW, IN_STEER, IN_SWITCH, IN_ADB, IN_COUNT, IN_OBJ };
enum { OBJ_ID, OBJ_CLASS, OBJ_HL, OBJ_HR, OBJ_VB, OBJ_VT, OBJ_DIST, OBJ_CONF, OBJ_N };
enum { COM_VEH_RX, COM_OBJ_RX, COM_VEH_E2E, COM_OBJ_E2E, COM_N };

static const char *const vehicle_field[] = { "speed", "yaw_rate", "steering", "light_switch",
					     "adb_enable" };
static const char *const object_field[OBJ_N] = { "id",	     "class", "h_left",	  "h_right",
						 "v_bottom", "v_top", "distance", "confidence" };
static const char *const com_name[COM_N] = { "COM_VehicleRxTime", "COM_ObjectsRxTime",
					     "COM_VehicleE2EErrors", "COM_ObjectsE2EErrors" };

struct hl_ecu_io {
	int slots;
	int n_in, n_out;
	char **in_names, **out_names;
	int n_lamps;
	int first[HL_ECU_MAX_LAMPS], sources[HL_ECU_MAX_LAMPS];
};

static int fail(char *err, size_t size, int rc, const char *fmt, ...)
	__attribute__((format(printf, 4, 5)));
static int fail(char *err, size_t size, int rc, const char *fmt, ...)
{
	va_list ap;

	if (err && size > 0) {
		va_start(ap, fmt);
		vsnprintf(err, size, fmt, ap);
		va_end(ap);
	}
	return rc;
}

static int obj_index(const struct hl_ecu_io *io, int field, int slot)
{
	return IN_OBJ + field * io->slots + slot;
}

static int com_index(const struct hl_ecu_io *io, int which)
{
	return IN_OBJ + OBJ_N * io->slots + which;
}

/* names[i] = the formatted name; -EINVAL when too long, -ENOMEM. */
static int set_name(char **names, int i, char *err, size_t size, const char *fmt, ...)
	__attribute__((format(printf, 5, 6)));
static int set_name(char **names, int i, char *err, size_t size, const char *fmt, ...)
{
	char buf[NAME_MAX_LEN + 1];
	va_list ap;
	int n;

	va_start(ap, fmt);
	n = vsnprintf(buf, sizeof(buf), fmt, ap);
	va_end(ap);
	if (n < 0 || n > NAME_MAX_LEN)
		return fail(err, size, -EINVAL, "the name '%.40s...' is longer than %d characters",
			    buf, NAME_MAX_LEN);
	names[i] = strdup(buf);
	return names[i] ? 0 : -ENOMEM;
}

static const struct hl_dbc_signal *signal_of(const struct hl_inputs_map *map, const char *field,
					     int slot, char *err, size_t size)
{
	const struct hl_dbc_signal *s = hl_inputs_map_signal(map, field, slot);

	if (!s)
		fail(err, size, -EINVAL,
		     "the input database has no signal for the field '%s' (slot %d)", field, slot);
	return s;
}

static int name_inputs(struct hl_ecu_io *io, const struct hl_inputs_map *map, char *err,
		       size_t size)
{
	const struct hl_dbc_signal *s;
	int rc;

	for (int f = 0; f < IN_COUNT; f++) {
		s = signal_of(map, vehicle_field[f], 0, err, size);
		if (!s)
			return -EINVAL;
		rc = set_name(io->in_names, f, err, size, "%s", s->name);
		if (rc < 0)
			return rc;
	}
	s = signal_of(map, "object_count", 0, err, size);
	if (!s)
		return -EINVAL;
	rc = set_name(io->in_names, IN_COUNT, err, size, "%s", s->name);
	for (int f = 0; rc == 0 && f < OBJ_N; f++)
		for (int k = 0; rc == 0 && k < io->slots; k++) {
			s = signal_of(map, object_field[f], k, err, size);
			if (!s)
				return -EINVAL;
			rc = set_name(io->in_names, obj_index(io, f, k), err, size, "%s[%d]",
				      s->name, k);
		}
	for (int c = 0; rc == 0 && c < COM_N; c++)
		rc = set_name(io->in_names, com_index(io, c), err, size, "%s", com_name[c]);
	return rc;
}

static int name_outputs(struct hl_ecu_io *io, const struct hl_lid *const *lids,
			const char *const *lamp_names, char *err, size_t size)
{
	for (int l = 0; l < io->n_lamps; l++)
		for (int k = 0; k < io->sources[l]; k++) {
			const char *src = hl_lid_name(lids[l], k);
			int rc;

			/* an unnamed source as its LID file channel (docs/lid-files.md) */
			if (src)
				rc = set_name(io->out_names, io->first[l] + k, err, size, "%s.%s",
					      lamp_names[l], src);
			else
				rc = set_name(io->out_names, io->first[l] + k, err, size,
					      "%s.src%04d", lamp_names[l], k + 1);
			if (rc < 0)
				return rc;
		}
	return 0;
}

int hl_ecu_io_new(const struct hl_inputs_map *map, const struct hl_lid *const *lids,
		  const char *const *lamp_names, int n_lamps, struct hl_ecu_io **ret, char *err,
		  size_t err_size)
{
	struct hl_ecu_io *io;
	int rc;

	if (n_lamps < 1 || n_lamps > HL_ECU_MAX_LAMPS)
		return fail(err, err_size, -EINVAL, "%d lamps: expected 1..%d", n_lamps,
			    HL_ECU_MAX_LAMPS);
	io = calloc(1, sizeof(*io));
	if (!io)
		return -ENOMEM;
	io->slots = hl_inputs_map_slots(map);
	io->n_in = IN_OBJ + OBJ_N * io->slots + COM_N;
	io->n_lamps = n_lamps;
	for (int l = 0; l < n_lamps; l++) {
		io->first[l] = io->n_out;
		io->sources[l] = hl_lid_n_sources(lids[l]);
		io->n_out += io->sources[l];
	}
	io->in_names = calloc((size_t)io->n_in, sizeof(char *));
	io->out_names = calloc((size_t)io->n_out, sizeof(char *));
	if (!io->in_names || !io->out_names) {
		rc = -ENOMEM;
		goto err_free;
	}
	rc = name_inputs(io, map, err, err_size);
	if (rc == 0)
		rc = name_outputs(io, lids, lamp_names, err, err_size);
	if (rc < 0)
		goto err_free;
	*ret = io;
	return 0;

err_free:
	hl_ecu_io_free(io);
	return rc;
}

void hl_ecu_io_free(struct hl_ecu_io *io)
{
	if (!io)
		return;
	for (int i = 0; io->in_names && i < io->n_in; i++)
		free(io->in_names[i]);
	for (int i = 0; io->out_names && i < io->n_out; i++)
		free(io->out_names[i]);
	free(io->in_names);
	free(io->out_names);
	free(io);
}

int hl_ecu_io_n_inputs(const struct hl_ecu_io *io)
{
	return io->n_in;
}

const char *hl_ecu_io_input_name(const struct hl_ecu_io *io, int i)
{
	return i >= 0 && i < io->n_in ? io->in_names[i] : NULL;
}

int hl_ecu_io_input_index(const struct hl_ecu_io *io, const char *name)
{
	for (int i = 0; i < io->n_in; i++)
		if (strcmp(io->in_names[i], name) == 0)
			return i;
	return -ENOENT;
}

int hl_ecu_io_n_outputs(const struct hl_ecu_io *io)
{
	return io->n_out;
}

const char *hl_ecu_io_output_name(const struct hl_ecu_io *io, int i)
{
	return i >= 0 && i < io->n_out ? io->out_names[i] : NULL;
}

int hl_ecu_io_output_index(const struct hl_ecu_io *io, const char *name)
{
	for (int i = 0; i < io->n_out; i++)
		if (strcmp(io->out_names[i], name) == 0)
			return i;
	return -ENOENT;
}

int hl_ecu_io_lamp_first(const struct hl_ecu_io *io, int lamp)
{
	return lamp >= 0 && lamp < io->n_lamps ? io->first[lamp] : -EINVAL;
}

int hl_ecu_io_lamp_sources(const struct hl_ecu_io *io, int lamp)
{
	return lamp >= 0 && lamp < io->n_lamps ? io->sources[lamp] : -EINVAL;
}

/* --- host side --- */

void hl_ecu_io_init_inputs(const struct hl_ecu_io *io, double *in)
{
	for (int i = 0; i < io->n_in; i++)
		in[i] = 0;
	in[com_index(io, COM_VEH_RX)] = -1;
	in[com_index(io, COM_OBJ_RX)] = -1;
}

void hl_ecu_io_set_vehicle(const struct hl_ecu_io *io, const struct hl_vehicle_state *s,
			   int64_t t_rx_ns, double *in)
{
	in[IN_SPEED] = s->speed_mps / KMH;
	in[IN_YAW] = s->yaw_rate_rad_s / DEG;
	in[IN_STEER] = s->steering_rad / DEG;
	in[IN_SWITCH] = (double)s->light_switch;
	in[IN_ADB] = s->adb_enable ? 1 : 0;
	in[com_index(io, COM_VEH_RX)] = (double)t_rx_ns / NS_PER_S;
	in[com_index(io, COM_VEH_E2E)] = 0;
}

void hl_ecu_io_set_objects(const struct hl_ecu_io *io, const struct hl_camera_objects *o,
			   int64_t t_rx_ns, double *in)
{
	int n = o->n < 0 ? 0 : o->n > io->slots ? io->slots : o->n;

	in[IN_COUNT] = n;
	for (int k = 0; k < io->slots; k++) {
		const struct hl_camera_object *ob = &o->obj[k];
		const double v[OBJ_N] = { ob->id,	   (double)ob->cls,  ob->h_left_deg,
					  ob->h_right_deg, ob->v_bottom_deg, ob->v_top_deg,
					  ob->distance_m,  ob->confidence };

		for (int f = 0; f < OBJ_N; f++)
			in[obj_index(io, f, k)] = k < n ? v[f] : 0;
	}
	in[com_index(io, COM_OBJ_RX)] = (double)t_rx_ns / NS_PER_S;
	in[com_index(io, COM_OBJ_E2E)] = 0;
}

void hl_ecu_io_set_e2e_error(const struct hl_ecu_io *io, enum hl_ecu_input which, double *in)
{
	in[com_index(io, which == HL_ECU_INPUT_VEHICLE ? COM_VEH_E2E : COM_OBJ_E2E)] += 1;
}

/* --- model side --- */

void hl_ecu_io_model_init(struct hl_ecu_io_model *m)
{
	*m = (struct hl_ecu_io_model){ .vehicle_rx_s = -1, .objects_rx_s = -1 };
}

/* v rounded to a whole number in [lo, hi]; NaN as lo (an FMU's host may set anything). */
static int whole(double v, int lo, int hi)
{
	if (!(v >= lo))
		return lo;
	if (v > hi)
		return hi;
	return (int)lround(v);
}

static void apply_vehicle(const double *in, double rx_s, struct hl_ecu *e)
{
	const struct hl_vehicle_state s = {
		.speed_mps = in[IN_SPEED] * KMH,
		.yaw_rate_rad_s = in[IN_YAW] * DEG,
		.steering_rad = in[IN_STEER] * DEG,
		.light_switch =
			(enum hl_light_switch)whole(in[IN_SWITCH], HL_SWITCH_OFF, HL_SWITCH_HIGH),
		.adb_enable = whole(in[IN_ADB], 0, 1) == 1,
	};

	hl_ecu_vehicle(e, &s, llround(rx_s * NS_PER_S));
}

static void apply_objects(const struct hl_ecu_io *io, const double *in, double rx_s,
			  struct hl_ecu *e)
{
	struct hl_camera_objects o = { .n = whole(in[IN_COUNT], 0, io->slots) };

	for (int k = 0; k < o.n; k++)
		o.obj[k] = (struct hl_camera_object){
			.id = (unsigned)whole(in[obj_index(io, OBJ_ID, k)], 0, 255),
			.cls = (enum hl_object_class)whole(in[obj_index(io, OBJ_CLASS, k)],
							   HL_OBJECT_OTHER, HL_OBJECT_PEDESTRIAN),
			.h_left_deg = in[obj_index(io, OBJ_HL, k)],
			.h_right_deg = in[obj_index(io, OBJ_HR, k)],
			.v_bottom_deg = in[obj_index(io, OBJ_VB, k)],
			.v_top_deg = in[obj_index(io, OBJ_VT, k)],
			.distance_m = in[obj_index(io, OBJ_DIST, k)],
			.confidence = in[obj_index(io, OBJ_CONF, k)],
		};
	hl_ecu_objects(e, &o, llround(rx_s * NS_PER_S));
}

/* The E2E errors counted since the model last looked, fed one by one. */
static void apply_errors(double count, double *seen, enum hl_ecu_input which, struct hl_ecu *e)
{
	double n = count - *seen;

	if (!(n >= 1))
		n = 0;
	if (n > MAX_ERRORS_PER_STEP)
		n = MAX_ERRORS_PER_STEP;
	for (int i = 0; i < (int)n; i++)
		hl_ecu_input_error(e, which);
	*seen = isfinite(count) ? count : *seen;
}

void hl_ecu_io_apply(const struct hl_ecu_io *io, struct hl_ecu_io_model *m, const double *in,
		     struct hl_ecu *e)
{
	const double veh_rx = in[com_index(io, COM_VEH_RX)];
	const double obj_rx = in[com_index(io, COM_OBJ_RX)];

	/* a new message resets the count of errors since the last accepted one */
	if (veh_rx >= 0 && veh_rx != m->vehicle_rx_s) {
		apply_vehicle(in, veh_rx, e);
		m->vehicle_rx_s = veh_rx;
		m->vehicle_errors = 0;
	}
	if (obj_rx >= 0 && obj_rx != m->objects_rx_s) {
		apply_objects(io, in, obj_rx, e);
		m->objects_rx_s = obj_rx;
		m->objects_errors = 0;
	}
	apply_errors(in[com_index(io, COM_VEH_E2E)], &m->vehicle_errors, HL_ECU_INPUT_VEHICLE, e);
	apply_errors(in[com_index(io, COM_OBJ_E2E)], &m->objects_errors, HL_ECU_INPUT_OBJECTS, e);
}

void hl_ecu_io_outputs(const struct hl_ecu_io *io, const struct hl_ecu *e, double *out)
{
	for (int l = 0; l < io->n_lamps; l++) {
		const float *v = hl_ecu_output(e, l);

		for (int k = 0; k < io->sources[l]; k++)
			out[io->first[l] + k] = v[k];
	}
}
