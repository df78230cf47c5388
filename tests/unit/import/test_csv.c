/* SPDX-License-Identifier: MIT */
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

#include "import_test_util.h"
#include "import/csv.h"
#include "import/export.h"
#include "import/resample.h"
#include "lamp/model.h"

static int parse(const char *text, struct hl_gonio **g, struct hl_import_error *err)
{
	return hl_csv_parse(text, strlen(text), "t.csv", g, err);
}

/* Rows and columns in either order give the same table; comments, blanks, CRLF are fine. */
static void csv_reads_rows_and_columns_in_either_order(void **state)
{
	static const char *const texts[] = {
		"A,-10,0,10\n-5,1,2,3\n5,4,5,6\n",
		"# descending V, image-like\r\n\r\nA, -10, 0, 10\r\n5, 4, 5, 6\r\n-5, 1, 2, 3\r\n",
		"A,10,0,-10\n  # comment\n5,6,5,4\n-5,3,2,1\n",
	};
	struct hl_import_error err;

	(void)state;
	for (int i = 0; i < 3; i++) {
		struct hl_gonio *g;

		assert_int_equal(parse(texts[i], &g, &err), 0);
		assert_int_equal(hl_gonio_system(g), HL_GONIO_A);
		assert_int_equal(hl_gonio_n_planes(g), 3);
		assert_int_equal(hl_gonio_n_in(g), 2);
		assert_true(hl_gonio_lookup(g, -10.0, -5.0) == 1.0);
		assert_true(hl_gonio_lookup(g, 10.0, 5.0) == 6.0);
		assert_true(hl_gonio_lookup(g, 5.0, 0.0) == 4.0); /* (2 + 3 + 5 + 6) / 4 */
		assert_true(hl_gonio_lookup(g, 10.5, 0.0) == 0.0); /* outside: zero */
		hl_gonio_free(g);
	}
}

/* Type C: a table over exactly 0..360 wraps, a partial one is zero outside. */
static void csv_type_c_wraps_only_when_closed(void **state)
{
	struct hl_import_error err;
	struct hl_gonio *g;

	(void)state;
	assert_int_equal(parse("C,0,180,360\n80,1,2,1\n100,3,4,3\n", &g, &err), 0);
	assert_true(hl_gonio_lookup(g, -90.0, 80.0) == 1.5);
	assert_true(hl_gonio_lookup(g, 450.0, 100.0) == 3.5);
	hl_gonio_free(g);
	assert_int_equal(parse("C,0,10,20\n80,1,2,1\n100,3,4,3\n", &g, &err), 0);
	assert_true(hl_gonio_lookup(g, 5.0, 90.0) == 2.5);
	assert_true(hl_gonio_lookup(g, 355.0, 90.0) == 0.0);
	assert_true(hl_gonio_lookup(g, 5.0, 101.0) == 0.0);
	hl_gonio_free(g);
}

/*
 * A LID source exported as CSV in its own system at its own step holds exactly the grid's
 * samples: read back, every sample of the source's box matches.
 */
static void csv_export_in_own_angles_is_exact(void **state)
{
	struct hl_import_error err;
	struct hl_gonio *out, *in;
	struct hl_lid *lid;
	char *text;
	size_t len;
	FILE *f;

	(void)state;
	assert_int_equal(hl_model_hd84(HL_SIDE_LEFT, &lid), 0);
	for (int k = 0; k < HL_HD84_SOURCES; k += 10) {
		const struct hl_lid_grid *g = hl_lid_grid(lid);
		struct hl_lid_box b;
		const float *src = hl_lid_source(lid, k, &b);
		int n = 0;

		assert_int_equal(hl_export_sample(lid, k, HL_GONIO_A, 0.0, &out), 0);
		f = open_memstream(&text, &len);
		assert_int_equal(hl_export_csv(out, NULL, f), 0);
		fclose(f);
		assert_int_equal(hl_csv_parse(text, len, "mem.csv", &in, &err), 0);
		for (int y = b.y0; y < b.y1; y++) {
			for (int x = b.x0; x < b.x1; x++) {
				const float want = src[(y - b.y0) * (b.x1 - b.x0) + (x - b.x0)];
				double p, q;

				hl_resample_sample_angles(g, x, y, HL_GONIO_A, &p, &q);
				if (fabs(hl_gonio_lookup(in, p, q) - want) > 1e-6 * want + 1e-9)
					fprintf(stderr,
						"k %d x %d y %d p %.9g q %.9g got %.9g want %.9g\n",
						k, x, y, p, q, hl_gonio_lookup(in, p, q), want);
				assert_true(fabs(hl_gonio_lookup(in, p, q) - want) <=
					    1e-6 * want + 1e-9);
				n++;
			}
		}
		assert_true(n > 0);
		hl_gonio_free(out);
		hl_gonio_free(in);
		free(text);
	}
	hl_lid_free(lid);
}

