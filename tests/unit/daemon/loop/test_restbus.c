/* SPDX-License-Identifier: MIT */
/*
 * The restbus without a CAN interface (the host has none): the shipped input database's
 * messages and cycle times, every counter zero before the start and the /status and /metrics
 * text of that state; the database's refusals (a missing file, cycle times outside
 * 1..HL_RESTBUS_MAX_CYCLE_MS or differing between objects messages, a field of view or range its
 * signals cannot carry) with their messages; and the thread started on an interface that does
 * not exist: every frame due counted as link_down once, nothing sent, the failure logged once,
 * and the camera cycles at scenario times k * 40 ms from t0.
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
#include <time.h>
#include <unistd.h>
#include <cmocka.h>

#include "base/clock.h"
#include "daemon/loop/restbus.h"
#include "testutil.h"

#define IFACE "hlnocan0" /* no such interface */

static const char scenario_json[] =
	"{\"version\": 1, \"duration_s\": 60,"
	" \"road\": {\"segments\": [{\"kind\": \"straight\", \"length_m\": 2000}]},"
	" \"ego\": {\"start_s_m\": 0, \"speed_mps\": 20},"
	" \"actors\": ["
	"  {\"id\": \"oncoming\", \"kind\": \"car\", \"role\": \"oncoming\","
	"   \"path\": {\"lane\": 2, \"start_s_m\": 300, \"speed_mps\": 10}}"
	" ]}";

static struct hl_scenario *sc;
static char dbc_path[512];

static int setup(void **state)
{
	struct hl_json_error err;

	(void)state;
	snprintf(dbc_path, sizeof(dbc_path), "%s/dbc/hd84_inputs.dbc", getenv("HL_SOURCE_DIR"));
	return hl_scenario_parse(scenario_json, "restbus.json", &sc, &err);
}

static int teardown(void **state)
{
	(void)state;
	hl_scenario_free(sc);
	return 0;
}

static struct hl_restbus_config config(const char *dbc, FILE *log)
{
	return (struct hl_restbus_config){
		.iface = IFACE,
		.dbc = dbc,
		.sc = sc,
		.cam = { .pos_m = { -1.8, 0, 1.3 },
			 .fov_h_deg = 50,
			 .fov_v_deg = 30,
			 .range_m = 200 },
		.light_switch = HL_SWITCH_AUTO,
		.adb_enable = true,
		.log = log,
	};
}

static void restbus_maps_the_shipped_database_and_counts_nothing_yet(void **state)
{
	struct hl_restbus_config cfg = config(dbc_path, NULL);
	struct hl_restbus *rb;
	struct hl_restbus_counts c;
	char err[512] = "";
	(void)state;

	if (hl_restbus_new(&cfg, &rb, err, sizeof(err)) < 0)
		fail_msg("%s", err);
	hl_restbus_counts(rb, &c);
	assert_int_equal(c.t0_ns, 0);
	assert_int_equal(c.n_messages, 3);
	assert_string_equal(c.msg[0].name, "HDI_Vehicle");
	assert_int_equal(c.msg[0].can_id, 272);
	assert_int_equal(c.msg[0].cycle_ms, 20);
	for (int i = 1; i < 3; i++) {
		assert_true(strcmp(c.msg[i].name, "HDI_CamObjInfo") == 0 ||
			    strcmp(c.msg[i].name, "HDI_CamObjBox") == 0);
		assert_int_equal(c.msg[i].can_id,
				 strcmp(c.msg[i].name, "HDI_CamObjInfo") ? 289 : 290);
		assert_int_equal(c.msg[i].cycle_ms, 40);
	}
	assert_string_not_equal(c.msg[1].name, c.msg[2].name);
	for (int i = 0; i < 3; i++) {
		assert_int_equal(c.msg[i].sent, 0);
		assert_int_equal(c.msg[i].failed, 0);
		assert_int_equal(c.msg[i].intervals, 0);
	}
	assert_int_equal(c.vehicle_cycles + c.camera_cycles + c.overruns + c.tx_full + c.tx_errors +
				 c.encode_errors + c.link_down + c.foreign_frames + c.objects_sent,
			 0);
	assert_false(c.have_cycle);
	assert_false(c.sock.open);
	hl_restbus_stop(rb); /* never started: nothing to stop */
	hl_restbus_free(rb);
	hl_restbus_free(NULL);
}

