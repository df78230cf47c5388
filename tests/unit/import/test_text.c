/* SPDX-License-Identifier: MIT */
/*
 * import/text.c: the cursor the readers share: lines and columns, strict numbers, tokens read
 * as numbers and integers with messages that name the file, the place and what was found, and
 * whole files read with their size limit.
 */
#include <errno.h>
#include <fcntl.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "import/text.h"
#include "testutil.h"

/* Decimal numbers only, parsed completely; anything else -EBADMSG with *ret untouched. */
static void number_parse_accepts_strict_decimals_only(void **state)
{
	static const struct {
		const char *s;
		double v;
	} good[] = {
		{ "0", 0.0 },	     { "-1", -1.0 },	{ "+2.5", 2.5 },   { "1.", 1.0 },
		{ ".5", 0.5 },	     { "-.25", -0.25 }, { "1e3", 1000.0 }, { "1E-3", 0.001 },
		{ "2.5e+2", 250.0 }, { "007", 7.0 },	{ "-0", -0.0 },
	};
	static const char *const bad[] = {
		"",	"+",	"-",	    ".",   "e5", "1e",	  "1e+", "nan",	 "inf",
		"-inf", "0x10", "1,5",	    " 1",  "1 ", "1e999", "--1", "1..2", "1e2.5",
		"1-",	"+-1",	"infinity", "1d3", "١",	 "1e-",	  "12a", "\t3",
	};
	char digits[1001];
	double v;

	(void)state;
	for (size_t i = 0; i < sizeof(good) / sizeof(good[0]); i++) {
		v = 99.0;
		assert_int_equal(hl_number_parse(good[i].s, strlen(good[i].s), &v), 0);
		assert_true(v == good[i].v);
	}
	for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
		v = 99.0;
		if (hl_number_parse(bad[i], strlen(bad[i]), &v) != -EBADMSG)
			fail_msg("'%s' accepted", bad[i]);
		assert_true(v == 99.0);
	}
	/* only the len bytes count: a NUL or a trailing character outside them */
	assert_int_equal(hl_number_parse("12", 1, &v), 0);
	assert_true(v == 1.0);
	assert_int_equal(hl_number_parse("1\0", 2, &v), -EBADMSG);
	/* 63 characters are read; longer tokens are refused, however many digits */
	memset(digits, '0', sizeof(digits) - 1);
	digits[62] = '5';
	assert_int_equal(hl_number_parse(digits, 63, &v), 0);
	assert_true(v == 5.0);
	v = 99.0;
	assert_int_equal(hl_number_parse(digits, 64, &v), -EBADMSG);
	assert_int_equal(hl_number_parse(digits, 1000, &v), -EBADMSG);
	assert_true(v == 99.0);
}

/* LF and CRLF lines, an empty one, a last one without LF, and a NUL inside a line. */
static void text_line_splits_lines_and_counts_them(void **state)
{
	static const char buf[] = "a\r\nbb\n\nc\0d\rx\nlast";
	struct hl_text t;
	const char *s;
	size_t n;

	(void)state;
	hl_text_init(&t, buf, sizeof(buf) - 1, "f", NULL);
	assert_int_equal(t.line, 1);
	assert_true(hl_text_line(&t, &s, &n));
	assert_int_equal(n, 1);
	assert_memory_equal(s, "a", 1);
	assert_int_equal(t.line, 2);
	assert_true(hl_text_line(&t, &s, &n));
	assert_int_equal(n, 2);
	assert_memory_equal(s, "bb", 2);
	assert_true(hl_text_line(&t, &s, &n));
	assert_int_equal(n, 0);
	assert_true(hl_text_line(&t, &s, &n));
	assert_int_equal(n, 5); /* the CR inside the line stays */
	assert_memory_equal(s, "c\0d\rx", 5);
	assert_true(hl_text_line(&t, &s, &n));
	assert_int_equal(n, 4);
	assert_memory_equal(s, "last", 4);
	assert_int_equal(t.line, 6);
	assert_int_equal(t.col, 1);
	assert_true(hl_text_eof(&t));
	assert_false(hl_text_line(&t, &s, &n));
	assert_int_equal(t.line, 6);
	hl_text_init(&t, buf, 0, "f", NULL);
	assert_false(hl_text_line(&t, &s, &n));
}

