/* SPDX-License-Identifier: MIT */
/*
 * verdict/suite.c: the ADB lab's suite files. The shipped suites carry exactly the numbers of
 * FMVSS 108 Table XXI and Table XXII, the IIHS thresholds and heights and the R149 glare set,
 * written out here (a change to a file fails this test); every value has a source. Each
 * malformed input is refused with -EBADMSG at its line and key path.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "verdict/suite.h"
#include "suite_util.h"

/* A valid fmvss108-adb file, one thing per line where the tests break it. */
static const char good[] =
	"{\n" /* 1 */
	"  \"version\": 1, \"name\": \"t\", \"title\": \"T\", \"procedure\": \"fmvss108-adb\", "
	"\"source\": \"S\",\n" /* 2 */
	"  \"bins\": [\n" /* 3 */
	"    {\"role\": \"oncoming\", \"from_m\": 15, \"to_m\": 29.9, \"max_lx\": 3.1, "
	"\"source\": \"S\"}\n" /* 4 */
	"  ],\n" /* 5 */
	"  \"photometers\": [\n" /* 6 */
	"    {\"id\": \"p\", \"role\": \"oncoming\", \"pos_m\": [-1.8, 0.37, 1.1], \"normal\": [0, "
	"0.6, 0.8], \"source\": \"S\"}\n" /* 7 */
	"  ],\n" /* 8 */
	"  \"scenarios\": [\n" /* 9 */
	"    {\"id\": \"a\", \"title\": \"A\", \"role\": \"oncoming\", \"road\": \"straight\", "
	"\"speed_mph\": [60, 70], \"range_m\": [15, 220], \"source\": \"S\"},\n" /* 10 */
	"    {\"id\": \"b\", \"title\": \"B\", \"role\": \"oncoming\", \"road\": \"left\", "
	"\"speed_mph\": [25, 30], \"radius_m\": [85, 115], \"range_m\": [15, 60], \"source\": "
	"\"S\"}\n" /* 11 */
	"  ]\n" /* 12 */
	"}\n";

/* good with the first occurrence of from replaced by to. */
static const char *edit(char *buf, size_t size, const char *from, const char *to)
{
	const char *at = strstr(good, from);

	assert_non_null(at);
	snprintf(buf, size, "%.*s%s%s", (int)(at - good), good, to, at + strlen(from));
	return buf;
}

/* Parses text, expects -EBADMSG at line naming key, with want in the message. */
static void expect_error(const char *text, int line, const char *key, const char *want)
{
	struct hl_suite *s = NULL;
	struct hl_json_error err;
	char formatted[1024];

	assert_int_equal(hl_suite_parse(text, "t.json", &s, &err), -EBADMSG);
	assert_null(s);
	hl_json_error_format(&err, formatted, sizeof(formatted));
	if (err.line != line || strcmp(err.key, key) || !strstr(err.msg, want))
		fail_msg("got '%s' (line %d, key '%s'), expected line %d key '%s' saying '%s'",
			 formatted, err.line, err.key, line, key, want);
	assert_string_equal(err.file, "t.json");
}

/* Every value has its source; every default says what, which value and why. */
static void assert_sourced(const struct hl_suite *s)
{
	assert_true(strlen(s->title) > 0 && strlen(s->source) > 0);
	if (s->has_rounding)
		assert_true(strlen(s->rounding_source) > 0);
	for (int i = 0; i < s->n_bins; i++)
		assert_true(strlen(s->bin[i].source) > 0);
	for (int i = 0; i < s->n_photometers; i++)
		assert_true(strlen(s->photometer[i].source) > 0);
	for (int i = 0; i < s->n_scenarios; i++)
		assert_true(strlen(s->scenario[i].source) > 0 && strlen(s->scenario[i].title) > 0);
	for (int i = 0; i < s->n_defaults; i++)
		assert_true(strlen(s->def[i].what) > 0 && strlen(s->def[i].value) > 0 &&
			    strlen(s->def[i].why) > 0);
	if (s->procedure == HL_SUITE_IIHS)
		assert_true(strlen(s->iihs_source) > 0);
}