static void restbus_status_and_metrics_before_the_start(void **state)
{
	struct hl_restbus_config cfg = config(dbc_path, NULL);
	struct hl_restbus *rb;
	struct hl_restbus_counts c;
	struct hl_prom p;
	char err[512] = "", buf[16384], want[2048], *text = NULL;
	size_t size = 0;
	FILE *m;
	(void)state;

	if (hl_restbus_new(&cfg, &rb, err, sizeof(err)) < 0)
		fail_msg("%s", err);
	hl_restbus_counts(rb, &c);
	m = open_memstream(&text, &size);
	assert_non_null(m);
	hl_restbus_status_json(rb, m);
	fclose(m);
	snprintf(want, sizeof(want),
		 ",\"restbus\":{\"interface\":\"" IFACE "\",\"dbc\":\"%s\",\"t0_monotonic_ns\":0,"
		 "\"open\":false,\"bus\":\"unknown\",\"bus_off\":0,\"error_frames\":0,"
		 "\"vehicle_cycles\":0,\"camera_cycles\":0,\"overruns\":0,\"tx_full\":0,"
		 "\"tx_errors\":0,\"encode_errors\":0,\"link_down\":0,\"foreign_frames\":0,"
		 "\"objects_sent\":0,\"unseen\":{\"behind\":0,\"beyond_range\":0,"
		 "\"outside_fov\":0,\"over_max\":0},\"messages\":[{\"name\":\"HDI_Vehicle\","
		 "\"id\":\"0x110\",\"cycle_ms\":20,\"sent\":0,\"failed\":0,\"intervals\":0,"
		 "\"jitter_ms\":{\"last\":0.0000,\"max\":0.0000,\"mean_abs\":0.0000},"
		 "\"late_ms\":{\"last\":0.0000,\"max\":0.0000}},",
		 dbc_path);
	assert_memory_equal(text, want, strlen(want));
	/* no camera cycle yet: the vehicle last, no camera object */
	assert_string_equal(text + strlen(text) - strlen("\"adb_enable\":false}}"),
			    "\"adb_enable\":false}}");
	assert_null(strstr(text, "\"camera\":"));
	free(text);

	hl_prom_init(&p, buf, sizeof(buf));
	hl_restbus_metrics(rb, &p);
	assert_true(hl_prom_end(&p) > 0);
	assert_non_null(strstr(buf, "hdlamp_restbus_frames_total{message=\"HDI_Vehicle\","
				    "result=\"sent\"} 0\n"));
	assert_non_null(strstr(buf, "hdlamp_restbus_tx_errors_total{reason=\"link_down\"} 0\n"));
	assert_non_null(strstr(buf, "hdlamp_restbus_cycles_total{task=\"camera\"} 0\n"));
	assert_non_null(strstr(buf, "\nhdlamp_restbus_link_up 0\n"));
	hl_restbus_free(rb);
}

/* The shipped database with one attribute line replaced, written to a scratch file. */
static const char *edited_dbc(char *path, size_t size, const char *from, const char *to)
{
	static char text[1 << 16];
	FILE *f = fopen(dbc_path, "r");
	char *at;
	size_t n;

	assert_non_null(f);
	n = fread(text, 1, sizeof(text) - 1, f);
	fclose(f);
	text[n] = '\0';
	at = strstr(text, from);
	assert_non_null(at);
	f = fopen(test_path(path, size, "edited.dbc"), "w");
	assert_non_null(f);
	fwrite(text, 1, (size_t)(at - text), f);
	fputs(to, f);
	fputs(at + strlen(from), f);
	fclose(f);
	return path;
}

static void restbus_refuses_what_the_database_cannot_carry(void **state)
{
	struct hl_restbus_config cfg = config(dbc_path, NULL);
	struct hl_restbus *rb = NULL;
	char err[512], want[1024], path[512];
	(void)state;

	cfg.dbc = "/nonexistent-dir/in.dbc";
	assert_int_equal(hl_restbus_new(&cfg, &rb, err, sizeof(err)), -ENOENT);
	assert_memory_equal(err, "restbus.dbc '/nonexistent-dir/in.dbc':", 38);

	cfg.dbc = dbc_path;
	cfg.cam.fov_h_deg = 164; /* h_left carries -81.92 .. 81.9 */
	assert_int_equal(hl_restbus_new(&cfg, &rb, err, sizeof(err)), -EINVAL);
	snprintf(want, sizeof(want),
		 "restbus.fov_deg 164,30: wider than the database '%s' can carry (its box "
		 "signals' ranges)",
		 dbc_path);
	assert_string_equal(err, want);
	cfg.cam.fov_h_deg = 163.8; /* the edge itself fits */
	assert_int_equal(hl_restbus_new(&cfg, &rb, err, sizeof(err)), 0);
	hl_restbus_free(rb);
	rb = NULL;
	cfg.cam.fov_v_deg = 41; /* v_top carries -20.48 .. 20.46 */
	assert_int_equal(hl_restbus_new(&cfg, &rb, err, sizeof(err)), -EINVAL);
	cfg.cam = config(dbc_path, NULL).cam;
	cfg.cam.range_m = 700; /* distance ends at 655.35 m */
	assert_int_equal(hl_restbus_new(&cfg, &rb, err, sizeof(err)), -EINVAL);
	snprintf(want, sizeof(want),
		 "restbus.range_m 700: farther than the database '%s' can carry (its distance "
		 "signal's range ends at 655.35 m)",
		 dbc_path);
	assert_string_equal(err, want);
	cfg.cam.range_m = 200;

	/* cycle times */
	cfg.dbc = edited_dbc(path, sizeof(path), "BA_ \"GenMsgCycleTime\" BO_ 272 20;",
			     "BA_ \"GenMsgCycleTime\" BO_ 272 1001;");
	assert_int_equal(hl_restbus_new(&cfg, &rb, err, sizeof(err)), -EINVAL);
	snprintf(want, sizeof(want),
		 "restbus.dbc '%s': message 'HDI_Vehicle': GenMsgCycleTime 1001: expected 1..1000 "
		 "ms",
		 path);
	assert_string_equal(err, want);
	cfg.dbc = edited_dbc(path, sizeof(path), "BA_ \"GenMsgCycleTime\" BO_ 272 20;",
			     "BA_ \"GenMsgCycleTime\" BO_ 272 1000;");
	assert_int_equal(hl_restbus_new(&cfg, &rb, err, sizeof(err)), 0);
	hl_restbus_free(rb);
	rb = NULL;
	cfg.dbc = edited_dbc(path, sizeof(path), "BA_ \"GenMsgCycleTime\" BO_ 289 40;",
			     "BA_ \"GenMsgCycleTime\" BO_ 289 20;");
	assert_int_equal(hl_restbus_new(&cfg, &rb, err, sizeof(err)), -EINVAL);
	assert_non_null(strstr(err, ": GenMsgCycleTime "));
	assert_non_null(strstr(err, "ms, the same for every objects message (one camera cycle)"));
	assert_null(rb);
	unlink(path);
}

