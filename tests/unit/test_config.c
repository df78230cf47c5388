/* SPDX-License-Identifier: MIT */
/* hdlampd's configuration: values, overrides, and errors naming the file, line and key. */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "daemon/config.h"
#include "testutil.h"

static const char *write_file(char *path, size_t size, const char *name, const char *text)
{
	FILE *f = fopen(test_path(path, size, name), "w");

	assert_non_null(f);
	fputs(text, f);
	fclose(f);
	return path;
}

static void config_defaults_are_the_documented_ones(void **state)
{
	struct hl_config c;
	(void)state;

	hl_config_defaults(&c);
	assert_string_equal(c.dbc, "dbc/hd84.dbc");
	assert_string_equal(c.lamps, "left,right");
	assert_int_equal(c.timeout_ms, 100);
	assert_int_equal(c.failsafe, HL_FAILSAFE_HOLD);
	assert_string_equal(c.scene, "road");
	assert_int_equal(c.width, 1280);
	assert_int_equal(c.height, 720);
	assert_string_equal(c.stream_tcp, "127.0.0.1:5600");
	assert_string_equal(c.http_listen, "127.0.0.1:8080");
	assert_false(c.http_capture);
	assert_false(c.dbc_strict); /* the DBC loads leniently */
}

static void config_file_then_overrides(void **state)
{
	struct hl_config c;
	struct hl_config_error err;
	char path[512];
	(void)state;

	hl_config_defaults(&c);
	write_file(path, sizeof(path), "ok.conf",
		   "; a bench\n[can]\ninterface = can1\ntimeout_ms = 150\n\n[lamps]\n"
		   "failsafe = preset:low\n[render]\nsize = 640x360\nexposure_ev = -1.5\n"
		   "[http]\ncapture = yes\n");
	assert_int_equal(hl_config_load(&c, path, &err), 0);
	assert_string_equal(c.interface, "can1");
	assert_int_equal(c.timeout_ms, 150);
	assert_int_equal(c.failsafe, HL_FAILSAFE_PRESET);
	assert_string_equal(c.failsafe_preset, "low");
	assert_int_equal(c.width, 640);
	assert_int_equal(c.height, 360);
	assert_true(c.exposure_ev == -1.5);
	assert_true(c.http_capture);
	assert_int_equal(hl_config_set_arg(&c, "lamps.failsafe=dark", "command line", &err), 0);
	assert_int_equal(c.failsafe, HL_FAILSAFE_DARK);
	assert_int_equal(hl_config_set_arg(&c, "dbc.strict=true", "command line", &err), 0);
	assert_true(c.dbc_strict);
	assert_int_equal(hl_config_set_arg(&c, "stream.tcp=", "command line", &err), 0);
	assert_string_equal(c.stream_tcp, "");
	assert_int_equal(hl_config_check(&c, &err), 0);
	unlink(path);
}

static void config_errors_name_file_line_and_key(void **state)
{
	struct hl_config c;
	struct hl_config_error err;
	char path[512], want[700];
	(void)state;

	hl_config_defaults(&c);
	write_file(path, sizeof(path), "bad.conf",
		   "[can]\ninterface = can0\n\n[render]\nsize = 640by360\n");
	assert_int_equal(hl_config_load(&c, path, &err), -EINVAL);
	snprintf(want, sizeof(want), "'%s':5: key 'render.size': expected WxH, each 16..8192",
		 path);
	assert_string_equal(err.msg, want);

	write_file(path, sizeof(path), "bad.conf", "[can]\ntimeout_ms = 0\n");
	assert_int_equal(hl_config_load(&c, path, &err), -EINVAL);
	snprintf(want, sizeof(want),
		 "'%s':2: key 'can.timeout_ms': '0': expected an integer 1..60000", path);
	assert_string_equal(err.msg, want);

	write_file(path, sizeof(path), "bad.conf", "[gpio]\nchip = gpiochip0\nstrobbe = 3\n");
	assert_int_equal(hl_config_load(&c, path, &err), -EINVAL);
	snprintf(want, sizeof(want),
		 "'%s':3: key 'gpio.strobbe': unknown key (see hdlampd --help-config)", path);
	assert_string_equal(err.msg, want);

	write_file(path, sizeof(path), "bad.conf", "[lamps\nleft = x\n");
	assert_int_equal(hl_config_load(&c, path, &err), -EINVAL);
	snprintf(want, sizeof(want), "'%s':1: expected [section], key = value, or a ; comment",
		 path);
	assert_string_equal(err.msg, want);
	unlink(path);

	assert_int_equal(hl_config_load(&c, path, &err), -ENOENT);
	assert_int_equal(hl_config_set_arg(&c, "render.view", "command line", &err), -EINVAL);
	assert_string_equal(err.msg, "command line: 'render.view': expected SECTION.KEY=VALUE");
	assert_int_equal(hl_config_set_arg(&c, "lamps.failsafe=bright", "command line", &err),
			 -EINVAL);
	assert_string_equal(
		err.msg, "command line: key 'lamps.failsafe': expected hold, dark or preset:NAME");
	assert_int_equal(hl_config_set_arg(&c, "render.combine=vulkan", "command line", &err),
			 -EINVAL);
	assert_int_equal(hl_config_set_arg(&c, "http.capture=maybe", "command line", &err),
			 -EINVAL);
}