static void suite_good_file_parses(void **state)
{
	(void)state;
	struct hl_suite *s;
	struct hl_json_error err;

	if (hl_suite_parse(good, "t.json", &s, &err) < 0)
		fail_msg("%s: %s", err.key, err.msg);
	assert_int_equal(s->procedure, HL_SUITE_FMVSS108_ADB);
	assert_false(s->has_rounding);
	assert_int_equal(s->n_bins, 1);
	assert_true(s->bin[0].max_lx == 3.1);
	assert_int_equal(s->n_photometers, 1);
	/* normalised: [0, 0.6, 0.8] is unit length already */
	assert_true(fabs(s->photometer[0].normal[1] - 0.6) < 1e-12);
	assert_int_equal(s->n_scenarios, 2);
	assert_true(s->scenario[0].radius_m[0] == 0.0 && s->scenario[0].radius_m[1] == 0.0);
	assert_int_equal(s->scenario[1].road, HL_SUITE_LEFT);
	assert_true(s->scenario[1].radius_m[0] == 85.0 && s->scenario[1].radius_m[1] == 115.0);
	hl_suite_free(s);
	hl_suite_free(NULL);
}

static void suite_null_limit_and_normalised_normal(void **state)
{
	(void)state;
	char a[4096], b[4096];
	struct hl_suite *s;
	struct hl_json_error err;

	if (hl_suite_parse(edit(a, sizeof(a), "\"max_lx\": 3.1", "\"max_lx\": null"), "t.json", &s,
			   &err) < 0)
		fail_msg("%s: %s", err.key, err.msg);
	assert_true(isnan(s->bin[0].max_lx));
	hl_suite_free(s);
	if (hl_suite_parse(edit(b, sizeof(b), "[0, 0.6, 0.8]", "[-2, 0, 0]"), "t.json", &s, &err) <
	    0)
		fail_msg("%s: %s", err.key, err.msg);
	assert_true(s->photometer[0].normal[0] == -1.0);
	assert_true(s->photometer[0].normal[1] == 0.0 && s->photometer[0].normal[2] == 0.0);
	hl_suite_free(s);
}

static void suite_rejections(void **state)
{
	(void)state;
	char buf[4096];

	/* an unknown key */
	expect_error(edit(buf, sizeof(buf), "\"max_lx\": 3.1,", "\"max_lx\": 3.1, \"min_lx\": 0,"),
		     4, "bins[0].min_lx", "unknown key 'min_lx'");
	/* bins missing from an fmvss108-adb suite */
	expect_error(edit(buf, sizeof(buf),
			  "  \"bins\": [\n    {\"role\": \"oncoming\", \"from_m\": 15, \"to_m\": "
			  "29.9, \"max_lx\": 3.1, \"source\": \"S\"}\n  ],\n",
			  ""),
		     1, "bins", "missing: a fmvss108-adb suite has bins");
	/* bins in an iihs suite */
	expect_error(edit(buf, sizeof(buf), "\"fmvss108-adb\"", "\"iihs\""), 3, "bins",
		     "only a fmvss108-adb suite has 'bins'");
	/* a glare set outside r149-adb */
	expect_error(edit(buf, sizeof(buf), "\"source\": \"S\",\n",
			  "\"source\": \"S\", \"glare_set\": \"g\",\n"),
		     2, "glare_set", "only a r149-adb suite has 'glare_set'");
	/* a radius on a straight */
	expect_error(edit(buf, sizeof(buf), "\"speed_mph\": [60, 70],",
			  "\"speed_mph\": [60, 70], \"radius_m\": [100, 100],"),
		     10, "scenarios[0].radius_m", "a straight road has no 'radius_m'");
	/* a curve without its radius */
	expect_error(edit(buf, sizeof(buf), "\"radius_m\": [85, 115], ", ""), 11,
		     "scenarios[1].radius_m", "missing: expected [lo, hi] in m");
	/* lo > hi */
	expect_error(edit(buf, sizeof(buf), "[60, 70]", "[70, 60]"), 10, "scenarios[0].speed_mph",
		     "expected lo <= hi");
	/* an empty range */
	expect_error(edit(buf, sizeof(buf), "[15, 220]", "[15, 15]"), 10, "scenarios[0].range_m",
		     "expected lo < hi");
	/* a speed out of range */
	expect_error(edit(buf, sizeof(buf), "[60, 70]", "[60, 700]"), 10,
		     "scenarios[0].speed_mph[1]", "700 is out of range");
	/* a zero normal */
	expect_error(edit(buf, sizeof(buf), "[0, 0.6, 0.8]", "[0, 0, 0]"), 7,
		     "photometers[0].normal", "expected a non-zero vector");
	/* a duplicate id */
	expect_error(edit(buf, sizeof(buf), "\"id\": \"b\"", "\"id\": \"a\""), 11,
		     "scenarios[1].id", "'a' is the id of scenarios[0] already");
	/* a wrong type */
	expect_error(edit(buf, sizeof(buf), "\"to_m\": 29.9", "\"to_m\": \"29.9\""), 4,
		     "bins[0].to_m", "found a string");
	expect_error(edit(buf, sizeof(buf), "\"max_lx\": 3.1", "\"max_lx\": true"), 4,
		     "bins[0].max_lx",
		     "expected a number in [0, 1e+06] lx or null, found a boolean");
	/* a bin role that is not a stimulus vehicle's */
	expect_error(edit(buf, sizeof(buf), "{\"role\": \"oncoming\", \"from_m\"",
			  "{\"role\": \"crossing\", \"from_m\""),
		     4, "bins[0].role", "expected one of");
	/* a scenario whose stimulus vehicle has no photometer */
	expect_error(edit(buf, sizeof(buf), "\"role\": \"oncoming\", \"road\": \"left\"",
			  "\"role\": \"preceding\", \"road\": \"left\""),
		     11, "scenarios[1].role", "no photometer sits on a preceding stimulus vehicle");
	/* a bin from after its end */
	expect_error(edit(buf, sizeof(buf), "\"from_m\": 15", "\"from_m\": 30"), 4, "bins[0].to_m",
		     "expected from_m < to_m");
	/* the name is the file's */
	expect_error(edit(buf, sizeof(buf), "\"name\": \"t\"", "\"name\": \"u\""), 2, "name",
		     "expected the file's name without .json, 't'");
}

