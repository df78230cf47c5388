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
#include "import/export.h"
#include "import/ies.h"
#include "import/resample.h"

static const char *const real_files[] = {
	"canopy_typeC_quadrant.ies",
	"flood_typeB_bilateral.ies",
	"flood_typeB_full.ies",
	"indoor_typeC_full.ies",
};

/*
 * The file's own table, read independently of the library: every number after the TILT=NONE
 * line, in LM-63 order.
 */
struct table {
	int n_v, n_h, type;
	double scale; /* multiplier x ballast factor x ballast-lamp factor (LM-63-2002 files) */
	double *vert, *hori, *cd; /* cd[i * n_v + j], as written (before scaling) */
	double *nums;
};

static void read_table(const char *path, struct table *t)
{
	char *text = slurp(path, NULL), *p = strstr(text, "TILT=NONE"), *end;
	size_t n = 0, cap = 1024;

	assert_non_null(p);
	p += strlen("TILT=NONE");
	t->nums = malloc(sizeof(double) * cap);
	for (;;) {
		double v = strtod(p, &end);

		if (end == p)
			break;
		if (n == cap)
			t->nums = realloc(t->nums, sizeof(double) * (cap *= 2));
		t->nums[n++] = v;
		p = end;
	}
	while (*p == ' ' || *p == '\r' || *p == '\n')
		p++;
	assert_int_equal(*p, '\0'); /* the whole file was numbers */
	t->n_v = (int)t->nums[3];
	t->n_h = (int)t->nums[4];
	t->type = (int)t->nums[5];
	t->scale = t->nums[2] * t->nums[10] * t->nums[11];
	assert_int_equal(n, 13 + t->n_v + t->n_h + (size_t)t->n_v * t->n_h);
	t->vert = t->nums + 13;
	t->hori = t->vert + t->n_v;
	t->cd = t->hori + t->n_h;
	free(text);
}

static double expected(const struct table *t, int i, int j)
{
	return t->cd[(size_t)i * t->n_v + j] * t->scale;
}

static void assert_cd(double got, double want)
{
	if (fabs(got - want) > 1e-6 * fmax(1.0, want)) {
		fprintf(stderr, "got %.9g cd, want %.9g cd\n", got, want);
		fail();
	}
}

/* Every entry of every real file reads back at its own (horizontal, vertical) angles. */
static void ies_real_files_match_their_tables(void **state)
{
	(void)state;
	for (size_t f = 0; f < sizeof(real_files) / sizeof(real_files[0]); f++) {
		struct hl_import_error err;
		struct hl_ies_info info;
		struct hl_gonio *g;
		struct table t;
		char path[4096];
		double peak = 0.0;

		data_path(path, sizeof(path), "photometry/");
		strcat(path, real_files[f]);
		read_table(path, &t);
		assert_int_equal(hl_ies_read(path, &g, &info, &err), 0);
		assert_string_equal(info.version, "IESNA:LM-63-2002");
		assert_int_equal(info.n_vertical, t.n_v);
		assert_int_equal(info.n_horizontal, t.n_h);
		assert_int_equal(info.photometric_type, t.type);
		assert_true(fabs(info.scale - t.scale) < 1e-12);
		assert_int_equal(hl_gonio_system(g), t.type == 1 ? HL_GONIO_C :
						     t.type == 2 ? HL_GONIO_B :
								   HL_GONIO_A);
		for (int i = 0; i < t.n_h; i++) {
			const double h = t.hori[i];

			for (int j = 0; j < t.n_v; j++) {
				const double want = expected(&t, i, j), v = t.vert[j];

				peak = fmax(peak, want);
				assert_cd(hl_gonio_lookup(g, h, v), want);
				/* the mirrored halves and quadrants LM-63 implies */
				if (t.type == 1 && t.hori[t.n_h - 1] == 90.0) {
					assert_cd(hl_gonio_lookup(g, 180.0 - h, v), want);
					assert_cd(hl_gonio_lookup(g, 180.0 + h, v), want);
					assert_cd(hl_gonio_lookup(g, 360.0 - h, v), want);
				}
				if (t.type != 1 && t.hori[0] == 0.0)
					assert_cd(hl_gonio_lookup(g, -h, v), want);
			}
		}
		assert_cd(hl_gonio_peak_cd(g), peak);
		hl_gonio_free(g);
		free(t.nums);
	}
}

