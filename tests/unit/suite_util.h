/* SPDX-License-Identifier: MIT */
/* Tests' helper: a shipped suite (suites/NAME.json), read or the test fails saying why. */
#ifndef HL_TESTS_SUITE_UTIL_H
#define HL_TESTS_SUITE_UTIL_H

#include <stdio.h>
#include <stdlib.h>

#include "verdict/suite.h"

static inline struct hl_suite *read_shipped(const char *name)
{
	const char *src = getenv("HL_SOURCE_DIR");
	struct hl_json_error err;
	struct hl_suite *s = NULL;
	char path[1024], msg[1024];

	assert_non_null(src);
	snprintf(path, sizeof(path), "%s/suites/%s.json", src, name);
	if (hl_suite_read(path, &s, &err) < 0)
		fail_msg("%s", hl_json_error_format(&err, msg, sizeof(msg)));
	return s;
}

#endif
