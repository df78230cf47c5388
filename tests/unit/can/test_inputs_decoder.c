/* SPDX-License-Identifier: MIT */
/*
 * The ECU's input codec on dbc/hd84_inputs.dbc: every input signal encoded and decoded back at
 * its minimum, maximum and values between, exact to its resolution; the bits of a frame against
 * a hand-computed layout; the camera-cycle rule; E2E faults; databases lacking an attribute.
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "can/inputs.h"
#include "inputs_fixture.h"

static void decode_vehicle(struct fixture *f, const struct hl_inputs_frame *fr,
			   struct hl_vehicle_state *ret)
{
	struct hl_camera_objects o;

	assert_int_equal(hl_inputs_decode(f->dec, fr->can_id, fr->data, fr->len, ret, &o),
			 HL_INPUTS_VEHICLE);
}

static void decode_all(struct fixture *f, const struct hl_inputs_frame *fr, int n,
		       struct hl_camera_objects *ret)
{
	struct hl_vehicle_state vs;

	for (int i = 0; i < n; i++)
		/* only the last frame completes the cycle */
		assert_int_equal(hl_inputs_decode(f->dec, fr[i].can_id, fr[i].data, fr[i].len, &vs,
						  ret),
				 i == n - 1 ? HL_INPUTS_OBJECTS : 0);
}

static struct hl_camera_objects three_objects(void)
{
	struct hl_camera_objects o = { .n = 3 };

	for (int i = 0; i < 3; i++)
		o.obj[i] = (struct hl_camera_object){
			10 + i, HL_OBJECT_ONCOMING, -5 + i, -4 + i, -0.5, 0.2, 80, 0.75
		};
	return o;
}

static void inputs_e2e_crc_and_counters(void **state)
{
	struct fixture *f = *state;
	const struct hl_inputs_counters *c = hl_inputs_decoder_counters(f->dec);
	struct hl_vehicle_state vs = { 20, 0, 0, HL_SWITCH_LOW, false }, out;
	struct hl_camera_objects o;
	struct hl_inputs_frame fr;

	/* one flipped bit anywhere fails the CRC */
	for (int bit = 0; bit < 64; bit++) {
		struct hl_inputs_frame bad;

		assert_int_equal(hl_inputs_encode_vehicle(f->map, &vs, 3, &bad), 0);
		bad.data[bit / 8] ^= (uint8_t)(1u << (bit % 8));
		assert_int_equal(hl_inputs_decode(f->dec, bad.can_id, bad.data, bad.len, &out, &o),
				 -EBADMSG);
	}
	assert_int_equal(c->crc_errors, 64);
	assert_int_equal(c->vehicle_states, 0);
	/* the same frame under another message's data ID fails too */
	assert_int_equal(hl_inputs_encode_vehicle(f->map, &vs, 3, &fr), 0);
	assert_int_equal(hl_inputs_decode(f->dec, 0x122, fr.data, fr.len, &out, &o), -EBADMSG);
	/* counters: 3 ok, 3 again repeated (dropped), 6 lost two, 14 -> 0 wraps */
	decode_vehicle(f, &fr, &out);
	assert_int_equal(hl_inputs_decode(f->dec, fr.can_id, fr.data, fr.len, &out, &o), -ESTALE);
	assert_int_equal(c->counter_repeated, 1);
	assert_int_equal(hl_inputs_encode_vehicle(f->map, &vs, 6, &fr), 0);
	decode_vehicle(f, &fr, &out);
	assert_int_equal(c->counter_lost, 2);
	assert_int_equal(hl_inputs_encode_vehicle(f->map, &vs, 14, &fr), 0);
	decode_vehicle(f, &fr, &out);
	assert_int_equal(hl_inputs_encode_vehicle(f->map, &vs, 0, &fr), 0);
	decode_vehicle(f, &fr, &out);
	assert_int_equal(c->counter_lost, 2 + 7);
	/* counter 15 is never sent */
	fr.data[1] |= 0x0f;
	{
		uint8_t in[9] = { 0x10, 0x01 };

		memcpy(in + 2, fr.data + 1, 7);
		fr.data[0] = hl_e2e_crc8_j1850(in, 9);
	}
	assert_int_equal(hl_inputs_decode(f->dec, fr.can_id, fr.data, fr.len, &out, &o), -ERANGE);
	/* short frame, unknown ID */
	assert_int_equal(hl_inputs_decode(f->dec, fr.can_id, fr.data, 7, &out, &o), -EMSGSIZE);
	assert_int_equal(hl_inputs_decode(f->dec, 0x320, fr.data, 8, &out, &o), -ENOENT);
	assert_int_equal(c->short_frames, 1);
	assert_int_equal(c->unknown_id, 1);
	assert_int_equal(c->frames, c->unknown_id + c->short_frames + c->crc_errors +
					    c->counter_repeated + c->bad_values + c->duplicates +
					    c->vehicle_states + c->object_frames);
}

