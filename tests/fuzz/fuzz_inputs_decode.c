/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target: any sequence of frames fed to the ECU's input decoder on
 * dbc/hd84_inputs.dbc (can/inputs_decoder.c) never reads out of bounds, counts every frame in
 * exactly one outcome, and hands out only states a struct can hold: a complete cycle has 0..8
 * objects, each with a class of the enum, left edge <= right edge, bottom <= top, a distance
 * >= 0 and a confidence in 0..1; a vehicle state has a light switch of the enum.
 *
 * Input: records of [selector][length][payload]: selector bits 0..1 pick the message (3: an ID
 * no input has), bit 6 seals the payload with the message's E2E (so the fuzzer gets past the
 * CRC), bits 2..5 the counter it seals with; length % 9 bytes of payload follow.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "can/inputs.h"

static struct hl_dbc *db;
static struct hl_inputs_map *map;

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	(void)argc;
	(void)argv;
	if (hl_dbc_parse_file(HL_DBC_DIR "/hd84_inputs.dbc", &db, NULL) < 0 ||
	    hl_inputs_map_new(db, &map, NULL, 0) < 0)
		abort();
	return 0;
}

static void check_objects(const struct hl_camera_objects *o)
{
	if (o->n < 0 || o->n > HL_INPUTS_MAX_OBJECTS)
		abort();
	for (int i = 0; i < o->n; i++) {
		const struct hl_camera_object *b = &o->obj[i];

		if (b->cls < HL_OBJECT_OTHER || b->cls > HL_OBJECT_PEDESTRIAN ||
		    !(b->h_left_deg <= b->h_right_deg) || !(b->v_bottom_deg <= b->v_top_deg) ||
		    !(b->distance_m >= 0) || !(b->confidence >= 0 && b->confidence <= 1) ||
		    b->id > 255)
			abort();
	}
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct hl_inputs_decoder *d;
	const struct hl_inputs_counters *c;
	size_t at = 0;

	if (hl_inputs_decoder_new(map, &d) < 0)
		abort();
	while (at + 2 <= size) {
		const uint8_t sel = data[at], len = data[at + 1] % 9;
		const int mi = sel & 3;
		struct hl_vehicle_state vs;
		struct hl_camera_objects o;
		uint32_t id = 0x7ff;
		uint8_t *frame;
		int rc;

		at += 2;
		if (len > size - at)
			break;
		/* an exact-size heap copy, so that ASan sees any read past the frame */
		frame = malloc(len ? len : 1);
		if (!frame)
			abort();
		memcpy(frame, data + at, len);
		at += len;
		if (mi < hl_inputs_map_n_messages(map)) {
			const struct hl_inputs_message *im = hl_inputs_map_message(map, mi);

			id = im->msg->can_id;
			if ((sel & 0x40) && len >= 8 && im->e2e.profile != HL_E2E_NONE)
				hl_e2e_protect(&im->e2e, frame, len, ((sel >> 2) & 15) % 15);
		}
		rc = hl_inputs_decode(d, id, frame, len, &vs, &o);
		if (rc == HL_INPUTS_OBJECTS)
			check_objects(&o);
		if (rc == HL_INPUTS_VEHICLE &&
		    (vs.light_switch < HL_SWITCH_OFF || vs.light_switch > HL_SWITCH_HIGH))
			abort();
		free(frame);
	}
	c = hl_inputs_decoder_counters(d);
	if (c->frames != c->unknown_id + c->short_frames + c->crc_errors + c->counter_repeated +
				 c->bad_values + c->duplicates + c->vehicle_states +
				 c->object_frames)
		abort();
	hl_inputs_decoder_free(d);
	return 0;
}
