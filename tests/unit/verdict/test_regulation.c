/* SPDX-License-Identifier: MIT */
/* verdict/regulation.c: the set files of regulations/, their angles, limits and rejections. */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "verdict/regulation.h"

#define HEAD                                                                                       \
	"{\n\"id\": \"t\",\n\"title\": \"t\",\n\"source\": \"doc\",\n\"applies_to\": "             \
	"\"each_lamp\",\n\"angles\": \"B\",\n\"receiver\": {\"shape\": \"square\", \"size_deg\": " \
	"0.149, \"source\": \"r\"},\n"

static const char good[] = HEAD
	"\"requirements\": [\n"
	"{\"id\": \"B50L\", \"kind\": \"point\", \"at\": [\"3.43L\", \"0.57U\"], \"max_cd\": 350, "
	"\"source\": \"Table 6\"},\n"
	"{\"id\": \"Segment BLL\", \"kind\": \"segment\", \"from\": [\"8L\", \"0.57U\"], \"to\": "
	"[\"20L\", \"0.57U\"], \"max_cd\": 625, \"source\": \"Table 6\"},\n"
	"{\"id\": \"Imax\", \"kind\": \"imax\", \"min_cd\": 40000, \"source\": \"Table 5\"},\n"
	"{\"id\": \"H-V\", \"kind\": \"point\", \"at\": [0, \"H\"], \"min_cd\": {\"of\": "
	"\"Imax\", \"factor\": 0.8}, \"source\": \"Table 5\"},\n"
	"{\"id\": \"open\", \"kind\": \"segment\", \"from\": [\"1.5L\", \"0.5U\"], \"to\": "
	"[\"L\", \"0.5U\"], \"max_cd\": 1000, \"source\": \"FMVSS\"}\n"
	"]}\n";

static void regulation_parses_kinds_angles_and_limits(void **state)
{
	(void)state;
	struct hl_regulation *reg;
	struct hl_regulation_error err;

	assert_int_equal(hl_regulation_parse(good, "good.json", &reg, &err), 0);
	assert_string_equal(reg->id, "t");
	assert_int_equal(reg->angles, HL_ANGLES_B);
	assert_int_equal(reg->receiver, HL_RECEIVER_SQUARE);
	assert_float_equal(reg->receiver_deg, 0.149, 0);
	assert_int_equal(reg->aim, HL_REG_AIM_NONE);
	assert_int_equal(reg->beam, HL_REG_BEAM_NONE); /* no "beam": every mode */
	assert_int_equal(reg->n_requirements, 5);
	assert_string_equal(reg->req[0].id, "B50L");
	assert_float_equal(reg->req[0].pts[0][0], -3.43, 0);
	assert_float_equal(reg->req[0].pts[0][1], 0.57, 0);
	assert_true(reg->req[0].max.set && reg->req[0].max.of < 0);
	assert_float_equal(reg->req[0].max.cd, 350, 0);
	assert_false(reg->req[0].min.set);
	assert_int_equal(reg->req[0].line, 9);
	assert_int_equal(reg->req[1].kind, HL_REQ_SEGMENT);
	assert_float_equal(reg->req[1].pts[1][0], -20.0, 0);
	assert_int_equal(reg->req[3].min.of, 2);
	assert_float_equal(reg->req[3].min.factor, 0.8, 0);
	assert_float_equal(reg->req[4].pts[1][0], HL_REG_OPEN_LEFT, 0);
	assert_int_equal(hl_regulation_find(reg, "Imax"), 2);
	assert_int_equal(hl_regulation_find(reg, "nope"), -ENOENT);
	hl_regulation_free(reg);
}

