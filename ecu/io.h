/* SPDX-License-Identifier: MIT */
/*
 * The ECU's inputs and outputs as named Real values (docs/ecu.md, "The ECU as an FMU"): the
 * interface an ECU in the loop is driven through, the in-process reference ECU and an FMU
 * alike, so that both see exactly the same numbers.
 *
 * The host side (the ECU node of software in the loop) receives the input database's messages
 * (can/inputs.h: decoded, E2E-checked, a camera cycle assembled from its frames) and, once per
 * ECU step, fills the input vector:
 *   - the vehicle state's signals, named after the input database's signals of its fields
 *     (hd84_inputs.dbc: VEH_Speed km/h, VEH_YawRate deg/s, VEH_SteeringAngle deg,
 *     VEH_LightSwitch 0..3, VEH_AdbEnable 0/1), in the database's units;
 *   - the newest complete camera cycle: its object count (CAMI_ObjCount) and per slot k
 *     (0-based, k < HL_INPUTS_MAX_OBJECTS) every object field's signal as NAME[k]
 *     (CAMI_ObjId[k], CAMI_ObjClass[k], CAMI_Distance[k] m, CAMI_Confidence[k],
 *     CAMB_HLeft[k], CAMB_HRight[k], CAMB_VBottom[k], CAMB_VTop[k] deg); slots at or past the
 *     count are 0;
 *   - the communication stack's status, names of ours: COM_VehicleRxTime and
 *     COM_ObjectsRxTime (s, the simulation time the newest accepted message / complete cycle
 *     was received; -1 before the first), COM_VehicleE2EErrors and COM_ObjectsE2EErrors
 *     (messages in a row that failed their E2E check since the last accepted one).
 * The ECU's outputs are each lamp's source intensities, 0..1, named "<lamp>.<source>" after the
 * lamp's name (left, right) and the LID's source names (left.row1_led01, ...).
 *
 * The model side (the reference ECU, in process or inside the exported FMU) turns the input
 * vector back into the lighting functions' calls (ecu/lighting.h): a new vehicle state or
 * camera cycle when its receive time changed (with that receive time), and E2E errors when the
 * count rose. Both sides are this file, so the in-process reference ECU and its FMU compute the
 * same bits.
 *
 * Exact by construction: the host side writes the decoded struct back in the database's units
 * (the inverse of can/inputs_decoder.c's km/h and deg conversions, receive times as t_rx_ns / 1e9),
 * the model side converts like the decoder (receive times rounded back to whole ns). struct ->
 * values -> struct may differ from the struct in the last bit of a converted value, so every ECU
 * in the loop, in process or in an FMU, always takes this roundtrip and sees the same bits. The
 * model side rounds and clamps what must be whole (switch 0..3, ADB 0/1, count 0..slots, class
 * 0..3, id 0..255): an FMU's importer may set any Real.
 *
 * Thread-safety: an hl_ecu_io is read-only after hl_ecu_io_new(); the model state belongs to
 * its caller.
 */
#ifndef HL_ECU_IO_H
#define HL_ECU_IO_H

#include <stddef.h>
#include <stdint.h>

#include "can/inputs.h"
#include "ecu/lighting.h"
#include "lamp/lid.h"

struct hl_ecu_io;

/*
 * The interface of an ECU for the input database map and n_lamps lamps (names[l], lids[l]).
 * 0, -EINVAL (a name too long, a field without its signal: err names it), -ENOMEM.
 */
int hl_ecu_io_new(const struct hl_inputs_map *map, const struct hl_lid *const *lids,
		  const char *const *lamp_names, int n_lamps, struct hl_ecu_io **ret, char *err,
		  size_t err_size);
void hl_ecu_io_free(struct hl_ecu_io *io);

int hl_ecu_io_n_inputs(const struct hl_ecu_io *io);
const char *hl_ecu_io_input_name(const struct hl_ecu_io *io, int i);
/* The index of the input called name, or -ENOENT. */
int hl_ecu_io_input_index(const struct hl_ecu_io *io, const char *name);
int hl_ecu_io_n_outputs(const struct hl_ecu_io *io); /* every lamp's sources, lamp by lamp */
const char *hl_ecu_io_output_name(const struct hl_ecu_io *io, int i);
int hl_ecu_io_output_index(const struct hl_ecu_io *io, const char *name);
/* Output index of lamp l's source 0 (its sources follow in order), and its count. */
int hl_ecu_io_lamp_first(const struct hl_ecu_io *io, int lamp);
int hl_ecu_io_lamp_sources(const struct hl_ecu_io *io, int lamp);

/* Host side: the input vector in[n_inputs] before the first message (all 0, times -1). */
void hl_ecu_io_init_inputs(const struct hl_ecu_io *io, double *in);
/* Host side: an accepted vehicle state / a complete camera cycle received at t_rx_ns. */
void hl_ecu_io_set_vehicle(const struct hl_ecu_io *io, const struct hl_vehicle_state *s,
			   int64_t t_rx_ns, double *in);
void hl_ecu_io_set_objects(const struct hl_ecu_io *io, const struct hl_camera_objects *o,
			   int64_t t_rx_ns, double *in);
/* Host side: a message of input which failed its E2E check (counts up until the next accepted). */
void hl_ecu_io_set_e2e_error(const struct hl_ecu_io *io, enum hl_ecu_input which, double *in);

/* Model side: what it has taken from the inputs so far. */
struct hl_ecu_io_model {
	double vehicle_rx_s, objects_rx_s; /* -1: none yet */
	double vehicle_errors, objects_errors;
};
void hl_ecu_io_model_init(struct hl_ecu_io_model *m);
/*
 * Model side, before a step: feeds e with what changed in in[] since the last call (a new
 * vehicle state or camera cycle with its receive time, new E2E errors).
 */
void hl_ecu_io_apply(const struct hl_ecu_io *io, struct hl_ecu_io_model *m, const double *in,
		     struct hl_ecu *e);
/* Model side, after hl_ecu_step(): every lamp's intensities into out[n_outputs]. */
void hl_ecu_io_outputs(const struct hl_ecu_io *io, const struct hl_ecu *e, double *out);

#endif
