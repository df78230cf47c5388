/* SPDX-License-Identifier: MIT */
/*
 * hdlampd's configuration file read with inih: the messages of a missing file and a directory,
 * "name : value" and both comment styles with the lines kept in set_at, an empty file, warnings
 * beyond those listed still counted, the first refused key the one reported, and hostile lines
 * (very long, a long key name, a NUL byte) refused or read without overrunning anything.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cmocka.h>

#include "daemon/core/config.h"
#include "testutil.h"

static const char *write_file(char *path, size_t size, const char *name, const char *text, size_t n)
{
	FILE *f = fopen(test_path(path, size, name), "w");

	assert_non_null(f);
	assert_int_equal(fwrite(text, 1, n, f), n);
	fclose(f);
	return path;
}

#define WRITE(path, name, text) write_file(path, sizeof(path), name, text, strlen(text))

/* The keys set from origin, by line: how many, and the line of each in the order of the table. */
static int set_from(const struct hl_config *c, const char *origin, int *lines, int max)
{
	int n = 0;

	for (int i = 0; i < HL_CONFIG_MAX_KEYS; i++)
		if (c->set_at[i].origin == origin && n < max)
			lines[n++] = c->set_at[i].line;
	return n;
}

static void config_file_missing_and_directory_are_refused_by_name(void **state)
{
	struct hl_config c;
	struct hl_config_error err;
	char path[512], want[700];
	(void)state;

	hl_config_defaults(&c);
	test_path(path, sizeof(path), "missing.conf");
	unlink(path);
	err.n_warnings = 99;
	assert_int_equal(hl_config_load(&c, path, &err), -ENOENT);
	snprintf(want, sizeof(want), "'%s': No such file or directory", path);
	assert_string_equal(err.msg, want);
	assert_int_equal(err.n_warnings, 0);
	test_path(path, sizeof(path), "dir.conf");
	assert_int_equal(mkdir(path, 0755), 0);
	assert_int_equal(hl_config_load(&c, path, &err), -EINVAL);
	snprintf(want, sizeof(want), "'%s': a directory; expected an INI file", path);
	assert_string_equal(err.msg, want);
	rmdir(path);
	/* err is optional */
	assert_int_equal(hl_config_load(&c, "/nonexistent-dir/x.conf", NULL), -ENOENT);
}

static void config_file_colon_and_comments_and_the_lines_in_set_at(void **state)
{
	struct hl_config c, d;
	struct hl_config_error err;
	char path[512];
	int lines[8];
	(void)state;

	hl_config_defaults(&c);
	WRITE(path, "colon.conf",
	      "; a comment\n"
	      "# another\n"
	      "\n"
	      "  [render]  \n"
	      "view : lux\n"
	      "size=160x90\n"
	      "[can]\n"
	      "timeout_ms = 250\n");
	if (hl_config_load(&c, path, &err) != 0)
		fail_msg("%s", err.msg);
	assert_int_equal(err.n_warnings, 0);
	assert_string_equal(c.view, "lux");
	assert_int_equal(c.width, 160);
	assert_int_equal(c.height, 90);
	assert_int_equal(c.timeout_ms, 250);
	/* three keys, each with its line, the origin the path given (borrowed) */
	assert_int_equal(set_from(&c, path, lines, 8), 3);
	{
		int seen5 = 0, seen6 = 0, seen8 = 0;

		for (int i = 0; i < 3; i++) {
			seen5 += lines[i] == 5;
			seen6 += lines[i] == 6;
			seen8 += lines[i] == 8;
		}
		assert_int_equal(seen5 + seen6 + seen8, 3);
		assert_int_equal(seen5 * seen6 * seen8, 1);
	}
	/* an empty file: nothing changes */
	hl_config_defaults(&d);
	WRITE(path, "empty.conf", "");
	memcpy(&c, &d, sizeof(c));
	assert_int_equal(hl_config_load(&c, path, &err), 0);
	assert_memory_equal(&c, &d, sizeof(c));
	unlink(path);
}