static void regulation_angles_as_written(void **state)
{
	(void)state;
	double x;

	assert_int_equal(hl_regulation_angle("3.43L", 'h', &x), 0);
	assert_float_equal(x, -3.43, 0);
	assert_int_equal(hl_regulation_angle("1.72R", 'h', &x), 0);
	assert_float_equal(x, 1.72, 0);
	assert_int_equal(hl_regulation_angle("0.86D", 'v', &x), 0);
	assert_float_equal(x, -0.86, 0);
	assert_int_equal(hl_regulation_angle("V", 'h', &x), 0);
	assert_float_equal(x, 0.0, 0);
	assert_int_equal(hl_regulation_angle("H", 'v', &x), 0);
	assert_float_equal(x, 0.0, 0);
	assert_int_equal(hl_regulation_angle("R", 'h', &x), 0);
	assert_float_equal(x, HL_REG_OPEN_RIGHT, 0);
	assert_int_equal(hl_regulation_angle("U", 'v', &x), 0);
	assert_float_equal(x, HL_REG_OPEN_UP, 0);
	assert_int_equal(hl_regulation_angle("-2.5", 'h', &x), 0);
	assert_float_equal(x, -2.5, 0);
	/* wrong axis letters, signs with letters, junk */
	assert_int_equal(hl_regulation_angle("3U", 'h', &x), -EINVAL);
	assert_int_equal(hl_regulation_angle("3L", 'v', &x), -EINVAL);
	assert_int_equal(hl_regulation_angle("-3L", 'h', &x), -EINVAL);
	assert_int_equal(hl_regulation_angle("3LL", 'h', &x), -EINVAL);
	assert_int_equal(hl_regulation_angle("", 'h', &x), -EINVAL);
	assert_int_equal(hl_regulation_angle("nan", 'h', &x), -EINVAL);
}

/* Each rejection names the file, the line and what was expected. */
static void expect_error(const char *text, int line, const char *needle)
{
	struct hl_regulation *reg = NULL;
	struct hl_regulation_error err;

	assert_int_equal(hl_regulation_parse(text, "bad.json", &reg, &err), -EBADMSG);
	assert_null(reg);
	if (!strstr(err.msg, needle))
		fail_msg("'%s' does not say '%s'", err.msg, needle);
	if (line) {
		char where[32];

		snprintf(where, sizeof(where), "bad.json:%d:", line);
		if (strncmp(err.msg, where, strlen(where)))
			fail_msg("'%s' does not start with '%s'", err.msg, where);
		assert_int_equal(err.line, line);
	}
}

