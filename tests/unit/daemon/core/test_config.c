/* SPDX-License-Identifier: MIT */
/* hdlampd's configuration: values, overrides, and errors naming the file, line and key. */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "daemon/core/config.h"
#include "render/scene.h"
#include "render/view.h"
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
	snprintf(want, sizeof(want),
		 "'%s':5: key 'render.size': '640by360': expected WxH, each 16..8192", path);
	assert_string_equal(err.msg, want);

	write_file(path, sizeof(path), "bad.conf", "[can]\ntimeout_ms = 0\n");
	assert_int_equal(hl_config_load(&c, path, &err), -EINVAL);
	snprintf(want, sizeof(want),
		 "'%s':2: key 'can.timeout_ms': '0': expected an integer 1..60000", path);
	assert_string_equal(err.msg, want);

	write_file(path, sizeof(path), "bad.conf", "[gpio]\nchip = gpiochip0\nstrobbe = 3\n");
	assert_int_equal(hl_config_load(&c, path, &err), -EINVAL);
	snprintf(want, sizeof(want),
		 "'%s':3: key 'gpio.strobbe': unknown key (hdlampd --print-config lists every key)",
		 path);
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
	assert_string_equal(err.msg, "command line: key 'lamps.failsafe': 'bright': expected hold, "
				     "dark or preset:NAME (NAME.json in lamps.presets)");
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
	c.interface[0] = '\0';
	strcpy(c.replay, "-");
	assert_int_equal(hl_config_check(&c, &err), -EINVAL);
	assert_string_equal(
		err.msg, "can.replay_loop needs a file: standard input cannot be replayed again");
	c.replay_loop = false;
	c.replay_passes = 2;
	assert_int_equal(hl_config_check(&c, &err), -EINVAL);
	assert_string_equal(err.msg, "can.replay_passes needs can.replay_loop");
	c.replay_passes = 0;
	assert_int_equal(hl_config_check(&c, &err), 0);
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
	/* the sets beside the binary: ../share/hdlamp/regulations (verdict/regulation.h) */
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
			    "command line: key 'verdict.modes': 'low': expected MODE:ID+ID,MODE:ID,"
			    "... (a mode's sets joined by +, no spaces)");
	assert_int_equal(hl_config_set_arg(&c, "verdict.modes=low:a,", "command line", &err),
			 -EINVAL);
	assert_int_equal(hl_config_set_arg(&c, "verdict.modes=:a", "command line", &err), -EINVAL);
	assert_int_equal(hl_config_set_arg(&c, "verdict.modes=low:a b", "command line", &err),
			 -EINVAL);
	assert_string_equal(c.verdict_modes, "low:a+b,high:c,off:");
	assert_int_equal(hl_config_set_arg(&c, "verdict.traffic=centre", "command line", &err),
			 -EINVAL);
	assert_string_equal(
		err.msg, "command line: key 'verdict.traffic': 'centre': expected right or left");
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

