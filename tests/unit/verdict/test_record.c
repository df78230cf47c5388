/* SPDX-License-Identifier: MIT */
/*
 * verdict/record.c: "now" kept apart from "so far", the longest failing stretch, the worst
 * margin and where, the recent strip and the whole-run strip, and their JSON.
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

#include "verdict/record.h"

static const char *const reqs[] = { "B50L", "75R", "50V" };
static const char *const parts[] = { "left", "right" };

static void add(struct hl_record *r, double t, char cell, int req, int part, double margin)
{
	const struct hl_record_frame f = { .t_s = t,
					   .cell = (enum hl_record_cell)cell,
					   .req = req,
					   .part = part,
					   .margin = margin,
					   .mode = cell == 'n' ? 1 : 2 };

	hl_record_add(r, &f);
}

/* The case of the live page that read "pass (failed 304 of 390 frames)": the newest frame passes
 * while the run failed; so far says FAIL. */
static void record_now_passes_while_so_far_failed(void **state)
{
	struct hl_record *r;
	struct hl_record_summary s;
	(void)state;

	assert_int_equal(hl_record_new(16, &r), 0);
	add(r, 0.00, 'f', 0, 1, -0.5);
	add(r, 0.02, 'f', 0, 1, -0.25);
	add(r, 0.04, 'p', 2, 0, 0.1);
	hl_record_summary(r, &s);
	assert_int_equal(s.now, 'p');
	assert_string_equal(hl_record_cell_word(s.now), "pass");
	assert_string_equal(hl_record_so_far_word(&s), "FAIL");
	assert_int_equal(s.frames, 3);
	assert_int_equal(s.evaluated, 3);
	assert_int_equal(s.failed, 2);
	assert_int_equal(s.not_applicable, 0);
	assert_true(s.worst_margin == -0.5);
	assert_int_equal(s.worst_req, 0);
	assert_int_equal(s.worst_part, 1);
	assert_true(s.worst_t_s == 0.0);
	hl_record_free(r);
}

/* A stretch lasts from its first failing frame to the first frame that did not fail; a frame
 * outside the set's mode ends it; an ongoing stretch counts to the newest frame. */
static void record_longest_failing_stretch(void **state)
{
	struct hl_record *r;
	struct hl_record_summary s;
	(void)state;

	assert_int_equal(hl_record_new(16, &r), 0);
	add(r, 1.0, 'p', 0, 0, 0.2);
	add(r, 1.5, 'f', 1, 0, -0.1); /* stretch 1: 1.5 .. 2.25 */
	add(r, 2.0, 'f', 1, 0, -0.1);
	add(r, 2.25, 'n', -1, -1, NAN);
	add(r, 3.0, 'f', 0, 0, -0.2); /* stretch 2: 3.0 .. 3.5 */
	add(r, 3.5, 'p', 0, 0, 0.3);
	hl_record_summary(r, &s);
	assert_true(s.longest_failing_s == 0.75);
	assert_true(s.longest_failing_from_s == 1.5);
	assert_int_equal(s.not_applicable, 1);
	assert_int_equal(s.evaluated, 5);
	add(r, 4.0, 'f', 2, 1, -0.3); /* stretch 3, ongoing: 4.0 .. 5.0 */
	add(r, 5.0, 'f', 2, 1, -0.3);
	hl_record_summary(r, &s);
	assert_true(s.longest_failing_s == 1.0);
	assert_true(s.longest_failing_from_s == 4.0);
	assert_int_equal(s.now, 'f');
	assert_int_equal(s.now_req, 2);
	hl_record_free(r);
}

static void record_never_in_its_mode_is_not_evaluated(void **state)
{
	struct hl_record *r;
	struct hl_record_summary s;
	(void)state;

	assert_int_equal(hl_record_new(4, &r), 0);
	hl_record_summary(r, &s);
	assert_int_equal(s.now, 0);
	assert_string_equal(hl_record_cell_word(s.now), "no frame yet");
	add(r, 0.0, 'n', -1, -1, NAN);
	add(r, 0.02, 'n', -1, -1, NAN);
	hl_record_summary(r, &s);
	assert_string_equal(hl_record_cell_word(s.now), "not applicable");
	assert_string_equal(hl_record_so_far_word(&s), "not evaluated");
	assert_int_equal(s.has_worst, 0);
	assert_int_equal(s.now_req, -1);
	hl_record_free(r);
}

/* The recent strip holds the last HL_RECORD_STRIP cells, oldest first. */
static void record_recent_strip_keeps_the_last_cells(void **state)
{
	struct hl_record *r;
	static struct hl_record_cellinfo cells[HL_RECORD_STRIP];
	size_t n;
	(void)state;

	assert_int_equal(hl_record_new(4, &r), 0);
	for (int i = 0; i < HL_RECORD_STRIP + 5; i++)
		add(r, i * 0.02, i % 3 == 0 ? 'f' : 'p', i % 3 == 0 ? 1 : 0, 0, 0.0);
	n = hl_record_strip(r, cells, HL_RECORD_STRIP);
	assert_int_equal(n, HL_RECORD_STRIP);
	/* cell 0 is frame 5 (5 % 3 != 0: pass), cell 1 frame 6 (fail, requirement 1) */
	assert_int_equal(cells[0].cell, 'p');
	assert_int_equal(cells[0].req, -1);
	assert_int_equal(cells[1].cell, 'f');
	assert_int_equal(cells[1].req, 1);
	assert_int_equal(hl_record_strip(r, cells, 2), 2);
	/* the last two frames: 3003 (fail), 3004 (pass) */
	assert_int_equal(cells[0].cell, 'f');
	assert_int_equal(cells[1].cell, 'p');
	hl_record_free(r);
}