/*
 * Type C files on a type A grid at 1 degree. With gamma from the nadir and C counter-clockwise
 * from the optical axis (typec.h), a type A direction (H, V) is exactly (C, gamma) =
 * (-H, 90 + V), so every table entry with integral angles in the grid's range is a grid sample.
 */
static void ies_type_c_files_on_a_type_a_grid(void **state)
{
	const struct hl_lid_grid grid = { 181, 51, HL_ANGLES_A, -90.0f, 90.0f, -30.0f, 20.0f };
	float *dense = malloc(sizeof(float) * grid.width * grid.height);
	const char *files[] = { "canopy_typeC_quadrant.ies", "indoor_typeC_full.ies" };

	(void)state;
	for (int f = 0; f < 2; f++) {
		struct hl_import_error err;
		struct hl_gonio *g;
		struct table t;
		char path[4096];
		int checked = 0, lit = 0;

		data_path(path, sizeof(path), "photometry/");
		strcat(path, files[f]);
		read_table(path, &t);
		assert_int_equal(hl_ies_read(path, &g, NULL, &err), 0);
		hl_resample(g, &grid, dense);
		for (int i = 0; i < t.n_h; i++) {
			const double c = t.hori[i];
			/* the quadrant file's plane c also stands for 180 - c, 180 + c, 360 - c */
			const double planes[4] = { c, 180.0 - c, 180.0 + c, 360.0 - c };
			const int n_planes = t.hori[t.n_h - 1] == 90.0 ? 4 : 1;

			for (int m = 0; m < n_planes; m++) {
				double h = -planes[m];

				while (h <= -180.0)
					h += 360.0;
				if (h != floor(h) || fabs(h) > 90.0)
					continue;
				for (int j = 0; j < t.n_v; j++) {
					const double v = t.vert[j] - 90.0;
					const int row = (int)(20 - v), col = (int)(h + 90);

					if (v != floor(v) || v < -30.0 || v > 20.0)
						continue;
					assert_cd(dense[row * grid.width + col],
						  expected(&t, i, j));
					checked++;
					lit += expected(&t, i, j) > 0.0;
				}
			}
		}
		assert_true(checked >= 50);
		assert_true(lit >= 25);
		hl_gonio_free(g);
		free(t.nums);
	}
	free(dense);
}

/* Type B files on a type B grid at 1 degree: every integral table angle is a grid sample. */
static void ies_type_b_files_on_a_type_b_grid(void **state)
{
	const struct hl_lid_grid grid = { 121, 51, HL_ANGLES_B, -60.0f, 60.0f, -30.0f, 20.0f };
	float *dense = malloc(sizeof(float) * grid.width * grid.height);
	const char *files[] = { "flood_typeB_bilateral.ies", "flood_typeB_full.ies" };

	(void)state;
	for (int f = 0; f < 2; f++) {
		struct hl_import_error err;
		struct hl_gonio *g;
		struct table t;
		char path[4096];
		int checked = 0;

		data_path(path, sizeof(path), "photometry/");
		strcat(path, files[f]);
		read_table(path, &t);
		assert_int_equal(hl_ies_read(path, &g, NULL, &err), 0);
		hl_resample(g, &grid, dense);
		for (int i = 0; i < t.n_h; i++) {
			for (int j = 0; j < t.n_v; j++) {
				const double h = t.hori[i], v = t.vert[j];

				if (h != floor(h) || v != floor(v) || fabs(h) > 60.0 || v < -30.0 ||
				    v > 20.0)
					continue;
				assert_cd(dense[(int)(20 - v) * grid.width + (int)(h + 60)],
					  expected(&t, i, j));
				if (t.hori[0] ==
				    0.0) /* bilateral: the left half mirrors the right */
					assert_cd(dense[(int)(20 - v) * grid.width + (int)(60 - h)],
						  expected(&t, i, j));
				checked++;
			}
		}
		assert_true(checked >= 100);
		hl_gonio_free(g);
		free(t.nums);
	}
	free(dense);
}