/* Every value is checked whole when it is set: syntax and range, with the value in the message. */
static void config_every_value_is_checked_when_set(void **state)
{
	static const struct {
		const char *arg, *msg;
	} bad[] = {
		{ "render.view=foo", "key 'render.view': 'foo': expected display, lux or hdr" },
		{ "render.view=lid", "key 'render.view': 'lid': expected display, lux or hdr" },
		{ "render.view=", "key 'render.view': '': expected display, lux or hdr" },
		{ "render.scene=moon",
		  "key 'render.scene': 'moon': expected sphere, wall, road, bird or bounce" },
		{ "render.combine=vulkan",
		  "key 'render.combine': 'vulkan': expected auto, cpu or gles" },
		{ "render.headlight=gl",
		  "key 'render.headlight': 'gl': expected auto, cpu or gles" },
		{ "gpio.trigger_edge=up",
		  "key 'gpio.trigger_edge': 'up': expected rising, falling or both" },
		{ "http.listen=999.1.1.1:80",
		  "key 'http.listen': '999.1.1.1:80': host '999.1.1.1': expected an IPv4 address, "
		  "[IPv6 address] or localhost" },
		{ "http.listen=127.0.0.1:99999",
		  "key 'http.listen': '127.0.0.1:99999': port '99999': expected 0..65535 (0 = any "
		  "free port)" },
		{ "http.listen=127.0.0.1:-1",
		  "key 'http.listen': '127.0.0.1:-1': port '-1': expected 0..65535 (0 = any free "
		  "port)" },
		{ "http.listen=127.0.0.1:",
		  "key 'http.listen': '127.0.0.1:': port '': expected 0..65535 (0 = any free port)" },
		{ "http.listen=8080",
		  "key 'http.listen': '8080': expected HOST:PORT (an IPv4 address, [IPv6] or "
		  "localhost; port 0..65535, 0 = any free port), or empty for off" },
		{ "stream.tcp=:0",
		  "key 'stream.tcp': ':0': expected HOST:PORT (an IPv4 address, [IPv6] or "
		  "localhost; port 0..65535, 0 = any free port), or empty for off" },
		{ "stream.tcp=example.org:5600",
		  "key 'stream.tcp': 'example.org:5600': host 'example.org': expected an IPv4 "
		  "address, [IPv6 address] or localhost" },
		{ "stream.tcp=::1:5600",
		  "key 'stream.tcp': '::1:5600': host '::1': expected an IPv4 address, [IPv6 "
		  "address] or localhost" },
		{ "can.interface=can 0",
		  "key 'can.interface': 'can 0': expected an interface name (1..15 characters, no "
		  "'/', ':' or spaces), or empty" },
		{ "can.interface=abcdefghijklmnop",
		  "key 'can.interface': 'abcdefghijklmnop': expected an interface name (1..15 "
		  "characters, no '/', ':' or spaces), or empty" },
		{ "can.lamps=left,,right",
		  "key 'can.lamps': 'left,,right': expected 1..8 lamp names (letters, digits, _ -) "
		  "separated by commas, such as left,right" },
		{ "can.lamps=",
		  "key 'can.lamps': '': expected 1..8 lamp names (letters, digits, _ -) separated by "
		  "commas, such as left,right" },
		{ "can.lamps=a,b,c,d,e,f,g,h,i",
		  "key 'can.lamps': 'a,b,c,d,e,f,g,h,i': expected 1..8 lamp names (letters, digits, "
		  "_ -) separated by commas, such as left,right" },
		{ "can.timeout_ms=99999999999999999999",
		  "key 'can.timeout_ms': '99999999999999999999': expected an integer 1..60000" },
		{ "can.replay_passes=-1",
		  "key 'can.replay_passes': '-1': expected an integer 0..1000000" },
		{ "render.size=640x0", "key 'render.size': '640x0': expected WxH, each 16..8192" },
		{ "render.size=640x360x2",
		  "key 'render.size': '640x360x2': expected WxH, each 16..8192" },
		{ "render.size=-640x360",
		  "key 'render.size': '-640x360': expected WxH, each 16..8192" },
		{ "render.exposure_ev=nan",
		  "key 'render.exposure_ev': 'nan': expected a number -20..20" },
		{ "stream.max_clients=0",
		  "key 'stream.max_clients': '0': expected an integer 1..64" },
		{ "lamps.failsafe=preset:../low",
		  "key 'lamps.failsafe': 'preset:../low': expected hold, dark or preset:NAME (NAME.json "
		  "in lamps.presets)" },
		{ "stream.raw=2", "key 'stream.raw': '2': expected true or false" },
	};
	static const char *const good[] = {
		"stream.tcp=localhost:5600", "stream.tcp=127.0.0.1:0",
		"stream.tcp=[::1]:0",	     "stream.tcp=",
		"http.listen=0.0.0.0:65535", "http.listen=localhost:0",
		"can.interface=vcan0",	     "can.lamps=left",
		"can.replay_passes=3",
	};
	struct hl_config c;
	struct hl_config_error err;
	char want[600];
	(void)state;

	hl_config_defaults(&c);
	for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
		if (hl_config_set_arg(&c, bad[i].arg, "--set x", &err) != -EINVAL)
			fail_msg("'%s' was taken", bad[i].arg);
		snprintf(want, sizeof(want), "--set x: %s", bad[i].msg);
		assert_string_equal(err.msg, want);
	}
	/* nothing of the refused values went in */
	assert_string_equal(c.view, "display");
	assert_string_equal(c.http_listen, "127.0.0.1:8080");
	assert_string_equal(c.lamps, "left,right");
	assert_int_equal(c.width, 1280);
	for (size_t i = 0; i < sizeof(good) / sizeof(good[0]); i++)
		if (hl_config_set_arg(&c, good[i], "--set x", &err) != 0)
			fail_msg("'%s' refused: %s", good[i], err.msg);
	assert_string_equal(c.http_listen, "localhost:0");
	assert_int_equal(c.replay_passes, 3);
}

