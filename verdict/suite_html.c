/* SPDX-License-Identifier: MIT */
/*
 * index.html of a suite run: one HTML5 page that reads offline — inline CSS, the plots pasted in
 * as SVG, no script and nothing fetched. The page is composed in memory first, so that a failing
 * allocation is an error return rather than half a report, then written whole
 * (base/file_replace.h).
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/file_replace.h"
#include "base/xml_write.h"
#include "verdict/suite_result.h"

static const char css[] =
	"body{font-family:sans-serif;margin:1.5em auto;max-width:1200px;color:#222}\n"
	"h1{margin-bottom:.2em}h2{margin-top:2em;border-bottom:1px solid #ccc}\n"
	"table{border-collapse:collapse;margin:.6em 0}\n"
	"th,td{border:1px solid #ccc;padding:.25em .5em;text-align:left;vertical-align:top}\n"
	"th{background:#f2f2f2}td.num{text-align:right;white-space:nowrap;font-variant-numeric:tabular-nums}\n"
	"tr.fail td,tr.nosamples td{background:#fde2e2}tr.fail td.result,tr.nosamples "
	"td.result{color:#b00;font-weight:bold}\n"
	"td.src{font-size:.85em;color:#555;max-width:22em}\n"
	".badge{display:inline-block;padding:.2em .8em;border-radius:.3em;color:#fff;"
	"font-weight:bold}\n"
	".badge.pass{background:#2a7d2a}.badge.fail{background:#c62828}\n"
	".error{color:#b00;font-weight:bold}dl.meta dt{font-weight:bold;float:left;clear:left;"
	"width:8em}dl.meta dd{margin-left:9em}\n"
	"svg{max-width:100%;height:auto;border:1px solid #ddd}\n";

static void text(FILE *f, const char *s)
{
	hl_xml_write_text(f, s);
}

/* A value in its unit: metres to 0.1, everything else to 3 significant figures; "-" if none. */
static void value(FILE *f, double v, const char *unit)
{
	if (!isfinite(v)) {
		fputs("&#8211;", f);
		return;
	}
	if (unit && strcmp(unit, "m") == 0) {
		fprintf(f, "%.1f", v);
	} else if (fabs(v) >= 1000.0) {
		const double p = pow(10.0, floor(log10(fabs(v))) - 2.0);

		fprintf(f, "%.0f", round(v / p) * p);
	} else {
		fprintf(f, "%.3g", v);
	}
	if (unit && *unit)
		fprintf(f, " %s", unit);
}

/* The anchor of a variant: its id with anything but [A-Za-z0-9_-] as '_'. */
static void anchor(FILE *f, const struct hl_suite_variant *v)
{
	fputs("v-", f);
	for (const char *c = v->id; *c; c++) {
		const char ch = *c;
		const int ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') ||
			       (ch >= '0' && ch <= '9') || ch == '-' || ch == '_';

		fputc(ok ? ch : '_', f);
	}
}

/* Words for a reader (the files' tokens are suite.h's hl_suite_*_name). */
static const char *procedure_words(enum hl_suite_procedure p)
{
	switch (p) {
	case HL_SUITE_FMVSS108_ADB:
		return "FMVSS 108 ADB track test";
	case HL_SUITE_IIHS:
		return "IIHS headlight evaluation";
	case HL_SUITE_R149_ADB:
		return "UN R149 ADB glare";
	}
	return "unknown";
}

static const char *road_words(enum hl_suite_road r)
{
	switch (r) {
	case HL_SUITE_STRAIGHT:
		return "straight";
	case HL_SUITE_LEFT:
		return "left curve";
	case HL_SUITE_RIGHT:
		return "right curve";
	}
	return "unknown";
}

struct variant_count {
	int cases, failed, no_samples;
	bool error;
};

static void count(const struct hl_suite_variant *v, struct variant_count *ret)
{
	*ret = (struct variant_count){ .cases = v->n_cases,
				       .error = v->error[0] != '\0' || v->exit_code != 0 };
	for (int c = 0; c < v->n_cases; c++) {
		ret->failed += v->cases[c].judged && !v->cases[c].pass;
		ret->no_samples += v->cases[c].no_samples;
	}
}

static const char *verdict_word(const struct variant_count *c)
{
	if (c->error)
		return "ERROR";
	return c->failed || c->no_samples ? "FAIL" : "PASS";
}