static int parse(const char *text, struct hl_gonio **g, struct hl_ies_info *info,
		 struct hl_import_error *err)
{
	return hl_ies_parse(text, strlen(text), "t.ies", g, info, err);
}

/* Each LM-63 symmetry: the stored planes and their mirror images read the same. */
static void ies_symmetries_mirror_as_lm63_defines(void **state)
{
	static const char head[] = "IESNA:LM-63-2002\n[TEST] x\nTILT=NONE\n";
	struct hl_import_error err;
	struct hl_gonio *g;
	char text[2048];

	(void)state;
	/* rotational: one plane at C 0 */
	snprintf(text, sizeof(text), "%s1 -1 1 3 1 1 2 0 0 0\n1 1 0\n0 90 180\n0\n10 20 30\n",
		 head);
	assert_int_equal(parse(text, &g, NULL, &err), 0);
	for (double c = 0.0; c < 360.0; c += 37.0)
		assert_cd(hl_gonio_lookup(g, c, 90.0), 20.0);
	assert_cd(hl_gonio_lookup(g, 123.0, 45.0), 15.0);
	hl_gonio_free(g);

	/* quadrant: C 0..90 stands for all four quadrants */
	snprintf(text, sizeof(text),
		 "%s1 -1 1 2 3 1 2 0 0 0\n1 1 0\n0 90\n0 30 90\n1 2\n3 4\n5 6\n", head);
	assert_int_equal(parse(text, &g, NULL, &err), 0);
	assert_cd(hl_gonio_lookup(g, 30.0, 90.0), 4.0);
	assert_cd(hl_gonio_lookup(g, 150.0, 90.0), 4.0);
	assert_cd(hl_gonio_lookup(g, 210.0, 90.0), 4.0);
	assert_cd(hl_gonio_lookup(g, 330.0, 90.0), 4.0);
	assert_cd(hl_gonio_lookup(g, 180.0, 0.0), 1.0);
	assert_cd(hl_gonio_lookup(g, 270.0, 90.0), 6.0);
	assert_cd(hl_gonio_lookup(g, 15.0, 90.0), 3.0); /* halfway 0..30 */
	hl_gonio_free(g);

	/* C0-C180: I(C) = I(360 - C) */
	snprintf(text, sizeof(text),
		 "%s1 -1 1 2 3 1 2 0 0 0\n1 1 0\n0 90\n0 60 180\n1 2\n3 4\n5 6\n", head);
	assert_int_equal(parse(text, &g, NULL, &err), 0);
	assert_cd(hl_gonio_lookup(g, 300.0, 90.0), 4.0);
	assert_cd(hl_gonio_lookup(g, 60.0, 90.0), 4.0);
	assert_cd(hl_gonio_lookup(g, 240.0, 0.0), 4.0); /* mirror of 120: halfway 60..180 */
	hl_gonio_free(g);

	/* C90-C270: I(C) = I(180 - C) */
	snprintf(text, sizeof(text),
		 "%s1 -1 1 2 3 1 2 0 0 0\n1 1 0\n0 90\n90 180 270\n1 2\n3 4\n5 6\n", head);
	assert_int_equal(parse(text, &g, NULL, &err), 0);
	assert_cd(hl_gonio_lookup(g, 0.0, 90.0), 4.0); /* mirror of 180 */
	assert_cd(hl_gonio_lookup(g, 360.0, 90.0), 4.0);
	assert_cd(hl_gonio_lookup(g, 45.0, 90.0), 3.0); /* mirror of 135 */
	assert_cd(hl_gonio_lookup(g, 315.0, 0.0), 4.0); /* mirror of 225 */
	hl_gonio_free(g);

	/* full 0..270 in steps of 90: closed at 360 by plane 0 */
	snprintf(text, sizeof(text),
		 "%s1 -1 1 2 4 1 2 0 0 0\n1 1 0\n0 90\n0 90 180 270\n1 1\n2 2\n3 3\n4 4\n", head);
	assert_int_equal(parse(text, &g, NULL, &err), 0);
	assert_cd(hl_gonio_lookup(g, 315.0, 45.0), 2.5);
	assert_cd(hl_gonio_lookup(g, -45.0, 45.0), 2.5);
	hl_gonio_free(g);

	/* type A laterally symmetric: H 0..90 mirrored to -90..0; V outside its range is 0 */
	snprintf(text, sizeof(text),
		 "%s1 -1 1 2 3 3 2 0 0 0\n1 1 0\n0 10\n0 20 90\n1 2\n3 4\n5 6\n", head);
	assert_int_equal(parse(text, &g, NULL, &err), 0);
	assert_int_equal(hl_gonio_system(g), HL_GONIO_A);
	assert_cd(hl_gonio_lookup(g, -20.0, 10.0), 4.0);
	assert_cd(hl_gonio_lookup(g, -10.0, 5.0), 2.5);
	assert_cd(hl_gonio_lookup(g, 10.0, -1.0), 0.0);
	assert_cd(hl_gonio_lookup(g, 10.0, 10.5), 0.0);
	hl_gonio_free(g);

	/* type B starting at -90: no mirror, exactly as given */
	snprintf(text, sizeof(text), "%s1 -1 1 2 2 2 2 0 0 0\n1 1 0\n-5 5\n-90 90\n1 2\n3 4\n",
		 head);
	assert_int_equal(parse(text, &g, NULL, &err), 0);
	assert_int_equal(hl_gonio_system(g), HL_GONIO_B);
	assert_cd(hl_gonio_lookup(g, 0.0, 0.0), 2.5);
	assert_cd(hl_gonio_lookup(g, -90.0, 5.0), 2.0);
	hl_gonio_free(g);
}