/* The names config.c takes are the renderer's (minus the LID view, no frame format). */
static void config_scene_and_view_names_are_the_renderers(void **state)
{
	static const char *const scenes[] = { "sphere", "wall", "road", "bird", "bounce" };
	static const char *const views[] = { "display", "lux", "hdr" };
	struct hl_config c;
	struct hl_config_error err;
	char arg[64];
	(void)state;

	hl_config_defaults(&c);
	for (size_t i = 0; i < sizeof(scenes) / sizeof(scenes[0]); i++) {
		snprintf(arg, sizeof(arg), "render.scene=%s", scenes[i]);
		assert_int_equal(hl_config_set_arg(&c, arg, "--set", &err), 0);
		assert_true(hl_scene_from_name(c.scene) >= 0);
	}
	for (int k = 0; k < 8; k++) /* every scene the renderer has is taken */
		if (hl_scene_name(k) && hl_scene_from_name(hl_scene_name(k)) == k) {
			snprintf(arg, sizeof(arg), "render.scene=%s", hl_scene_name(k));
			assert_int_equal(hl_config_set_arg(&c, arg, "--set", &err), 0);
		}
	for (size_t i = 0; i < sizeof(views) / sizeof(views[0]); i++) {
		snprintf(arg, sizeof(arg), "render.view=%s", views[i]);
		assert_int_equal(hl_config_set_arg(&c, arg, "--set", &err), 0);
		assert_true(hl_view_from_name(c.view) >= 0 &&
			    hl_view_from_name(c.view) != HL_VIEW_LID);
	}
}

/* A key set twice in the file: a warning naming both lines; the last value counts. */
static void config_duplicate_key_warns_with_both_lines(void **state)
{
	struct hl_config c;
	struct hl_config_error err;
	char path[512], want[700];
	(void)state;

	hl_config_defaults(&c);
	write_file(path, sizeof(path), "dup.conf",
		   "[render]\nview = lux\n; a comment\n[can]\ntimeout_ms = 50\n[render]\n"
		   "view = hdr\nsize = 160x90\nview=display\n");
	assert_int_equal(hl_config_load(&c, path, &err), 0);
	assert_string_equal(c.view, "display");
	assert_int_equal(err.n_warnings, 2);
	snprintf(want, sizeof(want),
		 "'%s':7: warning: key 'render.view' set again (first at line 2); the last value "
		 "counts",
		 path);
	assert_string_equal(err.warnings[0], want);
	snprintf(want, sizeof(want),
		 "'%s':9: warning: key 'render.view' set again (first at line 2); the last value "
		 "counts",
		 path);
	assert_string_equal(err.warnings[1], want);
	write_file(path, sizeof(path), "dup.conf", "[can]\ntimeout_ms = 50\n");
	assert_int_equal(hl_config_load(&c, path, &err), 0);
	assert_int_equal(err.n_warnings, 0);
	/* a file saved with a UTF-8 byte order mark: inih skips it, and so do the line numbers */
	write_file(path, sizeof(path), "dup.conf", "\xEF\xBB\xBF[render]\nview = lux\nview = 3d\n");
	assert_int_equal(hl_config_load(&c, path, &err), -EINVAL);
	snprintf(want, sizeof(want),
		 "'%s':3: key 'render.view': '3d': expected display, lux or hdr", path);
	assert_string_equal(err.msg, want);
	assert_int_equal(err.n_warnings, 1);
	unlink(path);
}

