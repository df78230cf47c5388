/* SPDX-License-Identifier: MIT */
/*
 * verdict/suite_plot.c: the SVG parses as XML (python3's xml.etree), a sample lands on the pixel
 * the geometry of verdict/suite_plot.h gives (computed here from its constants), the limit is one
 * horizontal line per bin at y(limit), the stretch over a limit is marked only when the value as
 * judged exceeds it, text is escaped, no "nan" or "inf" is ever written, and the bird's-eye puts
 * the visibility points where one scale for x and y puts them.
 */
#include <ctype.h>
#include <stdbool.h>
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

#include "suite_fixture.h"
#include "testutil.h"
#include "verdict/suite_plot.h"

#define PW (HL_SUITE_PLOT_RIGHT - HL_SUITE_PLOT_LEFT)
#define PH (HL_SUITE_PLOT_BOTTOM - HL_SUITE_PLOT_TOP)

/* The test's own mapping, from the header's description. */
static double px_x(double r, double lo, double hi)
{
	return HL_SUITE_PLOT_LEFT + (r - lo) / (hi - lo) * PW;
}

static double px_y(double lx, double top)
{
	return HL_SUITE_PLOT_BOTTOM -
	       log10(lx / HL_SUITE_PLOT_LX_MIN) / log10(top / HL_SUITE_PLOT_LX_MIN) * PH;
}

/* The SVG as a string (malloc'd): written to a temporary file and read back. */
static char *plot(const struct hl_suite_result *r, const struct hl_suite_variant *v)
{
	FILE *f = tmpfile();
	char *buf;
	long len;

	assert_non_null(f);
	assert_int_equal(hl_suite_plot_svg(r, v, f), 0);
	len = ftell(f);
	assert_true(len > 0);
	rewind(f);
	buf = malloc((size_t)len + 1);
	assert_non_null(buf);
	assert_int_equal(fread(buf, 1, (size_t)len, f), (size_t)len);
	buf[len] = '\0';
	assert_int_equal(fclose(f), 0);
	return buf;
}

/* svg parses as XML with python3's xml.etree (skips the test without python3). */
static void assert_well_formed(const char *svg)
{
	char path[512], cmd[1200];
	FILE *f;

	if (access("/usr/bin/python3", X_OK) != 0)
		fail_msg("/usr/bin/python3 is missing: tools/setup installs it");
	test_path(path, sizeof(path), "plot.svg");
	f = fopen(path, "w");
	assert_non_null(f);
	fputs(svg, f);
	assert_int_equal(fclose(f), 0);
	snprintf(cmd, sizeof(cmd),
		 "env -u LD_PRELOAD /usr/bin/python3 -c 'import sys, xml.etree.ElementTree as E; "
		 "t = E.parse(sys.argv[1]); "
		 "sys.exit(t.getroot().tag != \"{http://www.w3.org/2000/svg}svg\")' '%s'",
		 path);
	assert_int_equal(system(cmd), 0);
	unlink(path);
}

/* No "nan" or "inf" as printf writes them: as a word, not inside one ("illuminance"). */
static void assert_no_nan_inf(const char *svg)
{
	static const char *const bad[] = { "nan", "inf" };

	for (int b = 0; b < 2; b++)
		for (const char *at = strcasestr(svg, bad[b]); at;
		     at = strcasestr(at + 1, bad[b])) {
			const bool in_word = (at > svg && isalpha((unsigned char)at[-1])) ||
					     isalpha((unsigned char)at[3]);

			if (!in_word)
				fail_msg("'%.12s' in the SVG", at > svg + 4 ? at - 4 : at);
		}
}

static int count(const char *s, const char *what)
{
	int n = 0;

	for (const char *at = s; (at = strstr(at, what)); at += strlen(what))
		n++;
	return n;
}

/*
 * The driver photometer approaching from 200 m to 20 m in 10 m steps: under every limit but at
 * 50 and 40 m, where lx_30_59 is written (the 30.0-59.9 m bin's limit is 1.8 lx).
 */
static void approach(struct hl_suite_variant *v, double lx_30_59)
{
	struct hl_suite_series *s = &v->series[0];

	v->range_m[0] = 0.0; /* the axis: 0..200 m in steps of 50 (200 / 8 = 25 -> 50) */
	v->range_m[1] = 200.0;
	for (double r = 200.0; r >= 20.0; r -= 10.0) {
		double lx = r >= 120.0 ? 0.2 : r >= 60.0 ? 0.4 : r >= 30.0 ? 1.0 : 2.0;

		if (r == 50.0 || r == 40.0)
			lx = lx_30_59;
		assert_int_equal(hl_suite_series_add(s, r, lx, (200.0 - r) / 11.0), 0);
	}
}

