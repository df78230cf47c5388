/* SPDX-License-Identifier: MIT */
/*
 * world/scenario_clock.c: scenario time from the one origin t0, held at 0 before it and at the
 * duration after the end; the end of a run after its margin.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "world/scenario_clock.h"

static const char text[] = "{\"version\": 1, \"duration_s\": 5,\n"
			   " \"road\": {\"segments\": [{\"kind\": \"straight\", "
			   "\"length_m\": 100}]}}\n";

static struct hl_scenario *load(void)
{
	struct hl_scenario *sc = NULL;
	struct hl_json_error err;

	if (hl_scenario_parse(text, "c.json", &sc, &err) < 0)
		fail_msg("%s: %s", err.key, err.msg);
	return sc;
}

static void scenario_clock_counts_from_t0_in_seconds(void **state)
{
	struct hl_scenario *sc = load();
	(void)state;

	assert_true(hl_scenario_clock_at(sc, 1000000000, 1000000000) == 0.0);
	assert_true(hl_scenario_clock_at(sc, 1000000000, 1250000000) == 0.25);
	assert_true(hl_scenario_clock_at(sc, 1000000000, 5000000000) == 4.0);
	/* any timeline: a log's time since its pass started */
	assert_true(hl_scenario_clock_at(sc, -2000000000, -500000000) == 1.5);
	hl_scenario_free(sc);
}

static void scenario_clock_holds_at_0_before_and_at_the_duration_after(void **state)
{
	struct hl_scenario *sc = load();
	(void)state;

	assert_true(hl_scenario_clock_at(sc, 1000000000, 0) == 0.0);
	assert_true(hl_scenario_clock_at(sc, 1000000000, 6000000000) == 5.0);
	assert_true(hl_scenario_clock_at(sc, 1000000000, 60000000000) == 5.0);
	assert_true(hl_scenario_clock_clamp(sc, -0.001) == 0.0);
	assert_true(hl_scenario_clock_clamp(sc, 4.999) == 4.999);
	assert_true(hl_scenario_clock_clamp(sc, 5.001) == 5.0);
	hl_scenario_free(sc);
}

static void scenario_clock_over_after_duration_and_margin(void **state)
{
	struct hl_scenario *sc = load();
	const int64_t t0 = 1000000000, margin = 100000000;
	(void)state;

	assert_false(hl_scenario_clock_over(sc, t0, t0, margin));
	assert_false(hl_scenario_clock_over(sc, t0, t0 + 5000000000, margin));
	assert_false(hl_scenario_clock_over(sc, t0, t0 + 5099999999, margin));
	assert_true(hl_scenario_clock_over(sc, t0, t0 + 5100000000, margin));
	assert_true(hl_scenario_clock_over(sc, t0, t0 + 5000000000, 0));
	hl_scenario_free(sc);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(scenario_clock_counts_from_t0_in_seconds),
		cmocka_unit_test(scenario_clock_holds_at_0_before_and_at_the_duration_after),
		cmocka_unit_test(scenario_clock_over_after_duration_and_margin),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