/* The whole run: runs of equal cells with their failing requirement; frames past the last run
 * that fits are counted. */
static void record_whole_run_as_runs_and_what_did_not_fit(void **state)
{
	struct hl_record *r;
	struct hl_record_summary s;
	const struct hl_record_run *runs;
	size_t n;
	(void)state;

	assert_int_equal(hl_record_new(3, &r), 0);
	add(r, 0.0, 'p', 0, 0, 0.1);
	add(r, 0.02, 'p', 2, 1, 0.2); /* passing cells merge whatever decided them */
	add(r, 0.04, 'f', 1, 0, -0.1);
	add(r, 0.06, 'f', 1, 0, -0.2);
	add(r, 0.08, 'f', 0, 1, -0.1); /* another requirement: a new run */
	add(r, 0.10, 'n', -1, -1, NAN); /* a fourth run: does not fit */
	add(r, 0.12, 'f', 0, 1, -0.1); /* after the strip ran out: counted too */
	n = hl_record_runs(r, &runs);
	assert_int_equal(n, 3);
	assert_int_equal(runs[0].cell, 'p');
	assert_int_equal(runs[0].frames, 2);
	assert_int_equal(runs[0].req, -1);
	assert_int_equal(runs[1].cell, 'f');
	assert_int_equal(runs[1].frames, 2);
	assert_int_equal(runs[1].req, 1);
	assert_int_equal(runs[1].part, 0);
	assert_true(runs[1].t0_s == 0.04);
	assert_int_equal(runs[2].req, 0);
	assert_int_equal(runs[2].part, 1);
	hl_record_summary(r, &s);
	assert_int_equal(s.frames_unstripped, 2);
	assert_int_equal(s.frames, 7);
	hl_record_reset(r);
	assert_int_equal(hl_record_runs(r, &runs), 0);
	hl_record_summary(r, &s);
	assert_int_equal(s.frames, 0);
	hl_record_free(r);
	assert_int_equal(hl_record_new(0, &r), -EINVAL);
	hl_record_free(NULL);
}

static char *json_of(void (*fn)(struct hl_record *, FILE *), struct hl_record *r)
{
	char *buf = NULL;
	size_t size = 0;
	FILE *f = open_memstream(&buf, &size);

	fn(r, f);
	fclose(f);
	return buf;
}

static void summary_json(struct hl_record *r, FILE *f)
{
	struct hl_record_summary s;

	hl_record_summary(r, &s);
	hl_record_json_summary(&s, reqs, parts, f);
}

static const char *mode_name(const void *ud, int mode)
{
	(void)ud;
	return mode == 1 ? "low" : NULL;
}

static void strip_json(struct hl_record *r, FILE *f)
{
	struct hl_record_cellinfo cells[8];
	const size_t n = hl_record_strip(r, cells, 8);

	hl_record_json_strip(cells, n, reqs, parts, mode_name, NULL, f);
}

static void runs_json(struct hl_record *r, FILE *f)
{
	const struct hl_record_run *runs;
	const size_t n = hl_record_runs(r, &runs);

	hl_record_json_runs(runs, n, reqs, parts, f);
}

static void record_json_names_the_fields(void **state)
{
	struct hl_record *r;
	char *j;
	(void)state;

	assert_int_equal(hl_record_new(8, &r), 0);
	add(r, 0.5, 'f', 1, 0, -0.25);
	add(r, 0.75, 'f', 1, 0, -0.125);
	add(r, 1.0, 'n', -1, -1, NAN);
	add(r, 1.25, 'p', 2, 1, 0.5);
	j = json_of(summary_json, r);
	assert_string_equal(
		j, "\"now\":{\"result\":\"pass\",\"t_s\":1.2500,\"requirement\":\"50V\",\"part\":"
		   "\"right\"},\"so_far\":{\"result\":\"FAIL\",\"frames\":4,\"evaluated\":3,"
		   "\"failed\":2,\"not_applicable\":1,\"longest_failing_s\":0.5000,"
		   "\"longest_failing_from_s\":0.5000,\"worst\":{\"margin\":-0.25,\"requirement\":"
		   "\"75R\",\"part\":\"left\",\"t_s\":0.5000},\"frames_unstripped\":0}");
	free(j);
	j = json_of(strip_json, r);
	assert_string_equal(j, "\"cells\":\"ffnp\",\"failing\":[[0,2,\"75R\",\"left\"]],"
			       "\"modes\":[[0,2,2],[2,1,\"low\"],[3,1,2]]");
	free(j);
	j = json_of(runs_json, r);
	assert_string_equal(j, "[[0.5000,2,\"f\",\"75R\",\"left\"],[1.0000,1,\"n\",null,null],"
			       "[1.2500,1,\"p\",null,null]]");
	free(j);
	hl_record_free(r);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(record_now_passes_while_so_far_failed),
		cmocka_unit_test(record_longest_failing_stretch),
		cmocka_unit_test(record_never_in_its_mode_is_not_evaluated),
		cmocka_unit_test(record_recent_strip_keeps_the_last_cells),
		cmocka_unit_test(record_whole_run_as_runs_and_what_did_not_fit),
		cmocka_unit_test(record_json_names_the_fields),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
