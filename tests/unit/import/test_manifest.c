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
#include <unistd.h>

#include <cmocka.h>

#include "import_test_util.h"
#include "import/import.h"
#include "import/manifest.h"
#include "import/resample.h"

static int parse(const char *text, struct hl_manifest **m, struct hl_import_error *err)
{
	return hl_manifest_parse(text, strlen(text), "m.ini", "/data", m, err);
}

/* Without [grid]: docs/design.md's grid; names, files (resolved) and formats per source. */
static void manifest_defaults_and_sources(void **state)
{
	static const char text[] = "# lamp\n[source 2]\nfile = b.LDT\nname = two words\n\n"
				   "[source 1]\n  file =  /abs/a.ies  \nname=one\n"
				   "[source 3]\nfile = c.txt\nname = three\nformat = csv\n";
	struct hl_import_error err;
	struct hl_manifest *m;
	const struct hl_lid_grid *g;

	(void)state;
	assert_int_equal(parse(text, &m, &err), 0);
	g = hl_manifest_grid(m);
	assert_int_equal(g->width, 900);
	assert_int_equal(g->height, 250);
	assert_int_equal(g->angles, HL_ANGLES_A);
	assert_true(g->h_first_deg == -89.9f && g->h_last_deg == 89.9f);
	assert_true(g->v_first_deg == -29.9f && g->v_last_deg == 19.9f);
	assert_int_equal(hl_manifest_n_sources(m), 3);
	assert_string_equal(hl_manifest_file(m, 0), "/abs/a.ies");
	assert_string_equal(hl_manifest_name(m, 0), "one");
	assert_int_equal(hl_manifest_format(m, 0), HL_IMPORT_IES);
	assert_string_equal(hl_manifest_file(m, 1), "/data/b.LDT");
	assert_string_equal(hl_manifest_name(m, 1), "two words");
	assert_int_equal(hl_manifest_format(m, 1), HL_IMPORT_LDT);
	assert_int_equal(hl_manifest_format(m, 2), HL_IMPORT_CSV);
	assert_int_equal(hl_manifest_line(m, 2), 9);
	hl_manifest_free(m);
}

static void manifest_grid_can_be_set(void **state)
{
	static const char text[] = "[grid]\nangles = B\nh = -20, 20\nv = -5 5\nstep = 0.5\n"
				   "[source 1]\nfile = a.csv\nname = a\n";
	struct hl_import_error err;
	struct hl_manifest *m;
	const struct hl_lid_grid *g;

	(void)state;
	assert_int_equal(parse(text, &m, &err), 0);
	g = hl_manifest_grid(m);
	assert_int_equal(g->angles, HL_ANGLES_B);
	assert_int_equal(g->width, 81);
	assert_int_equal(g->height, 21);
	assert_true(g->h_first_deg == -20.0f && g->v_last_deg == 5.0f);
	hl_manifest_free(m);
}

static const struct {
	const char *text;
	int line;
	const char *says;
} bad[] = {
	{ "[source 1]\nfile = a.ies\n", 1, "expected 'file' and 'name'" },
	{ "[source 1]\nfile = a.ies\nname = a\n[source 3]\nfile = c.ies\nname = c\n", 7,
	  "[source 2] is missing" },
	{ "[source 1]\nfile = a.ies\nname = a\n[source 1]\n", 4, "again" },
	{ "[source 1]\nfile = a.ies\nfile = b.ies\nname = a\n", 3, "'file' again" },
	{ "[source 1]\nfile = a.ies\nname = a\ncolour = red\n", 4, "file, name or format" },
	{ "[source 0]\n", 1, "N from 1" },
	{ "[source x]\n", 1, "N from 1" },
	{ "[lamp]\n", 1, "[grid] or [source N]" },
	{ "file = a.ies\n", 1, "section before" },
	{ "[grid]\nstep = 0.3\n[source 1]\nfile = a.ies\nname = a\n", 1, "whole numbers" },
	{ "[grid]\nangles = C\n", 2, "angles A or B" },
	{ "[grid]\nh = -10\n", 2, "two angles" },
	{ "[grid]\nh = 10, -10\n[source 1]\nfile = a.ies\nname = a\n", 1, "whole numbers" },
	{ "[grid]\nstep = nan\n", 2, "a step in degrees" },
	{ "[source 1]\nfile = a.txt\nname = a\n", 2, "extension" },
	{ "[source 1]\nfile = a.ies\nname = a\nformat = xls\n", 4, "ies, ldt or csv" },
	{ "[source 1]\nfile =\n", 2, "a value after" },
	{ "[source 1\n", 1, "']'" },
	{ "# nothing\n", 2, "at least one [source N]" },
	{ "[grid]\n[grid]\n", 2, "at most once" },
};

