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

#define DEG (M_PI / 180.0)

static const struct hl_dbc_signal *sig(const struct hl_dbc *db, const char *msg, const char *name)
{
	const struct hl_dbc_message *m = hl_dbc_find_message(db, msg);

	assert_non_null(m);
	assert_non_null(hl_dbc_find_signal(m, name));
	return hl_dbc_find_signal(m, name);
}

/* The values a round trip tries for a signal: min, max and four between, in its unit. */
static void probe_values(const struct hl_dbc_signal *s, double ret[6])
{
	ret[0] = s->min;
	ret[1] = s->max;
	ret[2] = s->min + (s->max - s->min) * 0.25;
	ret[3] = s->min + (s->max - s->min) * 0.5 + s->factor * 0.3; /* off the grid */
	ret[4] = s->min + (s->max - s->min) * 0.71;
	ret[5] = s->min + s->factor; /* one step above the minimum */
}

static void decode_vehicle(struct fixture *f, const struct hl_inputs_frame *fr,
			   struct hl_vehicle_state *ret)
{
	struct hl_camera_objects o;

	assert_int_equal(hl_inputs_decode(f->dec, fr->can_id, fr->data, fr->len, ret, &o),
			 HL_INPUTS_VEHICLE);
}

/* Each vehicle signal alone at each probe value, the others mid-range. */
static void inputs_vehicle_round_trip_every_signal(void **state)
{
	struct fixture *f = *state;
	const char *names[3] = { "VEH_Speed", "VEH_YawRate", "VEH_SteeringAngle" };
	const double scale[3] = { 1 / 3.6, DEG, DEG }; /* DBC unit -> struct unit */
	unsigned counter = 0;

	for (int k = 0; k < 3; k++) {
		const struct hl_dbc_signal *s = sig(f->db, "HDI_Vehicle", names[k]);
		double v[6];

		probe_values(s, v);
		for (int j = 0; j < 6; j++) {
			struct hl_vehicle_state in = { 10 / 3.6, 0.1, -0.2, HL_SWITCH_AUTO, true };
			struct hl_vehicle_state out;
			struct hl_inputs_frame fr;
			double *field = k == 0 ? &in.speed_mps :
					k == 1 ? &in.yaw_rate_rad_s :
						 &in.steering_rad;
			double got, want = round(v[j] / s->factor) * s->factor;

			*field = v[j] * scale[k];
			assert_int_equal(hl_inputs_encode_vehicle(f->map, &in, counter, &fr), 0);
			counter = (counter + 1) % 15;
			decode_vehicle(f, &fr, &out);
			got = (k == 0 ? out.speed_mps :
			       k == 1 ? out.yaw_rate_rad_s :
					out.steering_rad) /
			      scale[k];
			/* exact to the resolution: the nearest step, to rounding of the unit scale */
			if (fabs(got - want) > 1e-9 * fmax(1, fabs(want)))
				fail_msg("%s %.6f: decoded %.9f, want %.9f", names[k], v[j], got,
					 want);
			assert_true(fabs(got - v[j]) <= s->factor / 2 + 1e-9);
			assert_int_equal(out.light_switch, HL_SWITCH_AUTO);
			assert_true(out.adb_enable);
		}
	}
	for (int sw = HL_SWITCH_OFF; sw <= HL_SWITCH_HIGH; sw++) {
		for (int adb = 0; adb <= 1; adb++) {
			struct hl_vehicle_state in = { 0, 0, 0, (enum hl_light_switch)sw, adb };
			struct hl_vehicle_state out;
			struct hl_inputs_frame fr;

			assert_int_equal(hl_inputs_encode_vehicle(f->map, &in, counter, &fr), 0);
			counter = (counter + 1) % 15;
			decode_vehicle(f, &fr, &out);
			assert_int_equal(out.light_switch, sw);
			assert_int_equal(out.adb_enable, adb);
		}
	}
	assert_int_equal(hl_inputs_decoder_counters(f->dec)->vehicle_states, 3 * 6 + 8);
	assert_int_equal(hl_inputs_decoder_counters(f->dec)->counter_lost, 0);
}

