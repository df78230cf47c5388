/* SPDX-License-Identifier: MIT */
/*
 * base/json_check.c: reading a JSON file whole, the index of where every key and element is,
 * and the strict checks whose errors name the file, line, column, key path and what was
 * expected.
 */
#include <errno.h>
#include <jansson.h>
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

#include "base/json_check.h"
#include "testutil.h"

/* Lines and columns of the keys and elements below are in the comments. */
static const char doc[] = "{\n" /* 1 */
			  "  \"a\": 1,\n" /* 2: a at 3 */
			  "  \"obj\": {\"x\": true, \"y\": [10, 20,\n" /* 3: obj 3, x 11, y 22,
									[0] 28, [1] 32 */
			  "     {\"z\": null}]},\n" /* 4: y[2] 6, z 7 */
			  "  \"s\\\"q\": \"v\"\n" /* 5: s"q at 3 */
			  "}\n";

struct parsed {
	json_t *root;
	struct hl_json_loc *loc;
	struct hl_json_error err;
	struct hl_json_ctx c;
};

static void parse_ok(struct parsed *p, const char *text)
{
	memset(p, 0, sizeof(*p));
	assert_int_equal(hl_json_parse(text, "t.json", &p->root, &p->loc, &p->err), 0);
	p->c = (struct hl_json_ctx){ .name = "t.json", .loc = p->loc, .err = &p->err };
}

static void parsed_free(struct parsed *p)
{
	json_decref(p->root);
	hl_json_loc_free(p->loc);
}

static void expect_place(const struct hl_json_loc *loc, const char *path, int line, int column)
{
	int l = -1, c = -1;

	hl_json_loc_find(loc, path, &l, &c);
	if (l != line || c != column)
		fail_msg("'%s': %d:%d, expected %d:%d", path, l, c, line, column);
}

/* Every key and array element by its path; a missing one at its nearest ancestor. */
static void json_loc_finds_keys_and_elements_by_path(void **state)
{
	struct parsed p;

	(void)state;
	parse_ok(&p, doc);
	expect_place(p.loc, "", 1, 1);
	expect_place(p.loc, "a", 2, 3);
	expect_place(p.loc, "obj", 3, 3);
	expect_place(p.loc, "obj.x", 3, 11);
	expect_place(p.loc, "obj.y", 3, 22);
	expect_place(p.loc, "obj.y[0]", 3, 28);
	expect_place(p.loc, "obj.y[1]", 3, 32);
	expect_place(p.loc, "obj.y[2]", 4, 6);
	expect_place(p.loc, "obj.y[2].z", 4, 7);
	expect_place(p.loc, "s\"q", 5, 3);
	/* missing: the nearest ancestor the text has */
	expect_place(p.loc, "obj.y[7]", 3, 22);
	expect_place(p.loc, "obj.y[2].nope.deeper", 4, 6);
	expect_place(p.loc, "obj.nope", 3, 3);
	expect_place(p.loc, "nope", 1, 1);
	expect_place(NULL, "a", 1, 1);
	parsed_free(&p);
}

/* Syntax errors and duplicate keys: -EBADMSG with jansson's place, nothing handed out. */
static void json_parse_refuses_syntax_errors_and_duplicate_keys(void **state)
{
	static const struct {
		const char *text;
		int line;
	} bad[] = {
		{ "{\"a\": 1, \"a\": 2}", 1 }, { "{\n\"a\": 1,\n}", 3 }, { "[1, 2", 1 }, { "", 1 },
		{ "{\"a\": nan}", 1 },
	};

	(void)state;
	for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
		json_t *root = (json_t *)&root; /* must stay untouched */
		struct hl_json_loc *loc = (struct hl_json_loc *)&loc;
		struct hl_json_error err;

		assert_int_equal(hl_json_parse(bad[i].text, "bad.json", &root, &loc, &err),
				 -EBADMSG);
		assert_ptr_equal(root, &root);
		assert_ptr_equal(loc, &loc);
		assert_string_equal(err.file, "bad.json");
		assert_int_equal(err.line, bad[i].line);
		assert_true(err.column >= 1);
		assert_string_equal(err.key, "");
		assert_true(strlen(err.msg) > 0);
	}
	/* jansson's words for a duplicate */
	{
		json_t *root;
		struct hl_json_loc *loc;
		struct hl_json_error err;

		assert_int_equal(hl_json_parse("{\"k\": 1, \"k\": 2}", "d.json", &root, &loc, &err),
				 -EBADMSG);
		assert_non_null(strstr(err.msg, "duplicate object key"));
	}
}