static void plot_sample_on_its_pixel(void **state)
{
	struct hl_suite *s = fixture_suite();
	struct hl_suite_result r;
	char *svg, want[64];

	(void)state;
	fixture_result(&r, s, 1);
	approach(&r.v[0], 1.0);
	svg = plot(&r, &r.v[0]);
	assert_well_formed(svg);
	/* 30 m, 1 lx: the axis 0..200 m, the top decade 100 lx (the largest value is 3.1 lx) */
	snprintf(want, sizeof(want), " %.1f,%.1f ", px_x(30.0, 0.0, 200.0), px_y(1.0, 100.0));
	assert_string_equal(want, " 167.0,260.0 ");
	assert_non_null(strstr(svg, want));
	/* the first sample opens the line: 200 m, 0.2 lx */
	snprintf(want, sizeof(want), "points=\"%.1f,%.1f ", px_x(200.0, 0.0, 200.0),
		 px_y(0.2, 100.0));
	assert_non_null(strstr(svg, want));
	assert_int_equal(count(svg, "class=\"series\""), 1);
	/* the axes: labelled, the decades 0.01..100 */
	assert_non_null(strstr(svg, ">range (m)</text>"));
	assert_non_null(strstr(svg, ">illuminance (lx)</text>"));
	assert_non_null(strstr(svg, ">0.01</text>"));
	assert_non_null(strstr(svg, ">100</text>"));
	assert_null(strstr(svg, ">1000</text>"));
	assert_non_null(strstr(svg, ">driver</text>"));
	assert_no_nan_inf(svg);
	free(svg);
	hl_suite_result_free(&r);
	free(s);
}

static void plot_limit_is_one_step_per_bin(void **state)
{
	struct hl_suite *s = fixture_suite();
	struct hl_suite_result r;
	const char *at;
	char *svg;
	int n = 0;

	(void)state;
	fixture_result(&r, s, 1);
	approach(&r.v[0], 1.0);
	/* a preceding photometer too: its only bin has no limit, so no line */
	snprintf(r.v[0].series[1].label, sizeof(r.v[0].series[1].label), "tail");
	r.v[0].series[1].role = HL_ROLE_PRECEDING;
	r.v[0].n_series = 2;
	assert_int_equal(hl_suite_series_add(&r.v[0].series[1], 25.0, 0.5, 0.0), 0);
	svg = plot(&r, &r.v[0]);
	assert_well_formed(svg);
	for (at = svg; (at = strstr(at, "<line class=\"limit\"")); at++, n++) {
		double x1, y1, x2, y2;
		char want[128], got[128];

		assert_int_equal(sscanf(at,
					"<line class=\"limit\" x1=\"%lf\" y1=\"%lf\" x2=\"%lf\" "
					"y2=\"%lf\"",
					&x1, &y1, &x2, &y2),
				 4);
		assert_true(n < FIXTURE_N_BINS);
		/* the last bin, 120-220 m, stops at the axis's end */
		snprintf(want, sizeof(want), "%.1f %.1f %.1f %.1f",
			 px_x(fixture_bins[n].from_m, 0.0, 200.0),
			 px_y(fixture_bins[n].max_lx, 100.0),
			 px_x(fmin(fixture_bins[n].to_m, 200.0), 0.0, 200.0),
			 px_y(fixture_bins[n].max_lx, 100.0));
		snprintf(got, sizeof(got), "%.1f %.1f %.1f %.1f", x1, y1, x2, y2);
		assert_string_equal(got, want);
	}
	assert_int_equal(n, FIXTURE_N_BINS);
	assert_int_equal(count(svg, "class=\"limit-riser\""), FIXTURE_N_BINS - 1);
	assert_int_equal(count(svg, "class=\"series\""), 2);
	free(svg);
	hl_suite_result_free(&r);
	free(s);
}

static void plot_marks_stretch_over_limit(void **state)
{
	struct hl_suite *s = fixture_suite();
	struct hl_suite_result r;
	char *svg, want[128];

	(void)state;
	fixture_result(&r, s, 1);
	approach(&r.v[0], 2.5);
	svg = plot(&r, &r.v[0]);
	assert_well_formed(svg);
	assert_int_equal(count(svg, "class=\"over-band\""), 1);
	assert_int_equal(count(svg, "<polyline class=\"over\""), 1);
	snprintf(want, sizeof(want), "points=\"%.1f,%.1f %.1f,%.1f\"", px_x(50.0, 0.0, 200.0),
		 px_y(2.5, 100.0), px_x(40.0, 0.0, 200.0), px_y(2.5, 100.0));
	assert_non_null(strstr(strstr(svg, "<polyline class=\"over\""), want));
	assert_non_null(strstr(svg, ">over the limit</text>"));
	free(svg);
	hl_suite_result_free(&r);
	free(s);
}