/* The bits of one frame, computed by hand from the layout in the file's comment. */
static void inputs_vehicle_frame_layout(void **state)
{
	struct fixture *f = *state;
	struct hl_vehicle_state in = { 100 / 3.6, -12.5 * DEG, 450.3 * DEG, HL_SWITCH_HIGH, true };
	struct hl_inputs_frame fr;
	uint8_t crc_in[9];
	int16_t yaw = -1250, steer = 4503;

	assert_int_equal(hl_inputs_encode_vehicle(f->map, &in, 9, &fr), 0);
	assert_int_equal(fr.can_id, 0x110);
	assert_int_equal(fr.len, 8);
	assert_false(fr.fd);
	assert_int_equal(fr.data[1], 9 | 3 << 4 | 1 << 6);
	assert_int_equal(fr.data[2] | fr.data[3] << 8, 10000);
	assert_int_equal(fr.data[4] | fr.data[5] << 8, (uint16_t)yaw);
	assert_int_equal(fr.data[6] | fr.data[7] << 8, (uint16_t)steer);
	crc_in[0] = 0x10; /* data ID 0x0110, low byte first */
	crc_in[1] = 0x01;
	memcpy(crc_in + 2, fr.data + 1, 7);
	assert_int_equal(fr.data[0], hl_e2e_crc8_j1850(crc_in, 9));
}

static int decode_all(struct fixture *f, const struct hl_inputs_frame *fr, int n,
		      struct hl_camera_objects *ret)
{
	struct hl_vehicle_state vs;
	int rc = -1;

	for (int i = 0; i < n; i++) {
		rc = hl_inputs_decode(f->dec, fr[i].can_id, fr[i].data, fr[i].len, &vs, ret);
		/* only the last frame completes the cycle */
		assert_int_equal(rc, i == n - 1 ? HL_INPUTS_OBJECTS : 0);
	}
	return rc;
}

static double *obj_field(struct hl_camera_object *o, int k)
{
	double *p[6] = { &o->h_left_deg, &o->h_right_deg, &o->v_bottom_deg,
			 &o->v_top_deg,	 &o->distance_m,  &o->confidence };
	return p[k];
}

