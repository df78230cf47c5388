/* SPDX-License-Identifier: MIT */
/*
 * world/scenario.c: scenario files. Each rejection names the exact line, column and key path
 * and what was expected; defaults are today's (HD84 lamp poses, 2 lanes of 3.5 m, the driver's
 * eye 1.1 m up); every shipped file in scenarios/ validates.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "world/scenario.h"
#include "testutil.h"

/* A valid file, one key per line where the tests break it (line numbers in comments). */
static const char good[] =
	"{\n" /* 1 */
	"  \"version\": 1,\n" /* 2 */
	"  \"title\": \"t\",\n" /* 3 */
	"  \"duration_s\": 10,\n" /* 4 */
	"  \"road\": {\n" /* 5 */
	"    \"segments\": [\n" /* 6 */
	"      {\"kind\": \"straight\", \"length_m\": 100},\n" /* 7 */
	"      {\"kind\": \"arc\", \"length_m\": 200, \"radius_m\": 250, \"turn\": \"left\"}\n" /* 8 */
	"    ],\n" /* 9 */
	"    \"lanes\": {\"count\": 2, \"width_m\": 3.5},\n" /* 10 */
	"    \"posts\": {\"spacing_m\": 50}\n" /* 11 */
	"  },\n" /* 12 */
	"  \"ego\": {\"start_s_m\": 0, \"lane\": 1, \"speed_mps\": 20},\n" /* 13 */
	"  \"actors\": [\n" /* 14 */
	"    {\"id\": \"car\", \"kind\": \"car\", \"role\": \"oncoming\",\n" /* 15 */
	"     \"path\": {\"lane\": 2, \"start_s_m\": 300, \"speed_mps\": 20}},\n" /* 16 */
	"    {\"id\": \"ped\", \"kind\": \"pedestrian\", \"role\": \"crossing\",\n" /* 17 */
	"     \"path\": {\"waypoints\": [\n" /* 18 */
	"       {\"t_s\": 0, \"x_m\": 60, \"y_m\": -5},\n" /* 19 */
	"       {\"t_s\": 4, \"x_m\": 60, \"y_m\": 5}\n" /* 20 */
	"     ]}}\n" /* 21 */
	"  ]\n" /* 22 */
	"}\n";

/* good with the first occurrence of from replaced by to. */
static const char *edit(char *buf, size_t size, const char *from, const char *to)
{
	const char *at = strstr(good, from);

	assert_non_null(at);
	snprintf(buf, size, "%.*s%s%s", (int)(at - good), good, to, at + strlen(from));
	return buf;
}

/* Parses text, expects a rejection at line:column naming key, with want in the message. */
static void expect_error(const char *text, int line, int column, const char *key, const char *want)
{
	struct hl_scenario *sc = NULL;
	struct hl_json_error err;
	char formatted[1024];

	assert_int_equal(hl_scenario_parse(text, "t.json", &sc, &err), -EBADMSG);
	assert_null(sc);
	hl_json_error_format(&err, formatted, sizeof(formatted));
	if (err.line != line || (column && err.column != column) || strcmp(err.key, key) ||
	    !strstr(err.msg, want))
		fail_msg("got '%s' (line %d, column %d, key '%s'), expected line %d column %d key "
			 "'%s' saying '%s'",
			 formatted, err.line, err.column, err.key, line, column, key, want);
	assert_string_equal(err.file, "t.json");
}

static void scenario_good_file_parses(void **state)
{
	(void)state;
	struct hl_scenario *sc;
	struct hl_json_error err;

	if (hl_scenario_parse(good, "t.json", &sc, &err) < 0)
		fail_msg("%s: %s", err.key, err.msg);
	assert_string_equal(sc->title, "t");
	assert_true(sc->duration_s == 10.0);
	assert_int_equal(sc->road.n_segments, 2);
	assert_int_equal(sc->road.seg[1].kind, HL_SEG_ARC);
	assert_int_equal(sc->road.seg[1].turn, 1);
	assert_true(sc->road.seg[1].radius_m == 250.0);
	assert_true(sc->road.length_m == 300.0);
	assert_true(sc->road.post_spacing_m == 50.0);
	assert_int_equal(sc->n_actors, 2);
	assert_int_equal(sc->actor[0].path.kind, HL_PATH_LANE);
	assert_int_equal(sc->actor[0].path.direction, -1); /* oncoming */
	assert_int_equal(sc->actor[1].path.kind, HL_PATH_WAYPOINTS);
	assert_int_equal(sc->actor[1].path.n_waypoints, 2);
	assert_true(sc->actor[1].path.wp[1].y_m == 5.0);
	hl_scenario_free(sc);
}