static void regulation_rejections_say_where(void **state)
{
	(void)state;
	char text[4096];

	expect_error("{\"id\": \"t\",\n\"title\": }", 2, "bad.json:2:");
	expect_error(HEAD "\"requirements\": [\n{\"id\": \"X\", \"kind\": \"point\", \"at\": "
			  "[\"1L\", \"1U\"], \"max_cd\": 1, \"source\": \"s\", \"colour\": 1}]}",
		     9, "unknown key 'colour'");
	expect_error(HEAD "\"requirements\": [\n{\"id\": \"X\", \"kind\": \"point\", \"at\": "
			  "[\"1U\", \"1U\"], \"max_cd\": 1, \"source\": \"s\"}]}",
		     9, "horizontal angle");
	expect_error(HEAD "\"requirements\": [\n{\"id\": \"X\", \"kind\": \"point\", \"at\": "
			  "[\"1L\", \"1U\"], \"max_cd\": \"lots\", \"source\": \"s\"}]}",
		     9, "'max_cd' of 'X': expected a number");
	expect_error(HEAD "\"requirements\": [\n{\"id\": \"X\", \"kind\": \"point\", \"at\": "
			  "[\"1L\", \"1U\"], \"source\": \"s\"}]}",
		     9, "expected 'min_cd' or 'max_cd'");
	expect_error(HEAD "\"requirements\": [\n{\"id\": \"X\", \"kind\": \"point\", \"at\": "
			  "[\"1L\", \"1U\"], \"min_cd\": 1}]}",
		     9, "missing key 'source'");
	expect_error(HEAD
		     "\"requirements\": [\n{\"id\": \"X\", \"kind\": \"point\", \"at\": "
		     "[\"1L\", \"1U\"], \"min_cd\": {\"of\": \"Imax\", \"factor\": 0.8}, "
		     "\"source\": \"s\"},\n{\"id\": \"Imax\", \"kind\": \"imax\", \"min_cd\": 1, "
		     "\"source\": \"s\"}]}",
		     9, "names no earlier requirement");
	expect_error(HEAD "\"requirements\": [\n{\"id\": \"X\", \"kind\": \"segment\", \"from\": "
			  "[\"1L\", \"1U\"], \"to\": [\"2L\", \"2U\"], \"min_cd\": 1, \"source\": "
			  "\"s\"}]}",
		     9, "horizontal (same v) or vertical");
	expect_error(HEAD
		     "\"requirements\": [\n{\"id\": \"X\", \"kind\": \"zone\", \"polygon\": "
		     "[[\"1L\", \"1U\"], [\"2L\", \"2U\"]], \"min_cd\": 1, \"source\": \"s\"}]}",
		     9, "expected an array of 3 to 16");
	expect_error(HEAD "\"requirements\": [\n{\"id\": \"X\", \"kind\": \"point\", \"from\": "
			  "[\"1L\", \"1U\"], \"min_cd\": 1, \"source\": \"s\"}]}",
		     9, "a point needs 'at'");
	expect_error(HEAD "\"requirements\": [\n{\"id\": \"X\", \"kind\": \"blob\", \"min_cd\": 1, "
			  "\"source\": \"s\"}]}",
		     9, "'kind' expected point");
	expect_error(HEAD "\"requirements\": [\n{\"id\": \"X\", \"kind\": \"imax\", \"min_cd\": 1, "
			  "\"source\": \"s\"},\n{\"id\": \"X\", \"kind\": \"imax\", \"min_cd\": 1, "
			  "\"source\": \"s\"}]}",
		     10, "used twice (first on line 9)");
	expect_error(HEAD "\"requirements\": [\n{\"id\": \"X\", \"kind\": \"imax\", \"min_cd\": 9, "
			  "\"max_cd\": 1, \"source\": \"s\"}]}",
		     9, "min_cd 9 is above max_cd 1");
	expect_error(HEAD "\"requirements\": []}", 8, "expected an array of 1 to");
	/* the JSON parser's own errors keep its line and column; duplicate keys are refused */
	expect_error("{\"id\": \"a\",\n \"id\": \"b\"}", 2, "duplicate");
	snprintf(text, sizeof(text), "%s", good);
	memcpy(strstr(text, "each_lamp"), "each_limp", 9);
	expect_error(text, 5, "'applies_to': expected");
	snprintf(text, sizeof(text), "%s", good);
	memcpy(strstr(text, "\"B\""), "\"C\"", 3);
	expect_error(text, 6, "'angles': expected \"A\" or \"B\"");
}

/* "beam": passing, driving or adb; anything else is refused on its line. */
static void regulation_beam_is_one_of_three(void **state)
{
	(void)state;
	static const char *const beams[] = { "passing", "driving", "adb" };
	static const enum hl_reg_beam want[] = { HL_REG_BEAM_PASSING, HL_REG_BEAM_DRIVING,
						 HL_REG_BEAM_ADB };
	char text[4096];
	const char *at = strstr(good, "\"angles\"");

	for (int b = 0; b < 3; b++) {
		struct hl_regulation *reg;
		struct hl_regulation_error err;

		snprintf(text, sizeof(text), "%.*s\"beam\": \"%s\",\n%s", (int)(at - good), good,
			 beams[b], at);
		assert_int_equal(hl_regulation_parse(text, "good.json", &reg, &err), 0);
		assert_int_equal(reg->beam, want[b]);
		assert_string_equal(hl_reg_beam_name(reg->beam), beams[b]);
		assert_int_equal(reg->req[0].line, 10); /* one line further down */
		hl_regulation_free(reg);
	}
	assert_null(hl_reg_beam_name(HL_REG_BEAM_NONE));
	snprintf(text, sizeof(text), "%.*s\"beam\": \"high\",\n%s", (int)(at - good), good, at);
	expect_error(text, 6, "bad.json:6: 'beam': expected \"passing\", \"driving\" or \"adb\"");
	snprintf(text, sizeof(text), "%.*s\"beam\": 1,\n%s", (int)(at - good), good, at);
	expect_error(text, 6, "'beam': expected \"passing\", \"driving\" or \"adb\"");
	snprintf(text, sizeof(text), "%.*s\"beam\": \"Passing\",\n%s", (int)(at - good), good, at);
	expect_error(text, 6, "'beam': expected"); /* as the files write it: lower case */
}