/* The index is built from text jansson accepted; text that is not JSON after all is refused,
 * as is nesting deeper than 256. */
static void json_loc_new_refuses_text_that_is_not_json(void **state)
{
	static const char *const bad[] = {
		"{\"a\" 1}", "{\"a\": 1 \"b\": 2}", "[1 2]", "{\"a\": \"open", "[1,", "{1: 2}", "",
	};
	struct hl_json_loc *loc = NULL;
	char deep[600];

	(void)state;
	for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
		loc = NULL;
		assert_int_equal(hl_json_loc_new(bad[i], &loc), -EBADMSG);
		assert_null(loc);
	}
	memset(deep, '[', 258);
	memset(deep + 258, ']', 258);
	deep[516] = '\0';
	assert_int_equal(hl_json_loc_new(deep, &loc), -EBADMSG);
	assert_null(loc);
	/* 257 levels (depth 0..256) are fine */
	memset(deep, '[', 257);
	memset(deep + 257, ']', 257);
	deep[514] = '\0';
	assert_int_equal(hl_json_loc_new(deep, &loc), 0);
	expect_place(loc, "[0][0]", 1, 3);
	hl_json_loc_free(loc);
	hl_json_loc_free(NULL);
}

/* "FILE:LINE:COL: KEY: MESSAGE" with the unknown parts left out; key paths built and cut. */
static void json_error_format_and_paths_leave_out_what_is_unknown(void **state)
{
	struct hl_json_error e;
	char buf[1024], small[12];

	(void)state;
	memset(&e, 0, sizeof(e));
	strcpy(e.file, "f.json");
	strcpy(e.msg, "bad");
	assert_string_equal(hl_json_error_format(&e, buf, sizeof(buf)), "f.json: bad");
	e.line = 4;
	assert_string_equal(hl_json_error_format(&e, buf, sizeof(buf)), "f.json:4: bad");
	e.column = 7;
	assert_string_equal(hl_json_error_format(&e, buf, sizeof(buf)), "f.json:4:7: bad");
	strcpy(e.key, "a.b[2]");
	assert_string_equal(hl_json_error_format(&e, buf, sizeof(buf)), "f.json:4:7: a.b[2]: bad");
	e.line = 0;
	assert_string_equal(hl_json_error_format(&e, buf, sizeof(buf)), "f.json: a.b[2]: bad");
	/* cut to the buffer, NUL-terminated */
	assert_ptr_equal(hl_json_error_format(&e, small, sizeof(small)), small);
	assert_string_equal(small, "f.json: a.b");

	/* paths: joined with '.' (nothing at the top), indices in brackets, cut to the buffer */
	assert_string_equal(hl_json_join(buf, sizeof(buf), "", "road"), "road");
	assert_string_equal(hl_json_join(buf, sizeof(buf), "road", "lanes"), "road.lanes");
	assert_string_equal(hl_json_index(buf, sizeof(buf), "actors", 12), "actors[12]");
	assert_string_equal(hl_json_index(buf, sizeof(buf), "", 0), "[0]");
	assert_string_equal(hl_json_join(small, 8, "abc", "defgh"), "abc.def");
	assert_string_equal(hl_json_index(small, 8, "abcde", 123), "abcde[1");
	assert_string_equal(hl_json_type_name(json_true()), "a boolean");
	assert_string_equal(hl_json_type_name(json_null()), "null");
}

static void write_file(const char *path, const void *data, size_t len)
{
	FILE *f = fopen(path, "wb");

	assert_non_null(f);
	assert_int_equal(fwrite(data, 1, len, f), len);
	assert_int_equal(fclose(f), 0);
}

/* The whole file, across the buffer's growth steps; missing, NUL bytes and a directory each with
 * their -errno and message. */