/* Exports stay within what the readers take back; bad arguments are -EINVAL. */
static void export_refuses_tables_too_large_to_read_back(void **state)
{
	struct hl_gonio *g = NULL;
	struct hl_lid *lid;

	(void)state;
	assert_int_equal(hl_model_hd84(HL_SIDE_LEFT, &lid), 0);
	assert_int_equal(hl_export_sample(lid, HL_HD84_APRON - 1, HL_GONIO_B, 0.001, &g), -EFBIG);
	assert_int_equal(hl_export_sample(lid, 0, HL_GONIO_A, 20.0, &g), -EINVAL);
	assert_int_equal(hl_export_sample(lid, 0, HL_GONIO_A, NAN, &g), -EINVAL);
	assert_int_equal(hl_export_sample(lid, HL_HD84_SOURCES, HL_GONIO_A, 0.0, &g), -EINVAL);
	assert_int_equal(hl_export_sample(lid, -1, HL_GONIO_A, 0.0, &g), -EINVAL);
	assert_null(g);
	hl_lid_free(lid);
}

static const struct corpus_case csv_corpus[] = {
	{ "csv_column_out_of_order.csv", -EBADMSG, 1 },
	{ "csv_nan.csv", -EBADMSG, 4 },
	{ "csv_negative.csv", -EBADMSG, 3 },
	{ "csv_no_system.csv", -EBADMSG, 2 },
	{ "csv_non_numeric.csv", -EBADMSG, 5 },
	{ "csv_out_of_order.csv", -EBADMSG, 5 },
	{ "csv_ragged.csv", -EBADMSG, 4 },
	{ "csv_truncated.csv", -EBADMSG, 3 },
};

static void csv_malformed_corpus_rejected(void **state)
{
	(void)state;
	for (size_t i = 0; i < sizeof(csv_corpus) / sizeof(csv_corpus[0]); i++) {
		struct hl_import_error err = { 0 };
		struct hl_gonio *g = NULL;
		char path[4096], where[4200];

		data_path(path, sizeof(path), "malformed/");
		strcat(path, csv_corpus[i].file);
		snprintf(where, sizeof(where), "'%s':%d:", path, csv_corpus[i].line);
		if (hl_csv_read(path, &g, &err) != csv_corpus[i].rc ||
		    err.line != csv_corpus[i].line || strncmp(err.msg, where, strlen(where)) != 0 ||
		    strlen(err.msg) < strlen(where) + 10) {
			fprintf(stderr, "%s: line %d: %s\n", csv_corpus[i].file, err.line, err.msg);
			fail();
		}
		assert_null(g);
	}
}

/* Column numbers point at the faulty cell. */
static void csv_errors_name_the_cell(void **state)
{
	struct hl_import_error err;
	struct hl_gonio *g = NULL;

	(void)state;
	assert_int_equal(parse("B,-1,1\n0,1,1\n1,1,x\n", &g, &err), -EBADMSG);
	assert_int_equal(err.line, 3);
	assert_int_equal(err.column, 5);
	assert_string_equal(err.msg, "'t.csv':3:5: expected value 2 of the row (cd, a finite "
				     "decimal number)");
	assert_int_equal(parse("A,-1,1\n0,1,1\n100,1,1\n", &g, &err), -EBADMSG);
	assert_string_equal(err.msg, "'t.csv':3:1: expected the V (row) angle in -90..90 degrees, "
				     "found 100");
	assert_null(g);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(csv_reads_rows_and_columns_in_either_order),
		cmocka_unit_test(csv_type_c_wraps_only_when_closed),
		cmocka_unit_test(csv_export_in_own_angles_is_exact),
		cmocka_unit_test(export_refuses_tables_too_large_to_read_back),
		cmocka_unit_test(csv_malformed_corpus_rejected),
		cmocka_unit_test(csv_errors_name_the_cell),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