static void plot_no_mark_within_limit(void **state)
{
	struct hl_suite *s = fixture_suite();
	struct hl_suite_result r;
	char *svg;

	(void)state;
	fixture_result(&r, s, 1);
	approach(&r.v[0], 1.84); /* as judged (one decimal, half-even) 1.8: not over 1.8 */
	svg = plot(&r, &r.v[0]);
	assert_well_formed(svg);
	assert_null(strstr(svg, "class=\"over"));
	assert_non_null(strstr(svg, ">over the limit: none</text>"));
	free(svg);
	hl_suite_result_free(&r);
	free(s);

	/* 1.86 is 1.9: over */
	s = fixture_suite();
	fixture_result(&r, s, 1);
	approach(&r.v[0], 1.86);
	svg = plot(&r, &r.v[0]);
	assert_int_equal(count(svg, "<polyline class=\"over\""), 1);
	free(svg);
	hl_suite_result_free(&r);
	free(s);
}

static void plot_escapes_text(void **state)
{
	struct hl_suite *s = fixture_suite();
	struct hl_suite_result r;
	char *svg;

	(void)state;
	fixture_result(&r, s, 1);
	snprintf(r.v[0].title, sizeof(r.v[0].title), "a <b> & \"c\"");
	snprintf(r.v[0].series[0].label, sizeof(r.v[0].series[0].label), "x<y");
	approach(&r.v[0], 1.0);
	svg = plot(&r, &r.v[0]);
	assert_well_formed(svg);
	assert_non_null(strstr(svg, "a &lt;b&gt; &amp; &quot;c&quot;"));
	assert_null(strstr(svg, "<b>"));
	assert_non_null(strstr(svg, ">x&lt;y</text>"));
	free(svg);
	hl_suite_result_free(&r);
	free(s);
}

/* No series, an empty series, all NaN, values past any axis: a plot still, finite numbers only. */
static void plot_hostile_values_stay_finite(void **state)
{
	static const double odd[] = { NAN, INFINITY, -INFINITY, 1e300, -1e300, 0.0, -5.0, 1e-300 };
	struct hl_suite *s = fixture_suite();
	struct hl_suite_result r;
	char *svg;

	(void)state;
	fixture_result(&r, s, 5);
	/* 0: no series, 1: a series without samples */
	r.v[0].n_series = 0;
	/* 2: every value NaN, and the range NaN too */
	r.v[2].range_m[0] = NAN;
	for (int i = 0; i < 10; i++)
		assert_int_equal(hl_suite_series_add(&r.v[2].series[0], NAN, NAN, NAN), 0);
	/* 3: every odd value against every odd range */
	for (size_t i = 0; i < sizeof(odd) / sizeof(odd[0]); i++)
		for (size_t j = 0; j < sizeof(odd) / sizeof(odd[0]); j++)
			assert_int_equal(hl_suite_series_add(&r.v[3].series[0], odd[i], odd[j], 0),
					 0);
	r.v[3].speed_mph = NAN;
	r.v[3].radius_m = INFINITY;
	/* 4: a huge range and illuminance: the axis tops out at LX_TOP_MAX */
	r.v[4].range_m[0] = -1e300;
	r.v[4].range_m[1] = 1e300;
	for (int i = 0; i < 10; i++)
		assert_int_equal(hl_suite_series_add(&r.v[4].series[0], i * 1e299, 1e200, 0), 0);
	for (int i = 0; i < 5; i++) {
		svg = plot(&r, &r.v[i]);
		assert_well_formed(svg);
		assert_no_nan_inf(svg);
		assert_non_null(strstr(svg, "</svg>\n"));
		if (i == 0)
			assert_non_null(strstr(svg, ">no series</text>"));
		if (i == 1)
			assert_non_null(strstr(svg, ">driver (no samples)</text>"));
		if (i == 4)
			assert_non_null(strstr(svg, ">1e6</text>"));
		free(svg);
	}
	/* a bird's-eye without points */
	r.v[0].has_birdseye = true;
	r.v[0].birdseye.vis_m[0] = r.v[0].birdseye.vis_m[1] = NAN;
	r.v[0].birdseye.ego[0] = NAN;
	svg = plot(&r, &r.v[0]);
	assert_well_formed(svg);
	assert_no_nan_inf(svg);
	free(svg);
	hl_suite_result_free(&r);
	free(s);
}

