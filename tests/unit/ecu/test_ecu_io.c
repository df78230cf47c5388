/* SPDX-License-Identifier: MIT */
/*
 * The ECU's named inputs and outputs (ecu/io.c) for the shipped hd84_inputs.dbc and the HD84
 * pair: the names, and an ECU fed through the input vector (host side set, model side apply)
 * giving bitwise the intensities of one fed the structs directly, over masking, an E2E error run
 * with its fail-safe, and a vehicle timeout.
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "ecu/beams.h"
#include "ecu/io.h"
#include "ecu/lighting.h"
#include "inputs_fixture.h"
#include "lamp/model.h"

#define MS 1000000LL
#define T0 (1000 * MS)

struct io_fixture {
	void *inputs; /* inputs_fixture.h's: the database and its map */
	struct hl_inputs_map *map;
	struct hl_lid *lid[2];
	float low[2][HL_HD84_SOURCES], high[2][HL_HD84_SOURCES];
	struct hl_ecu_lamp lamps[2];
	struct hl_ecu_io *io;
};

static const char *const lamp_names[2] = { "left", "right" };

static int io_setup(void **state)
{
	struct io_fixture *f = calloc(1, sizeof(*f));
	const struct hl_lid *lids[2];
	char err[256] = "";

	if (!f || setup(&f->inputs) != 0)
		return -1;
	f->map = ((struct fixture *)f->inputs)->map;
	for (int s = 0; s < 2; s++) {
		if (hl_model_hd84(s, &f->lid[s]) < 0 ||
		    hl_ecu_beams_default(f->lid[s], s, 0.05, f->low[s], f->high[s]) < 0)
			return -1;
		f->lamps[s] = (struct hl_ecu_lamp){
			.lid = f->lid[s],
			.mount = { .pos_m = { 0.0, s == 0 ? 0.7 : -0.7, 0.65 } },
			.low = f->low[s],
			.high = f->high[s],
		};
		lids[s] = f->lid[s];
	}
	if (hl_ecu_io_new(f->map, lids, lamp_names, 2, &f->io, err, sizeof(err)) < 0)
		fail_msg("%s", err);
	*state = f;
	return 0;
}

static int io_teardown(void **state)
{
	struct io_fixture *f = *state;

	hl_ecu_io_free(f->io);
	hl_lid_free(f->lid[0]);
	hl_lid_free(f->lid[1]);
	teardown(&f->inputs);
	free(f);
	return 0;
}

static void ecu_io_names_of_hd84_inputs(void **state)
{
	struct io_fixture *f = *state;
	const struct hl_ecu_io *io = f->io;
	char name[64];

	/* 5 vehicle fields, the count, 8 fields x 8 slots, 4 COM_* */
	assert_int_equal(hl_ecu_io_n_inputs(io), 5 + 1 + 8 * 8 + 4);
	assert_int_equal(hl_ecu_io_input_index(io, "VEH_Speed"), 0);
	assert_string_equal(hl_ecu_io_input_name(io, 0), "VEH_Speed");
	assert_string_equal(hl_ecu_io_input_name(io, 1), "VEH_YawRate");
	assert_string_equal(hl_ecu_io_input_name(io, 2), "VEH_SteeringAngle");
	assert_string_equal(hl_ecu_io_input_name(io, 3), "VEH_LightSwitch");
	assert_string_equal(hl_ecu_io_input_name(io, 4), "VEH_AdbEnable");
	assert_string_equal(hl_ecu_io_input_name(io, 5), "CAMI_ObjCount");
	assert_string_equal(hl_ecu_io_input_name(io, 6), "CAMI_ObjId[0]");
	for (int k = 0; k < 8; k++) {
		static const char *const fields[] = { "CAMI_ObjId",    "CAMI_ObjClass",
						      "CAMB_HLeft",    "CAMB_HRight",
						      "CAMB_VBottom",  "CAMB_VTop",
						      "CAMI_Distance", "CAMI_Confidence" };

		for (int fi = 0; fi < 8; fi++) {
			snprintf(name, sizeof(name), "%s[%d]", fields[fi], k);
			assert_int_equal(hl_ecu_io_input_index(io, name), 6 + fi * 8 + k);
		}
	}
	assert_int_equal(hl_ecu_io_input_index(io, "CAMB_HLeft[3]"), 6 + 2 * 8 + 3);
	assert_int_equal(hl_ecu_io_input_index(io, "COM_VehicleRxTime"), 70);
	assert_int_equal(hl_ecu_io_input_index(io, "COM_ObjectsRxTime"), 71);
	assert_int_equal(hl_ecu_io_input_index(io, "COM_VehicleE2EErrors"), 72);
	assert_int_equal(hl_ecu_io_input_index(io, "COM_ObjectsE2EErrors"), 73);
	assert_null(hl_ecu_io_input_name(io, 74));
	assert_null(hl_ecu_io_input_name(io, -1));

	assert_int_equal(hl_ecu_io_n_outputs(io), 2 * HL_HD84_SOURCES);
	assert_int_equal(hl_ecu_io_lamp_first(io, 0), 0);
	assert_int_equal(hl_ecu_io_lamp_first(io, 1), HL_HD84_SOURCES);
	assert_int_equal(hl_ecu_io_lamp_sources(io, 1), HL_HD84_SOURCES);
	assert_string_equal(hl_ecu_io_output_name(io, 0), "left.row1_led01");
	assert_int_equal(hl_ecu_io_output_index(io, "right.row1_led01"), HL_HD84_SOURCES);
	for (int l = 0; l < 2; l++)
		for (int k = 0; k < HL_HD84_SOURCES; k++) {
			snprintf(name, sizeof(name), "%s.%s", lamp_names[l],
				 hl_lid_name(f->lid[l], k));
			assert_int_equal(hl_ecu_io_output_index(io, name), l * HL_HD84_SOURCES + k);
		}
}

