/* SPDX-License-Identifier: MIT */
/*
 * import/export.c: a LID source sampled as a goniometer table (the grid's own samples kept in
 * its own angles, the coarse frame over the format's range, bad arguments and oversized tables
 * refused) and tables written as IES LM-63-2019 and CSV, byte for byte and read back.
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

#include "import/csv.h"
#include "import/export.h"
#include "import/ies.h"

/* 11 x 11 samples, H and V -5..5 every degree; row 0 is V = 5. */
static const struct hl_lid_grid grid = { 11, 11, HL_ANGLES_A, -5.0f, 5.0f, -5.0f, 5.0f };

/* Source 0 lit around (H 1, V 0); source 1 dark. */
static struct hl_lid *small_lid(float dense[121])
{
	struct hl_lid *lid;
	float zero[121] = { 0 };

	memset(dense, 0, sizeof(float) * 121);
	dense[5 * 11 + 6] = 100.0f; /* row 5 (V 0), column 6 (H 1) */
	dense[5 * 11 + 5] = 40.0f;
	dense[5 * 11 + 7] = 60.0f;
	dense[4 * 11 + 6] = 30.0f;
	dense[6 * 11 + 6] = 20.5f;
	assert_int_equal(hl_lid_new(2, &grid, false, &lid), 0);
	assert_int_equal(hl_lid_set_source(lid, 0, dense), 0);
	assert_int_equal(hl_lid_set_source(lid, 1, zero), 0);
	return lid;
}

static int index_of(const double *a, int n, double x)
{
	for (int i = 0; i < n; i++)
		if (a[i] == x)
			return i;
	return -1;
}

/* In the grid's own system at its step, the table holds the grid's samples exactly at the
 * grid's angles, framed every 5 degrees out to -90..90 with zeros. */
static void export_sample_in_own_angles_keeps_the_grid_samples(void **state)
{
	float dense[121];
	struct hl_lid *lid = small_lid(dense);
	struct hl_gonio *g = NULL;
	const double *p, *q;
	int np, nq;

	(void)state;
	assert_int_equal(hl_export_sample(lid, 0, HL_GONIO_A, 0.0, &g), 0);
	assert_int_equal(hl_gonio_system(g), HL_GONIO_A);
	np = hl_gonio_n_planes(g);
	nq = hl_gonio_n_in(g);
	p = hl_gonio_planes(g);
	q = hl_gonio_in(g);
	assert_true(p[0] == -90.0 && p[np - 1] == 90.0);
	assert_true(q[0] == -90.0 && q[nq - 1] == 90.0);
	for (int i = 1; i < np; i++)
		assert_true(p[i] > p[i - 1]);
	for (int j = 1; j < nq; j++)
		assert_true(q[j] > q[j - 1]);
	/* the lit box H 0..2, V -1..1 plus a margin of 2 grid and 2 table steps: every degree */
	for (int h = -3; h <= 5; h++)
		assert_true(index_of(p, np, h) >= 0);
	for (int v = -5; v <= 5; v++)
		assert_true(index_of(q, nq, v) >= 0);
	for (int row = 0; row < 11; row++)
		for (int col = 0; col < 11; col++) {
			const double h = col - 5.0, v = 5.0 - row;
			const int i = index_of(p, np, h), j = index_of(q, nq, v);

			if (i < 0 || j < 0)
				continue;
			assert_true(hl_gonio_values(g)[(size_t)i * nq + j] ==
				    dense[row * 11 + col]);
			assert_true(hl_gonio_lookup(g, h, v) == dense[row * 11 + col]);
		}
	assert_true(hl_gonio_peak_cd(g) == 100.0f);
	assert_true(hl_gonio_lookup(g, -90.0, 0.0) == 0.0);
	assert_true(hl_gonio_lookup(g, 45.0, 45.0) == 0.0);
	hl_gonio_free(g);
	hl_lid_free(lid);
}