static void manifest_errors_name_line_and_expectation(void **state)
{
	(void)state;
	for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
		struct hl_import_error err = { 0 };
		struct hl_manifest *m = NULL;
		char where[64];

		snprintf(where, sizeof(where), "'m.ini':%d:", bad[i].line);
		if (parse(bad[i].text, &m, &err) != -EBADMSG || err.line != bad[i].line ||
		    strncmp(err.msg, where, strlen(where)) != 0 || !strstr(err.msg, bad[i].says)) {
			fprintf(stderr, "case %zu: line %d: %s\n", i, err.line, err.msg);
			fail();
		}
		assert_null(m);
	}
}

static void write_file(const char *path, const char *text)
{
	FILE *f = fopen(path, "w");

	assert_non_null(f);
	fputs(text, f);
	fclose(f);
}

/*
 * A whole lamp from a manifest: a CSV table in type A, the real type C file and a broken
 * file (refused with its own line, and the source number).
 */
static void manifest_builds_a_lamp(void **state)
{
	const char *tmp = getenv("HL_TEST_TMPDIR");
	char dir[4096], path[4200], ies[4096], text[8192];
	struct hl_import_error err;
	struct hl_manifest *m;
	struct hl_lid *lid;
	float *dense;

	(void)state;
	snprintf(dir, sizeof(dir), "%s/manifest_%d", tmp ? tmp : "/tmp", (int)getpid());
	snprintf(path, sizeof(path), "mkdir -p '%s'", dir);
	assert_int_equal(system(path), 0);
	snprintf(path, sizeof(path), "%s/beam.csv", dir);
	write_file(path, "A,-2,0,2\n1,0,50,0\n0,100,200,100\n-1,0,50,0\n");
	data_path(ies, sizeof(ies), "photometry/indoor_typeC_full.ies");
	snprintf(text, sizeof(text),
		 "[grid]\nh = -10, 10\nv = -5, 5\nstep = 1\n"
		 "[source 1]\nfile = beam.csv\nname = beam\n"
		 "[source 2]\nfile = %s\nname = downlight\n",
		 ies);
	snprintf(path, sizeof(path), "%s/lamp.ini", dir);
	write_file(path, text);
	assert_int_equal(hl_manifest_read(path, &m, &err), 0);
	assert_int_equal(hl_import_lid(m, &lid, &err), 0);
	assert_int_equal(hl_lid_n_sources(lid), 2);
	assert_string_equal(hl_lid_name(lid, 0), "beam");
	assert_string_equal(hl_lid_name(lid, 1), "downlight");
	dense = malloc(sizeof(float) * 21 * 11);
	hl_lid_source_dense(lid, 0, dense);
	assert_true(dense[5 * 21 + 10] == 200.0f); /* H 0, V 0 */
	assert_true(dense[5 * 21 + 9] == 150.0f); /* H -1, V 0 */
	assert_true(dense[4 * 21 + 11] == 25.0f); /* H 1, V 1: halfway between 50 and 0 */
	assert_true(dense[5 * 21 + 7] == 0.0f); /* H -3: outside the table */
	hl_lid_free(lid);
	hl_manifest_free(m);

	/* a broken source: the reader's message, then which source it was */
	snprintf(path, sizeof(path), "%s/beam.csv", dir);
	write_file(path, "A,-2,0,2\n1,0,50,0\n0,100,oops,100\n");
	snprintf(path, sizeof(path), "%s/lamp.ini", dir);
	assert_int_equal(hl_manifest_read(path, &m, &err), 0);
	assert_int_equal(hl_import_lid(m, &lid, &err), -EBADMSG);
	assert_int_equal(err.line, 3);
	assert_non_null(strstr(err.msg, "beam.csv':3:"));
	assert_non_null(strstr(err.msg, "(source 1)"));
	hl_manifest_free(m);
	free(dense);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(manifest_defaults_and_sources),
		cmocka_unit_test(manifest_grid_can_be_set),
		cmocka_unit_test(manifest_errors_name_line_and_expectation),
		cmocka_unit_test(manifest_builds_a_lamp),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