/* The files the keys name, checked once everything is set, named with where they were set. */
static void config_check_files_names_where_each_was_set(void **state)
{
	struct hl_config c;
	struct hl_config_error err;
	char path[512], log[512], dbc[512], conf[1400], want[1400];
	(void)state;

	hl_config_defaults(&c);
	snprintf(dbc, sizeof(dbc), "%s/dbc/hd84.dbc", getenv("HL_SOURCE_DIR"));
	write_file(log, sizeof(log), "files.log", "# nothing\n\n");
	snprintf(conf, sizeof(conf), "[can]\nreplay = %s\n\ndbc = %s\n", log, dbc);
	write_file(path, sizeof(path), "files.conf", conf);
	assert_int_equal(hl_config_load(&c, path, &err), 0);
	assert_int_equal(hl_config_check(&c, &err), 0);
	assert_int_equal(hl_config_check_files(&c, false, &err), -EINVAL);
	snprintf(want, sizeof(want),
		 "'%s':2: key 'can.replay': '%s': no CAN frame in it; expected candump -L lines "
		 "such as '(1700000000.000000) can0 123#11223344'",
		 path, log);
	assert_string_equal(err.msg, want);

	write_file(log, sizeof(log), "files.log",
		   "(1700000000.000000) can0 320#96008292B5FFFFFF\n");
	assert_int_equal(hl_config_check_files(&c, false, &err), 0); /* decoding needs no lamps */
	assert_int_equal(hl_config_check_files(&c, true, &err), -EINVAL);
	assert_string_equal(err.msg,
			    "key 'lamps.left' (default): no LID file configured for lamp 1 "
			    "of can.lamps (make one with 'hdlamp model --out DIR')");
	assert_int_equal(hl_config_set_arg(&c, "lamps.left=/nonexistent/l.lid.exr",
					   "--set lamps.left=/nonexistent/l.lid.exr", &err),
			 0);
	assert_int_equal(hl_config_check_files(&c, true, &err), -EINVAL);
	assert_string_equal(err.msg,
			    "--set lamps.left=/nonexistent/l.lid.exr: key 'lamps.left': "
			    "'/nonexistent/l.lid.exr': No such file or directory; expected "
			    "a LID file (.lid.exr)");
	/* the LID files are there (any readable file passes here), the preset is not */
	assert_int_equal(hl_config_set_arg(&c, "lamps.left=/dev/null", "--set", &err), 0);
	assert_int_equal(hl_config_check_files(&c, true, &err), -EINVAL);
	assert_string_equal(err.msg, "key 'lamps.right' (default): no LID file configured for lamp "
				     "2 of can.lamps (make one with 'hdlamp model --out DIR')");
	assert_int_equal(hl_config_set_arg(&c, "lamps.right=/dev/null", "--set", &err), 0);
	assert_int_equal(hl_config_check_files(&c, true, &err), 0);
	assert_int_equal(hl_config_set_arg(&c, "lamps.presets=/nonexistent", "--set", &err), 0);
	assert_int_equal(hl_config_set_arg(&c, "lamps.failsafe=preset:low", "-p", &err), 0);
	assert_int_equal(hl_config_check_files(&c, true, &err), -EINVAL);
	assert_string_equal(err.msg, "-p: key 'lamps.failsafe': '/nonexistent/low.json': No such "
				     "file or directory; expected the preset NAME.json in the "
				     "directory lamps.presets");
	assert_int_equal(hl_config_set_arg(&c, "lamps.failsafe=dark", "--set", &err), 0);
	assert_int_equal(hl_config_set_arg(&c, "stream.unix=/nonexistent/f.sock", "-u", &err), 0);
	assert_int_equal(hl_config_check_files(&c, true, &err), -EINVAL);
	assert_string_equal(err.msg, "-u: key 'stream.unix': '/nonexistent': No such file or "
				     "directory; expected the directory of the socket to exist");
	assert_int_equal(hl_config_set_arg(&c, "can.lamps=a,b,c", "-l", &err), 0);
	assert_int_equal(hl_config_check_files(&c, true, &err), -EINVAL);
	assert_string_equal(err.msg, "-l: key 'can.lamps': 'a,b,c': the renderer takes one or two "
				     "lamps");
	assert_int_equal(hl_config_set_arg(&c, "can.dbc=/tmp", "-d", &err), 0);
	assert_int_equal(hl_config_check_files(&c, false, &err), -EINVAL);
	assert_string_equal(err.msg, "-d: key 'can.dbc': '/tmp': a directory; expected a DBC file");
	unlink(log);
	unlink(path);
}