static void header(FILE *f, const struct hl_suite_result *r)
{
	const struct hl_suite *s = r->suite;
	const bool pass = hl_suite_result_passed(r);
	struct hl_suite_totals t;

	hl_suite_result_totals(r, &t);
	fputs("<header>\n<h1>", f);
	text(f, s ? s->title : "suite");
	fprintf(f, " <span class=\"badge %s\">%s</span></h1>\n<dl class=\"meta\">\n",
		pass ? "pass" : "fail", pass ? "PASS" : "FAIL");
	if (s) {
		fputs("<dt>suite</dt><dd>", f);
		text(f, s->name);
		fputs("</dd>\n<dt>procedure</dt><dd>", f);
		text(f, procedure_words(s->procedure));
		fputs("</dd>\n<dt>source</dt><dd>", f);
		text(f, s->source);
		fputs("</dd>\n", f);
		if (s->has_rounding) {
			fprintf(f, "<dt>rounding</dt><dd>%d decimal%s, %s (", s->decimals,
				s->decimals == 1 ? "" : "s",
				s->rounding == HL_SUITE_HALF_UP ? "half up" : "half to even");
			text(f, s->rounding_source);
			fputs(")</dd>\n", f);
		}
	}
	if (r->ecu[0]) {
		fputs("<dt>ECU</dt><dd>", f);
		text(f, r->ecu);
	} else {
		fputs("<dt>preset</dt><dd>", f);
		text(f, r->preset[0] ? r->preset : "(none)");
	}
	fputs("</dd>\n", f);
	if (r->fault[0]) {
		fputs("<dt>fault</dt><dd>", f);
		text(f, r->fault);
		fputs("</dd>\n", f);
	}
	fputs("</dl>\n", f);
	fprintf(f,
		"<table class=\"totals\"><tr><th>cases</th><th>judged</th><th>failed</th>"
		"<th>no samples</th><th>errors</th></tr>\n<tr><td class=\"num\">%d</td>"
		"<td class=\"num\">%d</td><td class=\"num\">%d</td><td class=\"num\">%d</td>"
		"<td class=\"num\">%d</td></tr></table>\n</header>\n",
		t.cases, t.judged, t.failed, t.no_samples, t.errors);
}

static void summary(FILE *f, const struct hl_suite_result *r)
{
	fputs("<h2>Variants</h2>\n<table class=\"summary\"><tr><th>variant</th><th>cases</th>"
	      "<th>failed</th><th>no samples</th><th>result</th></tr>\n",
	      f);
	for (int i = 0; i < r->n_variants; i++) {
		const struct hl_suite_variant *v = &r->v[i];
		struct variant_count c;

		count(v, &c);
		fprintf(f, "<tr class=\"%s\"><td><a href=\"#",
			strcmp(verdict_word(&c), "PASS") ? "fail" : "pass");
		anchor(f, v);
		fputs("\">", f);
		text(f, v->title[0] ? v->title : v->id);
		fprintf(f,
			"</a></td><td class=\"num\">%d</td><td class=\"num\">%d</td>"
			"<td class=\"num\">%d</td><td class=\"result\">%s</td></tr>\n",
			c.cases, c.failed, c.no_samples, verdict_word(&c));
	}
	fputs("</table>\n", f);
}

static void defaults(FILE *f, const struct hl_suite *s)
{
	fputs("<h2>Documented defaults</h2>\n", f);
	if (!s || s->n_defaults == 0) {
		fputs("<p>None: every value is from the suite's source.</p>\n", f);
		return;
	}
	fputs("<table class=\"defaults\"><tr><th>what</th><th>value</th><th>why</th></tr>\n", f);
	for (int i = 0; i < s->n_defaults && i < HL_SUITE_MAX_DEFAULTS; i++) {
		fputs("<tr><td>", f);
		text(f, s->def[i].what);
		fputs("</td><td>", f);
		text(f, s->def[i].value);
		fputs("</td><td>", f);
		text(f, s->def[i].why);
		fputs("</td></tr>\n", f);
	}
	fputs("</table>\n", f);
}

static const char *case_result(const struct hl_suite_case *k, const char **ret_class)
{
	if (k->no_samples) {
		*ret_class = "nosamples";
		return "no samples";
	}
	if (!k->judged) {
		*ret_class = "notjudged";
		return "not judged";
	}
	*ret_class = k->pass ? "pass" : "fail";
	return k->pass ? "pass" : "FAIL";
}

static void cases(FILE *f, const struct hl_suite_variant *v)
{
	if (v->n_cases == 0) {
		fputs("<p>No cases.</p>\n", f);
		return;
	}
	fputs("<table class=\"cases\"><tr><th>case</th><th>photometer</th><th>bin</th>"
	      "<th>samples</th><th>max raw</th><th>value as judged</th><th>limit</th>"
	      "<th>margin</th><th>range at max</th><th>result</th><th>source</th></tr>\n",
	      f);
	for (int c = 0; c < v->n_cases; c++) {
		const struct hl_suite_case *k = &v->cases[c];
		const char *cls, *res = case_result(k, &cls);

		fprintf(f, "<tr class=\"%s\"><td>", cls);
		text(f, k->name);
		fputs("</td><td>", f);
		text(f, k->photometer);
		fputs("</td><td class=\"num\">", f);
		if (isfinite(k->from_m) && isfinite(k->to_m))
			fprintf(f, "%.1f&#8211;%.1f m", k->from_m, k->to_m);
		else
			fputs("&#8211;", f);
		fprintf(f, "</td><td class=\"num\">%d</td><td class=\"num\">", k->n_samples);
		value(f, k->max_raw, k->unit);
		fputs("</td><td class=\"num\">", f);
		value(f, k->value, k->unit);
		fputs("</td><td class=\"num\">", f);
		if (isfinite(k->limit))
			fputs(k->limit_is_min ? "&#8805; " : "&#8804; ", f);
		value(f, k->limit, k->unit);
		fputs("</td><td class=\"num\">", f);
		value(f, k->margin, k->unit);
		fputs("</td><td class=\"num\">", f);
		value(f, k->at_range_m, "m");
		fprintf(f, "</td><td class=\"result\">%s</td><td class=\"src\">", res);
		text(f, k->source);
		fputs("</td></tr>\n", f);
	}
	fputs("</table>\n", f);
}