/* What a file leaves out is today's: the HD84 lamp poses, 2 lanes of 3.5 m, a car's lamps and
 * its driver's eye 1.1 m above the road. */
static void scenario_defaults(void **state)
{
	(void)state;
	static const char text[] = "{\"version\": 1, \"duration_s\": 5,\n"
				   " \"road\": {\"segments\": [{\"kind\": \"straight\", "
				   "\"length_m\": 100}]},\n"
				   " \"actors\": [{\"id\": \"c\", \"kind\": \"car\", \"role\": "
				   "\"oncoming\",\n"
				   "   \"path\": {\"start_s_m\": 80, \"speed_mps\": 10}}]}\n";
	struct hl_scenario *sc;
	struct hl_json_error err;
	struct hl_lamp_pose pose;

	if (hl_scenario_parse(text, "d.json", &sc, &err) < 0)
		fail_msg("%s: %s", err.key, err.msg);
	assert_int_equal(sc->road.lanes, 2);
	assert_true(sc->road.lane_width_m == 3.5);
	assert_true(sc->road.post_spacing_m == 0.0);
	assert_int_equal(sc->road.edge, HL_MARK_SOLID);
	assert_int_equal(sc->road.separator, HL_MARK_DASHED);
	for (int l = 0; l < 2; l++) {
		hl_lamp_pose_default(l, &pose);
		assert_memory_equal(&sc->ego.lamp[l], &pose, sizeof(pose));
	}
	assert_int_equal(sc->ego.path.lane, 1);
	assert_true(sc->ego.path.speed.v_mps[0] == 0.0);
	assert_true(sc->ego.camera.fov_y_deg == 36.0);
	assert_int_equal(sc->actor[0].path.lane, 2); /* oncoming: the leftmost lane */
	assert_true(sc->actor[0].eye_m[2] == 1.1);
	assert_int_equal(sc->actor[0].n_lamps, 4);
	assert_int_equal(sc->actor[0].lamp[0].kind, HL_EMITTER_HEADLAMP);
	assert_true(sc->actor[0].lamp[2].rgb[1] == 0.0); /* tail lamps red */
	assert_true(sc->actor[0].lamp[2].pos_m[0] == -sc->actor[0].size_m[0]);
	hl_scenario_free(sc);
}

static void scenario_unknown_key(void **state)
{
	(void)state;
	char t[sizeof(good) + 256];

	expect_error(edit(t, sizeof(t), "\"title\"", "\"titel\""), 3, 3, "titel",
		     "unknown key 'titel'; expected one of: version, title, duration_s, road");
	expect_error(edit(t, sizeof(t), "\"width_m\": 3.5", "\"width\": 3.5"), 10, 27,
		     "road.lanes.width", "unknown key 'width'; expected one of: count, width_m");
	expect_error(edit(t, sizeof(t), "\"y_m\": 5}", "\"y_m\": 5, \"z_m\": 0}"), 20, 40,
		     "actors[1].path.waypoints[1].z_m", "unknown key 'z_m'");
	/* a lane key on a waypoint path */
	expect_error(edit(t, sizeof(t), "{\"waypoints\"", "{\"lane\": 1, \"waypoints\""), 18, 15,
		     "actors[1].path.lane", "expected one of: waypoints, heading_deg");
}

static void scenario_wrong_type(void **state)
{
	(void)state;
	char t[sizeof(good) + 256];

	expect_error(edit(t, sizeof(t), "\"duration_s\": 10", "\"duration_s\": \"10\""), 4, 3,
		     "duration_s", "expected a number in (0, 3600] s, found a string");
	expect_error(edit(t, sizeof(t), "\"count\": 2", "\"count\": 2.5"), 10, 15,
		     "road.lanes.count",
		     "expected an integer in [1, 8], found a number with a decimal point");
	expect_error(edit(t, sizeof(t), "\"x_m\": 60, \"y_m\": 5", "\"x_m\": \"60\", \"y_m\": 5"),
		     20, 19, "actors[1].path.waypoints[1].x_m", "found a string");
	expect_error(edit(t, sizeof(t), "\"turn\": \"left\"", "\"turn\": \"up\""), 8, 57,
		     "road.segments[1].turn", "expected one of \"left\", \"right\", found \"up\"");
	expect_error(edit(t, sizeof(t), "\"lanes\": {\"count\": 2, \"width_m\": 3.5}",
			  "\"lanes\": [2, 3.5]"),
		     10, 5, "road.lanes", "expected an object, found an array");
}

