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
#include "import/eulumdat.h"
#include "import/resample.h"

/* Intensity in cd/klm written for plane C at gamma: distinct everywhere, so mirrors show. */
static double f(double c, double gamma)
{
	return 100.0 + c + 0.25 * gamma;
}

/*
 * An EULUMDAT text with Mc planes every 360 / Mc degrees and gamma every 90 / 2 degrees
 * (0..180), two lamp sets of 1500 and 500 lm and conversion factor 1.5 (scale 3).
 */
static char *make_ldt(int isym, int mc, int *ret_planes, int *ret_first)
{
	const int ng = 5;
	int n_planes = isym == 0 ? mc : isym == 1 ? 1 : isym == 4 ? mc / 4 + 1 : mc / 2 + 1;
	int first = isym == 3 ? mc / 4 : 0;
	char *text;
	size_t len;
	FILE *o = open_memstream(&text, &len);

	fprintf(o, "hdlamp tests\r\n1\r\n%d\r\n%d\r\n%g\r\n%d\r\n45\r\n", isym, mc, 360.0 / mc, ng);
	fprintf(o, "report\nluminaire\nnumber\nfile.ldt\ndate\n");
	fprintf(o, "100\n50\n20\n90\n40\n0\n0\n0\n0\n100\n80\n1.5\n0\n");
	fprintf(o, "2\n1\n-2\nLED a\nLED b\n1500\n500\n4000K\n3000K\n80\n90\n12\n6\n");
	for (int i = 0; i < 10; i++)
		fprintf(o, "0.%d\n", i + 1);
	for (int i = 0; i < mc; i++)
		fprintf(o, "%g\n", i * 360.0 / mc);
	for (int j = 0; j < ng; j++)
		fprintf(o, "%g\n", j * 45.0);
	for (int i = 0; i < n_planes; i++)
		for (int j = 0; j < ng; j++)
			fprintf(o, "%.6g\n", f((first + i) * 360.0 / mc, j * 45.0));
	fclose(o);
	*ret_planes = n_planes;
	*ret_first = first;
	return text;
}

static void assert_cd(double got, double want)
{
	if (fabs(got - want) > 1e-6 * fmax(1.0, want)) {
		fprintf(stderr, "got %.9g cd, want %.9g cd\n", got, want);
		fail();
	}
}

/* Each symmetry indicator: stored planes read back scaled, their mirror images equal them. */
static void eulumdat_symmetries_expand_and_scale(void **state)
{
	(void)state;
	for (int isym = 0; isym <= 4; isym++) {
		const int mc = 24;
		struct hl_eulumdat_info info;
		struct hl_import_error err;
		struct hl_gonio *g;
		int n_planes, first;
		char *text = make_ldt(isym, mc, &n_planes, &first);

		if (hl_eulumdat_parse(text, strlen(text), "t.ldt", &g, &info, &err) != 0) {
			fprintf(stderr, "isym %d: %s\n", isym, err.msg);
			fail();
		}
		assert_int_equal(info.symmetry, isym);
		assert_int_equal(info.n_c_planes, mc);
		assert_int_equal(info.n_gamma, 5);
		assert_int_equal(info.n_planes_stored, n_planes);
		assert_int_equal(info.n_lamp_sets, 2);
		assert_true(info.lamp_flux_lm == 2000.0);
		assert_true(info.scale == 3.0);
		for (int i = 0; i < n_planes; i++) {
			const double c = (first + i) * 360.0 / mc;

			for (int j = 0; j < 5; j++) {
				const double gamma = j * 45.0, want = 3.0 * f(c, gamma);

				assert_cd(hl_gonio_lookup(g, c, gamma), want);
				switch (isym) {
				case 1:
					assert_cd(hl_gonio_lookup(g, 17.0 + 40.0 * j, gamma), want);
					break;
				case 2:
					assert_cd(hl_gonio_lookup(g, 360.0 - c, gamma), want);
					break;
				case 3:
					assert_cd(hl_gonio_lookup(g, fmod(540.0 - c, 360.0), gamma),
						  want);
					break;
				case 4:
					assert_cd(hl_gonio_lookup(g, 180.0 - c, gamma), want);
					assert_cd(hl_gonio_lookup(g, 180.0 + c, gamma), want);
					assert_cd(hl_gonio_lookup(g, 360.0 - c, gamma), want);
					break;
				}
			}
		}
		/* between planes: linear in C (gamma 90, halfway between two stored planes) */
		if (isym == 0)
			assert_cd(hl_gonio_lookup(g, 352.5, 90.0),
				  3.0 * 0.5 * (f(345.0, 90.0) + f(0.0, 90.0)));
		hl_gonio_free(g);
		free(text);
	}
}