/* A dark source: the coarse frame only, 37 x 37 angles every 5 degrees, all zero. */
static void export_sample_of_a_dark_source_is_the_coarse_frame(void **state)
{
	float dense[121];
	struct hl_lid *lid = small_lid(dense);
	struct hl_gonio *g = NULL;

	(void)state;
	for (int s = 0; s < 3; s++) {
		const double hi = s == HL_GONIO_C ? 360.0 : 90.0;

		assert_int_equal(hl_export_sample(lid, 1, (enum hl_gonio_system)s, 0.0, &g), 0);
		assert_int_equal(hl_gonio_system(g), s);
		assert_int_equal(hl_gonio_n_planes(g), (int)(hi - hl_gonio_planes(g)[0]) / 5 + 1);
		assert_int_equal(hl_gonio_n_in(g), 37);
		for (int i = 0; i < hl_gonio_n_planes(g); i++)
			assert_true(hl_gonio_planes(g)[i] == hl_gonio_planes(g)[0] + 5.0 * i);
		assert_true(hl_gonio_planes(g)[hl_gonio_n_planes(g) - 1] == hi);
		assert_true(hl_gonio_peak_cd(g) == 0.0f);
		hl_gonio_free(g);
		g = NULL;
	}
	hl_lid_free(lid);
}

/* Bad source numbers, steps and systems are -EINVAL; a step that makes too many values is
 * -EFBIG; *ret is untouched. */
static void export_sample_refuses_bad_arguments_and_oversized_tables(void **state)
{
	float dense[121];
	struct hl_lid *lid = small_lid(dense);
	struct hl_gonio *g = NULL;

	(void)state;
	assert_int_equal(hl_export_sample(lid, -1, HL_GONIO_A, 0.0, &g), -EINVAL);
	assert_int_equal(hl_export_sample(lid, 2, HL_GONIO_A, 0.0, &g), -EINVAL);
	assert_int_equal(hl_export_sample(lid, 0, (enum hl_gonio_system)3, 0.0, &g), -EINVAL);
	assert_int_equal(hl_export_sample(lid, 0, (enum hl_gonio_system) - 1, 0.0, &g), -EINVAL);
	assert_int_equal(hl_export_sample(lid, 0, HL_GONIO_A, 10.5, &g), -EINVAL);
	assert_int_equal(hl_export_sample(lid, 0, HL_GONIO_A, 0.0009, &g), -EINVAL);
	assert_int_equal(hl_export_sample(lid, 0, HL_GONIO_A, NAN, &g), -EINVAL);
	assert_int_equal(hl_export_sample(lid, 0, HL_GONIO_A, INFINITY, &g), -EINVAL);
	/* B for an A grid at the finest step: about 7000 x 7000 angles before refining */
	assert_int_equal(hl_export_sample(lid, 0, HL_GONIO_B, 0.001, &g), -EFBIG);
	assert_null(g);
	/* the limits themselves are fine */
	assert_int_equal(hl_export_sample(lid, 0, HL_GONIO_A, 10.0, &g), 0);
	hl_gonio_free(g);
	hl_lid_free(lid);
}

static char *write_to_string(int (*fn)(const struct hl_gonio *, const struct hl_export_meta *,
				       FILE *),
			     const struct hl_gonio *g, const struct hl_export_meta *meta)
{
	char *text = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&text, &len);

	assert_non_null(f);
	assert_int_equal(fn(g, meta, f), 0);
	assert_int_equal(fclose(f), 0);
	return text;
}

/* CSV: two comment lines, the header row, then rows by decreasing row angle; read back by the
 * CSV reader as the same table. */
