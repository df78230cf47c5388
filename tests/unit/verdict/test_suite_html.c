/* SPDX-License-Identifier: MIT */
/*
 * verdict/suite_html.c: index.html is one file that fetches nothing (no script, no stylesheet
 * link, no image source), holds the summary linking each variant's anchor, the PASS or FAIL
 * badge as hl_suite_result_passed says, the cases with their numbers, the plots as inline SVG,
 * the links to traces and scenarios, every text escaped; a directory that is not there is
 * -ENOENT and leaves nothing.
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
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "dir_util.h" /* list_dir */
#include "suite_fixture.h"
#include "testutil.h"

static char *slurp(const char *path)
{
	FILE *f = fopen(path, "r");
	char *buf;
	long n;

	assert_non_null(f);
	assert_int_equal(fseek(f, 0, SEEK_END), 0);
	n = ftell(f);
	assert_true(n > 0);
	rewind(f);
	buf = malloc((size_t)n + 1);
	assert_non_null(buf);
	assert_int_equal(fread(buf, 1, (size_t)n, f), (size_t)n);
	buf[n] = '\0';
	fclose(f);
	return buf;
}

/* Writes r as DIR/index.html in a fresh directory; the page, and the directory's listing. */
static char *written(const struct hl_suite_result *r, char *listing, size_t size)
{
	char dir[512], path[600];
	char *html;

	test_path(dir, sizeof(dir), "html");
	assert_int_equal(mkdir(dir, 0755), 0);
	snprintf(path, sizeof(path), "%s/index.html", dir);
	assert_int_equal(hl_suite_html_write(r, path), 0);
	list_dir(dir, listing, size);
	html = slurp(path);
	unlink(path);
	rmdir(dir);
	return html;
}

static void assert_fetches_nothing(const char *html)
{
	assert_null(strstr(html, "<script"));
	assert_null(strstr(html, "<link"));
	assert_null(strstr(html, "<img"));
	assert_null(strstr(html, "<iframe"));
	assert_null(strstr(html, " src="));
	assert_null(strstr(html, "href=\"http"));
	assert_null(strstr(html, "href=\"//"));
	assert_null(strstr(html, "url("));
	assert_null(strstr(html, "@import"));
}

static void html_page_of_passing_run(void **state)
{
	struct hl_suite *s = fixture_suite();
	struct hl_suite_result r;
	char listing[256], *html;

	(void)state;
	fixture_result(&r, s, 2);
	html = written(&r, listing, sizeof(listing));
	assert_string_equal(listing, "index.html");
	assert_true(strncmp(html, "<!DOCTYPE html>\n", 16) == 0);
	assert_fetches_nothing(html);
	assert_non_null(strstr(html, "<style>"));
	assert_non_null(
		strstr(html, "<h1>FMVSS 108 ADB track test <span class=\"badge pass\">PASS"));
	assert_null(strstr(html, ">FAIL<"));
	assert_non_null(strstr(html, "49 CFR 571.108 S14.9.3.11, Table XXI"));
	assert_non_null(strstr(html, "<dt>ECU</dt><dd>reference</dd>"));
	/* the totals: 8 cases, 8 judged, none failed */
	assert_non_null(strstr(html, "<td class=\"num\">8</td><td class=\"num\">8</td>"
				     "<td class=\"num\">0</td><td class=\"num\">0</td>"
				     "<td class=\"num\">0</td>"));
	for (int i = 0; i < 2; i++) {
		char want[128];

		snprintf(want, sizeof(want), "<a href=\"#v-oncoming-straight-%d\">", i);
		assert_non_null(strstr(html, want));
		snprintf(want, sizeof(want), "<section id=\"v-oncoming-straight-%d\">", i);
		assert_non_null(strstr(html, want));
		snprintf(want, sizeof(want), "<a href=\"oncoming-straight-%d.log\">", i);
		assert_non_null(strstr(html, want));
		snprintf(want, sizeof(want), "<a href=\"oncoming-straight-%d.json\">", i);
		assert_non_null(strstr(html, want));
	}
	/* the plots inline, without their XML declarations */
	assert_int_equal((int)(strstr(strstr(html, "<svg") + 1, "<svg") != NULL), 1);
	assert_null(strstr(html, "<?xml"));
	/* the defaults, escaped */
	assert_non_null(strstr(html, "<td>photometer height</td><td>1.1 m</td><td>driver's eye, "
				     "a &lt;guess&gt; &amp; &quot;typical&quot;</td>"));
	/* a case: 15.0-29.9 m, 1.55 raw, 1.6 as judged, 3.1 limit, 1.5 margin */
	assert_non_null(strstr(html, "<td class=\"num\">15.0&#8211;29.9 m</td><td class=\"num\">10"
				     "</td><td class=\"num\">1.55 lx</td><td class=\"num\">1.6 lx"
				     "</td><td class=\"num\">&#8804; 3.1 lx</td><td class=\"num\">"
				     "1.5 lx</td><td class=\"num\">15.0 m</td>"
				     "<td class=\"result\">pass</td>"));
	free(html);
	hl_suite_result_free(&r);
	free(s);
}

