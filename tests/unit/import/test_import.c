/* SPDX-License-Identifier: MIT */
/*
 * import/import.c: one measured file read in the format asked for, and a lamp built from a
 * manifest: each source read, resampled onto the manifest's grid and named; a failing file
 * named with its manifest source.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "import/import.h"
#include "import_test_util.h"
#include "testutil.h"

/* H -3..3 and V -2..2 every degree; the value at (H, V) is 10 (H + 3) + V + 2 + offset. */
static const char *write_table(char *path, size_t size, const char *name, int offset)
{
	FILE *f;

	test_path(path, size, name);
	f = fopen(path, "w");
	assert_non_null(f);
	fprintf(f, "# test table\nA,-3,-2,-1,0,1,2,3\n");
	for (int v = 2; v >= -2; v--) {
		fprintf(f, "%d", v);
		for (int h = -3; h <= 3; h++)
			fprintf(f, ",%d", 10 * (h + 3) + v + 2 + offset);
		fprintf(f, "\n");
	}
	assert_int_equal(fclose(f), 0);
	return path;
}

static const char *write_text(char *path, size_t size, const char *name, const char *text)
{
	FILE *f;

	test_path(path, size, name);
	f = fopen(path, "w");
	assert_non_null(f);
	assert_true(fputs(text, f) >= 0);
	assert_int_equal(fclose(f), 0);
	return path;
}

/* Each format by its reader, whatever the file's name says; an unknown format is -EINVAL. */
static void import_load_reads_the_file_in_the_format_given(void **state)
{
	char csv[4096], ies[4096], want[4300];
	struct hl_import_error err;
	struct hl_gonio *g = NULL;

	(void)state;
	write_table(csv, sizeof(csv), "load.csv", 0);
	assert_int_equal(hl_import_load(csv, HL_IMPORT_CSV, &g, &err), 0);
	assert_int_equal(hl_gonio_system(g), HL_GONIO_A);
	assert_int_equal(hl_gonio_n_planes(g), 7);
	assert_int_equal(hl_gonio_n_in(g), 5);
	assert_true(hl_gonio_lookup(g, 1.0, -1.0) == 41.0);
	hl_gonio_free(g);
	g = NULL;

	data_path(ies, sizeof(ies), "photometry/canopy_typeC_quadrant.ies");
	assert_int_equal(hl_import_load(ies, HL_IMPORT_IES, &g, &err), 0);
	assert_int_equal(hl_gonio_system(g), HL_GONIO_C);
	hl_gonio_free(g);
	g = NULL;

	/* the CSV file read as IES or EULUMDAT: those readers' errors, naming the file */
	snprintf(want, sizeof(want), "'%s':", csv);
	assert_int_equal(hl_import_load(csv, HL_IMPORT_IES, &g, &err), -EBADMSG);
	assert_memory_equal(err.msg, want, strlen(want));
	assert_int_equal(hl_import_load(csv, HL_IMPORT_LDT, &g, &err), -EBADMSG);
	assert_memory_equal(err.msg, want, strlen(want));
	/* the IES file read as CSV */
	assert_int_equal(hl_import_load(ies, HL_IMPORT_CSV, &g, &err), -EBADMSG);
	assert_int_equal(err.line, 1);

	assert_int_equal(hl_import_load(csv, (enum hl_import_format)7, &g, &err), -EINVAL);
	snprintf(want, sizeof(want), "'%s': unknown format", csv);
	assert_string_equal(err.msg, want);
	assert_int_equal(err.line, 0);
	assert_int_equal(hl_import_load(csv, (enum hl_import_format)7, &g, NULL), -EINVAL);
	assert_null(g);
	unlink(csv);
	assert_int_equal(hl_import_load(csv, HL_IMPORT_CSV, &g, &err), -ENOENT);
	assert_null(g);
}

static struct hl_manifest *manifest(const char *a, const char *b, const char *b_format)
{
	struct hl_manifest *m = NULL;
	struct hl_import_error err;
	char text[10000];

