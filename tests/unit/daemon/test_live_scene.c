/* SPDX-License-Identifier: MIT */
/*
 * daemon/live_scene.c: the daemon's moving scene made from the configuration (a shipped
 * scenario, its glare set, the pose input), and the -errno and configuration fault of each bad
 * part. No CAN involved.
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

#include "daemon/live_scene.h"

/* The glare tables' grid (as verdict/glare.h's tests use it), for both lamps. */
static const struct hl_lid_grid grid = { 201, 101, HL_ANGLES_B, -20.0f, 20.0f, -10.0f, 10.0f };
static const struct hl_lid_grid *const grids[2] = { &grid, &grid };

/* The defaults with the source tree's regulations and scenario NAME of scenarios/ (or none). */
static void config(struct hl_config *cfg, const char *name)
{
	const char *src = getenv("HL_SOURCE_DIR");

	assert_non_null(src);
	hl_config_defaults(cfg);
	snprintf(cfg->regulations, sizeof(cfg->regulations), "%s/regulations", src);
	if (name)
		snprintf(cfg->scenario, sizeof(cfg->scenario), "%s/scenarios/%s", src, name);
}

static void live_scene_without_scenario_is_none(void **state)
{
	struct hl_config cfg;
	struct hl_live_scene *s = (struct hl_live_scene *)&cfg; /* overwritten */
	bool config_error = false;

	(void)state;
	config(&cfg, NULL);
	assert_int_equal(hl_live_scene_new(&cfg, 2, grids, &s, &config_error), 0);
	assert_null(s);
	assert_null(hl_live_scene_scenario(s));
	assert_null(hl_live_scene_glare(s));
	assert_null(hl_live_scene_pose(s));
	hl_live_scene_free(NULL);
}

static void live_scene_shipped_scenario_loads_with_its_glare_set(void **state)
{
	struct hl_config cfg;
	struct hl_live_scene *s = NULL;
	struct hl_scenario *ref;
	struct hl_json_error jerr;
	bool config_error = false;

	(void)state;
	config(&cfg, "preceding-car.json");
	assert_int_equal(hl_live_scene_new(&cfg, 2, grids, &s, &config_error), 0);
	assert_non_null(s);
	assert_false(config_error);
	assert_int_equal(hl_scenario_read(cfg.scenario, &ref, &jerr), 0);
	assert_string_equal(hl_live_scene_scenario(s)->title, ref->title);
	assert_int_equal(hl_live_scene_scenario(s)->n_actors, ref->n_actors);
	assert_non_null(hl_live_scene_glare(s));
	assert_ptr_equal(hl_glare_live_scenario(hl_live_scene_glare(s)), hl_live_scene_scenario(s));
	assert_string_equal(hl_glare_live_regulation(hl_live_scene_glare(s))->id,
			    "unece-r149-01-adb-glare");
	assert_null(hl_live_scene_pose(s)); /* no pose.listen */
	hl_scenario_free(ref);
	hl_live_scene_free(s);
}

static void live_scene_missing_scenario_is_a_config_error(void **state)
{
	struct hl_config cfg;
	struct hl_live_scene *s = NULL;
	bool config_error = false;

	(void)state;
	config(&cfg, "no-such-scenario.json");
	assert_int_equal(hl_live_scene_new(&cfg, 2, grids, &s, &config_error), -ENOENT);
	assert_true(config_error);
	assert_null(s);
}

static void live_scene_one_lamp_is_a_config_error(void **state)
{
	struct hl_config cfg;
	struct hl_live_scene *s = NULL;
	bool config_error = false;

	(void)state;
	config(&cfg, "preceding-car.json");
	assert_int_equal(hl_live_scene_new(&cfg, 1, grids, &s, &config_error), -EINVAL);
	assert_true(config_error);
	assert_null(s);
}

static void live_scene_missing_glare_set_is_a_config_error(void **state)
{
	struct hl_config cfg;
	struct hl_live_scene *s = NULL;
	bool config_error = false;

	(void)state;
	config(&cfg, "preceding-car.json");
	strcpy(cfg.glare_set, "no-such-set");
	assert_int_equal(hl_live_scene_new(&cfg, 2, grids, &s, &config_error), -ENOENT);
	assert_true(config_error);
	assert_null(s);
}

/* A set that is not a glare table (a passing beam's) cannot be planned as one. */
static void live_scene_set_not_a_glare_table_is_a_config_error(void **state)
{
	struct hl_config cfg;
	struct hl_live_scene *s = NULL;
	bool config_error = false;

	(void)state;
	config(&cfg, "preceding-car.json");
	strcpy(cfg.glare_set, "unece-r149-01-passing-c");
	assert_int_equal(hl_live_scene_new(&cfg, 2, grids, &s, &config_error), -EINVAL);
	assert_true(config_error);
	assert_null(s);
}

static void live_scene_pose_input_on_loopback(void **state)
{
	struct hl_config cfg;
	struct hl_live_scene *s = NULL;
	bool config_error = false;

	(void)state;
	config(&cfg, "preceding-car.json");
	strcpy(cfg.pose_listen, "udp:127.0.0.1:0");
	assert_int_equal(hl_live_scene_new(&cfg, 2, grids, &s, &config_error), 0);
	assert_non_null(hl_live_scene_pose(s));
	assert_true(hl_pose_input_port(hl_live_scene_pose(s)) > 0);
	hl_live_scene_free(s);
}

static void live_scene_bad_pose_listen_is_a_config_error(void **state)
{
	struct hl_config cfg;
	struct hl_live_scene *s = NULL;
	bool config_error = false;

	(void)state;
	config(&cfg, "preceding-car.json");
	strcpy(cfg.pose_listen, "tcp:127.0.0.1:9");
	assert_int_equal(hl_live_scene_new(&cfg, 2, grids, &s, &config_error), -EINVAL);
	assert_true(config_error);
	assert_null(s);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(live_scene_without_scenario_is_none),
		cmocka_unit_test(live_scene_shipped_scenario_loads_with_its_glare_set),
		cmocka_unit_test(live_scene_missing_scenario_is_a_config_error),
		cmocka_unit_test(live_scene_one_lamp_is_a_config_error),
		cmocka_unit_test(live_scene_missing_glare_set_is_a_config_error),
		cmocka_unit_test(live_scene_set_not_a_glare_table_is_a_config_error),
		cmocka_unit_test(live_scene_pose_input_on_loopback),
		cmocka_unit_test(live_scene_bad_pose_listen_is_a_config_error),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