/* Candela multiplier, ballast factor and (before 2019) the ballast-lamp factor scale. */
static void ies_multipliers_scale_candela(void **state)
{
	static const char body[] =
		"TILT=NONE\n1 1000 2.5 2 2 2 2 0 0 0\n0.8 0.5 20\n-10 10\n-10 10\n1 2 3 4\n";
	struct hl_import_error err;
	struct hl_ies_info info;
	struct hl_gonio *g;
	char text[1024];

	(void)state;
	snprintf(text, sizeof(text), "IESNA:LM-63-1995\n[TEST] x\n%s", body);
	assert_int_equal(parse(text, &g, &info, &err), 0);
	assert_true(info.scale == 2.5 * 0.8 * 0.5);
	assert_true(info.lumens_per_lamp == 1000.0);
	assert_cd(hl_gonio_lookup(g, 10.0, 10.0), 4.0 * 1.0);
	hl_gonio_free(g);
	/* 2019: the third factor is "future use" and does not scale */
	snprintf(text, sizeof(text), "IES:LM-63-2019\n[TEST] x\n%s", body);
	assert_int_equal(parse(text, &g, &info, &err), 0);
	assert_true(info.scale == 2.5 * 0.8);
	assert_cd(hl_gonio_lookup(g, 10.0, 10.0), 8.0);
	hl_gonio_free(g);
	/* absolute photometry: lumens -1, values as written */
	snprintf(text, sizeof(text),
		 "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 2 2 2 2 0 0 0\n1 1 20\n-10 10\n-10 10\n"
		 "1 2 3 4\n");
	assert_int_equal(parse(text, &g, &info, &err), 0);
	assert_true(info.lumens_per_lamp == -1.0);
	assert_cd(hl_gonio_lookup(g, -10.0, 10.0), 2.0);
	hl_gonio_free(g);
}

