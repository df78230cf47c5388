/* SPDX-License-Identifier: MIT */
/*
 * The merged page of hdlamp batch (tools/batch.h): the verdict over every task, pass/fail by
 * suite, scenario, ECU and preset, the worst margins, the loop latency and the tasks that ended
 * in error, each linked to its own folder. One HTML file that reads offline: inline CSS, no
 * script, nothing fetched. Composed in memory, then written whole (base/file_replace.h), like a
 * suite's page (verdict/suite_html.c).
 *
 * Ids, keys and reasons come from users' files and were cut to the struct's fixed sizes, which
 * can split a UTF-8 sequence: every string is escaped, and a byte that does not begin a valid
 * sequence is written as U+FFFD.
 */
#include <assert.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/file_replace.h"
#include "base/xml_write.h"
#include "tools/batch.h"

static const char css[] =
	"body{font-family:sans-serif;margin:1.5em auto;max-width:1200px;padding:0 1em;"
	"color:#222}\n"
	"h1{margin-bottom:.3em}h2{margin-top:1.8em;border-bottom:1px solid #ccc}\n"
	"p.lead{font-size:1.1em;margin:.3em 0 1em}\n"
	"table{border-collapse:collapse;margin:.6em 0}\n"
	"th,td{border:1px solid #ccc;padding:.25em .5em;text-align:left;vertical-align:top}\n"
	"th{background:#f2f2f2}th.num,td.num{text-align:right;white-space:nowrap;"
	"font-variant-numeric:tabular-nums}\n"
	"td.id{overflow-wrap:anywhere;max-width:34em}td.reason{overflow-wrap:anywhere;"
	"max-width:40em}\n"
	"table.totals,table.groups{width:50em}table.totals td:first-child,"
	"table.groups td:first-child{width:100%}\n"
	"tr.fail td{background:#fde2e2}tr.error td{background:#fff0d9}\n"
	".badge{display:inline-block;padding:.2em .8em;border-radius:.3em;color:#fff;"
	"font-weight:bold;font-size:.8em;vertical-align:middle}\n"
	".badge.pass{background:#2a7d2a}.badge.fail{background:#c62828}"
	".badge.error{background:#d35400}\n"
	"td.bar{vertical-align:middle}div.bar{display:flex;width:14em;height:.8em;"
	"background:#eee;border-radius:.2em;overflow:hidden}\n"
	"div.bar span{min-width:2px}.bar .p{background:#2a7d2a}.bar .f{background:#c62828}"
	".bar .e{background:#e67e22}\n"
	"td.over{color:#b00;font-weight:bold;white-space:nowrap}p.error,span.error{color:#b00;"
	"font-weight:bold}\n"
	"p.none{color:#555;font-style:italic}p.more{font-weight:bold}\n"
	"p.nav a{margin-right:1em}\n";

/*
 * The character at s: true and its length, or false and the length of the broken sequence's
 * maximal subpart (at least 1 byte), which is one U+FFFD as browsers decode it. Valid is as RFC
 * 3629 says: nothing overlong, no surrogate, nothing past U+10FFFF. Reads no byte past the
 * first that breaks the sequence, so never past the terminating NUL.
 */
static bool utf8_next(const unsigned char *s, size_t *ret_len)
{
	unsigned lo = 0x80, hi = 0xbf;
	size_t need;

	if (s[0] < 0x80) {
		*ret_len = 1;
		return true;
	}
	if (s[0] >= 0xc2 && s[0] <= 0xdf) {
		need = 1;
	} else if (s[0] >= 0xe0 && s[0] <= 0xef) {
		need = 2;
		lo = s[0] == 0xe0 ? 0xa0 : lo;
		hi = s[0] == 0xed ? 0x9f : hi;
	} else if (s[0] >= 0xf0 && s[0] <= 0xf4) {
		need = 3;
		lo = s[0] == 0xf0 ? 0x90 : lo;
		hi = s[0] == 0xf4 ? 0x8f : hi;
	} else {
		*ret_len = 1;
		return false;
	}
	for (size_t i = 1; i <= need; i++) {
		if (s[i] < lo || s[i] > hi) {
			*ret_len = i;
			return false;
		}
		lo = 0x80;
		hi = 0xbf;
	}
	*ret_len = need + 1;
	return true;
}

