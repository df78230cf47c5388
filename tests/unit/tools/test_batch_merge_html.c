/* SPDX-License-Identifier: MIT */
/*
 * tools/batch_merge_html.c: the merged page of hdlamp batch says PASSED only when every task
 * passed, FAILED or ERRORS otherwise; holds the totals, a table per grouping (or "no task ran by
 * ..."), the worst margins linked to each task's page and plots, the loop latency in ms, the
 * errors linked to each task's folder and "and K more" past the listed ones; every string from
 * users' files escaped (and read back as the same text by libxml2's HTML parser, without a parse
 * error); a path that cannot be written is -errno and leaves nothing.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>
#include <libxml/HTMLparser.h>
#include <libxml/tree.h>
#include <libxml/xmlerror.h>

#include "dir_util.h" /* list_dir */
#include "testutil.h"
#include "tools/batch.h"

static const char error_id[] = "sil/<script>alert(1)</script>/reference";
static const char error_reason[] = "exit 1: \"can't open\" <script>x</script> & 'more'";
static const char error_id2[] = "drive/a&b\"c";
static const char error_reason2[] = "no result.json: the folder is empty & <b>bold</b>";

/* A summary with two groups per grouping, three worst margins (one over the limit), a loop
 * latency, and 2 of its 4 errors listed. */
struct fixture {
	struct hl_batch_summary s;
	struct hl_batch_group suite[2], scenario[2], ecu[2], preset[2];
	struct hl_batch_error err[2];
};

static void group(struct hl_batch_group *g, const char *key, unsigned passed, unsigned failed,
		  unsigned errors)
{
	snprintf(g->key, sizeof(g->key), "%s", key);
	g->passed = passed;
	g->failed = failed;
	g->errors = errors;
}

static void worst(struct hl_batch_worst *w, unsigned index, const char *id, const char *name,
		  double margin_lx)
{
	w->index = index;
	snprintf(w->id, sizeof(w->id), "%s", id);
	snprintf(w->case_name, sizeof(w->case_name), "%s", name);
	w->margin_lx = margin_lx;
}

static void error(struct hl_batch_error *e, unsigned index, const char *id, const char *reason)
{
	e->index = index;
	snprintf(e->id, sizeof(e->id), "%s", id);
	snprintf(e->reason, sizeof(e->reason), "%s", reason);
}

static void fixture_failed(struct fixture *x)
{
	struct hl_batch_summary *s = &x->s;

	memset(x, 0, sizeof(*x));
	s->tasks = 12;
	s->passed = 7;
	s->failed = 1;
	s->errors = 4;
	s->tests = 340;
	s->test_failures = 3;
	s->test_errors = 4;
	group(&x->suite[0], "fmvss108-adb", 4, 1, 1);
	group(&x->suite[1], "r149-adb", 3, 0, 0);
	group(&x->scenario[0], "iihs-approach-straight", 0, 0, 2);
	group(&x->scenario[1], "night-01", 0, 0, 1);
	group(&x->ecu[0], "reference", 6, 1, 3);
	group(&x->ecu[1], "naive", 1, 0, 1);
	group(&x->preset[0], "high", 2, 0, 0);
	group(&x->preset[1], "held-low", 1, 0, 1);
	s->by_suite = x->suite;
	s->by_scenario = x->scenario;
	s->by_ecu = x->ecu;
	s->by_preset = x->preset;
	s->n_suite = s->n_scenario = s->n_ecu = s->n_preset = 2;
	worst(&s->worst[0], 7, "suite/fmvss108-adb/preceding-straight-60mph/reference/none",
	      "oncoming 30.0-59.9 m, photometer driver", -0.42);
	worst(&s->worst[1], 3, "suite/fmvss108-adb/oncoming-straight-40mph/reference/none",
	      "oncoming 60.0-119.9 m, photometer passenger", 0.125);
	worst(&s->worst[2], 11, "suite/r149-adb/preceding-left/reference/none",
	      "preceding 50 m, B50L", 1.5);
	s->n_worst = 3;
	s->latency_tasks = 5;
	s->p50_of_p50 = 1.2344;
	s->p50_of_p99 = 2.5;
	s->p99_of_p99 = 4.0001;
	s->max_of_max = 12.75;
	error(&x->err[0], 4, error_id, error_reason);
	error(&x->err[1], 9, error_id2, error_reason2);
	s->errors_list = x->err;
	s->n_errors_list = 2;
}