/* Blanks, commas and newlines skipped as asked, the column and line kept. */
static void text_skip_blanks_and_advance_track_the_place(void **state)
{
	static const char buf[] = " \t\r,\n ,x";
	struct hl_text t;

	(void)state;
	hl_text_init(&t, buf, sizeof(buf) - 1, "f", NULL);
	hl_text_skip_blanks(&t, false, false);
	assert_int_equal(*t.p, ',');
	assert_int_equal(t.col, 4);
	hl_text_skip_blanks(&t, false, true);
	assert_int_equal(*t.p, '\n');
	assert_int_equal(t.line, 1);
	hl_text_skip_blanks(&t, true, false);
	assert_int_equal(*t.p, ',');
	assert_int_equal(t.line, 2);
	assert_int_equal(t.col, 2);
	hl_text_skip_blanks(&t, true, true);
	assert_int_equal(*t.p, 'x');
	assert_int_equal(t.col, 3);
	hl_text_advance(&t);
	assert_true(hl_text_eof(&t));
	assert_int_equal(t.col, 4);
	hl_text_advance(&t); /* at the end: stays */
	assert_int_equal(t.col, 4);
	assert_ptr_equal(t.p, buf + sizeof(buf) - 1);
	hl_text_skip_blanks(&t, true, true);
	assert_ptr_equal(t.p, buf + sizeof(buf) - 1);
}

/* Tokens across lines, with and without commas; a bad token is shown as found (unprintable
 * bytes and quotes escaped, long ones cut), at its line and column. */
static void text_number_reads_tokens_and_names_what_it_found(void **state)
{
	static const char buf[] = "  1.5\n\t-2,3 x";
	struct hl_import_error err;
	struct hl_text t;
	double v;

	(void)state;
	hl_text_init(&t, buf, sizeof(buf) - 1, "f.ies", &err);
	assert_int_equal(hl_text_number(&t, false, "the width", &v), 0);
	assert_true(v == 1.5);
	assert_int_equal(hl_text_number(&t, false, "the length", &v), -EBADMSG);
	assert_int_equal(err.line, 2);
	assert_int_equal(err.column, 2);
	assert_string_equal(err.msg, "'f.ies':2:2: expected the length (a finite decimal number), "
				     "found '-2,3'");
	assert_true(v == 1.5);

	hl_text_init(&t, buf, sizeof(buf) - 1, "f.ies", &err);
	assert_int_equal(hl_text_number(&t, true, "a", &v), 0);
	assert_int_equal(hl_text_number(&t, true, "b", &v), 0);
	assert_true(v == -2.0);
	assert_int_equal(hl_text_number(&t, true, "c", &v), 0);
	assert_true(v == 3.0);
	assert_int_equal(hl_text_number(&t, true, "the height", &v), -EBADMSG);
	assert_string_equal(err.msg, "'f.ies':2:7: expected the height (a finite decimal number), "
				     "found 'x'");
	t.p++;
	t.col++;
	assert_int_equal(hl_text_number(&t, true, "the depth", &v), -EBADMSG);
	assert_string_equal(err.msg, "'f.ies':2:8: expected the depth, found the end of the file");

	hl_text_init(&t, "\x01'\xff", 3, "g", &err);
	assert_int_equal(hl_text_number(&t, false, "n", &v), -EBADMSG);
	assert_string_equal(
		err.msg, "'g':1:1: expected n (a finite decimal number), found '\\x01\\x27\\xff'");
	hl_text_init(&t, "abcdefghijklmnopqrstuvwxyz0123456789", 36, "g", &err);
	assert_int_equal(hl_text_number(&t, false, "n", &v), -EBADMSG);
	assert_string_equal(err.msg, "'g':1:1: expected n (a finite decimal number), found "
				     "'abcdefghijklmnopqrstuvwx...'");
	/* no error to fill: still the code */
	hl_text_init(&t, "x", 1, "g", NULL);
	assert_int_equal(hl_text_number(&t, false, "n", &v), -EBADMSG);
}

/* Integers in [min, max]: a fraction or a value outside is named at the token's place. */
static void text_int_takes_integers_in_range(void **state)
{
	static const char buf[] = "12 1e1\n  1.5 51 -1";
	struct hl_import_error err;
	struct hl_text t;
	long v = -7;

	(void)state;
	hl_text_init(&t, buf, sizeof(buf) - 1, "f.ldt", &err);
	assert_int_equal(hl_text_int(&t, false, "the count", 0, 50, &v), 0);
	assert_int_equal(v, 12);
	assert_int_equal(hl_text_int(&t, false, "the count", 0, 50, &v), 0);
	assert_int_equal(v, 10);
	assert_int_equal(hl_text_int(&t, false, "the count", 0, 50, &v), -EBADMSG);
	assert_int_equal(err.line, 2);
	assert_int_equal(err.column, 3);
	assert_string_equal(err.msg, "'f.ldt':2:3: expected the count, an integer from 0 to 50, "
				     "found 1.5");
	assert_int_equal(hl_text_int(&t, false, "the count", 0, 50, &v), -EBADMSG);
	assert_string_equal(err.msg, "'f.ldt':2:7: expected the count, an integer from 0 to 50, "
				     "found 51");
	assert_int_equal(hl_text_int(&t, false, "the count", 0, 50, &v), -EBADMSG);
	assert_string_equal(err.msg, "'f.ldt':2:10: expected the count, an integer from 0 to 50, "
				     "found -1");
	assert_int_equal(v, 10);
}