/* s escaped (base/xml_write.h), invalid UTF-8 as U+FFFD; NULL as nothing. */
static void text(FILE *f, const char *s)
{
	static const char replacement[] = "\xef\xbf\xbd";
	char buf[256];
	size_t n = 0;

	for (const unsigned char *p = (const unsigned char *)s; p && *p;) {
		size_t len;
		const bool valid = utf8_next(p, &len);
		const char *from = valid ? (const char *)p : replacement;
		const size_t from_len = valid ? len : sizeof(replacement) - 1;

		if (n + from_len >= sizeof(buf)) {
			buf[n] = '\0';
			hl_xml_write_text(f, buf);
			n = 0;
		}
		memcpy(buf + n, from, from_len);
		n += from_len;
		p += len;
	}
	buf[n] = '\0';
	hl_xml_write_text(f, buf);
}

/* The opening tag of a link to task index's file or folder: prefix + "<index>/" + rest. */
static void task_link(FILE *f, const char *prefix, unsigned index, const char *rest)
{
	fputs("<a href=\"", f);
	text(f, prefix);
	fprintf(f, "%u/%s\">", index, rest);
}

static void segment(FILE *f, const char *cls, unsigned long count, double total)
{
	if (count > 0)
		fprintf(f, "<span class=\"%s\" style=\"width:%.2f%%\"></span>", cls,
			100.0 * (double)count / total);
}

/* A cell with a bar of passed, failed and errors, each as wide as its share. */
static void bar(FILE *f, unsigned long passed, unsigned long failed, unsigned long errors)
{
	const double total = (double)passed + (double)failed + (double)errors;

	fprintf(f,
		"<td class=\"bar\"><div class=\"bar\" title=\"%lu passed, %lu failed, %lu errors\">",
		passed, failed, errors);
	if (total > 0) {
		segment(f, "p", passed, total);
		segment(f, "f", failed, total);
		segment(f, "e", errors, total);
	}
	fputs("</div></td>", f);
}

static const char *row_class(unsigned long failed, unsigned long errors)
{
	if (failed)
		return "fail";
	return errors ? "error" : "pass";
}

/* PASSED only when every task ran and passed; FAILED when one failed; otherwise ERRORS. */
static const char *verdict(const struct hl_batch_summary *s, const char **ret_class)
{
	if (s->tasks > 0 && s->passed == s->tasks && s->failed == 0 && s->errors == 0) {
		*ret_class = "pass";
		return "PASSED";
	}
	if (s->failed > 0) {
		*ret_class = "fail";
		return "FAILED";
	}
	*ret_class = "error";
	return "ERRORS";
}

static void headline(FILE *f, const struct hl_batch_summary *s)
{
	const unsigned long counted = (unsigned long)s->passed + s->failed + s->errors;
	const char *cls, *word = verdict(s, &cls);

	fprintf(f, "<h1>hdlamp batch <span class=\"badge %s\">%s</span></h1>\n", cls, word);
	if (s->tasks == 0)
		fputs("<p class=\"lead error\">No task ran.</p>\n", f);
	else
		fprintf(f,
			"<p class=\"lead\">%u task%s: %u passed, %u failed, %s%u ended in error%s.</p>\n",
			s->tasks, s->tasks == 1 ? "" : "s", s->passed, s->failed,
			s->errors ? "<span class=\"error\">" : "", s->errors,
			s->errors ? "</span>" : "");
	if (counted != s->tasks)
		fprintf(f,
			"<p class=\"error\">The counts do not add up: %u passed + %u failed + %u "
			"errors make %lu, not the %u tasks.</p>\n",
			s->passed, s->failed, s->errors, counted, s->tasks);
	fputs("<p class=\"nav\"><a href=\"#by-suite\">by suite</a><a href=\"#by-scenario\">by "
	      "scenario</a><a href=\"#by-ecu\">by ECU</a><a href=\"#by-preset\">by preset</a>"
	      "<a href=\"#worst\">worst margins</a><a href=\"#latency\">loop latency</a>"
	      "<a href=\"#errors\">errors</a></p>\n",
	      f);
}

