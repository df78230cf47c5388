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

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(config_defaults_are_the_documented_ones),
		cmocka_unit_test(config_file_then_overrides),
		cmocka_unit_test(config_errors_name_file_line_and_key),
		cmocka_unit_test(config_check_wants_exactly_one_input),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