/* Every object field of every slot at each probe value; n objects in a cycle, 2n frames. */
static void inputs_objects_round_trip_every_signal(void **state)
{
	struct fixture *f = *state;
	const char *names[6] = { "CAMB_HLeft", "CAMB_HRight",	"CAMB_VBottom",
				 "CAMB_VTop",  "CAMI_Distance", "CAMI_Confidence" };
	const char *msgs[6] = { "HDI_CamObjBox", "HDI_CamObjBox",  "HDI_CamObjBox",
				"HDI_CamObjBox", "HDI_CamObjInfo", "HDI_CamObjInfo" };
	unsigned counter = 0;
	int cycles = 0;

	assert_int_equal(hl_inputs_map_slots(f->map), 8);
	for (int k = 0; k < 6; k++) {
		const struct hl_dbc_signal *s = sig(f->db, msgs[k], names[k]);
		double v[6];

		probe_values(s, v);
		for (int j = 0; j < 6; j++) {
			struct hl_camera_objects in = { 0 }, out;
			struct hl_inputs_frame fr[HL_INPUTS_MAX_CYCLE_FRAMES];
			int n;

			in.n = 1 + (k * 6 + j) % HL_INPUTS_MAX_OBJECTS;
			for (int i = 0; i < in.n; i++) {
				struct hl_camera_object *o = &in.obj[i];

				*o = (struct hl_camera_object){
					1 + i * 36, (enum hl_object_class)(i % 4),
					-1,	    1,
					-0.5,	    0.5,
					50,	    0.9
				};
				*obj_field(o, k) = v[j];
				/* keep the box ordered: move its partner edge out of the way */
				if (k == 0 && o->h_right_deg < v[j])
					o->h_right_deg = v[j];
				if (k == 1 && o->h_left_deg > v[j])
					o->h_left_deg = v[j];
				if (k == 2 && o->v_top_deg < v[j])
					o->v_top_deg = v[j];
				if (k == 3 && o->v_bottom_deg > v[j])
					o->v_bottom_deg = v[j];
			}
			n = hl_inputs_encode_objects(f->map, &in, counter, fr);
			assert_int_equal(n, 2 * in.n);
			assert_int_equal(fr[0].can_id, 0x122); /* the count comes first */
			assert_int_equal(fr[1].can_id, 0x121);
			counter = (counter + 1) % 15;
			decode_all(f, fr, n, &out);
			cycles++;
			assert_int_equal(out.n, in.n);
			for (int i = 0; i < in.n; i++) {
				double want = round(v[j] / s->factor) * s->factor;
				double got = *obj_field(&out.obj[i], k);

				if (fabs(got - want) > 1e-9)
					fail_msg("%s slot %d %.6f: decoded %.9f, want %.9f",
						 names[k], i, v[j], got, want);
				assert_int_equal(out.obj[i].id, in.obj[i].id);
				assert_int_equal(out.obj[i].cls, in.obj[i].cls);
			}
		}
	}
	/* id and class over their whole range */
	for (int id = 0; id <= 255; id += 51) {
		struct hl_camera_objects in = { 0 }, out;
		struct hl_inputs_frame fr[HL_INPUTS_MAX_CYCLE_FRAMES];

		in.n = 4;
		for (int i = 0; i < 4; i++)
			in.obj[i] = (struct hl_camera_object){
				(unsigned)id, (enum hl_object_class)i, -2, 2, -1, 1, 10, 1
			};
		assert_int_equal(hl_inputs_encode_objects(f->map, &in, counter, fr), 8);
		counter = (counter + 1) % 15;
		decode_all(f, fr, 8, &out);
		cycles++;
		for (int i = 0; i < 4; i++) {
			assert_int_equal(out.obj[i].id, id);
			assert_int_equal(out.obj[i].cls, i);
		}
	}
	assert_int_equal(hl_inputs_decoder_counters(f->dec)->cycles_complete, cycles);
	assert_int_equal(hl_inputs_decoder_counters(f->dec)->cycles_incomplete, 0);
}

/* No object: one frame, slot 0 of the count message with count 0. */
static void inputs_objects_empty_cycle_one_frame(void **state)
{
	struct fixture *f = *state;
	struct hl_camera_objects in = { 0 }, out = { .n = 5 };
	struct hl_inputs_frame fr[HL_INPUTS_MAX_CYCLE_FRAMES];

	assert_int_equal(hl_inputs_encode_objects(f->map, &in, 4, fr), 1);
	assert_int_equal(fr[0].can_id, 0x122);
	assert_int_equal(fr[0].data[1], 4); /* counter 4, slot 0 */
	assert_int_equal(fr[0].data[2] & 0x0f, 0); /* count 0 */
	decode_all(f, fr, 1, &out);
	assert_int_equal(out.n, 0);
	in.n = 9;
	assert_int_equal(hl_inputs_encode_objects(f->map, &in, 5, fr), -E2BIG);
	in.n = 1;
	in.obj[0] = (struct hl_camera_object){ 1, HL_OBJECT_ONCOMING, -90, 1, 0, 1, 10, 1 };
	assert_int_equal(hl_inputs_encode_objects(f->map, &in, 5, fr), -ERANGE);
	in.obj[0].h_left_deg = -1;
	assert_int_equal(hl_inputs_encode_objects(f->map, &in, 15, fr), -EINVAL);
}

/*
 * Another ECU's layout, mapped by the attributes alone: the whole object in one 24-byte CAN FD
 * message with E2E P5 (CRC-16, 8-bit counter), one signal per slot for the distance, and a
 * vehicle message without E2E or counter, Motorola speed.
 */