static void totals(FILE *f, const struct hl_batch_summary *s)
{
	const unsigned long bad = s->test_failures + s->test_errors;

	fputs("<h2 id=\"totals\">Totals</h2>\n<table class=\"totals\"><tr><th></th>"
	      "<th class=\"num\">total</th><th class=\"num\">passed</th><th class=\"num\">failed"
	      "</th><th class=\"num\">errors</th><th></th></tr>\n",
	      f);
	fprintf(f,
		"<tr class=\"%s\"><td>tasks</td><td class=\"num\">%u</td><td class=\"num\">%u</td>"
		"<td class=\"num\">%u</td><td class=\"num\">%u</td>",
		row_class(s->failed, s->errors), s->tasks, s->passed, s->failed, s->errors);
	bar(f, s->passed, s->failed, s->errors);
	fprintf(f,
		"</tr>\n<tr class=\"%s\"><td>JUnit test cases</td><td class=\"num\">%lu</td>"
		"<td class=\"num\">",
		row_class(s->test_failures, s->test_errors), s->tests);
	if (s->tests >= bad)
		fprintf(f, "%lu", s->tests - bad);
	else
		fputs("&#8211;", f);
	fprintf(f, "</td><td class=\"num\">%lu</td><td class=\"num\">%lu</td>", s->test_failures,
		s->test_errors);
	bar(f, s->tests >= bad ? s->tests - bad : 0, s->test_failures, s->test_errors);
	fputs("</tr>\n</table>\n", f);
}

/* One grouping's table; groups with an empty key are not listed. */
static void groups(FILE *f, const char *anchor, const char *what, const struct hl_batch_group *g,
		   unsigned n)
{
	unsigned listed = 0;

	assert(n == 0 || g);
	for (unsigned i = 0; i < n; i++)
		listed += g[i].key[0] != '\0';
	fprintf(f, "<h2 id=\"%s\">By %s</h2>\n", anchor, what);
	if (listed == 0) {
		fprintf(f, "<p class=\"none\">No task ran by %s.</p>\n", what);
		return;
	}
	fprintf(f,
		"<table class=\"groups\"><tr><th>%s</th><th class=\"num\">tasks</th>"
		"<th class=\"num\">passed</th><th class=\"num\">failed</th>"
		"<th class=\"num\">errors</th><th></th></tr>\n",
		what);
	for (unsigned i = 0; i < n; i++) {
		const struct hl_batch_group *k = &g[i];

		if (!k->key[0])
			continue;
		fprintf(f, "<tr class=\"%s\"><td class=\"id\">", row_class(k->failed, k->errors));
		text(f, k->key);
		fprintf(f,
			"</td><td class=\"num\">%lu</td><td class=\"num\">%u</td>"
			"<td class=\"num\">%u</td><td class=\"num\">%u</td>",
			(unsigned long)k->passed + k->failed + k->errors, k->passed, k->failed,
			k->errors);
		bar(f, k->passed, k->failed, k->errors);
		fputs("</tr>\n", f);
	}
	fputs("</table>\n", f);
}

/* A margin with its sign, in lx; "-" when there is none. */
static void margin(FILE *f, double v)
{
	if (!isfinite(v)) {
		fputs("&#8211;", f);
		return;
	}
	if (v == 0.0)
		v = 0.0; /* not "-0" */
	if (fabs(v) >= 1000.0)
		fprintf(f, "%+.0f lx", v);
	else
		fprintf(f, "%+.3g lx", v);
}

static void worst(FILE *f, const struct hl_batch_summary *s, const char *prefix)
{
	const unsigned n = s->n_worst < HL_BATCH_WORST_N ? s->n_worst : HL_BATCH_WORST_N;

	fputs("<h2 id=\"worst\">Worst margins</h2>\n", f);
	if (n == 0) {
		fputs("<p class=\"none\">No task reported a margin.</p>\n", f);
		return;
	}
	fputs("<p>The smallest margins to a limit over all tasks, smallest first; a negative margin "
	      "is past the limit by that much.</p>\n<table class=\"worst\"><tr>"
	      "<th class=\"num\">task</th><th>id</th><th>case</th><th class=\"num\">margin</th>"
	      "<th>result</th><th>files</th></tr>\n",
	      f);
	for (unsigned i = 0; i < n; i++) {
		const struct hl_batch_worst *w = &s->worst[i];
		const bool over = w->margin_lx < 0.0;

		fprintf(f, "<tr class=\"%s\"><td class=\"num\">%u</td><td class=\"id\">",
			over ? "fail" : "pass", w->index);
		task_link(f, prefix, w->index, "index.html");
		text(f, w->id[0] ? w->id : "(no id)");
		fputs("</a></td><td>", f);
		text(f, w->case_name);
		fputs("</td><td class=\"num\">", f);
		margin(f, w->margin_lx);
		fprintf(f, "</td><td%s>%s</td><td>", over ? " class=\"over\"" : "",
			over ? "over the limit" : "within");
		task_link(f, prefix, w->index, "plots/");
		fputs("plots</a></td></tr>\n", f);
	}
	fputs("</table>\n", f);
}

