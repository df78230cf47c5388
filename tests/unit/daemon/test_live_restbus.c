/* SPDX-License-Identifier: MIT */
/*
 * daemon/live_restbus.c: when the daemon makes a restbus, and the -errno and configuration
 * fault of a database it cannot read (the socket is made, never opened: no CAN involved).
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
#include <cmocka.h>

#include "daemon/live_restbus.h"
#include "scenario_util.h"

static void live_restbus_none_without_interface_or_scenario(void **state)
{
	struct hl_scenario *sc = shipped("preceding-car.json");
	struct hl_config cfg;
	struct hl_restbus *rb = (struct hl_restbus *)&cfg; /* overwritten */
	bool config_error = false;

	(void)state;
	hl_config_defaults(&cfg);
	assert_int_equal(hl_live_restbus_new(&cfg, sc, NULL, NULL, NULL, &rb, &config_error), 0);
	assert_null(rb);
	strcpy(cfg.restbus_interface, "vcan9");
	rb = (struct hl_restbus *)&cfg;
	assert_int_equal(hl_live_restbus_new(&cfg, NULL, NULL, NULL, NULL, &rb, &config_error), 0);
	assert_null(rb);
	assert_false(config_error);
	hl_scenario_free(sc);
}

static void live_restbus_missing_dbc_is_a_config_error(void **state)
{
	struct hl_scenario *sc = shipped("preceding-car.json");
	struct hl_config cfg;
	struct hl_restbus *rb = NULL;
	bool config_error = false;

	(void)state;
	hl_config_defaults(&cfg);
	strcpy(cfg.restbus_interface, "vcan9");
	strcpy(cfg.restbus_dbc, "/nonexistent-dir/inputs.dbc");
	assert_int_equal(hl_live_restbus_new(&cfg, sc, NULL, NULL, NULL, &rb, &config_error),
			 -ENOENT);
	assert_true(config_error);
	assert_null(rb);
	hl_scenario_free(sc);
}

static void live_restbus_shipped_dbc_makes_it(void **state)
{
	struct hl_scenario *sc = shipped("preceding-car.json");
	struct hl_config cfg;
	struct hl_restbus *rb = NULL;
	bool config_error = false;

	(void)state;
	hl_config_defaults(&cfg);
	strcpy(cfg.restbus_interface, "vcan9");
	snprintf(cfg.restbus_dbc, sizeof(cfg.restbus_dbc), "%s/dbc/hd84_inputs.dbc",
		 getenv("HL_SOURCE_DIR"));
	assert_int_equal(hl_live_restbus_new(&cfg, sc, NULL, NULL, NULL, &rb, &config_error), 0);
	assert_non_null(rb);
	assert_false(config_error);
	hl_restbus_free(rb);
	hl_scenario_free(sc);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(live_restbus_none_without_interface_or_scenario),
		cmocka_unit_test(live_restbus_missing_dbc_is_a_config_error),
		cmocka_unit_test(live_restbus_shipped_dbc_makes_it),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