/* Keyword block with [MORE] and blank lines, CRLF, commas, rows wrapped anywhere. */
static void ies_keywords_more_and_wrapped_rows(void **state)
{
	static const char text[] =
		"IESNA:LM-63-2002\r\n[TEST] 1\r\n[LUMINAIRE] a long\r\n[MORE] description\r\n"
		"\r\n[_LED DRIVER] custom keyword with a blank\r\nTILT=NONE\r\n"
		"1 -1 1\r\n3 2 2 2 0 0 0 1 1 20 -10,0,\r\n10 -5 5\r\n1\r\n2 3\r\n4 5\r\n6\r\n\x1a";
	struct hl_import_error err;
	struct hl_gonio *g;

	(void)state;
	assert_int_equal(parse(text, &g, NULL, &err), 0);
	assert_cd(hl_gonio_lookup(g, -5.0, -10.0), 1.0);
	assert_cd(hl_gonio_lookup(g, 5.0, 10.0), 6.0);
	assert_cd(hl_gonio_lookup(g, 5.0, 0.0), 5.0);
	assert_cd(hl_gonio_lookup(g, 0.0, 0.0), 3.5);
	hl_gonio_free(g);
}

static const struct corpus_case ies_corpus[] = {
	{ "ies_angles_out_of_order.ies", -EBADMSG, 7 }, { "ies_bad_type.ies", -EBADMSG, 5 },
	{ "ies_bad_version.ies", -EBADMSG, 1 },		{ "ies_empty.ies", -EBADMSG, 1 },
	{ "ies_extra_values.ies", -EBADMSG, 12 },	{ "ies_inf.ies", -EBADMSG, 9 },
	{ "ies_more_first.ies", -EBADMSG, 2 },		{ "ies_nan.ies", -EBADMSG, 10 },
	{ "ies_negative_candela.ies", -EBADMSG, 11 },	{ "ies_no_tilt.ies", -EBADMSG, 4 },
	{ "ies_non_numeric.ies", -EBADMSG, 10 },	{ "ies_tilt_file.ies", -ENOTSUP, 4 },
	{ "ies_tilt_include.ies", -ENOTSUP, 4 },	{ "ies_truncated.ies", -EBADMSG, 10 },
	{ "ies_type_c_range.ies", -EBADMSG, 8 },	{ "ies_vertical_range.ies", -EBADMSG, 7 },
	{ "ies_wrong_count.ies", -EBADMSG, 9 },		{ "ies_zero_multiplier.ies", -EBADMSG, 5 },
};

/* Every malformed file is refused with its -errno and a message naming file and line. */
static void ies_malformed_corpus_rejected(void **state)
{
	(void)state;
	for (size_t i = 0; i < sizeof(ies_corpus) / sizeof(ies_corpus[0]); i++) {
		struct hl_import_error err = { 0 };
		struct hl_gonio *g = NULL;
		char path[4096], where[4200];

		data_path(path, sizeof(path), "malformed/");
		strcat(path, ies_corpus[i].file);
		snprintf(where, sizeof(where), "'%s':%d:", path, ies_corpus[i].line);
		if (hl_ies_read(path, &g, NULL, &err) != ies_corpus[i].rc ||
		    err.line != ies_corpus[i].line || strncmp(err.msg, where, strlen(where)) != 0 ||
		    strlen(err.msg) < strlen(where) + 10) {
			fprintf(stderr, "%s: line %d: %s\n", ies_corpus[i].file, err.line, err.msg);
			fail();
		}
		assert_null(g);
	}
}

