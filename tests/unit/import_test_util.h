/* SPDX-License-Identifier: MIT */
/* Helpers shared by the import/ unit tests (header only; not a test itself). */
#ifndef HL_TESTS_IMPORT_TEST_UTIL_H
#define HL_TESTS_IMPORT_TEST_UTIL_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* tests/data/<rel>, found from this header's own path (CMake compiles with absolute paths). */
static inline void data_path(char *buf, size_t size, const char *rel)
{
	const char *f = __FILE__;
	const char *unit = strstr(f, "/unit/import_test_util.h");

	if (unit)
		snprintf(buf, size, "%.*s/data/%s", (int)(unit - f), f, rel);
	else
		snprintf(buf, size, "tests/data/%s", rel);
}

/* The whole file as a NUL-terminated string (aborts on failure: a broken test setup). */
static inline char *slurp(const char *path, size_t *ret_len)
{
	FILE *f = fopen(path, "rb");
	char *buf;
	long n;

	if (!f) {
		fprintf(stderr, "cannot open %s\n", path);
		abort();
	}
	fseek(f, 0, SEEK_END);
	n = ftell(f);
	fseek(f, 0, SEEK_SET);
	buf = malloc((size_t)n + 1);
	if (!buf || fread(buf, 1, (size_t)n, f) != (size_t)n)
		abort();
	buf[n] = '\0';
	fclose(f);
	if (ret_len)
		*ret_len = (size_t)n;
	return buf;
}

/* One expected rejection of the malformed corpus. */
struct corpus_case {
	const char *file; /* under tests/data/malformed/ */
	int rc;
	int line;
};

#endif