/* Table XXI as the issue gives it; NAN: no limit (the preceding row beyond 119.9 m). */
static const struct {
	enum hl_actor_role role;
	double from_m, to_m, max_lx;
} table_xxi[] = {
	{ HL_ROLE_ONCOMING, 15.0, 29.9, 3.1 },	 { HL_ROLE_ONCOMING, 30.0, 59.9, 1.8 },
	{ HL_ROLE_ONCOMING, 60.0, 119.9, 0.6 },	 { HL_ROLE_ONCOMING, 120.0, 220.0, 0.3 },
	{ HL_ROLE_PRECEDING, 15.0, 29.9, 18.9 }, { HL_ROLE_PRECEDING, 30.0, 59.9, 18.9 },
	{ HL_ROLE_PRECEDING, 60.0, 119.9, 4.0 }, { HL_ROLE_PRECEDING, 120.0, 220.0, NAN },
};

/* Table XXII: speed (mph), radius (m, 0 on a straight), range (m). */
static const struct {
	const char *id;
	bool oncoming;
	enum hl_suite_road road;
	double speed[2], radius[2], range[2];
} table_xxii[] = {
	{ "oncoming-straight", true, HL_SUITE_STRAIGHT, { 60, 70 }, { 0, 0 }, { 15, 220 } },
	{ "oncoming-left-85m", true, HL_SUITE_LEFT, { 25, 30 }, { 85, 115 }, { 15, 60 } },
	{ "oncoming-left-210m", true, HL_SUITE_LEFT, { 40, 45 }, { 210, 250 }, { 15, 150 } },
	{ "oncoming-left-335m", true, HL_SUITE_LEFT, { 50, 55 }, { 335, 400 }, { 15, 220 } },
	{ "oncoming-right-210m", true, HL_SUITE_RIGHT, { 40, 45 }, { 210, 250 }, { 15, 50 } },
	{ "oncoming-right-335m", true, HL_SUITE_RIGHT, { 50, 55 }, { 335, 400 }, { 15, 70 } },
	{ "preceding-straight", false, HL_SUITE_STRAIGHT, { 60, 70 }, { 0, 0 }, { 15, 100 } },
	{ "preceding-left-210m", false, HL_SUITE_LEFT, { 40, 45 }, { 210, 250 }, { 15, 100 } },
};

static void suite_fmvss108_tables(void **state)
{
	(void)state;
	struct hl_suite *s = read_shipped("fmvss108-adb");
	int n_on = 0, n_pre = 0;

	assert_string_equal(s->name, "fmvss108-adb");
	assert_int_equal(s->procedure, HL_SUITE_FMVSS108_ADB);
	assert_true(s->has_rounding);
	assert_int_equal(s->decimals, 1);
	assert_int_equal(s->rounding, HL_SUITE_HALF_EVEN);
	assert_int_equal(s->n_bins, 8);
	for (int i = 0; i < 8; i++) {
		assert_int_equal(s->bin[i].role, table_xxi[i].role);
		assert_true(s->bin[i].from_m == table_xxi[i].from_m);
		assert_true(s->bin[i].to_m == table_xxi[i].to_m);
		if (isnan(table_xxi[i].max_lx))
			assert_true(isnan(s->bin[i].max_lx));
		else
			assert_true(s->bin[i].max_lx == table_xxi[i].max_lx);
	}
	assert_int_equal(s->n_scenarios, 8);
	for (int i = 0; i < 8; i++) {
		const struct hl_suite_scenario *sc = &s->scenario[i];

		assert_string_equal(sc->id, table_xxii[i].id);
		assert_true(sc->has_role);
		assert_int_equal(sc->role,
				 table_xxii[i].oncoming ? HL_ROLE_ONCOMING : HL_ROLE_PRECEDING);
		assert_int_equal(sc->road, table_xxii[i].road);
		for (int k = 0; k < 2; k++) {
			assert_true(sc->speed_mph[k] == table_xxii[i].speed[k]);
			assert_true(sc->radius_m[k] == table_xxii[i].radius[k]);
			assert_true(sc->range_m[k] == table_xxii[i].range[k]);
		}
	}
	/* oncoming photometers face the test vehicle ahead of them (+x), preceding ones the one
	 * behind (-x) */
	for (int i = 0; i < s->n_photometers; i++) {
		const struct hl_suite_photometer *ph = &s->photometer[i];

		if (ph->role == HL_ROLE_ONCOMING) {
			n_on++;
			assert_true(ph->normal[0] == 1.0);
		} else {
			n_pre++;
			assert_true(ph->normal[0] == -1.0);
		}
	}
	assert_true(n_on >= 1 && n_pre >= 1);
	assert_true(s->n_defaults >= 1);
	assert_sourced(s);
	hl_suite_free(s);
}