static void ies_messages_say_what_was_expected(void **state)
{
	struct hl_import_error err;
	struct hl_gonio *g = NULL;
	char path[4096];

	(void)state;
	data_path(path, sizeof(path), "malformed/ies_tilt_include.ies");
	assert_int_equal(hl_ies_read(path, &g, NULL, &err), -ENOTSUP);
	assert_non_null(strstr(err.msg, "TILT=INCLUDE"));
	assert_non_null(strstr(err.msg, "expected TILT=NONE"));
	data_path(path, sizeof(path), "malformed/ies_nan.ies");
	assert_int_equal(hl_ies_read(path, &g, NULL, &err), -EBADMSG);
	assert_int_equal(err.column, 5);
	assert_non_null(strstr(err.msg, "found 'nan'"));
	data_path(path, sizeof(path), "malformed/does_not_exist.ies");
	assert_int_equal(hl_ies_read(path, &g, NULL, &err), -ENOENT);
	assert_int_equal(err.line, 0);
	assert_non_null(strstr(err.msg, "does_not_exist.ies"));
	assert_null(g);
}

/* Exports are LM-63-2019 with the required keywords and the right photometric type. */
static void ies_export_writes_lm63_2019(void **state)
{
	const struct hl_lid_grid grid = { 5, 3, HL_ANGLES_A, -2.0f, 2.0f, -1.0f, 1.0f };
	const float dense[15] = { 0, 1, 2, 1, 0, 1, 2, 4, 2, 1, 0, 1, 2, 1, 0 };
	const struct hl_export_meta meta = { "beam", "source 1 of test", "2026-11-21" };
	static const char *const keywords[] = {
		"[TEST] ",    "[TESTLAB] ",	 "[ISSUEDATE] 2026-11-21\n",
		"[MANUFAC] ", "[LUMCAT] beam\n", "\nTILT=NONE\n"
	};
	struct hl_lid *lid;

	(void)state;
	assert_int_equal(hl_lid_new(1, &grid, false, &lid), 0);
	assert_int_equal(hl_lid_set_source(lid, 0, dense), 0);
	for (int s = 0; s < 3; s++) {
		const enum hl_gonio_system system = (enum hl_gonio_system)s;
		struct hl_import_error err;
		struct hl_ies_info info;
		struct hl_gonio *out, *in;
		char *text;
		size_t len;
		FILE *f;

		assert_int_equal(hl_export_sample(lid, 0, system, 0.0, &out), 0);
		f = open_memstream(&text, &len);
		assert_int_equal(hl_export_ies(out, &meta, f), 0);
		fclose(f);
		assert_int_equal(strncmp(text, "IES:LM-63-2019\n", 15), 0);
		for (size_t k = 0; k < sizeof(keywords) / sizeof(keywords[0]); k++)
			assert_non_null(strstr(text, keywords[k]));
		assert_int_equal(hl_ies_parse(text, len, "mem.ies", &in, &info, &err), 0);
		assert_string_equal(info.version, "IES:LM-63-2019");
		assert_int_equal(info.photometric_type, s == 0 ? 3 : s == 1 ? 2 : 1);
		assert_true(info.lumens_per_lamp == -1.0 && info.scale == 1.0);
		assert_int_equal(hl_gonio_system(in), system);
		/* the centre sample, (H, V) = (0, 0), is (0, 0) in A and B and (0, 90) in C */
		assert_cd(hl_gonio_lookup(in, 0.0, s == 2 ? 90.0 : 0.0), 4.0);
		hl_gonio_free(out);
		hl_gonio_free(in);
		free(text);
	}
	hl_lid_free(lid);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(ies_real_files_match_their_tables),
		cmocka_unit_test(ies_type_c_files_on_a_type_a_grid),
		cmocka_unit_test(ies_type_b_files_on_a_type_b_grid),
		cmocka_unit_test(ies_symmetries_mirror_as_lm63_defines),
		cmocka_unit_test(ies_multipliers_scale_candela),
		cmocka_unit_test(ies_keywords_more_and_wrapped_rows),
		cmocka_unit_test(ies_malformed_corpus_rejected),
		cmocka_unit_test(ies_messages_say_what_was_expected),
		cmocka_unit_test(ies_export_writes_lm63_2019),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