static void export_csv_writes_rows_by_decreasing_angle(void **state)
{
	static const double planes[2] = { -10.0, 12.5 }, in[3] = { -5.0, 0.0, 5.0 };
	static const float values[6] = { 1.0f, 2.0f, 3.0f, 4.5f, 0.125f, 1e-6f };
	const struct hl_export_meta meta = { .name = "low beam" };
	struct hl_import_error err;
	struct hl_gonio *g, *back;
	char *text;

	(void)state;
	assert_int_equal(hl_gonio_new(HL_GONIO_B, 2, planes, 3, in, values, &g), 0);
	text = write_to_string(hl_export_csv, g, &meta);
	assert_string_equal(text,
			    "# hdlamp lid export of low beam: luminous intensity in cd\n"
			    "# type B: columns H (deg, positive right), rows V (deg, positive up)\n"
			    "B,-10,12.5\n"
			    "5,3,9.99999997e-07\n"
			    "0,2,0.125\n"
			    "-5,1,4.5\n");
	assert_int_equal(hl_csv_parse(text, strlen(text), "x.csv", &back, &err), 0);
	assert_int_equal(hl_gonio_system(back), HL_GONIO_B);
	assert_memory_equal(hl_gonio_planes(back), planes, sizeof(planes));
	assert_memory_equal(hl_gonio_in(back), in, sizeof(in));
	assert_memory_equal(hl_gonio_values(back), values, sizeof(values));
	hl_gonio_free(back);
	free(text);
	hl_gonio_free(g);

	assert_int_equal(hl_gonio_new(HL_GONIO_C, 2, (const double[]){ 0.0, 90.0 }, 2,
				      (const double[]){ 0.0, 180.0 }, values, &g),
			 0);
	text = write_to_string(hl_export_csv, g, NULL);
	assert_string_equal(text,
			    "# hdlamp lid export: luminous intensity in cd\n"
			    "# type C: columns C (deg, C0 forward, C90 left), rows gamma (deg, "
			    "0 = nadir)\n"
			    "C,0,90\n"
			    "180,2,4.5\n"
			    "0,1,3\n");
	free(text);
	hl_gonio_free(g);
}

/* A line break in the name stays inside the comment line: the file reads back. */
static void export_csv_name_with_a_line_break_stays_one_comment(void **state)
{
	static const double planes[2] = { -10.0, 12.5 }, in[3] = { -5.0, 0.0, 5.0 };
	static const float values[6] = { 1.0f, 2.0f, 3.0f, 4.5f, 0.125f, 1e-6f };
	const struct hl_export_meta meta = { .name = "low\nbeam\r1" };
	struct hl_import_error err;
	struct hl_gonio *g, *back;
	char *text;

	(void)state;
	assert_int_equal(hl_gonio_new(HL_GONIO_B, 2, planes, 3, in, values, &g), 0);
	text = write_to_string(hl_export_csv, g, &meta);
	assert_non_null(
		strstr(text, "# hdlamp lid export of low beam 1: luminous intensity in cd\n"));
	assert_int_equal(hl_csv_parse(text, strlen(text), "x.csv", &back, &err), 0);
	hl_gonio_free(back);
	hl_gonio_free(g);
	free(text);
}

/* IES: the keywords (line breaks in values made blanks), TILT=NONE, absolute photometry, ten
 * numbers a line; read back by the IES reader as the same table. */
