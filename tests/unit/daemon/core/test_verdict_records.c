/* SPDX-License-Identifier: MIT */
/*
 * daemon/core/verdict_records.c: a frame's cell per set from its header's masks (not
 * applicable, pass, FAIL), the deciding requirement the smallest margin over the set's parts,
 * the frame's time since the run's first frame on the cycles' receive clock, and the whole-run
 * strip as the report writes it.
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "daemon/core/verdict_records.h"
#include "lamp/model.h"

/* The HD84 pair's grids and the two test sets: test-adb-glare (pair: Oncoming 50 m, Imax),
 * test-each-lamp (left, right: H-V "centre", Imax). */
struct sets {
	struct hl_lid *lamps[2];
	struct hl_verdicts *v;
};

static void load(struct sets *s)
{
	static const char *const lamp_names[2] = { "left", "right" };
	const struct hl_lid_grid *grids[2];
	struct hl_lamp_pose poses[2];
	struct hl_config cfg;
	char err[512];

	hl_config_defaults(&cfg);
	snprintf(cfg.regulations, sizeof(cfg.regulations), "%s/tests/data/regulations",
		 getenv("HL_SOURCE_DIR"));
	snprintf(cfg.verdict_sets[0], sizeof(cfg.verdict_sets[0]), "test-adb-glare");
	snprintf(cfg.verdict_sets[1], sizeof(cfg.verdict_sets[1]), "test-each-lamp");
	cfg.n_verdict_sets = 2;
	for (int l = 0; l < 2; l++) {
		assert_int_equal(hl_model_hd84(l, &s->lamps[l]), 0);
		grids[l] = hl_lid_grid(s->lamps[l]);
		hl_lamp_pose_default(l, &poses[l]);
	}
	assert_int_equal(hl_verdicts_new(&cfg, 2, lamp_names, grids, poses, NULL, &s->v, err,
					 sizeof(err)),
			 0);
}

static void unload(struct sets *s)
{
	hl_verdicts_free(s->v);
	for (int l = 0; l < 2; l++)
		hl_lid_free(s->lamps[l]);
}

/* A frame at t_ns whose results have margin m everywhere but at (set, part, req): low. */
static void frame_at(const struct hl_verdicts *v, struct hl_frame *f, int64_t t_ns,
		     uint32_t evaluated, uint32_t failed, int set, int part, int req, double low)
{
	for (int k = 0; k < f->n_results; k++)
		f->results[k].margin = 0.5;
	f->results[hl_verdicts_part(v, set, part)->first + req].margin = low;
	f->hdr.t_cycle_rx_ns = t_ns;
	f->hdr.sets_evaluated = evaluated;
	f->hdr.sets_failed = failed;
	f->beam_mode = -1;
}

struct seen {
	struct hl_record_summary sum[2];
	struct hl_record_cellinfo cells[2][8];
	size_t n[2];
	char runs[2][512];
	const struct hl_verdicts *v;
};

static void copy(void *ud, const struct hl_record *const *records, int n)
{
	struct seen *s = ud;

	assert_int_equal(n, 2);
	for (int i = 0; i < n; i++) {
		FILE *f = fmemopen(s->runs[i], sizeof(s->runs[i]), "w");

		hl_record_summary(records[i], &s->sum[i]);
		s->n[i] = hl_record_strip(records[i], s->cells[i], 8);
		hl_verdict_records_json_runs(s->v, i, records[i], f);
		fclose(f);
	}
}

static void verdict_records_cells_from_the_masks_and_the_smallest_margin(void **state)
{
	struct sets s;
	struct hl_verdict_records *r;
	struct hl_frame f = { 0 };
	struct seen seen = { 0 };
	(void)state;

	load(&s);
	seen.v = s.v;
	f.n_results = hl_verdicts_n_results(s.v);
	f.results = calloc(f.n_results, sizeof(*f.results));
	assert_non_null(f.results);
	assert_int_equal(hl_verdict_records_new(s.v, &r), 0);
	/* frame 1 at 7 s on the cycles' clock: set 0 fails on its pair part's Oncoming 50 m, set
	 * 1 passes, its right lamp's Imax deciding */
	frame_at(s.v, &f, 7000000000, 0x3, 0x1, 0, 0, 0, -0.25);
	f.results[hl_verdicts_part(s.v, 1, 1)->first + 1].margin = 0.125;
	hl_verdict_records_add(r, &f);
	/* frame 2, 20 ms later: set 1 outside the frame's mode; set 0 fails on its Imax */
	frame_at(s.v, &f, 7020000000, 0x1, 0x1, 0, 0, 1, -0.75);
	hl_verdict_records_add(r, &f);
	/* frame 3: both pass */
	frame_at(s.v, &f, 7040000000, 0x3, 0x0, 1, 0, 0, 0.0625);
	hl_verdict_records_add(r, &f);
	hl_verdict_records_read(r, copy, &seen);

	assert_int_equal(seen.n[0], 3);
	assert_int_equal(seen.cells[0][0].cell, 'f');
	assert_int_equal(seen.cells[0][0].req, 0);
	assert_int_equal(seen.cells[0][1].cell, 'f');
	assert_int_equal(seen.cells[0][1].req, 1);
	assert_int_equal(seen.cells[0][2].cell, 'p');
	assert_int_equal(seen.sum[0].failed, 2);
	assert_true(seen.sum[0].worst_margin == -0.75);
	assert_int_equal(seen.sum[0].worst_req, 1);
	assert_true(seen.sum[0].worst_t_s == 0.02);
	assert_true(seen.sum[0].longest_failing_s == 0.04);
	assert_int_equal(seen.cells[1][0].cell, 'p');
	assert_int_equal(seen.cells[1][1].cell, 'n');
	assert_int_equal(seen.cells[1][2].cell, 'p');
	assert_int_equal(seen.sum[1].evaluated, 2);
	assert_int_equal(seen.sum[1].not_applicable, 1);
	/* set 1's smallest margin: frame 1 the right lamp's Imax, frame 3 the left's H-V */
	assert_true(seen.sum[1].worst_margin == 0.0625);
	assert_int_equal(seen.sum[1].worst_req, 0);
	assert_int_equal(seen.sum[1].worst_part, 0);
	assert_int_equal(seen.sum[1].now_part, 0);
	assert_string_equal(seen.runs[0], "\"strip_runs\":[[0.0000,1,\"f\",\"Oncoming 50 m\","
					  "\"pair\"],[0.0200,1,\"f\",\"Imax\",\"pair\"],"
					  "[0.0400,1,\"p\",null,null]]");
	assert_string_equal(seen.runs[1], "\"strip_runs\":[[0.0000,1,\"p\",null,null],"
					  "[0.0200,1,\"n\",null,null],[0.0400,1,\"p\",null,null]]");
	hl_verdict_records_free(r);
	hl_verdict_records_free(NULL);
	free(f.results);
	unload(&s);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(verdict_records_cells_from_the_masks_and_the_smallest_margin),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