/* [restbus]: defaults, the camera's three numbers, and the scenario it needs. */
static void config_restbus_keys(void **state)
{
	struct hl_config c;
	struct hl_config_error err;

	(void)state;
	hl_config_defaults(&c);
	assert_string_equal(c.restbus_interface, "");
	assert_string_equal(c.restbus_dbc, "");
	assert_true(c.restbus_camera_pos_m[0] == -1.8 && c.restbus_camera_pos_m[1] == 0 &&
		    c.restbus_camera_pos_m[2] == 1.3);
	assert_true(c.restbus_fov_deg[0] == 50 && c.restbus_fov_deg[1] == 30);
	assert_true(c.restbus_range_m == 250);
	assert_string_equal(c.restbus_light_switch, "auto");
	assert_true(c.restbus_adb_enable);
	assert_int_equal(hl_config_set_arg(&c, "restbus.camera_pos_m=-2.1,0.2,1.45", "cl", &err),
			 0);
	assert_true(c.restbus_camera_pos_m[0] == -2.1 && c.restbus_camera_pos_m[1] == 0.2 &&
		    c.restbus_camera_pos_m[2] == 1.45);
	assert_int_equal(hl_config_set_arg(&c, "restbus.camera_pos_m=1,2", "cl", &err), -EINVAL);
	assert_string_equal(err.msg,
			    "cl: key 'restbus.camera_pos_m': '1,2': expected three numbers "
			    "-30..30, as X,Y,Z");
	assert_int_equal(hl_config_set_arg(&c, "restbus.camera_pos_m=1,2,3,4", "cl", &err),
			 -EINVAL);
	assert_int_equal(hl_config_set_arg(&c, "restbus.camera_pos_m=1,2,31", "cl", &err), -EINVAL);
	assert_int_equal(hl_config_set_arg(&c, "restbus.camera_pos_m=1,,3", "cl", &err), -EINVAL);
	assert_true(c.restbus_camera_pos_m[2] == 1.45); /* untouched */
	assert_int_equal(hl_config_set_arg(&c, "restbus.light_switch=dim", "cl", &err), -EINVAL);
	assert_string_equal(err.msg, "cl: key 'restbus.light_switch': 'dim': expected off, auto, "
				     "low or high");
	assert_int_equal(hl_config_set_arg(&c, "can.interface=can0", "cl", &err), 0);
	assert_int_equal(hl_config_set_arg(&c, "restbus.interface=can1", "cl", &err), 0);
	assert_int_equal(hl_config_check(&c, &err), -EINVAL);
	assert_string_equal(err.msg,
			    "restbus.interface needs scene.scenario or scene.world: the restbus "
			    "sends its state");
	assert_int_equal(hl_config_set_arg(&c, "scene.scenario=s.json", "cl", &err), 0);
	assert_int_equal(hl_config_check(&c, &err), 0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(config_defaults_are_the_documented_ones),
		cmocka_unit_test(config_file_then_overrides),
		cmocka_unit_test(config_errors_name_file_line_and_key),
		cmocka_unit_test(config_check_wants_exactly_one_input),
		cmocka_unit_test(config_verdict_and_road_keys),
		cmocka_unit_test(config_every_value_is_checked_when_set),
		cmocka_unit_test(config_scene_and_view_names_are_the_renderers),
		cmocka_unit_test(config_duplicate_key_warns_with_both_lines),
		cmocka_unit_test(config_check_files_names_where_each_was_set),
		cmocka_unit_test(config_restbus_keys),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
