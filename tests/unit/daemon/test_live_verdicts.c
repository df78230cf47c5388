/* SPDX-License-Identifier: MIT */
/*
 * daemon/live_verdicts.c: the daemon's verdicts made for the lamps the assembler names, the beam
 * mode taken from the shipped hd84.dbc's mode signal, and a missing set refused as a
 * configuration fault (exit 2) with the -errno of hl_verdicts_new(). No CAN involved.
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

#include "daemon/live_verdicts.h"
#include "lamp/model.h"

static const char *const lamp_names[2] = { "left", "right" };

struct parts {
	struct hl_dbc *db;
	struct hl_assembler *a;
	struct hl_lid *lamps[2];
	const struct hl_lid_grid *grids[2];
	struct hl_config cfg;
};

static void make(struct parts *p, const char *sets)
{
	const char *src = getenv("HL_SOURCE_DIR");
	struct hl_dbc_error derr;
	struct hl_asm_error aerr;
	char path[4096], what[256];

	snprintf(path, sizeof(path), "%s/dbc/hd84.dbc", src);
	assert_int_equal(hl_dbc_parse_file(path, &p->db, &derr), 0);
	assert_int_equal(hl_assembler_new(p->db, lamp_names, 2, 100, 0, &p->a, &aerr), 0);
	for (int l = 0; l < 2; l++) {
		assert_int_equal(hl_model_hd84(l, &p->lamps[l]), 0);
		p->grids[l] = hl_lid_grid(p->lamps[l]);
	}
	hl_config_defaults(&p->cfg);
	snprintf(p->cfg.regulations, sizeof(p->cfg.regulations), "%s/regulations", src);
	assert_int_equal(hl_cfg_parse_sets(sets, p->cfg.verdict_sets, &p->cfg.n_verdict_sets, what,
					   sizeof(what)),
			 0);
}

static void unmake(struct parts *p)
{
	for (int l = 0; l < 2; l++)
		hl_lid_free(p->lamps[l]);
	hl_assembler_free(p->a);
	hl_dbc_free(p->db);
}

static void live_verdicts_follow_the_shipped_dbcs_beam_mode(void **state)
{
	struct parts p;
	struct hl_verdicts *v = NULL;
	bool config_error = true;
	(void)state;

	make(&p, "unece-r149-01-passing-c, unece-r149-01-driving-b");
	assert_int_equal(
		hl_live_verdicts_new(&p.cfg, p.a, 2, lamp_names, p.grids, &v, &config_error), 0);
	assert_non_null(v);
	assert_int_equal(hl_verdicts_n_sets(v), 2);
	assert_int_equal(hl_verdicts_mode_lamp(v), 0);
	assert_true(hl_verdicts_mode_aware(v));
	/* hd84.dbc's VAL_: 1 low, 2 high; each set in its own beam's mode */
	assert_int_equal(hl_verdicts_active(v, 1), 0x1);
	assert_int_equal(hl_verdicts_active(v, 2), 0x2);
	hl_verdicts_free(v);
	unmake(&p);
}

static void live_verdicts_missing_set_is_a_configuration_fault(void **state)
{
	struct parts p;
	struct hl_verdicts *v = (struct hl_verdicts *)&p; /* left alone on failure */
	bool config_error = false;
	(void)state;

	make(&p, "no-such-set");
	assert_int_equal(hl_live_verdicts_new(&p.cfg, p.a, 2, lamp_names, p.grids, &v,
					      &config_error),
			 -ENOENT);
	assert_true(config_error);
	assert_ptr_equal(v, &p);
	unmake(&p);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(live_verdicts_follow_the_shipped_dbcs_beam_mode),
		cmocka_unit_test(live_verdicts_missing_set_is_a_configuration_fault),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
