/* SPDX-License-Identifier: MIT */
/* Preset JSON: values, round trip, and every error with its line and column. */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "lamp/preset.h"
#include "testutil.h"

static void preset_parses_both_lamps(void **state)
{
	struct hl_preset *p;
	struct hl_preset_error err;
	float i[3];
	(void)state;

	assert_int_equal(
		hl_preset_parse(" {\"right\": [1, 2, 63],\n \"left\":[0,31,7]}\n", &p, &err), 0);
	assert_int_equal(p->n_sources, 3);
	assert_int_equal(p->dim[HL_SIDE_LEFT][1], 31);
	assert_int_equal(p->dim[HL_SIDE_RIGHT][2], 63);
	hl_preset_intensities(p, HL_SIDE_RIGHT, i);
	assert_true(i[2] == 1.0f);
	assert_true(i[0] == 1.0f / 63.0f);
	hl_preset_free(p);
}

static void preset_round_trips_through_a_file(void **state)
{
	struct hl_preset *p, *back;
	struct hl_preset_error err;
	char path[512];
	(void)state;

	assert_int_equal(hl_preset_new(95, &p), 0);
	for (int k = 0; k < 95; k++) {
		p->dim[0][k] = (uint8_t)(k % 64);
		p->dim[1][k] = (uint8_t)(63 - k % 64);
	}
	assert_int_equal(hl_preset_write(p, test_path(path, sizeof(path), "p.json")), 0);
	assert_int_equal(hl_preset_read(path, &back, &err), 0);
	assert_int_equal(back->n_sources, 95);
	assert_memory_equal(back->dim[0], p->dim[0], 95);
	assert_memory_equal(back->dim[1], p->dim[1], 95);
	hl_preset_free(back);
	hl_preset_free(p);
	unlink(path);
	assert_int_equal(hl_preset_read(path, &back, &err), -ENOENT);
	assert_int_equal(err.line, 0);
	assert_string_equal(err.msg, "cannot open: No such file or directory");
}

static void expect_error(const char *text, int line, int column, const char *msg)
{
	struct hl_preset *p = NULL;
	struct hl_preset_error err;

	assert_int_equal(hl_preset_parse(text, &p, &err), -EBADMSG);
	assert_null(p);
	if (err.line != line || err.column != column || strcmp(err.msg, msg) != 0)
		fail_msg("'%s': got %d:%d '%s', want %d:%d '%s'", text, err.line, err.column,
			 err.msg, line, column, msg);
}

static void preset_errors_name_line_and_column(void **state)
{
	(void)state;
	/* syntax errors: jansson's place and words */
	expect_error("{\"left\" [1]}", 1, 9, "':' expected near '['");
	expect_error("{\"left\": [1] \"right\": [1]}", 1, 20, "'}' expected near '\"right\"'");
	expect_error("{\"left\": [1], \"right\": [3]} x", 1, 29, "end of file expected near 'x'");
	expect_error("{\"left\": [1], \"left\": [2]}", 1, 20,
		     "duplicate object key near '\"left\"'");
	expect_error("", 1, 1, "'[' or '{' expected near end of file");
	/* the preset's shape: at the key or element, its path first */
	expect_error("[1]", 1, 1, "expected an object, found an array");
	expect_error("{\"left\": [1, 64], \"right\": [1, 2]}", 1, 14,
		     "left[1]: 64 is out of range: expected an integer in [0, 63]");
	expect_error("{\"left\": [1, -1]}", 1, 14,
		     "left[1]: -1 is out of range: expected an integer in [0, 63]");
	expect_error(
		"{\"left\": [1,\n 2.5]}", 2, 2,
		"left[1]: expected an integer in [0, 63], found a number with a decimal point");
	expect_error("{\"left\": [1], \"right\": [\"a\"]}", 1, 25,
		     "right[0]: expected an integer in [0, 63], found a string");
	expect_error("{\"left\": [1],\n  \"centre\": [2]}", 2, 3,
		     "centre: unknown key 'centre'; expected one of: left, right");
	expect_error("{\"left\": [1]}", 1, 1,
		     "right: missing: expected both \"left\" and \"right\", each a list of dimming "
		     "values");
	expect_error("{\"left\": [1, 2], \"right\": [3]}", 1, 18,
		     "right: has 1 dimming values; expected as many as \"left\" (2)");
	expect_error("{\"left\": []}", 1, 2,
		     "left: expected a list of 1 to 4096 dimming values, found an empty list");
	expect_error("{\"left\": {}, \"right\": [1]}", 1, 2,
		     "left: expected a list of 1 to 4096 dimming values, found an object");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(preset_parses_both_lamps),
		cmocka_unit_test(preset_round_trips_through_a_file),
		cmocka_unit_test(preset_errors_name_line_and_column),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
