/* SPDX-License-Identifier: MIT */
/*
 * A file replaced whole or not at all: the new content appears under the path at once, the
 * temporary file is gone afterwards, and on a failure (no such directory, a path too long) the
 * old file stays as it was and nothing is left beside it.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "base/file_replace.h"
#include "testutil.h"

static void write_text(void *ctx, FILE *f)
{
	fputs(ctx, f);
}

static char *slurp(const char *path)
{
	static char buf[256];
	FILE *f = fopen(path, "r");
	size_t n;

	if (!f)
		return NULL;
	n = fread(buf, 1, sizeof(buf) - 1, f);
	buf[n] = '\0';
	fclose(f);
	return buf;
}

static void file_replace_whole(void **state)
{
	char path[512], tmp[600], long_path[5000];

	(void)state;
	test_path(path, sizeof(path), "replace.json");
	snprintf(tmp, sizeof(tmp), "%s.tmp", path);
	assert_int_equal(hl_file_replace(path, write_text, "{\"a\":1}\n"), 0);
	assert_string_equal(slurp(path), "{\"a\":1}\n");
	assert_int_equal(access(tmp, F_OK), -1);
	assert_int_equal(hl_file_replace(path, write_text, "{\"b\":2}\n"), 0);
	assert_string_equal(slurp(path), "{\"b\":2}\n");
	/* a directory that is not there: the error, nothing written */
	assert_int_equal(hl_file_replace("/nonexistent-dir/r.json", write_text, "x"), -ENOENT);
	memset(long_path, 'a', sizeof(long_path) - 1);
	long_path[sizeof(long_path) - 1] = '\0';
	assert_int_equal(hl_file_replace(long_path, write_text, "x"), -ENAMETOOLONG);
	assert_string_equal(slurp(path), "{\"b\":2}\n");
	unlink(path);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(file_replace_whole),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
