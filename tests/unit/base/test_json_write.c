/* SPDX-License-Identifier: MIT */
/* JSON strings and numbers as every writer of the daemon and the CLI prints them. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "base/json_write.h"

/* What fn wrote, as a string the caller frees. */
static char *written(void (*fn)(FILE *f, const void *arg), const void *arg)
{
	char *buf = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&buf, &len);

	assert_non_null(f);
	fn(f, arg);
	assert_int_equal(fclose(f), 0);
	return buf;
}

static void write_str(FILE *f, const void *arg)
{
	hl_json_write_str(f, arg);
}

static void write_num(FILE *f, const void *arg)
{
	hl_json_write_num(f, *(const double *)arg, "%.3f");
}

static void strings_are_escaped(void **state)
{
	static const struct {
		const char *in, *want;
	} cases[] = {
		{ "plain", "\"plain\"" },
		{ "", "\"\"" },
		{ "a\"b", "\"a\\\"b\"" },
		{ "back\\slash", "\"back\\\\slash\"" },
		{ "tab\tnl\n", "\"tab\\u0009nl\\u000a\"" },
		{ "\x01\x1f", "\"\\u0001\\u001f\"" },
		/* bytes above 0x7f pass as they are: UTF-8 stays UTF-8 */
		{ "l\xc3\xbcx", "\"l\xc3\xbcx\"" },
		{ "/", "\"/\"" },
	};
	(void)state;

	for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
		char *got = written(write_str, cases[i].in);

		assert_string_equal(got, cases[i].want);
		free(got);
	}
}

static void null_string_is_empty(void **state)
{
	char *got = written(write_str, NULL);
	(void)state;

	assert_string_equal(got, "\"\"");
	free(got);
}

static void numbers_use_the_format_and_null_when_not_finite(void **state)
{
	static const struct {
		double x;
		const char *want;
	} cases[] = {
		{ 1.5, "1.500" }, { -0.0004, "-0.000" }, { 12345.6789, "12345.679" },
		{ NAN, "null" },  { INFINITY, "null" },	 { -INFINITY, "null" },
	};
	(void)state;

	for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
		char *got = written(write_num, &cases[i].x);

		assert_string_equal(got, cases[i].want);
		free(got);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(strings_are_escaped),
		cmocka_unit_test(null_string_is_empty),
		cmocka_unit_test(numbers_use_the_format_and_null_when_not_finite),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