static const char other_db[] =
	"VERSION \"\"\nNS_ :\nBS_:\nBU_: X\n"
	"BO_ 1792 Veh: 8 X\n"
	" SG_ Speed : 7|16@0+ (0.1,0) [0|6553.5] \"km/h\" X\n"
	" SG_ Yaw : 16|16@1- (0.001,0) [-32.768|32.767] \"deg/s\" X\n"
	" SG_ Steer : 32|16@1- (1,0) [-32768|32767] \"deg\" X\n"
	" SG_ Sw : 48|2@1+ (1,0) [0|3] \"\" X\n"
	" SG_ Adb : 50|1@1+ (1,0) [0|1] \"\" X\n"
	"BO_ 1793 Obj: 24 X\n"
	" SG_ Crc : 0|16@1+ (1,0) [0|65535] \"\" X\n"
	" SG_ Cnt : 16|8@1+ (1,0) [0|255] \"\" X\n"
	" SG_ Idx M : 24|3@1+ (1,0) [0|3] \"\" X\n"
	" SG_ N m0 : 27|4@1+ (1,0) [0|4] \"\" X\n"
	" SG_ Id m0 : 32|8@1+ (1,0) [0|255] \"\" X\n"
	" SG_ Cls m0 : 40|2@1+ (1,0) [0|3] \"\" X\n"
	" SG_ HL m0 : 48|16@1- (0.01,0) [-327.68|327.67] \"deg\" X\n"
	" SG_ HR m0 : 64|16@1- (0.01,0) [-327.68|327.67] \"deg\" X\n"
	" SG_ VB m0 : 80|16@1- (0.01,0) [-327.68|327.67] \"deg\" X\n"
	" SG_ VT m0 : 96|16@1- (0.01,0) [-327.68|327.67] \"deg\" X\n"
	" SG_ D0 m0 : 112|16@1+ (0.1,0) [0|6553.5] \"m\" X\n"
	" SG_ D1 m1 : 112|16@1+ (0.1,0) [0|6553.5] \"m\" X\n"
	" SG_ D2 m2 : 112|16@1+ (0.1,0) [0|6553.5] \"m\" X\n"
	" SG_ D3 m3 : 112|16@1+ (0.1,0) [0|6553.5] \"m\" X\n"
	" SG_ Conf m0 : 128|8@1+ (0.005,0) [0|1] \"\" X\n"
	"BA_DEF_ BO_ \"HdlInput\" STRING ;\nBA_DEF_ SG_ \"HdlInputSignal\" STRING ;\n"
	"BA_DEF_ BO_ \"HdlE2E\" STRING ;\nBA_DEF_ BO_ \"GenMsgCycleTime\" INT 0 10000;\n"
	"BA_DEF_ BO_ \"VFrameFormat\" ENUM \"StandardCAN\",\"ExtendedCAN\",\"StandardCAN_FD\";\n"
	"BA_DEF_DEF_ \"HdlInput\" \"\";\nBA_DEF_DEF_ \"HdlInputSignal\" \"\";\n"
	"BA_DEF_DEF_ \"HdlE2E\" \"none\";\nBA_DEF_DEF_ \"GenMsgCycleTime\" 0;\n"
	"BA_DEF_DEF_ \"VFrameFormat\" \"StandardCAN\";\n"
	"BA_ \"HdlInput\" BO_ 1792 \"vehicle\";\nBA_ \"HdlInput\" BO_ 1793 \"objects\";\n"
	"BA_ \"HdlE2E\" BO_ 1793 \"P5 dataid=0x0701\";\nBA_ \"GenMsgCycleTime\" BO_ 1792 10;\n"
	"BA_ \"GenMsgCycleTime\" BO_ 1793 50;\nBA_ \"VFrameFormat\" BO_ 1793 2;\n"
	"BA_ \"HdlInputSignal\" SG_ 1792 Speed \"speed\";\n"
	"BA_ \"HdlInputSignal\" SG_ 1792 Yaw \"yaw_rate\";\n"
	"BA_ \"HdlInputSignal\" SG_ 1792 Steer \"steering\";\n"
	"BA_ \"HdlInputSignal\" SG_ 1792 Sw \"light_switch\";\n"
	"BA_ \"HdlInputSignal\" SG_ 1792 Adb \"adb_enable\";\n"
	"BA_ \"HdlInputSignal\" SG_ 1793 Crc \"crc\";\n"
	"BA_ \"HdlInputSignal\" SG_ 1793 Cnt \"alive\";\n"
	"BA_ \"HdlInputSignal\" SG_ 1793 Idx \"object_index\";\n"
	"BA_ \"HdlInputSignal\" SG_ 1793 N \"object_count\";\n"
	"BA_ \"HdlInputSignal\" SG_ 1793 Id \"id\";\n"
	"BA_ \"HdlInputSignal\" SG_ 1793 Cls \"class\";\n"
	"BA_ \"HdlInputSignal\" SG_ 1793 HL \"h_left\";\n"
	"BA_ \"HdlInputSignal\" SG_ 1793 HR \"h_right\";\n"
	"BA_ \"HdlInputSignal\" SG_ 1793 VB \"v_bottom\";\n"
	"BA_ \"HdlInputSignal\" SG_ 1793 VT \"v_top\";\n"
	"BA_ \"HdlInputSignal\" SG_ 1793 D0 \"distance\";\n"
	"BA_ \"HdlInputSignal\" SG_ 1793 D1 \"distance\";\n"
	"BA_ \"HdlInputSignal\" SG_ 1793 D2 \"distance\";\n"
	"BA_ \"HdlInputSignal\" SG_ 1793 D3 \"distance\";\n"
	"BA_ \"HdlInputSignal\" SG_ 1793 Conf \"confidence\";\n"
	"SG_MUL_VAL_ 1793 N Idx 0-3;\nSG_MUL_VAL_ 1793 Id Idx 0-3;\nSG_MUL_VAL_ 1793 Cls Idx 0-3;\n"
	"SG_MUL_VAL_ 1793 HL Idx 0-3;\nSG_MUL_VAL_ 1793 HR Idx 0-3;\nSG_MUL_VAL_ 1793 VB Idx 0-3;\n"
	"SG_MUL_VAL_ 1793 VT Idx 0-3;\nSG_MUL_VAL_ 1793 Conf Idx 0-3;\n";