static void config_check_wants_exactly_one_input(void **state)
{
	struct hl_config c;
	struct hl_config_error err;
	(void)state;

	hl_config_defaults(&c);
	assert_int_equal(hl_config_check(&c, &err), -EINVAL);
	assert_string_equal(err.msg, "exactly one of can.interface and can.replay is needed");
	strcpy(c.interface, "can0");
	strcpy(c.replay, "x.log");
	assert_int_equal(hl_config_check(&c, &err), -EINVAL);
	c.replay[0] = '\0';
	c.replay_loop = true;
	assert_int_equal(hl_config_check(&c, &err), -EINVAL);
	assert_string_equal(err.msg, "can.replay_fast and can.replay_loop need can.replay");
}

static void config_verdict_and_road_keys(void **state)
{
	struct hl_config c;
	struct hl_config_error err;
	char path[512], want[700], many[2048];
	int n = 0;
	(void)state;

	hl_config_defaults(&c);
	assert_int_equal(c.n_verdict_sets, 0); /* no verdicts unless asked */
	assert_false(c.traffic_left);
	assert_true(c.road_levels_lx[0] == 1.0 && c.road_levels_lx[1] == 3.0);
	assert_true(c.road_width_at_m[0] == 25.0 && c.road_width_at_m[1] == 50.0);
	/* the sets beside the binary: ../share/hdlamp/regulations (lamp/regulation.h) */
	assert_true(c.regulations[0] == '/');
	assert_non_null(strstr(c.regulations, "/hdlamp/regulations"));
	assert_string_equal(strstr(c.regulations, "/hdlamp/regulations"), "/hdlamp/regulations");

	write_file(path, sizeof(path), "verdict.conf",
		   "[verdict]\nsets = unece-r149-01-adb-glare , unece-r149-01-driving-b,x_1.2+y\n"
		   "regulations = /srv/regs\ntraffic = left\n[road]\nlevels = 0.5,2\n"
		   "width_at = 20,40.5\n");
	assert_int_equal(hl_config_load(&c, path, &err), 0);
	assert_int_equal(c.n_verdict_sets, 3);
	assert_string_equal(c.verdict_sets[0], "unece-r149-01-adb-glare");
	assert_string_equal(c.verdict_sets[1], "unece-r149-01-driving-b");
	assert_string_equal(c.verdict_sets[2], "x_1.2+y");
	assert_string_equal(c.regulations, "/srv/regs");
	assert_true(c.traffic_left);
	assert_true(c.road_levels_lx[0] == 0.5 && c.road_levels_lx[1] == 2.0);
	assert_true(c.road_width_at_m[0] == 20.0 && c.road_width_at_m[1] == 40.5);
	unlink(path);

	/* empty: no verdicts */
	assert_int_equal(hl_config_set_arg(&c, "verdict.sets=", "command line", &err), 0);
	assert_int_equal(c.n_verdict_sets, 0);
	assert_int_equal(hl_config_set_arg(&c, "verdict.sets=a,b", "command line", &err), 0);
	assert_int_equal(c.n_verdict_sets, 2);

	/* errors name the key and leave the sets as they were */
	assert_int_equal(hl_config_set_arg(&c, "verdict.sets=a,,b", "command line", &err), -EINVAL);
	assert_string_equal(err.msg,
			    "command line: key 'verdict.sets': '': expected set ids (letters, "
			    "digits, . _ + -, at most 47 characters) separated by commas");
	assert_int_equal(hl_config_set_arg(&c, "verdict.sets=../etc/passwd", "command line", &err),
			 -EINVAL);
	assert_int_equal(hl_config_set_arg(&c, "verdict.sets=a,b,a", "command line", &err),
			 -EINVAL);
	assert_string_equal(err.msg, "command line: key 'verdict.sets': 'a' is named twice");
	assert_int_equal(hl_config_set_arg(&c, "verdict.sets=a,", "command line", &err), -EINVAL);
	assert_string_equal(err.msg,
			    "command line: key 'verdict.sets': a set id after the last comma");
	n = snprintf(many, sizeof(many), "verdict.sets=");
	for (int i = 0; i < 33; i++)
		n += snprintf(many + n, sizeof(many) - n, "%ss%d", i ? "," : "", i);
	assert_int_equal(hl_config_set_arg(&c, many, "command line", &err), -EINVAL);
	assert_string_equal(
		err.msg,
		"command line: key 'verdict.sets': at most 32 sets (one bit each in the frame header)");
	many[strrchr(many, ',') - many] = '\0'; /* 32 sets: the most */
	assert_int_equal(hl_config_set_arg(&c, many, "command line", &err), 0);
	assert_int_equal(c.n_verdict_sets, 32);
	assert_string_equal(c.verdict_sets[31], "s31");

	assert_int_equal(hl_config_set_arg(&c, "verdict.modes=low:a+b,high:c,off:", "command line",
					   &err),
			 0);
	assert_string_equal(c.verdict_modes, "low:a+b,high:c,off:");
	assert_int_equal(hl_config_set_arg(&c, "verdict.modes=low", "command line", &err), -EINVAL);
	assert_string_equal(err.msg,
			    "command line: key 'verdict.modes': expected MODE:ID+ID,MODE:ID,"
			    "... (a mode's sets joined by +, no spaces)");
	assert_int_equal(hl_config_set_arg(&c, "verdict.modes=low:a,", "command line", &err),
			 -EINVAL);
	assert_int_equal(hl_config_set_arg(&c, "verdict.modes=:a", "command line", &err), -EINVAL);
	assert_int_equal(hl_config_set_arg(&c, "verdict.modes=low:a b", "command line", &err),
			 -EINVAL);
	assert_string_equal(c.verdict_modes, "low:a+b,high:c,off:");
	assert_int_equal(hl_config_set_arg(&c, "verdict.traffic=centre", "command line", &err),
			 -EINVAL);
	assert_string_equal(err.msg, "command line: key 'verdict.traffic': expected right or left");
	write_file(path, sizeof(path), "bad.conf", "[road]\nlevels = 1\n");
	assert_int_equal(hl_config_load(&c, path, &err), -EINVAL);
	snprintf(want, sizeof(want),
		 "'%s':2: key 'road.levels': '1': expected two numbers 0.01..1000, as A,B", path);
	assert_string_equal(err.msg, want);
	unlink(path);
	assert_int_equal(hl_config_set_arg(&c, "road.width_at=25,500", "command line", &err),
			 -EINVAL);
	assert_string_equal(err.msg, "command line: key 'road.width_at': '25,500': expected two "
				     "numbers 1..300, as A,B");
	assert_int_equal(hl_config_set_arg(&c, "road.levels=1,nan", "command line", &err), -EINVAL);
	assert_int_equal(hl_config_set_arg(&c, "road.levels=1,3,5", "command line", &err), -EINVAL);
	assert_true(c.road_levels_lx[0] == 0.5 && c.road_levels_lx[1] == 2.0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(config_defaults_are_the_documented_ones),
		cmocka_unit_test(config_file_then_overrides),
		cmocka_unit_test(config_errors_name_file_line_and_key),
		cmocka_unit_test(config_check_wants_exactly_one_input),
		cmocka_unit_test(config_verdict_and_road_keys),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