/* The plot as inline SVG: hl_suite_plot_svg's document without its XML declaration. */
static int plot(FILE *f, const struct hl_suite_result *r, const struct hl_suite_variant *v)
{
	char *buf = NULL;
	size_t len = 0;
	FILE *m = open_memstream(&buf, &len);
	const char *svg;
	int rc;

	if (!m)
		return -errno;
	rc = hl_suite_plot_svg(r, v, m);
	if (fclose(m) != 0 && rc == 0)
		rc = -ENOMEM;
	if (rc == 0) {
		svg = buf;
		if (strncmp(svg, "<?xml", 5) == 0) {
			const char *end = strstr(svg, "?>");

			svg = end ? end + 2 : svg;
			svg += strspn(svg, "\n");
		}
		fputs("<figure>", f);
		fputs(svg, f);
		fputs("</figure>\n", f);
	}
	free(buf);
	return rc;
}

static void link(FILE *f, const char *label, const char *file)
{
	if (!file[0])
		return;
	fprintf(f, "<li>%s: <a href=\"", label);
	text(f, file);
	fputs("\">", f);
	text(f, file);
	fputs("</a></li>\n", f);
}

static int variant(FILE *f, const struct hl_suite_result *r, const struct hl_suite_variant *v)
{
	struct variant_count c;

	count(v, &c);
	fputs("<section id=\"", f);
	anchor(f, v);
	fputs("\">\n<h2>", f);
	text(f, v->title[0] ? v->title : v->id);
	fprintf(f, " <span class=\"badge %s\">%s</span></h2>\n<dl class=\"meta\">\n<dt>id</dt><dd>",
		strcmp(verdict_word(&c), "PASS") ? "fail" : "pass", verdict_word(&c));
	text(f, v->id);
	fputs("</dd>\n<dt>road</dt><dd>", f);
	text(f, road_words(v->road));
	if (isfinite(v->radius_m) && v->radius_m > 0.0)
		fprintf(f, ", radius %.0f m", v->radius_m);
	fputs("</dd>\n<dt>speed</dt><dd>", f);
	if (isfinite(v->speed_mph))
		fprintf(f, "%.0f mph (%.1f km/h)", v->speed_mph, v->speed_mph * 1.609344);
	else
		fputs("&#8211;", f);
	fputs("</dd>\n<dt>range</dt><dd>", f);
	value(f, v->range_m[0], "m");
	fputs(" to ", f);
	value(f, v->range_m[1], "m");
	fprintf(f, "</dd>\n<dt>frames</dt><dd>%d</dd>\n<dt>exit</dt><dd>%d</dd>\n", v->n_frames,
		v->exit_code);
	if (v->error[0]) {
		fputs("<dt>error</dt><dd class=\"error\">", f);
		text(f, v->error);
		fputs("</dd>\n", f);
	}
	fputs("</dl>\n", f);
	cases(f, v);
	if (plot(f, r, v) < 0)
		return -ENOMEM;
	if (v->trace_file[0] || v->scenario_file[0] || v->plot_file[0]) {
		fputs("<ul class=\"files\">\n", f);
		link(f, "scenario", v->scenario_file);
		link(f, "trace", v->trace_file);
		link(f, "plot", v->plot_file);
		fputs("</ul>\n", f);
	}
	fputs("</section>\n", f);
	return 0;
}

static int page(FILE *f, const struct hl_suite_result *r)
{
	fputs("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
	      "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>",
	      f);
	text(f, r->suite ? r->suite->title : "suite");
	fprintf(f, "</title>\n<style>\n%s</style>\n</head>\n<body>\n", css);
	header(f, r);
	summary(f, r);
	defaults(f, r->suite);
	for (int i = 0; i < r->n_variants; i++)
		if (variant(f, r, &r->v[i]) < 0)
			return -ENOMEM;
	fputs("</body>\n</html>\n", f);
	return 0;
}

int hl_suite_html_write(const struct hl_suite_result *r, const char *path)
{
	char *buf = NULL;
	size_t len = 0;
	FILE *m = open_memstream(&buf, &len);
	int rc;

	if (!m)
		return -errno;
	rc = page(m, r);
	if (fclose(m) != 0 && rc == 0)
		rc = -ENOMEM;
	if (rc == 0) {
		rc = hl_file_replace_bytes(path, buf, len);
	}
	free(buf);
	return rc;
}
