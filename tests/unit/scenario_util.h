/* SPDX-License-Identifier: MIT */
/* Tests' helper: a shipped scenario (scenarios/NAME), read or the test fails. */
#ifndef HL_TESTS_SCENARIO_UTIL_H
#define HL_TESTS_SCENARIO_UTIL_H

#include <stdio.h>
#include <stdlib.h>

#include "world/scenario.h"

static inline struct hl_scenario *shipped(const char *name)
{
	struct hl_scenario *sc = NULL;
	struct hl_json_error err;
	char path[4096];

	snprintf(path, sizeof(path), "%s/scenarios/%s", getenv("HL_SOURCE_DIR"), name);
	assert_int_equal(hl_scenario_read(path, &sc, &err), 0);
	return sc;
}

#endif