static void ecu_io_unknown_name_is_enoent(void **state)
{
	struct io_fixture *f = *state;

	assert_int_equal(hl_ecu_io_input_index(f->io, "VEH_Nothing"), -ENOENT);
	assert_int_equal(hl_ecu_io_input_index(f->io, "CAMB_HLeft[8]"), -ENOENT);
	assert_int_equal(hl_ecu_io_input_index(f->io, "CAMB_HLeft"), -ENOENT);
	assert_int_equal(hl_ecu_io_output_index(f->io, "left.row9_led99"), -ENOENT);
	assert_int_equal(hl_ecu_io_output_index(f->io, "VEH_Speed"), -ENOENT);
}

static void ecu_io_init_inputs_zero_and_times_minus_one(void **state)
{
	struct io_fixture *f = *state;
	double in[74];

	hl_ecu_io_init_inputs(f->io, in);
	for (int i = 0; i < 74; i++)
		assert_true(in[i] == (i == 70 || i == 71 ? -1.0 : 0.0));
}

static void ecu_io_values_in_dbc_units(void **state)
{
	struct io_fixture *f = *state;
	const struct hl_vehicle_state s = { .speed_mps = 25,
					    .yaw_rate_rad_s = M_PI / 18,
					    .steering_rad = -M_PI / 2,
					    .light_switch = HL_SWITCH_AUTO,
					    .adb_enable = true };
	struct hl_camera_objects o = { .n = 1 };
	double in[74];

	o.obj[0] =
		(struct hl_camera_object){ 7, HL_OBJECT_PRECEDING, -2, 1.5, -0.5, 0.25, 80, 0.9 };
	hl_ecu_io_init_inputs(f->io, in);
	hl_ecu_io_set_vehicle(f->io, &s, 1500 * MS, in);
	hl_ecu_io_set_objects(f->io, &o, 1520 * MS, in);
	assert_true(fabs(in[0] - 90) < 1e-12); /* km/h */
	assert_true(fabs(in[1] - 10) < 1e-12); /* deg/s */
	assert_true(fabs(in[2] + 90) < 1e-12); /* deg */
	assert_true(in[3] == 1 && in[4] == 1 && in[5] == 1);
	assert_true(in[hl_ecu_io_input_index(f->io, "CAMI_ObjId[0]")] == 7);
	assert_true(in[hl_ecu_io_input_index(f->io, "CAMI_ObjClass[0]")] == 2);
	assert_true(in[hl_ecu_io_input_index(f->io, "CAMB_HRight[0]")] == 1.5);
	assert_true(in[hl_ecu_io_input_index(f->io, "CAMI_Distance[0]")] == 80);
	assert_true(in[hl_ecu_io_input_index(f->io, "CAMI_Distance[1]")] == 0);
	assert_true(in[70] == 1.5 && in[71] == 1.52);
	hl_ecu_io_set_e2e_error(f->io, HL_ECU_INPUT_OBJECTS, in);
	hl_ecu_io_set_e2e_error(f->io, HL_ECU_INPUT_OBJECTS, in);
	assert_true(in[73] == 2 && in[72] == 0);
	hl_ecu_io_set_objects(f->io, &o, 1560 * MS, in);
	assert_true(in[73] == 0);
}

/* Vehicle every cycle, camera every other; what happens at cycle c. */
struct plan {
	bool vehicle, objects, objects_e2e;
};

