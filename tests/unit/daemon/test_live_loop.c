/* SPDX-License-Identifier: MIT */
/*
 * daemon/live_loop.c: when the daemon makes a loop judge, its events file, and the -errno and
 * configuration fault of an events path it cannot write. No CAN involved.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "daemon/live_loop.h"
#include "testutil.h"
#include "scenario_util.h"

static void live_loop_none_without_scenario_or_anything_asked(void **state)
{
	struct hl_scenario *sc = shipped("preceding-car.json");
	struct hl_config cfg;
	struct hl_live_loop *lp = (struct hl_live_loop *)&cfg; /* overwritten */
	bool config_error = false;

	(void)state;
	hl_config_defaults(&cfg);
	strcpy(cfg.loop_report, "report.json");
	assert_int_equal(hl_live_loop_new(&cfg, NULL, &lp, &config_error), 0);
	assert_null(lp);
	cfg.loop_report[0] = '\0';
	lp = (struct hl_live_loop *)&cfg;
	assert_int_equal(hl_live_loop_new(&cfg, sc, &lp, &config_error), 0);
	assert_null(lp);
	assert_null(hl_live_loop_latency(NULL));
	hl_live_loop_free(NULL);
	hl_scenario_free(sc);
}

static void live_loop_judge_for_a_report(void **state)
{
	struct hl_scenario *sc = shipped("preceding-car.json");
	struct hl_config cfg;
	struct hl_live_loop *lp = NULL;
	bool config_error = false;

	(void)state;
	hl_config_defaults(&cfg);
	cfg.loop_exit_at_end = true;
	assert_int_equal(hl_live_loop_new(&cfg, sc, &lp, &config_error), 0);
	assert_non_null(lp);
	assert_non_null(hl_live_loop_latency(lp));
	assert_false(config_error);
	hl_live_loop_free(lp);
	hl_scenario_free(sc);
}

static void live_loop_events_file_is_created(void **state)
{
	struct hl_scenario *sc = shipped("preceding-car.json");
	struct hl_config cfg;
	struct hl_live_loop *lp = NULL;
	bool config_error = false;
	char path[256];

	(void)state;
	hl_config_defaults(&cfg);
	test_path(path, sizeof(path), "loop-events.jsonl");
	unlink(path);
	snprintf(cfg.loop_events, sizeof(cfg.loop_events), "%s", path);
	assert_int_equal(hl_live_loop_new(&cfg, sc, &lp, &config_error), 0);
	assert_non_null(lp);
	assert_int_equal(access(path, W_OK), 0);
	hl_live_loop_free(lp);
	unlink(path);
	hl_scenario_free(sc);
}

static void live_loop_unwritable_events_is_a_config_error(void **state)
{
	struct hl_scenario *sc = shipped("preceding-car.json");
	struct hl_config cfg;
	struct hl_live_loop *lp = NULL;
	bool config_error = false;

	(void)state;
	hl_config_defaults(&cfg);
	strcpy(cfg.loop_events, "/nonexistent-dir/events.jsonl");
	assert_int_equal(hl_live_loop_new(&cfg, sc, &lp, &config_error), -ENOENT);
	assert_true(config_error);
	assert_null(lp);
	hl_scenario_free(sc);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(live_loop_none_without_scenario_or_anything_asked),
		cmocka_unit_test(live_loop_judge_for_a_report),
		cmocka_unit_test(live_loop_events_file_is_created),
		cmocka_unit_test(live_loop_unwritable_events_is_a_config_error),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
