/* SPDX-License-Identifier: MIT */
/* Small helpers shared by the unit tests (header-only; each test is its own executable). */
#ifndef HL_TESTS_TESTUTIL_H
#define HL_TESTS_TESTUTIL_H

#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

/* A path under the test scratch directory, unique to this process. */
static inline const char *test_path(char *buf, size_t size, const char *name)
{
	const char *dir = getenv("HL_TEST_TMPDIR");

	snprintf(buf, size, "%s/%d-%s", dir ? dir : "/tmp", (int)getpid(), name);
	return buf;
}

/* Deterministic pseudo-random numbers (xorshift64*), so failures reproduce. */
static inline unsigned long long test_rand(unsigned long long *state)
{
	*state ^= *state >> 12;
	*state ^= *state << 25;
	*state ^= *state >> 27;
	return *state * 2685821657736338717ULL;
}

static inline double test_uniform(unsigned long long *state)
{
	return (double)(test_rand(state) >> 11) / 9007199254740992.0;
}

#endif