static void html_fail_badge_and_failing_row(void **state)
{
	struct hl_suite *s = fixture_suite();
	struct hl_suite_result r;
	char listing[256], *html;

	(void)state;
	fixture_result(&r, s, 2);
	r.v[1].cases[1] = fixture_case(1, 2.46, 42.0);
	r.v[1].cases[3] = fixture_case(3, NAN, NAN);
	r.v[0].exit_code = 1;
	snprintf(r.v[0].error, sizeof(r.v[0].error), "the ECU <stopped> answering");
	r.preset[0] = '\0';
	r.ecu[0] = '\0';
	snprintf(r.preset, sizeof(r.preset), "held-low");
	snprintf(r.fault, sizeof(r.fault), "stuck-frame");
	html = written(&r, listing, sizeof(listing));
	assert_string_equal(listing, "index.html");
	assert_fetches_nothing(html);
	assert_non_null(strstr(html, "<span class=\"badge fail\">FAIL</span></h1>"));
	assert_non_null(strstr(html, "<dt>preset</dt><dd>held-low</dd>"));
	assert_non_null(strstr(html, "<dt>fault</dt><dd>stuck-frame</dd>"));
	/* 8 cases, 7 judged, 1 failed, 1 without samples, 1 run that did not finish */
	assert_non_null(strstr(html, "<td class=\"num\">8</td><td class=\"num\">7</td>"
				     "<td class=\"num\">1</td><td class=\"num\">1</td>"
				     "<td class=\"num\">1</td>"));
	assert_non_null(strstr(html, "<td class=\"result\">ERROR</td>"));
	assert_non_null(strstr(html, "<dd class=\"error\">the ECU &lt;stopped&gt; answering</dd>"));
	/* the failing case: 2.46 raw, 2.5 as judged over 1.8, margin -0.7 at 42.0 m */
	assert_non_null(strstr(html, "<tr class=\"fail\"><td>oncoming 30.0-59.9 m, photometer "
				     "driver</td>"));
	assert_non_null(strstr(html,
			       "<td class=\"num\">2.46 lx</td><td class=\"num\">2.5 lx</td>"
			       "<td class=\"num\">&#8804; 1.8 lx</td><td class=\"num\">-0.7 lx"
			       "</td><td class=\"num\">42.0 m</td><td class=\"result\">FAIL"
			       "</td>"));
	assert_non_null(strstr(html, "<tr class=\"nosamples\">"));
	assert_non_null(strstr(html, "<td class=\"result\">no samples</td>"));
	assert_non_null(strstr(html, "<section id=\"v-oncoming-straight-1\">"));
	free(html);
	hl_suite_result_free(&r);
	free(s);
}

static void html_escapes_titles(void **state)
{
	struct hl_suite *s = fixture_suite();
	struct hl_suite_result r;
	char listing[256], *html;

	(void)state;
	snprintf(s->title, sizeof(s->title), "Suite <i>\"A&B\"</i>");
	fixture_result(&r, s, 1);
	snprintf(r.v[0].title, sizeof(r.v[0].title), "<script>alert(1)</script>");
	snprintf(r.v[0].id, sizeof(r.v[0].id), "odd id\"><b");
	snprintf(r.v[0].trace_file, sizeof(r.v[0].trace_file), "a\"b.log");
	html = written(&r, listing, sizeof(listing));
	assert_fetches_nothing(html);
	assert_null(strstr(html, "<i>"));
	assert_null(strstr(html, "id\"><b"));
	assert_non_null(strstr(html, "<dd>odd id&quot;&gt;&lt;b</dd>"));
	assert_non_null(
		strstr(html, "<title>Suite &lt;i&gt;&quot;A&amp;B&quot;&lt;/i&gt;</title>"));
	assert_non_null(strstr(html, "&lt;script&gt;alert(1)&lt;/script&gt;"));
	/* the anchor from the id: only [A-Za-z0-9_-] */
	assert_non_null(strstr(html, "<section id=\"v-odd_id___b\">"));
	assert_non_null(strstr(html, "<a href=\"#v-odd_id___b\">"));
	assert_non_null(strstr(html, "<a href=\"a&quot;b.log\">"));
	free(html);
	hl_suite_result_free(&r);
	free(s);
}

static void html_missing_directory_leaves_nothing(void **state)
{
	struct hl_suite *s = fixture_suite();
	struct hl_suite_result r;
	char dir[512], path[700], listing[256];

	(void)state;
	fixture_result(&r, s, 1);
	test_path(dir, sizeof(dir), "html-parent");
	assert_int_equal(mkdir(dir, 0755), 0);
	snprintf(path, sizeof(path), "%s/not-there/index.html", dir);
	assert_int_equal(hl_suite_html_write(&r, path), -ENOENT);
	list_dir(dir, listing, sizeof(listing));
	assert_string_equal(listing, "");
	assert_int_equal(rmdir(dir), 0);
	hl_suite_result_free(&r);
	free(s);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(html_page_of_passing_run),
		cmocka_unit_test(html_fail_badge_and_failing_row),
		cmocka_unit_test(html_escapes_titles),
		cmocka_unit_test(html_missing_directory_leaves_nothing),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