	snprintf(text, sizeof(text),
		 "[grid]\nangles = A\nh = -2, 2\nv = -1, 1\nstep = 1\n"
		 "[source 1]\nfile = %s\nname = low\n"
		 "[source 2]\nfile = %s\nname = high beam\nformat = %s\n",
		 a, b, b_format);
	if (hl_manifest_parse(text, strlen(text), "m.ini", NULL, &m, &err) < 0)
		fail_msg("%s", err.msg);
	return m;
}

/* Two sources on the manifest's 5 x 3 grid, named, each sample the table's value there. */
static void import_lid_builds_one_named_source_per_entry(void **state)
{
	char a[4096], b[4096];
	struct hl_manifest *m;
	struct hl_import_error err;
	struct hl_lid *lid = NULL;
	float dense[15];

	(void)state;
	write_table(a, sizeof(a), "a.csv", 0);
	write_table(b, sizeof(b), "b.csv", 1000);
	m = manifest(a, b, "csv");
	assert_int_equal(hl_import_lid(m, &lid, &err), 0);
	assert_int_equal(hl_lid_n_sources(lid), 2);
	assert_false(hl_lid_is_combined(lid));
	assert_true(hl_lid_grid_equal(hl_lid_grid(lid), hl_manifest_grid(m)));
	assert_int_equal(hl_lid_grid(lid)->width, 5);
	assert_int_equal(hl_lid_grid(lid)->height, 3);
	assert_string_equal(hl_lid_name(lid, 0), "low");
	assert_string_equal(hl_lid_name(lid, 1), "high beam");
	for (int k = 0; k < 2; k++) {
		hl_lid_source_dense(lid, k, dense);
		for (int row = 0; row < 3; row++)
			for (int col = 0; col < 5; col++) {
				const int h = col - 2, v = 1 - row;
				const float want = (float)(10 * (h + 3) + v + 2 + 1000 * k);

				if (dense[row * 5 + col] != want)
					fail_msg("source %d (H %d, V %d): %g, expected %g", k, h, v,
						 dense[row * 5 + col], want);
			}
	}
	hl_lid_free(lid);
	hl_manifest_free(m);
	unlink(a);
	unlink(b);
}

/* The first failing file stops the import: its reader's -errno and message, with the manifest
 * source it is; *ret untouched. */
static void import_lid_names_the_failing_source(void **state)
{
	char a[4096], b[4096], want[4300];
	struct hl_manifest *m;
	struct hl_import_error err;
	struct hl_lid *lid = NULL;
	size_t n;

	(void)state;
	write_table(a, sizeof(a), "fa.csv", 0);
	write_text(b, sizeof(b), "fb.csv", "A,-1,1\n0,1,1\n1,1,-1\n");
	m = manifest(a, b, "csv");
	assert_int_equal(hl_import_lid(m, &lid, &err), -EBADMSG);
	assert_null(lid);
	snprintf(want, sizeof(want),
		 "'%s':3:5: expected value 2 of the row in 0..3e38 cd, found -1 (source 2)", b);
	assert_string_equal(err.msg, want);
	assert_int_equal(err.line, 3);
	assert_int_equal(hl_import_lid(m, &lid, NULL), -EBADMSG);
	assert_null(lid);
	hl_manifest_free(m);

	/* read in the wrong format */
	write_table(b, sizeof(b), "fb.csv", 0);
	m = manifest(a, b, "ies");
	assert_int_equal(hl_import_lid(m, &lid, &err), -EBADMSG);
	n = strlen(err.msg);
	assert_true(n > strlen(" (source 2)"));
	assert_string_equal(err.msg + n - strlen(" (source 2)"), " (source 2)");
	hl_manifest_free(m);

	/* a file that is gone */
	unlink(b);
	m = manifest(a, b, "csv");
	assert_int_equal(hl_import_lid(m, &lid, &err), -ENOENT);
	snprintf(want, sizeof(want), "'%s': cannot open: No such file or directory (source 2)", b);
	assert_string_equal(err.msg, want);
	assert_int_equal(err.line, 0);
	assert_null(lid);
	hl_manifest_free(m);
	unlink(a);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(import_load_reads_the_file_in_the_format_given),
		cmocka_unit_test(import_lid_builds_one_named_source_per_entry),
		cmocka_unit_test(import_lid_names_the_failing_source),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