/* Everything passed: one group per grouping, no error. */
static void fixture_passed(struct fixture *x)
{
	fixture_failed(x);
	x->s.passed = x->s.tasks;
	x->s.failed = x->s.errors = 0;
	x->s.test_failures = x->s.test_errors = 0;
	x->s.n_suite = x->s.n_scenario = x->s.n_ecu = x->s.n_preset = 1;
	x->suite[0].failed = x->suite[0].errors = 0;
	x->scenario[0].passed = 2;
	x->scenario[0].errors = 0;
	x->ecu[0].failed = x->ecu[0].errors = 0;
	x->s.worst[0].margin_lx = 0.01;
	x->s.n_errors_list = 0;
}

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

static void count_error(void *ctx, xmlErrorPtr e)
{
	(void)e;
	++*(int *)ctx;
}

/* Writes s as DIR/index.html in a fresh directory with prefix "tasks/"; the page's text. When
 * ret_doc is given, also the page as libxml2's HTML parser reads it and its count of errors. */
static char *written(const struct hl_batch_summary *s, htmlDocPtr *ret_doc, int *ret_parse_errors)
{
	char dir[512], path[600], listing[256];
	char *html;

	test_path(dir, sizeof(dir), "batch-html");
	assert_int_equal(mkdir(dir, 0755), 0);
	snprintf(path, sizeof(path), "%s/index.html", dir);
	assert_int_equal(hl_batch_html_write(s, "tasks/", path), 0);
	list_dir(dir, listing, sizeof(listing));
	assert_string_equal(listing, "index.html");
	html = slurp(path);
	if (ret_doc) {
		*ret_parse_errors = 0;
		xmlSetStructuredErrorFunc(ret_parse_errors, count_error);
		*ret_doc = htmlReadFile(path, "utf-8", HTML_PARSE_NONET);
		xmlSetStructuredErrorFunc(NULL, NULL);
		assert_non_null(*ret_doc);
	}
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

static int count_of(const char *html, const char *what)
{
	int n = 0;

	for (const char *p = strstr(html, what); p; p = strstr(p + 1, what))
		n++;
	return n;
}

static void batch_html_failed_run(void **state)
{
	struct fixture x;
	char *html;

	(void)state;
	fixture_failed(&x);
	html = written(&x.s, NULL, NULL);
	assert_true(strncmp(html, "<!DOCTYPE html>\n", 16) == 0);
	assert_fetches_nothing(html);
	assert_non_null(strstr(html, "<style>"));
	assert_non_null(strstr(html, "<title>hdlamp batch: FAILED</title>"));
	assert_non_null(strstr(html, "<h1>hdlamp batch <span class=\"badge fail\">FAILED</span>"));
	assert_null(strstr(html, "PASSED"));
	assert_non_null(strstr(html, "12 tasks: 7 passed, 1 failed, <span class=\"error\">4 ended "
				     "in error</span>."));
	assert_null(strstr(html, "do not add up"));
	/* the totals: tasks, then the JUnit test cases (340 - 3 - 4 passed) */
	assert_non_null(strstr(html, "<td>tasks</td><td class=\"num\">12</td><td class=\"num\">7"
				     "</td><td class=\"num\">1</td><td class=\"num\">4</td>"));
	assert_non_null(strstr(html, "<td>JUnit test cases</td><td class=\"num\">340</td><td "
				     "class=\"num\">333</td><td class=\"num\">3</td><td "
				     "class=\"num\">4</td>"));
	/* a table per grouping, rows with their sum and their bar */
	assert_int_equal(count_of(html, "<table class=\"groups\">"), 4);
	assert_null(strstr(html, "No task ran by"));
	assert_non_null(strstr(html,
			       "<tr class=\"fail\"><td class=\"id\">fmvss108-adb</td><td "
			       "class=\"num\">6</td><td class=\"num\">4</td><td "
			       "class=\"num\">1</td><td class=\"num\">1</td><td class=\"bar\">"
			       "<div class=\"bar\" title=\"4 passed, 1 failed, 1 errors\">"
			       "<span class=\"p\" style=\"width:66.67%\"></span><span "
			       "class=\"f\" style=\"width:16.67%\"></span><span class=\"e\" "
			       "style=\"width:16.67%\"></span></div></td></tr>"));
	assert_non_null(strstr(html, "<tr class=\"pass\"><td class=\"id\">r149-adb</td><td "
				     "class=\"num\">3</td><td class=\"num\">3</td><td "
				     "class=\"num\">0</td><td class=\"num\">0</td>"));
	assert_non_null(strstr(html, "<tr class=\"error\"><td class=\"id\">night-01</td>"));
	assert_non_null(strstr(html, "<th>ECU</th>"));
	assert_non_null(strstr(html, ">held-low</td>"));
	/* the worst margins, linked to each task's page and plots */
	assert_non_null(strstr(html, "<tr class=\"fail\"><td class=\"num\">7</td><td class=\"id\">"
				     "<a href=\"tasks/7/index.html\">suite/fmvss108-adb/"
				     "preceding-straight-60mph/reference/none</a></td><td>oncoming "
				     "30.0-59.9 m, photometer driver</td><td class=\"num\">-0.42 lx"
				     "</td><td class=\"over\">over the limit</td><td><a "
				     "href=\"tasks/7/plots/\">plots</a></td></tr>"));
	assert_non_null(strstr(html, "<a href=\"tasks/3/index.html\">"));
	assert_non_null(strstr(html, "<td class=\"num\">+0.125 lx</td><td>within</td>"));
	assert_non_null(strstr(html, "<td class=\"num\">+1.5 lx</td><td>within</td>"));
	assert_int_equal(count_of(html, "over the limit"), 1);
	/* the loop latency in ms */
	assert_non_null(strstr(html, "<tr><td class=\"num\">5</td><td class=\"num\">1.234 ms</td>"
				     "<td class=\"num\">2.500 ms</td><td class=\"num\">4.000 ms"
				     "</td><td class=\"num\">12.750 ms</td></tr>"));
	assert_null(strstr(html, "No task with a loop"));
	/* the errors, linked to the tasks' folders, and the ones not listed */
	assert_non_null(
		strstr(html, "<td class=\"num\">4</td><td class=\"id\"><a href=\"tasks/4/\">"));
	assert_non_null(strstr(html, "<a href=\"tasks/9/\">"));
	assert_non_null(strstr(html, "and 2 more: see the merged JUnit/JSON."));
	free(html);
}

static void batch_html_escapes_users_strings(void **state)
{
	struct fixture x;
	char *html;

	(void)state;
	fixture_failed(&x);
	snprintf(x.suite[1].key, sizeof(x.suite[1].key), "<i>r149</i> & \"co\"");
	snprintf(x.s.worst[1].case_name, sizeof(x.s.worst[1].case_name), "<b>B50L</b>");
	html = written(&x.s, NULL, NULL);
	assert_fetches_nothing(html);
	assert_null(strstr(html, "<i>"));
	assert_null(strstr(html, "<b>"));
	assert_non_null(strstr(html, "<a href=\"tasks/4/\">sil/&lt;script&gt;alert(1)&lt;/script"
				     "&gt;/reference</a></td><td class=\"reason\">exit 1: "
				     "&quot;can't open&quot; &lt;script&gt;x&lt;/script&gt; &amp; "
				     "'more'</td>"));
	assert_non_null(strstr(html, ">drive/a&amp;b&quot;c</a>"));
	assert_non_null(strstr(html, "the folder is empty &amp; &lt;b&gt;bold&lt;/b&gt;</td>"));
	assert_non_null(strstr(html, "<td class=\"id\">&lt;i&gt;r149&lt;/i&gt; &amp; &quot;co"
				     "&quot;</td>"));
	assert_non_null(strstr(html, "<td>&lt;b&gt;B50L&lt;/b&gt;</td>"));
	free(html);
}

static void collect(xmlNodePtr n, const char *name, xmlNodePtr *out, int *count, int max)
{
	for (; n; n = n->next) {
		if (n->type == XML_ELEMENT_NODE && xmlStrcasecmp(n->name, BAD_CAST name) == 0) {
			if (*count < max)
				out[*count] = n;
			++*count;
		}
		collect(n->children, name, out, count, max);
	}
}

static int elements(htmlDocPtr doc, const char *name, xmlNodePtr *out, int max)
{
	int n = 0;

	collect(xmlDocGetRootElement(doc), name, out, &n, max);
	return n;
}

static bool has_text(htmlDocPtr doc, const char *name, const char *want)
{
	xmlNodePtr nodes[512];
	const int n = elements(doc, name, nodes, 512);
	bool found = false;

	assert_true(n <= 512);
	for (int i = 0; i < n && !found; i++) {
		xmlChar *t = xmlNodeGetContent(nodes[i]);

		found = t && strcmp((const char *)t, want) == 0;
		xmlFree(t);
	}
	return found;
}

static void batch_html_parses_back_to_the_same_text(void **state)
{
	struct fixture x;
	xmlNodePtr nodes[64];
	htmlDocPtr doc;
	int parse_errors, n, links = 0;
	char *html;

	(void)state;
	fixture_failed(&x);
	html = written(&x.s, &doc, &parse_errors);
	assert_int_equal(parse_errors, 0);
	/* totals, 4 groupings, worst margins, latency, errors */
	assert_int_equal(elements(doc, "table", nodes, 64), 8);
	assert_int_equal(elements(doc, "script", nodes, 64), 0);
	assert_int_equal(elements(doc, "h1", nodes, 64), 1);
	/* what the users wrote, read back as text */
	assert_true(has_text(doc, "a", error_id));
	assert_true(has_text(doc, "td", error_reason));
	assert_true(has_text(doc, "a", error_id2));
	assert_true(has_text(doc, "td", error_reason2));
	assert_true(has_text(doc, "td", "-0.42 lx"));
	/* every link is a task's page, plots or folder, or an anchor of the page */
	n = elements(doc, "a", nodes, 64);
	assert_true(n > 0 && n <= 64);
	for (int i = 0; i < n; i++) {
		xmlChar *href = xmlGetProp(nodes[i], BAD_CAST "href");
		const char *h = (const char *)href;

		assert_non_null(href);
		assert_true(h[0] == '#' || strncmp(h, "tasks/", 6) == 0);
		links += strcmp(h, "tasks/7/index.html") == 0 || strcmp(h, "tasks/4/") == 0;
		xmlFree(href);
	}
	assert_int_equal(links, 2);
	xmlFreeDoc(doc);
	free(html);
}

static void batch_html_all_passed(void **state)
{
	struct fixture x;
	htmlDocPtr doc;
	int parse_errors;
	char *html;

	(void)state;
	fixture_passed(&x);
	html = written(&x.s, &doc, &parse_errors);
	assert_int_equal(parse_errors, 0);
	assert_fetches_nothing(html);
	assert_non_null(strstr(html, "<title>hdlamp batch: PASSED</title>"));
	assert_non_null(strstr(html, "<span class=\"badge pass\">PASSED</span>"));
	assert_null(strstr(html, "FAILED"));
	assert_null(strstr(html, "ERRORS"));
	assert_non_null(strstr(html, "12 tasks: 12 passed, 0 failed, 0 ended in error."));
	assert_non_null(strstr(html, "No task ended in error."));
	assert_null(strstr(html, "over the limit"));
	assert_null(strstr(html, "more: see"));
	assert_int_equal(count_of(html, "<table class=\"groups\">"), 4);
	xmlFreeDoc(doc);
	free(html);
}

/* No failure, but errors (or no task at all, or counts that do not add up): ERRORS, not
 * PASSED, and no error left out. */
static void batch_html_errors_without_failures(void **state)
{
	struct fixture x;
	char *html;

	(void)state;
	fixture_passed(&x);
	x.s.passed = 10;
	x.s.errors = 2;
	x.s.errors_list = x.err;
	x.s.n_errors_list = 2;
	html = written(&x.s, NULL, NULL);
	assert_non_null(strstr(html, "<span class=\"badge error\">ERRORS</span>"));
	assert_non_null(strstr(html, "<a href=\"tasks/9/\">"));
	assert_null(strstr(html, "more: see"));
	free(html);

	x.s.errors = 0;
	x.s.n_errors_list = 0;
	html = written(&x.s, NULL, NULL);
	assert_non_null(strstr(html, "<span class=\"badge error\">ERRORS</span>"));
	assert_non_null(strstr(html, "The counts do not add up: 10 passed + 0 failed + 0 errors "
				     "make 10, not the 12 tasks."));
	free(html);

	/* errors beyond the list, none listed */
	x.s.errors = 2;
	x.s.n_errors_list = 0;
	x.s.errors_list = NULL;
	html = written(&x.s, NULL, NULL);
	assert_non_null(strstr(html, "and 2 more: see the merged JUnit/JSON."));
	assert_null(strstr(html, "<table class=\"errors\">"));
	free(html);

	memset(&x.s, 0, sizeof(x.s));
	html = written(&x.s, NULL, NULL);
	assert_non_null(strstr(html, "<span class=\"badge error\">ERRORS</span>"));
	assert_non_null(strstr(html, "No task ran.</p>"));
	assert_null(strstr(html, "PASSED"));
	free(html);
}

static void batch_html_empty_groupings_and_no_loop(void **state)
{
	struct fixture x;
	htmlDocPtr doc;
	int parse_errors;
	xmlNodePtr nodes[64];
	char *html;

	(void)state;
	fixture_failed(&x);
	x.s.n_preset = 0;
	x.s.by_preset = NULL;
	/* groups with an empty key are not listed: a grouping of only those is none */
	x.scenario[0].key[0] = x.scenario[1].key[0] = '\0';
	x.ecu[1].key[0] = '\0';
	x.s.latency_tasks = 0;
	x.s.n_worst = 0;
	html = written(&x.s, &doc, &parse_errors);
	assert_int_equal(parse_errors, 0);
	assert_non_null(strstr(html, "No task ran by preset."));
	assert_non_null(strstr(html, "No task ran by scenario."));
	assert_null(strstr(html, "No task ran by suite."));
	assert_null(strstr(html, "No task ran by ECU."));
	assert_null(strstr(html, "naive"));
	assert_non_null(strstr(html, "No task with a loop."));
	assert_non_null(strstr(html, "No task reported a margin."));
	/* totals, suite, ECU, errors */
	assert_int_equal(elements(doc, "table", nodes, 64), 4);
	xmlFreeDoc(doc);
	free(html);
}

/* A UTF-8 sequence cut by the struct's fixed size is U+FFFD, not a broken byte. */
static void batch_html_cut_utf8_is_a_replacement(void **state)
{
	struct fixture x;
	char *html;

	(void)state;
	fixture_failed(&x);
	snprintf(x.err[0].reason, sizeof(x.err[0].reason), "Stra\xc3\xa1\x65 \xe2\x82");
	snprintf(x.suite[0].key, sizeof(x.suite[0].key), "\xff\xc0\xafok");
	html = written(&x.s, NULL, NULL);
	assert_non_null(strstr(html, ">Stra\xc3\xa1\x65 \xef\xbf\xbd</td>"));
	assert_non_null(strstr(html, ">\xef\xbf\xbd\xef\xbf\xbd\xef\xbf\xbdok</td>"));
	free(html);
}

static void batch_html_unwritable_path_leaves_nothing(void **state)
{
	struct fixture x;
	char dir[512], path[700], keep[720], listing[256];

	(void)state;
	fixture_failed(&x);
	test_path(dir, sizeof(dir), "batch-html-parent");
	assert_int_equal(mkdir(dir, 0755), 0);
	snprintf(path, sizeof(path), "%s/not-there/index.html", dir);
	assert_int_equal(hl_batch_html_write(&x.s, "tasks/", path), -ENOENT);
	list_dir(dir, listing, sizeof(listing));
	assert_string_equal(listing, "");
	/* a directory in the page's place stays as it was */
	snprintf(path, sizeof(path), "%s/index.html", dir);
	assert_int_equal(mkdir(path, 0755), 0);
	snprintf(keep, sizeof(keep), "%s/keep", path);
	assert_int_equal(mkdir(keep, 0755), 0);
	assert_int_equal(hl_batch_html_write(&x.s, "tasks/", path), -EISDIR);
	list_dir(dir, listing, sizeof(listing));
	assert_string_equal(listing, "index.html");
	assert_int_equal(rmdir(keep), 0);
	assert_int_equal(rmdir(path), 0);
	assert_int_equal(rmdir(dir), 0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(batch_html_failed_run),
		cmocka_unit_test(batch_html_escapes_users_strings),
		cmocka_unit_test(batch_html_parses_back_to_the_same_text),
		cmocka_unit_test(batch_html_all_passed),
		cmocka_unit_test(batch_html_errors_without_failures),
		cmocka_unit_test(batch_html_empty_groupings_and_no_loop),
		cmocka_unit_test(batch_html_cut_utf8_is_a_replacement),
		cmocka_unit_test(batch_html_unwritable_path_leaves_nothing),
	};
	int rc;

	xmlInitParser();
	rc = cmocka_run_group_tests(tests, NULL, NULL);
	xmlCleanupParser();
	return rc;
}