static void json_read_file_reads_whole_files_and_refuses_the_rest(void **state)
{
	char path[4096], dir[4096], *text = (char *)&text;
	struct hl_json_error err;
	const size_t big = 200001;
	char *want = malloc(big);

	(void)state;
	assert_non_null(want);
	for (size_t i = 0; i < big; i++)
		want[i] = (char)('a' + i % 26);
	test_path(path, sizeof(path), "big.json");
	write_file(path, want, big);
	assert_int_equal(hl_json_read_file(path, &text, &err), 0);
	assert_int_equal(strlen(text), big);
	assert_memory_equal(text, want, big);
	assert_string_equal(err.file, path);
	free(text);

	write_file(path, "", 0);
	assert_int_equal(hl_json_read_file(path, &text, NULL), 0);
	assert_string_equal(text, "");
	free(text);

	text = (char *)&text;
	write_file(path, "{\"a\"\0: 1}", 9);
	assert_int_equal(hl_json_read_file(path, &text, &err), -EBADMSG);
	assert_string_equal(err.msg, "expected JSON text, found a NUL byte");
	assert_ptr_equal(text, &text);
	assert_int_equal(hl_json_read_file(path, &text, NULL), -EBADMSG);

	test_path(path, sizeof(path), "missing.json");
	unlink(path);
	assert_int_equal(hl_json_read_file(path, &text, &err), -ENOENT);
	assert_string_equal(err.file, path);
	assert_string_equal(err.msg, "cannot open: No such file or directory");
	assert_int_equal(err.line, 0);

	test_path(dir, sizeof(dir), "adir");
	assert_int_equal(mkdir(dir, 0700), 0);
	assert_int_equal(hl_json_read_file(dir, &text, &err), -EIO);
	assert_string_equal(err.msg, "read error");
	assert_int_equal(rmdir(dir), 0);

	test_path(path, sizeof(path), "big.json");
	unlink(path);
	free(want);
}

/* 64 MiB exactly is read; one byte more is -EFBIG, "larger than 64 MiB". */
static void json_read_file_takes_64_mib_and_refuses_one_byte_more(void **state)
{
	const size_t max = (size_t)64 << 20;
	char path[4096], *text = NULL;
	struct hl_json_error err;
	char *spaces = malloc(max + 1);

	(void)state;
	assert_non_null(spaces);
	memset(spaces, ' ', max + 1);
	test_path(path, sizeof(path), "max.json");
	write_file(path, spaces, max);
	assert_int_equal(hl_json_read_file(path, &text, &err), 0);
	assert_int_equal(strlen(text), max);
	free(text);
	text = (char *)&text;
	write_file(path, spaces, max + 1);
	assert_int_equal(hl_json_read_file(path, &text, &err), -EFBIG);
	assert_string_equal(err.msg, "larger than 64 MiB");
	assert_ptr_equal(text, &text);
	unlink(path);
	free(spaces);
}

/* An unknown key is named with its path and place and the keys that are allowed. */
static void json_check_object_names_the_unknown_key(void **state)
{
	static const char *const allowed[] = { "x", "y", NULL };
	static const char *const top[] = { "a", "obj", "s\"q", NULL };
	struct parsed p;
	const json_t *obj;

	(void)state;
	parse_ok(&p, doc);
	obj = json_object_get(p.root, "obj");
	assert_int_equal(hl_json_check_object(&p.c, "", p.root, top), 0);
	assert_int_equal(hl_json_check_object(&p.c, "obj", obj, allowed + 1), -EBADMSG);
	assert_string_equal(p.err.file, "t.json");
	assert_string_equal(p.err.key, "obj.x");
	assert_int_equal(p.err.line, 3);
	assert_int_equal(p.err.column, 11);
	assert_string_equal(p.err.msg, "unknown key 'x'; expected one of: y");
	assert_int_equal(hl_json_check_object(&p.c, "obj.y", json_object_get(obj, "y"), allowed),
			 -EBADMSG);
	assert_string_equal(p.err.key, "obj.y");
	assert_int_equal(p.err.line, 3);
	assert_int_equal(p.err.column, 22);
	assert_string_equal(p.err.msg, "expected an object, found an array");
	/* without an error to fill, still -EBADMSG */
	p.c.err = NULL;
	assert_int_equal(hl_json_check_object(&p.c, "obj", obj, allowed + 1), -EBADMSG);
	parsed_free(&p);
}