static void config_file_counts_every_warning_and_lists_the_first_eight(void **state)
{
	struct hl_config c;
	struct hl_config_error err;
	char path[512], text[512] = "[render]\n", want[700];
	(void)state;

	/* view on lines 2..12: ten repeats of the first */
	for (int i = 0; i < 11; i++)
		strcat(text, i % 2 ? "view = lux\n" : "view = hdr\n");
	hl_config_defaults(&c);
	WRITE(path, "dups.conf", text);
	assert_int_equal(hl_config_load(&c, path, &err), 0);
	assert_string_equal(c.view, "hdr"); /* line 12, the last */
	assert_int_equal(err.n_warnings, 10);
	for (int i = 0; i < HL_CONFIG_MAX_WARNINGS; i++) {
		snprintf(want, sizeof(want),
			 "'%s':%d: warning: key 'render.view' set again (first at line 2); the "
			 "last value counts",
			 path, i + 3);
		assert_string_equal(err.warnings[i], want);
	}
	/* the same key in two sections is two keys */
	WRITE(path, "dups.conf", "[can]\ntimeout_ms = 20\n[http]\ncapture = true\n");
	assert_int_equal(hl_config_load(&c, path, &err), 0);
	assert_int_equal(err.n_warnings, 0);
	unlink(path);
}

static void config_file_reports_the_first_refused_key(void **state)
{
	struct hl_config c;
	struct hl_config_error err;
	char path[512], want[700];
	(void)state;

	hl_config_defaults(&c);
	WRITE(path, "bad2.conf", "[can]\ntimeout_ms = 0\ntimeout_ms = -5\n[nosuch]\nkey = 1\n");
	assert_int_equal(hl_config_load(&c, path, &err), -EINVAL);
	snprintf(want, sizeof(want),
		 "'%s':2: key 'can.timeout_ms': '0': expected an integer 1..60000", path);
	assert_string_equal(err.msg, want);
	/* a key before any section */
	WRITE(path, "bad2.conf", "view = lux\n");
	assert_int_equal(hl_config_load(&c, path, &err), -EINVAL);
	snprintf(want, sizeof(want),
		 "'%s':1: key '.view': unknown key (hdlampd --print-config lists every key)", path);
	assert_string_equal(err.msg, want);
	/* a line that is neither: inih's line number */
	WRITE(path, "bad2.conf", "[render]\nview = lux\njust words\n");
	assert_int_equal(hl_config_load(&c, path, &err), -EINVAL);
	snprintf(want, sizeof(want), "'%s':3: expected [section], key = value, or a ; comment",
		 path);
	assert_string_equal(err.msg, want);
	unlink(path);
}

/* Hostile files: whatever they hold, a bounded answer naming the file, nothing overrun. */
static void config_file_hostile_lines_are_refused_or_bounded(void **state)
{
	struct hl_config c;
	struct hl_config_error err;
	char path[512], big[9000];
	(void)state;

	hl_config_defaults(&c);
	/* a value of 8000 bytes: longer than any field; refused, the message cut to its size */
	snprintf(big, sizeof(big), "[can]\ninterface = %08000d\n", 0);
	WRITE(path, "hostile.conf", big);
	assert_int_equal(hl_config_load(&c, path, &err), -EINVAL);
	assert_true(strlen(err.msg) < sizeof(err.msg));
	assert_memory_equal(err.msg, "'", 1);
	assert_string_equal(c.interface, ""); /* unchanged default */
	/* a key name of 300 bytes */
	memset(big, 'k', 300);
	snprintf(big, sizeof(big), "[render]\n%0300d = 1\n", 0);
	WRITE(path, "hostile.conf", big);
	assert_int_equal(hl_config_load(&c, path, &err), -EINVAL);
	assert_true(strlen(err.msg) < sizeof(err.msg));
	/* a NUL byte in a value: the value ends there, and what is left is refused or read */
	{
		static const char nul[] = "[render]\nview = lux\0hdr\n";

		write_file(path, sizeof(path), "hostile.conf", nul, sizeof(nul) - 1);
		assert_int_equal(hl_config_load(&c, path, &err), 0);
		assert_string_equal(c.view, "lux");
	}
	unlink(path);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(config_file_missing_and_directory_are_refused_by_name),
		cmocka_unit_test(config_file_colon_and_comments_and_the_lines_in_set_at),
		cmocka_unit_test(config_file_counts_every_warning_and_lists_the_first_eight),
		cmocka_unit_test(config_file_reports_the_first_refused_key),
		cmocka_unit_test(config_file_hostile_lines_are_refused_or_bounded),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