static void plot_birdseye_one_scale(void **state)
{
	struct hl_suite *s = fixture_suite();
	struct hl_suite_result r;
	struct hl_suite_birdseye *be;
	char *svg, want[128];
	double sc, cx, cy;

	(void)state;
	s->procedure = HL_SUITE_IIHS;
	s->visibility_lx = 5.0;
	s->visibility_height_m = 0.25;
	fixture_result(&r, s, 1);
	r.v[0].has_birdseye = true;
	r.v[0].n_series = 0;
	be = &r.v[0].birdseye;
	/* a straight road north: edges at x -5 and 2, 0..200 m; the ego at the origin heading north */
	be->n = 21;
	be->left = calloc(21, sizeof(*be->left));
	be->right = calloc(21, sizeof(*be->right));
	assert_non_null(be->left);
	assert_non_null(be->right);
	for (int i = 0; i < 21; i++) {
		be->left[i][0] = -5.0;
		be->right[i][0] = 2.0;
		be->left[i][1] = be->right[i][1] = 10.0 * i;
	}
	be->ego_heading_rad = M_PI / 2.0;
	be->vis_m[0] = 85.3;
	be->vis_at[0][0] = -5.0;
	be->vis_at[0][1] = 85.3;
	be->vis_m[1] = NAN;
	svg = plot(&r, &r.v[0]);
	assert_well_formed(svg);
	assert_no_nan_inf(svg);
	/* the box: x -5..2 (less than 10 m: 10), y 0..200, padded; one scale, the smaller */
	sc = fmin(PW / (10.0 * (1.0 + 2.0 * HL_SUITE_PLOT_PAD)),
		  PH / (200.0 * (1.0 + 2.0 * HL_SUITE_PLOT_PAD)));
	cx = -1.5;
	cy = 100.0;
	snprintf(want, sizeof(want), "class=\"vis\" data-edge=\"left\" cx=\"%.1f\" cy=\"%.1f\"",
		 HL_SUITE_PLOT_LEFT + PW / 2.0 + (-5.0 - cx) * sc,
		 HL_SUITE_PLOT_TOP + PH / 2.0 - (85.3 - cy) * sc);
	assert_non_null(strstr(svg, want));
	/* the edges: the left one from (-5, 0) north, the right 7 m east of it at the same scale */
	snprintf(want, sizeof(want), "points=\"%.1f,%.1f %.1f,%.1f ",
		 HL_SUITE_PLOT_LEFT + PW / 2.0 + (-5.0 - cx) * sc,
		 HL_SUITE_PLOT_TOP + PH / 2.0 - (0.0 - cy) * sc,
		 HL_SUITE_PLOT_LEFT + PW / 2.0 + (-5.0 - cx) * sc,
		 HL_SUITE_PLOT_TOP + PH / 2.0 - (10.0 - cy) * sc);
	assert_non_null(strstr(strstr(svg, "data-edge=\"left\" fill"), want));
	snprintf(want, sizeof(want), "points=\"%.1f,%.1f ",
		 HL_SUITE_PLOT_LEFT + PW / 2.0 + (2.0 - cx) * sc,
		 HL_SUITE_PLOT_TOP + PH / 2.0 - (0.0 - cy) * sc);
	assert_non_null(strstr(strstr(svg, "data-edge=\"right\" fill"), want));
	assert_int_equal(count(svg, "class=\"edge\""), 2);
	assert_non_null(strstr(svg, "left edge: 85.3 m"));
	assert_non_null(strstr(svg, "right edge: not reached"));
	assert_null(strstr(svg, "data-edge=\"right\" cx"));
	assert_non_null(strstr(svg, "class=\"ego\""));
	assert_non_null(strstr(svg, "class=\"scale\""));
	assert_null(strstr(svg, "class=\"series\""));
	free(svg);
	hl_suite_result_free(&r);
	free(s);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(plot_sample_on_its_pixel),
		cmocka_unit_test(plot_limit_is_one_step_per_bin),
		cmocka_unit_test(plot_marks_stretch_over_limit),
		cmocka_unit_test(plot_no_mark_within_limit),
		cmocka_unit_test(plot_escapes_text),
		cmocka_unit_test(plot_hostile_values_stay_finite),
		cmocka_unit_test(plot_birdseye_one_scale),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