static void expect_error(const struct parsed *p, const char *key, int line, int column,
			 const char *msg)
{
	assert_string_equal(p->err.key, key);
	assert_int_equal(p->err.line, line);
	assert_int_equal(p->err.column, column);
	assert_string_equal(p->err.msg, msg);
}

/* Numbers and integers: presence, type, closed and open ranges; the default kept when absent. */
static void json_get_number_and_int_check_type_and_range(void **state)
{
	static const char text[] = "{\"n\": 2.5,\n \"i\": 7, \"r\": 7.0, \"lo\": 0,\n"
				   " \"s\": \"x\"}";
	const struct hl_json_range closed = { 0, 10, false, "m" }, open = { 0, 10, true, "m" };
	struct parsed p;
	double d = -1;
	int i = -1;

	(void)state;
	parse_ok(&p, text);
	assert_int_equal(hl_json_get_number(&p.c, "", p.root, "n", true, &closed, &d), 0);
	assert_true(d == 2.5);
	assert_int_equal(hl_json_get_number(&p.c, "", p.root, "i", true, &closed, &d), 0);
	assert_true(d == 7.0);
	assert_int_equal(hl_json_get_number(&p.c, "", p.root, "lo", true, &closed, &d), 0);
	assert_true(d == 0.0);
	d = 42;
	assert_int_equal(hl_json_get_number(&p.c, "", p.root, "absent", false, &closed, &d), 0);
	assert_true(d == 42.0);
	assert_int_equal(hl_json_get_number(&p.c, "", p.root, "absent", true, &closed, &d),
			 -EBADMSG);
	expect_error(&p, "absent", 1, 1, "missing: expected a number in [0, 10] m");
	assert_int_equal(hl_json_get_number(&p.c, "", p.root, "lo", true, &open, &d), -EBADMSG);
	expect_error(&p, "lo", 2, 20, "0 is out of range: expected a number in (0, 10] m");
	assert_int_equal(hl_json_get_number(&p.c, "", p.root, "s", true, &closed, &d), -EBADMSG);
	expect_error(&p, "s", 3, 2, "expected a number in [0, 10] m, found a string");
	assert_true(d == 42.0);

	assert_int_equal(hl_json_get_int(&p.c, "", p.root, "i", true, 0, 10, &i), 0);
	assert_int_equal(i, 7);
	assert_int_equal(hl_json_get_int(&p.c, "", p.root, "absent", false, 0, 10, &i), 0);
	assert_int_equal(i, 7);
	assert_int_equal(hl_json_get_int(&p.c, "", p.root, "r", true, 0, 10, &i), -EBADMSG);
	expect_error(&p, "r", 2, 10,
		     "expected an integer in [0, 10], found a number with a decimal point");
	assert_int_equal(hl_json_get_int(&p.c, "", p.root, "i", true, 0, 6, &i), -EBADMSG);
	expect_error(&p, "i", 2, 2, "7 is out of range: expected an integer in [0, 6]");
	assert_int_equal(hl_json_get_int(&p.c, "", p.root, "absent", true, 1, 3, &i), -EBADMSG);
	expect_error(&p, "absent", 1, 1, "missing: expected an integer in [1, 3]");
	assert_int_equal(hl_json_get_int(&p.c, "", p.root, "s", true, 0, 10, &i), -EBADMSG);
	expect_error(&p, "s", 3, 2, "expected an integer in [0, 10], found a string");
	assert_int_equal(i, 7);
	parsed_free(&p);
}