static void scenario_waypoints_not_increasing(void **state)
{
	(void)state;
	char t[sizeof(good) + 256];

	expect_error(edit(t, sizeof(t), "\"t_s\": 4", "\"t_s\": 0"), 20, 9,
		     "actors[1].path.waypoints[1].t_s",
		     "0 s is not after the previous waypoint's 0 s: expected strictly increasing");
	expect_error(edit(t, sizeof(t), "\"speed_mps\": 20},\n  \"actors",
			  "\"speed_mps\": [{\"t_s\": 2, \"v_mps\": 5},\n"
			  "{\"t_s\": 1, \"v_mps\": 9}]},\n  \"actors"),
		     14, 2, "ego.speed_mps[1].t_s", "1 s is not after the previous point's 2 s");
}

static void scenario_road_does_not_connect(void **state)
{
	(void)state;
	char t[sizeof(good) + 256];

	expect_error(edit(t, sizeof(t), "\"turn\": \"left\"}",
			  "\"turn\": \"left\", \"start_s_m\": 90}"),
		     8, 73, "road.segments[1].start_s_m",
		     "the road does not connect: this segment starts at s = 90 m, expected 100 m");
	expect_error(edit(t, sizeof(t), "\"length_m\": 100}",
			  "\"length_m\": 100, \"start_s_m\": 3}"),
		     7, 45, "road.segments[0].start_s_m", "starts at s = 3 m, expected 0 m");
	/* a stated start that matches is fine: no error */
	{
		struct hl_scenario *sc;
		struct hl_json_error err;

		assert_int_equal(hl_scenario_parse(edit(t, sizeof(t), "\"turn\": \"left\"}",
							"\"turn\": \"left\", \"start_s_m\": 100}"),
						   "t.json", &sc, &err),
				 0);
		hl_scenario_free(sc);
	}
	expect_error("{\"version\": 1, \"duration_s\": 1,\n \"road\": {\"segments\": []}}", 2, 11,
		     "road.segments", "the road has no segments");
	expect_error("{\"version\": 1, \"duration_s\": 1,\n \"road\": {\"lanes\": {}}}", 2, 2,
		     "road.segments", "missing: the road has no segments");
	expect_error("{\"version\": 1, \"duration_s\": 1}", 1, 1, "road", "missing");
}

static void scenario_out_of_range(void **state)
{
	(void)state;
	char t[sizeof(good) + 256];

	expect_error(edit(t, sizeof(t), "\"radius_m\": 250", "\"radius_m\": 5"), 8, 40,
		     "road.segments[1].radius_m", "5 is out of range: expected a number in [10, ");
	expect_error(edit(t, sizeof(t), "\"lane\": 2", "\"lane\": 3"), 16, 15,
		     "actors[0].path.lane", "3 is out of range: expected an integer in [1, 2]");
	expect_error(edit(t, sizeof(t), "\"duration_s\": 10", "\"duration_s\": 0"), 4, 3,
		     "duration_s", "0 is out of range: expected a number in (0, 3600] s");
	expect_error(edit(t, sizeof(t), "\"version\": 1", "\"version\": 2"), 2, 3, "version",
		     "2 is out of range: expected an integer in [1, 1]");
	expect_error(edit(t, sizeof(t), "\"speed_mps\": 20}}", "\"speed_mps\": -1}}"), 16, 44,
		     "actors[0].path.speed_mps",
		     "-1 is out of range: expected a number in [0, 100]");
}

static void scenario_other_rejections(void **state)
{
	(void)state;
	char t[sizeof(good) + 256];

	expect_error(edit(t, sizeof(t), "\"length_m\": 100}",
			  "\"length_m\": 100, \"radius_m\": 9}"),
		     7, 45, "road.segments[0].radius_m", "a straight segment has no 'radius_m'");
	expect_error(edit(t, sizeof(t), "\"path\": {\"waypoints\"",
			  "\"path\": {\"start_s_m\": 1, \"speed_mps\": 1, \"waypoints_\""),
		     18, 47, "actors[1].path.waypoints_", "unknown key 'waypoints_'");
	expect_error(edit(t, sizeof(t), "\"id\": \"ped\"", "\"id\": \"car\""), 17, 6,
		     "actors[1].id", "'car' is the id of actors[0] already");
	/* jansson's own errors keep its line and column; duplicate keys are refused */
	expect_error("{\"version\": 1,\n \"version\": 1}", 2, 0, "", "duplicate");
	expect_error("{\"version\": 1,\n \"road\": [1,]}", 2, 0, "", "");
}