/* An EULUMDAT table on a type A grid: (H, V) looks at (C, gamma) = (-H, 90 + V). */
static void eulumdat_on_a_type_a_grid(void **state)
{
	const struct hl_lid_grid grid = { 181, 51, HL_ANGLES_A, -90.0f, 90.0f, -30.0f, 20.0f };
	float *dense = malloc(sizeof(float) * grid.width * grid.height);
	struct hl_import_error err;
	struct hl_gonio *g;
	int n_planes, first;
	char *text = make_ldt(0, 24, &n_planes, &first);

	(void)state;
	assert_int_equal(hl_eulumdat_parse(text, strlen(text), "t.ldt", &g, NULL, &err), 0);
	hl_resample(g, &grid, dense);
	/* V = 0 is gamma 90; H = -15 is C 15, H = 30 is C 330 */
	assert_cd(dense[20 * grid.width + 90 - 15], 3.0 * f(15.0, 90.0));
	assert_cd(dense[20 * grid.width + 90 + 30], 3.0 * f(330.0, 90.0));
	assert_cd(dense[20 * grid.width + 90], 3.0 * f(0.0, 90.0));
	hl_gonio_free(g);
	free(text);
	free(dense);
}

static const struct corpus_case ldt_corpus[] = {
	{ "ldt_bad_symmetry.ldt", -EBADMSG, 3 },	{ "ldt_extra_data.ldt", -EBADMSG, 59 },
	{ "ldt_gamma_out_of_order.ldt", -EBADMSG, 48 }, { "ldt_nan.ldt", -EBADMSG, 51 },
	{ "ldt_negative_intensity.ldt", -EBADMSG, 54 }, { "ldt_non_numeric.ldt", -EBADMSG, 50 },
	{ "ldt_planes_mismatch.ldt", -EBADMSG, 43 },	{ "ldt_truncated.ldt", -EBADMSG, 53 },
	{ "ldt_wrong_count.ldt", -EBADMSG, 4 },		{ "ldt_zero_flux.ldt", -EBADMSG, 29 },
};

static void eulumdat_malformed_corpus_rejected(void **state)
{
	(void)state;
	for (size_t i = 0; i < sizeof(ldt_corpus) / sizeof(ldt_corpus[0]); i++) {
		struct hl_import_error err = { 0 };
		struct hl_gonio *g = NULL;
		char path[4096], where[4200];

		data_path(path, sizeof(path), "malformed/");
		strcat(path, ldt_corpus[i].file);
		snprintf(where, sizeof(where), "'%s':%d:", path, ldt_corpus[i].line);
		if (hl_eulumdat_read(path, &g, NULL, &err) != ldt_corpus[i].rc ||
		    err.line != ldt_corpus[i].line || strncmp(err.msg, where, strlen(where)) != 0 ||
		    strlen(err.msg) < strlen(where) + 10) {
			fprintf(stderr, "%s: line %d: %s\n", ldt_corpus[i].file, err.line, err.msg);
			fail();
		}
		assert_null(g);
	}
}

/* The corpus' base file (the malformed ones minus their fault) is valid: the faults matter. */
static void eulumdat_corpus_base_is_valid(void **state)
{
	struct hl_import_error err;
	struct hl_gonio *g;
	char path[4096], *text;
	size_t len;
	char *cut;

	(void)state;
	/* ldt_extra_data.ldt is the base plus one line: drop it and the file parses */
	data_path(path, sizeof(path), "malformed/ldt_extra_data.ldt");
	text = slurp(path, &len);
	cut = strstr(text, "\n99\n");
	assert_non_null(cut);
	cut[1] = '\0';
	assert_int_equal(hl_eulumdat_parse(text, strlen(text), path, &g, NULL, &err), 0);
	/* Isym 2, Mc 4: planes C0, C90, C180 stored; flux 1000 lm, factor 1: cd = cd/klm */
	assert_cd(hl_gonio_lookup(g, 90.0, 90.0), 21.0);
	assert_cd(hl_gonio_lookup(g, 270.0, 90.0), 21.0);
	hl_gonio_free(g);
	free(text);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(eulumdat_symmetries_expand_and_scale),
		cmocka_unit_test(eulumdat_on_a_type_a_grid),
		cmocka_unit_test(eulumdat_malformed_corpus_rejected),
		cmocka_unit_test(eulumdat_corpus_base_is_valid),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
