/* SPDX-License-Identifier: MIT */
/*
 * The map's body, shared by the map and encoder (can/inputs.c) and the decoder
 * (can/inputs_decoder.c); not for callers outside can/.
 */
#ifndef HL_CAN_INPUTS_INTERNAL_H
#define HL_CAN_INPUTS_INTERNAL_H

#include <math.h>

#include "can/inputs.h"

#define DEG (M_PI / 180.0)
#define KMH (1.0 / 3.6) /* m/s per km/h */

enum { VF_SPEED, VF_YAW, VF_STEER, VF_SWITCH, VF_ADB, VF_N };

enum { OF_COUNT, OF_ID, OF_CLASS, OF_HL, OF_HR, OF_VB, OF_VT, OF_DIST, OF_CONF, OF_N };

struct hl_inputs_obj_msg {
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
	struct hl_inputs_obj_msg obj[HL_INPUTS_MAX_OBJ_MESSAGES]; /* obj[k] is m[1 + k] */
	int slots;
};

#endif