/* A crossing road user needs waypoints (a lane path runs along the road). */
static void scenario_crossing_needs_waypoints(void **state)
{
	(void)state;
	char t[sizeof(good) + 256];

	expect_error(edit(t, sizeof(t), "\"role\": \"oncoming\"", "\"role\": \"crossing\""), 16, 6,
		     "actors[0].path", "a crossing road user crosses the road");
}

static void scenario_error_format_and_read(void **state)
{
	(void)state;
	struct hl_json_error err = { .file = "f.json", .line = 3, .column = 7 };
	struct hl_scenario *sc;
	char buf[512], text[sizeof(good) + 64], path[256];
	FILE *f;

	snprintf(err.key, sizeof(err.key), "actors[1].path");
	snprintf(err.msg, sizeof(err.msg), "what");
	assert_string_equal(hl_json_error_format(&err, buf, sizeof(buf)),
			    "f.json:3:7: actors[1].path: what");
	err.key[0] = '\0';
	err.column = 0;
	assert_string_equal(hl_json_error_format(&err, buf, sizeof(buf)), "f.json:3: what");

	test_path(path, sizeof(path), "scenario.json");
	f = fopen(path, "w");
	assert_non_null(f);
	fputs(good, f);
	fclose(f);
	assert_int_equal(hl_scenario_read(path, &sc, &err), 0);
	assert_int_equal(sc->n_actors, 2);
	hl_scenario_free(sc);
	f = fopen(path, "w");
	assert_non_null(f);
	fputs(edit(text, sizeof(text), "\"t_s\": 4", "\"t_s\": -4"), f);
	fclose(f);
	assert_int_equal(hl_scenario_read(path, &sc, &err), -EBADMSG);
	assert_string_equal(err.file, path);
	assert_int_equal(err.line, 20);
	assert_string_equal(err.key, "actors[1].path.waypoints[1].t_s");
	unlink(path);
	assert_int_equal(hl_scenario_read(path, &sc, &err), -ENOENT);
	assert_non_null(strstr(err.msg, "cannot open"));
}

static int is_json(const struct dirent *e)
{
	const size_t n = strlen(e->d_name);

	return n > 5 && !strcmp(e->d_name + n - 5, ".json");
}

/* Every file in scenarios/ validates, and the ones the issue asks for are there. */
static void scenario_shipped_files_validate(void **state)
{
	(void)state;
	static const char *const wanted[] = {
		"iihs-approach-straight.json",
		"iihs-approach-curve-250m-left.json",
		"iihs-approach-curve-250m-right.json",
		"iihs-approach-curve-150m-left.json",
		"iihs-approach-curve-150m-right.json",
		"preceding-car.json",
		"pedestrian-edge-60m.json",
		"demo-drive.json",
	};
	const char *src = getenv("HL_SOURCE_DIR");
	struct dirent **names;
	char dir[1024], path[1400];
	int n, found = 0;

	assert_non_null(src);
	snprintf(dir, sizeof(dir), "%s/scenarios", src);
	n = scandir(dir, &names, is_json, alphasort);
	assert_true(n >= 8);
	for (int i = 0; i < n; i++) {
		struct hl_scenario *sc;
		struct hl_json_error err;

		snprintf(path, sizeof(path), "%s/%s", dir, names[i]->d_name);
		if (hl_scenario_read(path, &sc, &err) < 0) {
			char buf[1024];

			fail_msg("%s", hl_json_error_format(&err, buf, sizeof(buf)));
		}
		assert_true(strlen(sc->title) > 10);
		assert_true(sc->n_actors >= 1);
		for (size_t k = 0; k < sizeof(wanted) / sizeof(wanted[0]); k++)
			found += !strcmp(names[i]->d_name, wanted[k]);
		hl_scenario_free(sc);
		free(names[i]);
	}
	free(names);
	assert_int_equal(found, (int)(sizeof(wanted) / sizeof(wanted[0])));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(scenario_good_file_parses),
		cmocka_unit_test(scenario_defaults),
		cmocka_unit_test(scenario_unknown_key),
		cmocka_unit_test(scenario_wrong_type),
		cmocka_unit_test(scenario_waypoints_not_increasing),
		cmocka_unit_test(scenario_road_does_not_connect),
		cmocka_unit_test(scenario_out_of_range),
		cmocka_unit_test(scenario_other_rejections),
		cmocka_unit_test(scenario_crossing_needs_waypoints),
		cmocka_unit_test(scenario_error_format_and_read),
		cmocka_unit_test(scenario_shipped_files_validate),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