static void inputs_other_layout_maps_by_attributes(void **state)
{
	struct hl_dbc *db = parse(other_db);
	struct hl_inputs_map *map = NULL;
	struct hl_inputs_decoder *dec;
	struct hl_vehicle_state vs = { 33.3 / 3.6, -1.234 * DEG, 540 * DEG, HL_SWITCH_LOW, false },
				vo;
	struct hl_camera_objects in = { .n = 4 }, out;
	struct hl_inputs_frame fr[HL_INPUTS_MAX_CYCLE_FRAMES];
	char msg[256] = "";
	uint8_t crc_in[24];

	(void)state;
	if (hl_inputs_map_new(db, &map, msg, sizeof(msg)) < 0)
		fail_msg("%s", msg);
	assert_int_equal(hl_inputs_map_n_messages(map), 2);
	assert_int_equal(hl_inputs_map_slots(map), 4); /* Idx's range 0..3 */
	assert_int_equal(hl_inputs_map_counter_max(map, 0), 0); /* no counter at all */
	assert_int_equal(hl_inputs_map_counter_max(map, 1), 255);
	assert_true(hl_inputs_map_message(map, 1)->fd);
	assert_int_equal(hl_inputs_map_message(map, 1)->cycle_ms, 50);
	assert_int_equal(hl_inputs_decoder_new(map, &dec), 0);
	/* the vehicle: Motorola speed 333 (0.1 km/h) in bytes 0..1, big endian */
	assert_int_equal(hl_inputs_encode_vehicle(map, &vs, 0, fr), 0);
	assert_int_equal(fr[0].data[0] << 8 | fr[0].data[1], 333);
	assert_int_equal(hl_inputs_decode(dec, fr[0].can_id, fr[0].data, fr[0].len, &vo, &out),
			 HL_INPUTS_VEHICLE);
	assert_true(fabs(vo.speed_mps * 3.6 - 33.3) < 1e-9);
	assert_true(fabs(vo.yaw_rate_rad_s / DEG - -1.234) < 1e-9);
	assert_true(fabs(vo.steering_rad / DEG - 540) < 1e-9);
	assert_int_equal(vo.light_switch, HL_SWITCH_LOW);
	assert_false(vo.adb_enable);
	/* without a counter the same frame again is a new state */
	assert_int_equal(hl_inputs_decode(dec, fr[0].can_id, fr[0].data, fr[0].len, &vo, &out),
			 HL_INPUTS_VEHICLE);
	/* four objects in four FD frames, the distance in slot i from signal Di */
	for (int i = 0; i < 4; i++)
		in.obj[i] =
			(struct hl_camera_object){ 200 + i,	   (enum hl_object_class)(3 - i),
						   -30.5 + i,	   12.25 + i,
						   -1.5,	   2.75,
						   12.3 + 100 * i, 0.455 };
	assert_int_equal(hl_inputs_encode_objects(map, &in, 254, fr), 4);
	assert_int_equal(fr[0].len, 24);
	assert_true(fr[0].fd);
	/* P5: CRC-16/CCITT-FALSE over bytes 2..23, then the data ID low and high, little endian */
	memcpy(crc_in, fr[2].data + 2, 22);
	crc_in[22] = 0x01;
	crc_in[23] = 0x07;
	assert_int_equal(fr[2].data[0] | fr[2].data[1] << 8, hl_e2e_crc16_ccitt(crc_in, 24));
	assert_int_equal(fr[2].data[2], 254);
	for (int i = 0; i < 4; i++)
		assert_int_equal(hl_inputs_decode(dec, fr[i].can_id, fr[i].data, fr[i].len, &vo,
						  &out),
				 i == 3 ? HL_INPUTS_OBJECTS : 0);
	assert_int_equal(out.n, 4);
	for (int i = 0; i < 4; i++) {
		assert_int_equal(out.obj[i].id, 200 + i);
		assert_int_equal(out.obj[i].cls, 3 - i);
		assert_true(fabs(out.obj[i].h_left_deg - (-30.5 + i)) < 1e-9);
		assert_true(fabs(out.obj[i].h_right_deg - (12.25 + i)) < 1e-9);
		assert_true(fabs(out.obj[i].v_bottom_deg - -1.5) < 1e-9);
		assert_true(fabs(out.obj[i].v_top_deg - 2.75) < 1e-9);
		assert_true(fabs(out.obj[i].distance_m - (12.3 + 100 * i)) < 1e-9);
		assert_true(fabs(out.obj[i].confidence - 0.455) < 1e-9);
	}
	/* the counter wraps 255 -> 0 without a loss */
	in.n = 0;
	assert_int_equal(hl_inputs_encode_objects(map, &in, 255, fr), 1);
	assert_int_equal(hl_inputs_decode(dec, fr[0].can_id, fr[0].data, fr[0].len, &vo, &out),
			 HL_INPUTS_OBJECTS);
	assert_int_equal(hl_inputs_encode_objects(map, &in, 0, fr), 1);
	assert_int_equal(hl_inputs_decode(dec, fr[0].can_id, fr[0].data, fr[0].len, &vo, &out),
			 HL_INPUTS_OBJECTS);
	assert_int_equal(out.n, 0);
	assert_int_equal(hl_inputs_decoder_counters(dec)->counter_lost, 0);
	assert_int_equal(hl_inputs_decoder_counters(dec)->cycles_complete, 3);
	/* five objects do not fit four slots */
	in.n = 5;
	assert_int_equal(hl_inputs_encode_objects(map, &in, 1, fr), -E2BIG);
	hl_inputs_decoder_free(dec);
	hl_inputs_map_free(map);
	hl_dbc_free(db);
}