/* Enums, strings and vectors: each wrong value named with its place. */
static void json_get_enum_string_and_vec3_name_what_was_expected(void **state)
{
	static const char text[] = "{\"o\": {\"e\": \"green\", \"bad\": \"blue\", \"num\": 3,\n"
				   "  \"str\": \"abc\", \"empty\": \"\", \"long\": \"abcdef\",\n"
				   "  \"v\": [1, 2, 3], \"v2\": [1, 2], \"vr\": [1, 20, 3]}}";
	static const char *const colours[] = { "red", "green", NULL };
	const struct hl_json_range r[3] = { { -5, 5, false, "m" },
					    { -5, 5, false, "m" },
					    { -5, 5, false, "m" } };
	const json_t *o;
	struct parsed p;
	double v[3] = { 9, 9, 9 };
	char s[4] = "";
	int k = -1;

	(void)state;
	parse_ok(&p, text);
	o = json_object_get(p.root, "o");
	assert_int_equal(hl_json_get_enum(&p.c, "o", o, "e", true, colours, &k), 0);
	assert_int_equal(k, 1);
	assert_int_equal(hl_json_get_enum(&p.c, "o", o, "bad", true, colours, &k), -EBADMSG);
	expect_error(&p, "o.bad", 1, 22, "expected one of \"red\", \"green\", found \"blue\"");
	assert_int_equal(hl_json_get_enum(&p.c, "o", o, "num", true, colours, &k), -EBADMSG);
	expect_error(&p, "o.num", 1, 37, "expected one of \"red\", \"green\", found a number");
	assert_int_equal(hl_json_get_enum(&p.c, "o", o, "none", true, colours, &k), -EBADMSG);
	expect_error(&p, "o.none", 1, 2, "missing: expected one of \"red\", \"green\"");
	assert_int_equal(hl_json_get_enum(&p.c, "o", o, "none", false, colours, &k), 0);
	assert_int_equal(k, 1);

	assert_int_equal(hl_json_get_string(&p.c, "o", o, "str", true, s, sizeof(s)), 0);
	assert_string_equal(s, "abc");
	assert_int_equal(hl_json_get_string(&p.c, "o", o, "long", true, s, sizeof(s)), -EBADMSG);
	expect_error(&p, "o.long", 2, 30, "expected at most 3 characters, found 6");
	assert_int_equal(hl_json_get_string(&p.c, "o", o, "empty", true, s, sizeof(s)), -EBADMSG);
	expect_error(&p, "o.empty", 2, 17, "expected a non-empty string, found an empty one");
	assert_int_equal(hl_json_get_string(&p.c, "o", o, "num", true, s, sizeof(s)), -EBADMSG);
	expect_error(&p, "o.num", 1, 37, "expected a non-empty string, found a number");
	assert_string_equal(s, "abc");

	assert_int_equal(hl_json_get_vec3(&p.c, "o", o, "v", true, r, v), 0);
	assert_true(v[0] == 1.0 && v[1] == 2.0 && v[2] == 3.0);
	assert_int_equal(hl_json_get_vec3(&p.c, "o", o, "v2", true, r, v), -EBADMSG);
	expect_error(&p, "o.v2", 3, 19,
		     "expected [x, y, z] in m, found another number of elements");
	assert_int_equal(hl_json_get_vec3(&p.c, "o", o, "vr", true, r, v), -EBADMSG);
	expect_error(&p, "o.vr[1]", 3, 43, "20 is out of range: expected a number in [-5, 5] m");
	assert_int_equal(hl_json_get_vec3(&p.c, "o", o, "e", true, r, v), -EBADMSG);
	expect_error(&p, "o.e", 1, 8, "expected [x, y, z] in m, found a string");
	assert_int_equal(hl_json_get_vec3(&p.c, "o", o, "none", true, r, v), -EBADMSG);
	expect_error(&p, "o.none", 1, 2, "missing: expected [x, y, z] in m");
	parsed_free(&p);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(json_loc_finds_keys_and_elements_by_path),
		cmocka_unit_test(json_parse_refuses_syntax_errors_and_duplicate_keys),
		cmocka_unit_test(json_loc_new_refuses_text_that_is_not_json),
		cmocka_unit_test(json_error_format_and_paths_leave_out_what_is_unknown),
		cmocka_unit_test(json_read_file_reads_whole_files_and_refuses_the_rest),
		cmocka_unit_test(json_read_file_takes_64_mib_and_refuses_one_byte_more),
		cmocka_unit_test(json_check_object_names_the_unknown_key),
		cmocka_unit_test(json_get_number_and_int_check_type_and_range),
		cmocka_unit_test(json_get_enum_string_and_vec3_name_what_was_expected),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