static void suite_iihs(void **state)
{
	(void)state;
	static const struct {
		const char *id;
		enum hl_suite_road road;
		double radius_m, speed_mph;
	} want[] = {
		{ "straight", HL_SUITE_STRAIGHT, 0, 40 },  { "left-150m", HL_SUITE_LEFT, 150, 40 },
		{ "right-150m", HL_SUITE_RIGHT, 150, 40 }, { "left-250m", HL_SUITE_LEFT, 250, 50 },
		{ "right-250m", HL_SUITE_RIGHT, 250, 50 },
	};
	struct hl_suite *s = read_shipped("iihs");

	assert_string_equal(s->name, "iihs");
	assert_int_equal(s->procedure, HL_SUITE_IIHS);
	assert_true(s->visibility_lx == 5.0);
	assert_true(s->visibility_height_m == 0.25);
	assert_true(s->glare_height_m == 1.1);
	assert_int_equal(s->n_bins, 0);
	assert_string_equal(s->glare_set, "");
	assert_int_equal(s->n_scenarios, 5);
	for (int i = 0; i < 5; i++) {
		const struct hl_suite_scenario *sc = &s->scenario[i];

		assert_string_equal(sc->id, want[i].id);
		assert_false(sc->has_role);
		assert_int_equal(sc->road, want[i].road);
		assert_true(sc->radius_m[0] == want[i].radius_m &&
			    sc->radius_m[1] == want[i].radius_m);
		assert_true(sc->speed_mph[0] == want[i].speed_mph &&
			    sc->speed_mph[1] == want[i].speed_mph);
	}
	assert_sourced(s);
	hl_suite_free(s);
}

static void suite_r149(void **state)
{
	(void)state;
	struct hl_suite *s = read_shipped("r149-adb");

	assert_string_equal(s->name, "r149-adb");
	assert_int_equal(s->procedure, HL_SUITE_R149_ADB);
	assert_string_equal(s->glare_set, "unece-r149-01-adb-glare");
	assert_int_equal(s->n_bins, 0);
	assert_int_equal(s->n_scenarios, 2);
	assert_string_equal(s->scenario[0].id, "oncoming-straight");
	assert_int_equal(s->scenario[0].role, HL_ROLE_ONCOMING);
	assert_string_equal(s->scenario[1].id, "preceding-straight");
	assert_int_equal(s->scenario[1].role, HL_ROLE_PRECEDING);
	for (int i = 0; i < 2; i++) {
		assert_int_equal(s->scenario[i].road, HL_SUITE_STRAIGHT);
		assert_true(s->scenario[i].range_m[0] == 50.0 &&
			    s->scenario[i].range_m[1] == 220.0);
	}
	assert_sourced(s);
	hl_suite_free(s);
}

static void suite_names(void **state)
{
	(void)state;
	assert_string_equal(hl_suite_procedure_name(HL_SUITE_R149_ADB), "r149-adb");
	assert_string_equal(hl_suite_road_name(HL_SUITE_RIGHT), "right");
	assert_string_equal(hl_suite_road_name((enum hl_suite_road)7), "?");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(suite_good_file_parses),
		cmocka_unit_test(suite_null_limit_and_normalised_normal),
		cmocka_unit_test(suite_rejections),
		cmocka_unit_test(suite_fmvss108_tables),
		cmocka_unit_test(suite_iihs),
		cmocka_unit_test(suite_r149),
		cmocka_unit_test(suite_names),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