/* fail at the cursor or an explicit place, and import_fail without one; NULL err: rc only. */
static void text_fail_messages_name_the_file_and_place(void **state)
{
	struct hl_import_error err;
	struct hl_text t;

	(void)state;
	hl_text_init(&t, "abc\ndef", 7, "lamp.ies", &err);
	hl_text_skip_blanks(&t, true, false);
	t.p += 2;
	t.col += 2;
	assert_int_equal(hl_text_fail(&t, -EBADMSG, "expected %d angles", 45), -EBADMSG);
	assert_int_equal(err.line, 1);
	assert_int_equal(err.column, 3);
	assert_string_equal(err.msg, "'lamp.ies':1:3: expected 45 angles");
	assert_int_equal(hl_text_fail_at(&t, 12, 5, -ERANGE, "x %s", "y"), -ERANGE);
	assert_int_equal(err.line, 12);
	assert_int_equal(err.column, 5);
	assert_string_equal(err.msg, "'lamp.ies':12:5: x y");
	assert_int_equal(hl_import_fail(&err, "m.ini", -ENOENT, "cannot open: %s", "gone"),
			 -ENOENT);
	assert_int_equal(err.line, 0);
	assert_int_equal(err.column, 0);
	assert_string_equal(err.msg, "'m.ini': cannot open: gone");
	assert_int_equal(hl_import_fail(NULL, "m.ini", -EIO, "x"), -EIO);
	t.err = NULL;
	assert_int_equal(hl_text_fail(&t, -EBADMSG, "x"), -EBADMSG);
	assert_int_equal(hl_text_fail_at(&t, 1, 1, -EBADMSG, "x"), -EBADMSG);
}

/* A whole file with a NUL after it; empty files; missing, not regular and over the limit are
 * refused with their -errno and a message naming the file. */
static void import_read_file_reads_regular_files_up_to_the_limit(void **state)
{
	static const char data[] = "IESNA:LM-63-2019\n\0binary\xff";
	struct hl_import_error err;
	char path[4096], want[4200], *buf = (char *)&buf;
	size_t len = 12345;
	FILE *f;
	int fd;

	(void)state;
	test_path(path, sizeof(path), "text.ies");
	f = fopen(path, "wb");
	assert_non_null(f);
	assert_int_equal(fwrite(data, 1, sizeof(data) - 1, f), sizeof(data) - 1);
	assert_int_equal(fclose(f), 0);
	assert_int_equal(hl_import_read_file(path, &buf, &len, &err), 0);
	assert_int_equal(len, sizeof(data) - 1);
	assert_memory_equal(buf, data, sizeof(data) - 1);
	assert_int_equal(buf[len], '\0');
	free(buf);

	assert_int_equal(truncate(path, 0), 0);
	assert_int_equal(hl_import_read_file(path, &buf, &len, NULL), 0);
	assert_int_equal(len, 0);
	assert_int_equal(buf[0], '\0');
	free(buf);

	/* a sparse file one byte over the limit: refused before it is read */
	fd = open(path, O_WRONLY | O_TRUNC);
	assert_true(fd >= 0);
	assert_int_equal(ftruncate(fd, (off_t)HL_IMPORT_MAX_FILE + 1), 0);
	assert_int_equal(close(fd), 0);
	buf = (char *)&buf;
	assert_int_equal(hl_import_read_file(path, &buf, &len, &err), -EFBIG);
	snprintf(want, sizeof(want), "'%s': larger than 268435456 bytes", path);
	assert_string_equal(err.msg, want);
	assert_int_equal(err.line, 0);
	assert_ptr_equal(buf, &buf);
	assert_int_equal(unlink(path), 0);

	assert_int_equal(hl_import_read_file(path, &buf, &len, &err), -ENOENT);
	snprintf(want, sizeof(want), "'%s': cannot open: No such file or directory", path);
	assert_string_equal(err.msg, want);
	assert_int_equal(hl_import_read_file("/", &buf, &len, &err), -EINVAL);
	assert_string_equal(err.msg, "'/': not a regular file");
	assert_int_equal(hl_import_read_file("/", &buf, &len, NULL), -EINVAL);
	assert_ptr_equal(buf, &buf);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(number_parse_accepts_strict_decimals_only),
		cmocka_unit_test(text_line_splits_lines_and_counts_them),
		cmocka_unit_test(text_skip_blanks_and_advance_track_the_place),
		cmocka_unit_test(text_number_reads_tokens_and_names_what_it_found),
		cmocka_unit_test(text_int_takes_integers_in_range),
		cmocka_unit_test(text_fail_messages_name_the_file_and_place),
		cmocka_unit_test(import_read_file_reads_regular_files_up_to_the_limit),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