static void restbus_without_an_interface_counts_every_due_frame_as_link_down(void **state)
{
	FILE *log = tmpfile();
	struct hl_restbus_config cfg = config(dbc_path, log);
	struct hl_restbus *rb;
	struct hl_restbus_counts c;
	const int64_t t0 = hl_clock_monotonic_ns() - 1000000000LL; /* scenario time 1 s now */
	char err[512] = "", line[512];
	uint64_t failed = 0;
	int lines = 0;
	(void)state;

	assert_non_null(log);
	if (hl_restbus_new(&cfg, &rb, err, sizeof(err)) < 0)
		fail_msg("%s", err);
	assert_int_equal(hl_restbus_start(rb, t0), 0);
	/* wait for a few deadlines of each task (bounded: a stuck thread fails, never hangs) */
	for (int k = 0; k < 2000; k++) {
		hl_restbus_counts(rb, &c);
		if (c.vehicle_cycles >= 5 && c.camera_cycles >= 3)
			break;
		usleep(5000);
	}
	hl_restbus_stop(rb);
	hl_restbus_counts(rb, &c);
	assert_true(c.vehicle_cycles >= 5);
	assert_true(c.camera_cycles >= 3);
	assert_int_equal(c.t0_ns, t0);
	for (int i = 0; i < c.n_messages; i++) {
		assert_int_equal(c.msg[i].sent, 0);
		assert_int_equal(c.msg[i].intervals, 0);
		failed += c.msg[i].failed;
	}
	/* each due frame counted once, as link_down, and nothing else */
	assert_int_equal(failed, c.link_down);
	assert_int_equal(c.msg[0].failed, c.vehicle_cycles);
	assert_true(c.link_down >= c.vehicle_cycles + c.camera_cycles);
	assert_int_equal(c.tx_full + c.tx_errors + c.encode_errors + c.foreign_frames, 0);
	assert_false(c.sock.open);
	/* the state still made: the switch as configured, the camera's cycle at k * 40 ms */
	assert_int_equal(c.vehicle.light_switch, HL_SWITCH_AUTO);
	assert_true(c.vehicle.adb_enable);
	assert_true(fabs(c.vehicle.speed_mps - 20.0) < 1e-9);
	assert_true(c.have_cycle);
	assert_true(c.cycle_t_s >= 1.0 && c.cycle_t_s < 60.0);
	assert_true(fabs(c.cycle_t_s / 0.04 - round(c.cycle_t_s / 0.04)) < 1e-6);
	/* the objects sent are the camera's view of the scenario at that time */
	{
		struct hl_world_state w;
		struct hl_camera_objects o;
		struct hl_restbus_unseen un;

		hl_world_at(sc, c.cycle_t_s, &w);
		hl_restbus_objects(sc, &w, &cfg.cam, HL_INPUTS_MAX_OBJECTS, &o, &un);
		assert_int_equal(c.objects.n, o.n);
		for (int i = 0; i < o.n; i++)
			assert_int_equal(c.objects.obj[i].id, o.obj[i].id);
	}
	/* the interface's failure logged once, not per retry */
	rewind(log);
	while (fgets(line, sizeof(line), log))
		if (strstr(line, "hdlampd: restbus: '" IFACE "': ") == line) {
			assert_non_null(strstr(line, "; retrying, the frames due meanwhile counted "
						     "as link_down\n"));
			lines++;
		}
	assert_int_equal(lines, 1);
	fclose(log);
	hl_restbus_free(rb);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(restbus_maps_the_shipped_database_and_counts_nothing_yet),
		cmocka_unit_test(restbus_status_and_metrics_before_the_start),
		cmocka_unit_test(restbus_refuses_what_the_database_cannot_carry),
		cmocka_unit_test(restbus_without_an_interface_counts_every_due_frame_as_link_down),
	};

	return cmocka_run_group_tests(tests, setup, teardown);
}