static void export_ies_writes_lm63_2019_that_reads_back(void **state)
{
	double in[12];
	static const double planes[2] = { 0.0, 180.0 };
	float values[24];
	const struct hl_export_meta meta = { .name = "low\nbeam",
					     .origin = "source 3 of x.lid.exr",
					     .issue_date = "2026-01-02" };
	struct hl_import_error err;
	struct hl_ies_info info;
	struct hl_gonio *g, *back;
	char *text;

	(void)state;
	for (int j = 0; j < 12; j++)
		in[j] = 15.0 * j + (j == 11 ? 15.0 : 0.0); /* 0..150, 180 */
	for (int i = 0; i < 24; i++)
		values[i] = (float)i * 0.5f;
	assert_int_equal(hl_gonio_new(HL_GONIO_C, 2, planes, 12, in, values, &g), 0);
	text = write_to_string(hl_export_ies, g, &meta);
	assert_string_equal(text,
			    "IES:LM-63-2019\n"
			    "[TEST] hdlamp lid export\n"
			    "[TESTLAB] hdlamp (resampled LID, not a measurement)\n"
			    "[ISSUEDATE] 2026-01-02\n"
			    "[MANUFAC] hdlamp\n"
			    "[LUMCAT] low beam\n"
			    "[LUMINAIRE] source 3 of x.lid.exr\n"
			    "[_HDLAMP_ANGLES] type C, gamma from the nadir, C0 forward (+z), C90 "
			    "left (-x)\n"
			    "TILT=NONE\n"
			    "1 -1 1 12 2 1 2 0 0 0\n"
			    "1 1 0\n"
			    "0 15 30 45 60 75 90 105 120 135\n"
			    "150 180\n"
			    "0 180\n"
			    "0 0.5 1 1.5 2 2.5 3 3.5 4 4.5\n"
			    "5 5.5\n"
			    "6 6.5 7 7.5 8 8.5 9 9.5 10 10.5\n"
			    "11 11.5\n");
	assert_int_equal(hl_ies_parse(text, strlen(text), "x.ies", &back, &info, &err), 0);
	assert_int_equal(info.photometric_type, 1);
	assert_int_equal(hl_gonio_n_in(back), 12);
	for (int i = 0; i < 2; i++)
		for (int j = 0; j < 12; j++)
			assert_true(hl_gonio_lookup(back, planes[i], in[j]) == values[i * 12 + j]);
	hl_gonio_free(back);
	free(text);
	hl_gonio_free(g);

	/* no meta: the date is "unknown", no LUMCAT or LUMINAIRE; type A is photometric type 3 */
	assert_int_equal(hl_gonio_new(HL_GONIO_A, 2, (const double[]){ -1.0, 1.0 }, 2,
				      (const double[]){ -1.0, 1.0 }, values, &g),
			 0);
	text = write_to_string(hl_export_ies, g, NULL);
	assert_non_null(strstr(text, "[ISSUEDATE] unknown\n[MANUFAC] hdlamp\n[_HDLAMP_ANGLES] "
				     "type A, H positive right, V positive up\nTILT=NONE\n"
				     "1 -1 1 2 2 3 2 0 0 0\n"));
	assert_null(strstr(text, "[LUMCAT]"));
	free(text);
	hl_gonio_free(g);
}

/* A write that fails (a full device) is an error, not a short file reported as written. */
static void export_writers_report_a_failed_write(void **state)
{
	static const float values[4] = { 1, 2, 3, 4 };
	struct hl_gonio *g;
	FILE *f;

	(void)state;
	assert_int_equal(hl_gonio_new(HL_GONIO_A, 2, (const double[]){ -1.0, 1.0 }, 2,
				      (const double[]){ -1.0, 1.0 }, values, &g),
			 0);
	f = fopen("/dev/full", "w");
	if (!f) {
		hl_gonio_free(g);
		skip();
	}
	/* the write's -errno: the device is full */
	assert_int_equal(hl_export_csv(g, NULL, f), -ENOSPC);
	clearerr(f);
	assert_int_equal(hl_export_ies(g, NULL, f), -ENOSPC);
	fclose(f);
	hl_gonio_free(g);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(export_sample_in_own_angles_keeps_the_grid_samples),
		cmocka_unit_test(export_sample_of_a_dark_source_is_the_coarse_frame),
		cmocka_unit_test(export_sample_refuses_bad_arguments_and_oversized_tables),
		cmocka_unit_test(export_csv_writes_rows_by_decreasing_angle),
		cmocka_unit_test(export_csv_name_with_a_line_break_stays_one_comment),
		cmocka_unit_test(export_ies_writes_lm63_2019_that_reads_back),
		cmocka_unit_test(export_writers_report_a_failed_write),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