/* The shipped file with every occurrence of text replaced (removed: with == ""), mapped: the
 * error. */
static void expect_rejected(const char *text_old, const char *with, const char *want)
{
	size_t len, ol = strlen(text_old), wl = strlen(with), n = 0;
	char *text = read_text(&len), *edited, *out;
	const char *p, *q;
	struct hl_inputs_map *map = NULL;
	struct hl_dbc *db;
	char msg[256] = "";

	for (p = text; (q = strstr(p, text_old)); p = q + ol)
		n++;
	if (n == 0)
		fail_msg("no '%s' in hd84_inputs.dbc", text_old);
	edited = malloc(len + n * wl + 1);
	out = edited;
	for (p = text; (q = strstr(p, text_old)); p = q + ol) {
		memcpy(out, p, (size_t)(q - p));
		out += q - p;
		memcpy(out, with, wl);
		out += wl;
	}
	strcpy(out, p);
	db = parse(edited);
	assert_int_equal(hl_inputs_map_new(db, &map, msg, sizeof(msg)), -EINVAL);
	assert_null(map);
	if (strcmp(msg, want) != 0)
		fail_msg("message\n  '%s'\nexpected\n  '%s'", msg, want);
	hl_dbc_free(db);
	free(edited);
	free(text);
}

static void inputs_map_rejects_missing_attributes(void **state)
{
	(void)state;
	expect_rejected("BA_ \"HdlInputSignal\" SG_ 289 CAMB_VTop \"v_top\";\n", "",
			"no signal with HdlInputSignal \"v_top\" in the objects messages "
			"(HDI_CamObjInfo, HDI_CamObjBox)");
	expect_rejected("BA_ \"HdlInputSignal\" SG_ 272 VEH_YawRate \"yaw_rate\";\n", "",
			"message 'HDI_Vehicle' (HdlInput \"vehicle\"): no signal with "
			"HdlInputSignal \"yaw_rate\"");
	expect_rejected("BA_ \"HdlInput\" BO_ 272 \"vehicle\";\n", "",
			"no message with HdlInput \"vehicle\"");
	expect_rejected("\"objects\";\nBA_ \"GenMsgCycleTime\" BO_ 289",
			"\"\";\nBA_ \"GenMsgCycleTime\" BO_ 289",
			"no signal with HdlInputSignal \"object_count\" in the objects messages "
			"(HDI_CamObjBox)");
	expect_rejected("\"HdlInput\"", "\"HdlRole\"",
			"no message has the attribute HdlInput (expected BA_DEF_ BO_ \"HdlInput\" "
			"STRING and BA_ \"HdlInput\" BO_ <id> \"vehicle\" / \"objects\")");
	expect_rejected("CAMB_ObjIndex \"object_index\"", "CAMB_ObjIndex \"index\"",
			"message 'HDI_CamObjBox' signal 'CAMB_ObjIndex': HdlInputSignal \"index\" "
			"is no object field (expected object_index, object_count, id, class, "
			"h_left, h_right, v_bottom, v_top, distance, confidence, crc or alive)");
	expect_rejected("BA_ \"HdlInputSignal\" SG_ 272 VEH_Alive \"alive\";\n", "",
			"message 'HDI_Vehicle': HdlE2E P1 needs a signal with HdlInputSignal "
			"\"alive\" at 8|4@1, found none");
	expect_rejected("\"P1 dataid=0x0121\"", "\"P1 data=0x0121\"",
			"message 'HDI_CamObjBox': HdlE2E \"P1 data=0x0121\": expected \"P1 "
			"dataid=0x....\", \"P5 dataid=0x....\" or \"none\"");
	expect_rejected("SG_MUL_VAL_ 289 CAMB_VTop CAMB_ObjIndex 0-7;",
			"SG_MUL_VAL_ 289 CAMB_VTop CAMB_ObjIndex 0-6;",
			"message 'HDI_CamObjBox': HdlInputSignal \"v_top\" is missing in slot 7");
	expect_rejected("BA_ \"HdlInput\" BO_ 289 \"objects\";",
			"BA_ \"HdlInput\" BO_ 289 \"camera\";",
			"message 'HDI_CamObjBox': HdlInput \"camera\": expected \"vehicle\" or "
			"\"objects\"");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(inputs_vehicle_round_trip_every_signal, setup,
						teardown),
		cmocka_unit_test_setup_teardown(inputs_vehicle_frame_layout, setup, teardown),
		cmocka_unit_test_setup_teardown(inputs_objects_round_trip_every_signal, setup,
						teardown),
		cmocka_unit_test_setup_teardown(inputs_objects_empty_cycle_one_frame, setup,
						teardown),
		cmocka_unit_test(inputs_other_layout_maps_by_attributes),
		cmocka_unit_test(inputs_map_rejects_missing_attributes),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