static void regulation_loads_by_id_and_lists(void **state)
{
	(void)state;
	const char *dir = getenv("HL_TEST_TMPDIR");
	char path[1200], d[1024];
	struct hl_regulation *reg;
	struct hl_regulation_error err;
	char **ids;
	FILE *f;

	assert_non_null(dir);
	snprintf(d, sizeof(d), "%s/regs-%d", dir, (int)getpid());
	snprintf(path, sizeof(path), "mkdir -p '%s'", d);
	assert_int_equal(system(path), 0);
	snprintf(path, sizeof(path), "%s/t.json", d);
	f = fopen(path, "w");
	assert_non_null(f);
	fputs(good, f);
	fclose(f);
	snprintf(path, sizeof(path), "%s/other.json", d);
	f = fopen(path, "w");
	assert_non_null(f);
	fputs(good, f); /* its id says "t" */
	fclose(f);
	assert_int_equal(hl_regulation_load(d, "t", &reg, &err), 0);
	assert_int_equal(reg->n_requirements, 5);
	hl_regulation_free(reg);
	assert_int_equal(hl_regulation_load(d, "other", &reg, &err), -EBADMSG);
	assert_non_null(strstr(err.msg, "'id' is 't', expected 'other'"));
	assert_int_equal(hl_regulation_load(d, "missing", &reg, &err), -ENOENT);
	assert_non_null(strstr(err.msg, "no regulation set 'missing'"));
	assert_int_equal(hl_regulation_load(d, "../etc/passwd", &reg, &err), -EINVAL);
	assert_int_equal(hl_regulation_list(d, &ids), 0);
	assert_string_equal(ids[0], "other");
	assert_string_equal(ids[1], "t");
	assert_null(ids[2]);
	hl_regulation_list_free(ids);
	snprintf(path, sizeof(path), "rm -rf '%s'", d);
	assert_int_equal(system(path), 0);
}

/* Every shipped set in regulations/ parses, its id is its file name, each value is cited. */
static void regulation_shipped_sets_load(void **state)
{
	(void)state;
	const char *src = getenv("HL_SOURCE_DIR");
	char dir[1024];
	char **ids;
	int n = 0;

	assert_non_null(src);
	snprintf(dir, sizeof(dir), "%s/regulations", src);
	assert_int_equal(hl_regulation_list(dir, &ids), 0);
	for (char **id = ids; *id; id++, n++) {
		struct hl_regulation *reg;
		struct hl_regulation_error err;

		if (hl_regulation_load(dir, *id, &reg, &err) < 0)
			fail_msg("%s", err.msg);
		/* every shipped set says its beam; the file name says which */
		if (strstr(*id, "passing") || strstr(*id, "lower"))
			assert_int_equal(reg->beam, HL_REG_BEAM_PASSING);
		else if (strstr(*id, "driving") || strstr(*id, "upper"))
			assert_int_equal(reg->beam, HL_REG_BEAM_DRIVING);
		else if (strstr(*id, "adb"))
			assert_int_equal(reg->beam, HL_REG_BEAM_ADB);
		else
			fail_msg("%s: which beam?", *id);
		for (int k = 0; k < reg->n_requirements; k++)
			assert_true(strlen(reg->req[k].source) > 8);
		hl_regulation_free(reg);
	}
	hl_regulation_list_free(ids);
	assert_true(n >= 7);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(regulation_parses_kinds_angles_and_limits),
		cmocka_unit_test(regulation_angles_as_written),
		cmocka_unit_test(regulation_rejections_say_where),
		cmocka_unit_test(regulation_beam_is_one_of_three),
		cmocka_unit_test(regulation_loads_by_id_and_lists),
		cmocka_unit_test(regulation_shipped_sets_load),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