static void inputs_object_cycle_rule(void **state)
{
	struct fixture *f = *state;
	const struct hl_inputs_counters *c = hl_inputs_decoder_counters(f->dec);
	struct hl_camera_objects in = three_objects(), out;
	struct hl_inputs_frame fr[HL_INPUTS_MAX_CYCLE_FRAMES], fr2[HL_INPUTS_MAX_CYCLE_FRAMES];
	struct hl_vehicle_state vs;

	assert_int_equal(hl_inputs_encode_objects(f->map, &in, 1, fr), 6);
	decode_all(f, fr, 6, &out);
	assert_int_equal(out.n, 3);
	assert_int_equal(out.obj[2].id, 12);
	assert_true(fabs(out.obj[2].h_left_deg - -3) < 1e-12);
	assert_true(fabs(out.obj[1].confidence - 0.75) < 1e-12);
	/* the same cycle again: every frame stale */
	for (int i = 0; i < 6; i++)
		assert_int_equal(hl_inputs_decode(f->dec, fr[i].can_id, fr[i].data, fr[i].len, &vs,
						  &out),
				 -ESTALE);
	assert_int_equal(c->counter_repeated, 6);
	/* a lost frame: cycle 2 lacks its last box; cycle 3's first frame ends it incomplete */
	assert_int_equal(hl_inputs_encode_objects(f->map, &in, 2, fr), 6);
	for (int i = 0; i < 5; i++)
		assert_int_equal(hl_inputs_decode(f->dec, fr[i].can_id, fr[i].data, fr[i].len, &vs,
						  &out),
				 0);
	assert_int_equal(hl_inputs_encode_objects(f->map, &in, 3, fr), 6);
	decode_all(f, fr, 6, &out);
	assert_int_equal(c->cycles_incomplete, 1);
	assert_int_equal(c->cycles_complete, 2);
	assert_int_equal(c->counter_lost, 0);
	/* a skipped cycle: 3 -> 5 loses one counter value */
	assert_int_equal(hl_inputs_encode_objects(f->map, &in, 5, fr), 6);
	decode_all(f, fr, 6, &out);
	assert_int_equal(c->counter_lost, 1);
	/* the same slot twice ends the cycle; the rest of it is dropped */
	assert_int_equal(hl_inputs_encode_objects(f->map, &in, 6, fr), 6);
	assert_int_equal(hl_inputs_decode(f->dec, fr[0].can_id, fr[0].data, 8, &vs, &out), 0);
	assert_int_equal(hl_inputs_decode(f->dec, fr[0].can_id, fr[0].data, 8, &vs, &out), -EEXIST);
	assert_int_equal(hl_inputs_decode(f->dec, fr[1].can_id, fr[1].data, 8, &vs, &out), -ESTALE);
	assert_int_equal(c->duplicates, 1);
	assert_int_equal(c->cycles_incomplete, 2);
	/* counts that disagree within one cycle: 3 objects in slot 0, 2 in slot 1 */
	assert_int_equal(hl_inputs_encode_objects(f->map, &in, 7, fr), 6);
	in.n = 2;
	assert_int_equal(hl_inputs_encode_objects(f->map, &in, 7, fr2), 4);
	assert_int_equal(hl_inputs_decode(f->dec, fr[0].can_id, fr[0].data, 8, &vs, &out), 0);
	assert_int_equal(hl_inputs_decode(f->dec, fr2[2].can_id, fr2[2].data, 8, &vs, &out),
			 -ERANGE);
	assert_int_equal(c->bad_values, 1);
	/* a box frame of slot 2 in a cycle of 2 objects */
	assert_int_equal(hl_inputs_encode_objects(f->map, &in, 8, fr2), 4);
	for (int i = 0; i < 3; i++)
		assert_int_equal(hl_inputs_decode(f->dec, fr2[i].can_id, fr2[i].data, 8, &vs, &out),
				 0);
	in.n = 3;
	assert_int_equal(hl_inputs_encode_objects(f->map, &in, 8, fr), 6);
	assert_int_equal(hl_inputs_decode(f->dec, fr[5].can_id, fr[5].data, 8, &vs, &out), -ERANGE);
	assert_int_equal(c->bad_values, 2);
	assert_int_equal(c->cycles_incomplete, 4);
	/* a box whose left edge lies right of its right edge is no box */
	in.obj[1].h_left_deg = 3;
	in.obj[1].h_right_deg = 2;
	assert_int_equal(hl_inputs_encode_objects(f->map, &in, 9, fr), 6);
	for (int i = 0; i < 5; i++)
		assert_int_equal(hl_inputs_decode(f->dec, fr[i].can_id, fr[i].data, 8, &vs, &out),
				 0);
	assert_int_equal(hl_inputs_decode(f->dec, fr[5].can_id, fr[5].data, 8, &vs, &out), -ERANGE);
	assert_int_equal(c->frames, c->unknown_id + c->short_frames + c->crc_errors +
					    c->counter_repeated + c->bad_values + c->duplicates +
					    c->vehicle_states + c->object_frames);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(inputs_e2e_crc_and_counters, setup, teardown),
		cmocka_unit_test_setup_teardown(inputs_object_cycle_rule, setup, teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