static struct plan plan_at(int c)
{
	struct plan p = { .vehicle = true, .objects = c % 2 == 0 };

	if (c >= 30 && c < 40) /* the camera's frames fail E2E: the fail-safe after 3 */
		p.objects = false, p.objects_e2e = c % 2 == 0;
	if (c >= 60 && c < 70) /* no vehicle state: the fail-safe after the timeout */
		p.vehicle = false;
	return p;
}

static void ecu_io_roundtrip_gives_the_direct_outputs(void **state)
{
	struct io_fixture *f = *state;
	struct hl_ecu_config c;
	struct hl_ecu *direct, *via;
	struct hl_ecu_io_model m;
	double in[74], out[2 * HL_HD84_SOURCES];
	int masked_cycles = 0, failsafe_cycles = 0;

	hl_ecu_config_default(&c);
	assert_int_equal(hl_ecu_new(&c, f->lamps, 2, &direct, NULL), 0);
	assert_int_equal(hl_ecu_new(&c, f->lamps, 2, &via, NULL), 0);
	hl_ecu_io_init_inputs(f->io, in);
	hl_ecu_io_model_init(&m);
	for (int cyc = 0; cyc < 100; cyc++) {
		const int64_t now = T0 + cyc * 20 * MS, t_rx = now - 3 * MS;
		const struct plan p = plan_at(cyc);
		const struct hl_vehicle_state s = {
			.speed_mps = 20 + 0.137 * cyc,
			.yaw_rate_rad_s = 0.01 * sin(cyc * 0.1),
			.steering_rad = 0.05 * cos(cyc * 0.07),
			.light_switch = HL_SWITCH_HIGH,
			.adb_enable = true,
		};
		struct hl_camera_objects o = { .n = 2 };
		struct hl_ecu_status sd, sv;

		o.obj[0] = (struct hl_camera_object){ 3,
						      HL_OBJECT_ONCOMING,
						      -4 + 0.05 * cyc,
						      -3 + 0.05 * cyc,
						      -0.3,
						      0.4,
						      120 - cyc,
						      0.95 };
		o.obj[1] =
			(struct hl_camera_object){ 9,  HL_OBJECT_PRECEDING, 1.1, 2.3, -0.6, 0.2, 60,
						   0.8 };
		if (p.vehicle) {
			hl_ecu_vehicle(direct, &s, t_rx);
			hl_ecu_io_set_vehicle(f->io, &s, t_rx, in);
		}
		if (p.objects) {
			hl_ecu_objects(direct, &o, t_rx);
			hl_ecu_io_set_objects(f->io, &o, t_rx, in);
		}
		if (p.objects_e2e) {
			for (int i = 0; i < 2; i++) {
				hl_ecu_input_error(direct, HL_ECU_INPUT_OBJECTS);
				hl_ecu_io_set_e2e_error(f->io, HL_ECU_INPUT_OBJECTS, in);
			}
		}
		hl_ecu_step(direct, now, &sd);
		hl_ecu_io_apply(f->io, &m, in, via);
		hl_ecu_step(via, now, &sv);
		hl_ecu_io_outputs(f->io, via, out);
		assert_int_equal(sd.mode, sv.mode);
		assert_int_equal(sd.failsafe, sv.failsafe);
		for (int l = 0; l < 2; l++) {
			const float *d = hl_ecu_output(direct, l);

			assert_memory_equal(d, hl_ecu_output(via, l),
					    HL_HD84_SOURCES * sizeof(float));
			for (int k = 0; k < HL_HD84_SOURCES; k++)
				assert_true(out[l * HL_HD84_SOURCES + k] == (double)d[k]);
		}
		masked_cycles += sd.masked[0] > 0 && sd.masked[1] > 0;
		failsafe_cycles += sd.failsafe != 0;
		if (cyc == 36)
			assert_true(sd.failsafe & HL_ECU_FS_OBJECTS_E2E);
		if (cyc == 68)
			assert_true(sd.failsafe & HL_ECU_FS_VEHICLE_MISSING);
	}
	/* the run shows what it claims to: masking and both fail-safes */
	assert_true(masked_cycles > 50);
	assert_true(failsafe_cycles > 10);
	hl_ecu_free(direct);
	hl_ecu_free(via);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(ecu_io_names_of_hd84_inputs),
		cmocka_unit_test(ecu_io_unknown_name_is_enoent),
		cmocka_unit_test(ecu_io_init_inputs_zero_and_times_minus_one),
		cmocka_unit_test(ecu_io_values_in_dbc_units),
		cmocka_unit_test(ecu_io_roundtrip_gives_the_direct_outputs),
	};

	return cmocka_run_group_tests(tests, io_setup, io_teardown);
}