static void ms(FILE *f, double v)
{
	if (isfinite(v))
		fprintf(f, "%.3f ms", v);
	else
		fputs("&#8211;", f);
}

static void latency(FILE *f, const struct hl_batch_summary *s)
{
	fputs("<h2 id=\"latency\">Loop latency</h2>\n", f);
	if (s->latency_tasks == 0) {
		fputs("<p class=\"none\">No task with a loop.</p>\n", f);
		return;
	}
	fprintf(f,
		"<p>Each task's own percentiles of its loop latency, and their distribution over "
		"the %u task%s with a loop.</p>\n",
		s->latency_tasks, s->latency_tasks == 1 ? "" : "s");
	fputs("<table class=\"latency\"><tr><th class=\"num\">tasks with a loop</th>"
	      "<th class=\"num\">p50 of the tasks' p50</th><th class=\"num\">p50 of the tasks' "
	      "p99</th><th class=\"num\">p99 of the tasks' p99</th><th class=\"num\">max of the "
	      "tasks' max</th></tr>\n",
	      f);
	fprintf(f, "<tr><td class=\"num\">%u</td><td class=\"num\">", s->latency_tasks);
	ms(f, s->p50_of_p50);
	fputs("</td><td class=\"num\">", f);
	ms(f, s->p50_of_p99);
	fputs("</td><td class=\"num\">", f);
	ms(f, s->p99_of_p99);
	fputs("</td><td class=\"num\">", f);
	ms(f, s->max_of_max);
	fputs("</td></tr>\n</table>\n", f);
}

static void errors(FILE *f, const struct hl_batch_summary *s, const char *prefix)
{
	fputs("<h2 id=\"errors\">Errors</h2>\n", f);
	if (s->errors == 0 && s->n_errors_list == 0) {
		fputs("<p class=\"none\">No task ended in error.</p>\n", f);
		return;
	}
	assert(s->n_errors_list == 0 || s->errors_list);
	if (s->n_errors_list > 0) {
		fputs("<p>Tasks that did not finish, were ended by a signal or a runtime error, or "
		      "left no result.</p>\n<table class=\"errors\"><tr><th class=\"num\">task</th>"
		      "<th>id</th><th>reason</th></tr>\n",
		      f);
		for (unsigned i = 0; i < s->n_errors_list; i++) {
			const struct hl_batch_error *e = &s->errors_list[i];

			fprintf(f, "<tr class=\"error\"><td class=\"num\">%u</td><td class=\"id\">",
				e->index);
			task_link(f, prefix, e->index, "");
			text(f, e->id[0] ? e->id : "(no id)");
			fputs("</a></td><td class=\"reason\">", f);
			text(f, e->reason[0] ? e->reason : "(no reason given)");
			fputs("</td></tr>\n", f);
		}
		fputs("</table>\n", f);
	}
	if (s->errors > s->n_errors_list)
		fprintf(f, "<p class=\"more\">and %u more: see the merged JUnit/JSON.</p>\n",
			s->errors - s->n_errors_list);
}

static void page(FILE *f, const struct hl_batch_summary *s, const char *prefix)
{
	const char *cls, *word = verdict(s, &cls);

	fprintf(f,
		"<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
		"<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
		"<title>hdlamp batch: %s</title>\n<style>\n%s</style>\n</head>\n<body>\n",
		word, css);
	headline(f, s);
	totals(f, s);
	groups(f, "by-suite", "suite", s->by_suite, s->n_suite);
	groups(f, "by-scenario", "scenario", s->by_scenario, s->n_scenario);
	groups(f, "by-ecu", "ECU", s->by_ecu, s->n_ecu);
	groups(f, "by-preset", "preset", s->by_preset, s->n_preset);
	worst(f, s, prefix);
	latency(f, s);
	errors(f, s, prefix);
	fputs("</body>\n</html>\n", f);
}

int hl_batch_html_write(const struct hl_batch_summary *s, const char *task_href_prefix,
			const char *path)
{
	char *buf = NULL;
	size_t len = 0;
	FILE *m;
	int rc = 0;

	assert(s && path);
	m = open_memstream(&buf, &len);
	if (!m)
		return -errno;
	page(m, s, task_href_prefix ? task_href_prefix : "");
	if (ferror(m))
		rc = -ENOMEM;
	if (fclose(m) != 0 && rc == 0)
		rc = -ENOMEM;
	if (rc == 0) {
		rc = hl_file_replace_bytes(path, buf, len);
	}
	free(buf);
	return rc;
}
