/* SPDX-License-Identifier: MIT */
/* A suite run's report.json and junit.xml: see verdict/suite_report.h. */
#include "verdict/suite_report.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "base/file_replace.h"
#include "base/json_write.h"
#include "base/xml_write.h"

static void num(FILE *f, const char *key, double x, const char *fmt)
{
	fprintf(f, "\"%s\": ", key);
	hl_json_write_num(f, x, fmt);
}

static void str(FILE *f, const char *key, const char *s)
{
	fprintf(f, "\"%s\": ", key);
	hl_json_write_str(f, s);
}

static const char *case_status(const struct hl_suite_case *c)
{
	return c->no_samples ? "no_samples" : !c->judged ? "reported" : c->pass ? "pass" : "fail";
}

static void write_case(FILE *f, const struct hl_suite_case *c)
{
	fputs("        {", f);
	str(f, "name", c->name);
	fputs(", ", f);
	str(f, "photometer", c->photometer);
	fputs(", ", f);
	num(f, "from_m", c->from_m, "%.1f");
	fputs(", ", f);
	num(f, "to_m", c->to_m, "%.1f");
	fputs(", ", f);
	str(f, "unit", c->unit);
	fprintf(f, ", \"samples\": %d, ", c->n_samples);
	num(f, "max_raw", c->max_raw, "%.9g");
	fputs(", ", f);
	num(f, "value", c->value, "%.9g");
	fputs(", ", f);
	num(f, "limit", c->limit, "%.9g");
	fprintf(f, ", \"limit_is_min\": %s, ", c->limit_is_min ? "true" : "false");
	num(f, "margin", c->margin, "%.9g");
	fputs(", ", f);
	num(f, "at_range_m", c->at_range_m, "%.3f");
	fputs(", ", f);
	num(f, "at_t_s", c->at_t_s, "%.3f");
	fprintf(f, ", \"status\": \"%s\", ", case_status(c));
	str(f, "source", c->source);
	fputs("}", f);
}

static void write_series(FILE *f, const struct hl_suite_series *s)
{
	fputs("        {", f);
	str(f, "label", s->label);
	fputs(", ", f);
	str(f, "role", hl_actor_role_name(s->role));
	fprintf(f, ", \"n\": %d, \"range_m\": [", s->n);
	for (int i = 0; i < s->n; i++) {
		fputs(i ? ", " : "", f);
		hl_json_write_num(f, s->range_m[i], "%.3f");
	}
	fputs("], \"lx\": [", f);
	for (int i = 0; i < s->n; i++) {
		fputs(i ? ", " : "", f);
		hl_json_write_num(f, s->lx[i], "%.6g");
	}
	fputs("]}", f);
}

static void write_report(void *ctx, FILE *f)
{
	const struct hl_suite_result *r = ctx;
	const struct hl_suite *s = r->suite;
	struct hl_suite_totals t;

	hl_suite_result_totals(r, &t);
	fputs("{\n  \"version\": 1,\n  ", f);
	str(f, "suite", s->name);
	fputs(",\n  ", f);
	str(f, "title", s->title);
	fputs(",\n  ", f);
	str(f, "procedure", hl_suite_procedure_name(s->procedure));
	fputs(",\n  ", f);
	str(f, "source", s->source);
	fputs(",\n  ", f);
	str(f, "ecu", r->ecu);
	fputs(",\n  ", f);
	str(f, "preset", r->preset);
	fputs(",\n  ", f);
	str(f, "fault", r->fault);
	fprintf(f,
		",\n  \"passed\": %s,\n  \"totals\": {\"variants\": %d, \"cases\": %d, \"judged\": "
		"%d, \"failed\": %d, \"no_samples\": %d, \"errors\": %d},\n",
		hl_suite_result_passed(r) ? "true" : "false", r->n_variants, t.cases, t.judged,
		t.failed, t.no_samples, t.errors);
	if (s->has_rounding) {
		fprintf(f, "  \"rounding\": {\"decimals\": %d, \"rule\": \"%s\", ", s->decimals,
			s->rounding == HL_SUITE_HALF_EVEN ? "half-even" : "half-up");
		str(f, "source", s->rounding_source);
		fputs("},\n", f);
	}
	fputs("  \"defaults\": [", f);
	for (int i = 0; i < s->n_defaults; i++) {
		fputs(i ? ",\n    {" : "\n    {", f);
		str(f, "what", s->def[i].what);
		fputs(", ", f);
		str(f, "value", s->def[i].value);
		fputs(", ", f);
		str(f, "why", s->def[i].why);
		fputs("}", f);
	}
	fputs("\n  ],\n  \"variants\": [", f);
	for (int i = 0; i < r->n_variants; i++) {
		const struct hl_suite_variant *v = &r->v[i];

		fputs(i ? ",\n    {" : "\n    {", f);
		str(f, "id", v->id);
		fputs(", ", f);
		str(f, "scenario", v->scenario_id);
		fputs(",\n      ", f);
		str(f, "title", v->title);
		fputs(",\n      ", f);
		str(f, "road", hl_suite_road_name(v->road));
		fputs(", ", f);
		num(f, "speed_mph", v->speed_mph, "%.9g");
		fputs(", ", f);
		num(f, "radius_m", v->radius_m, "%.9g");
		fputs(", \"range_m\": [", f);
		hl_json_write_num(f, v->range_m[0], "%.9g");
		fputs(", ", f);
		hl_json_write_num(f, v->range_m[1], "%.9g");
		fprintf(f, "], \"frames\": %d, \"exit\": %d,\n      ", v->n_frames, v->exit_code);
		str(f, "error", v->error);
		fputs(", ", f);
		str(f, "scenario_file", v->scenario_file);
		fputs(", ", f);
		str(f, "trace_file", v->trace_file);
		fputs(", ", f);
		str(f, "plot_file", v->plot_file);
		if (v->has_birdseye) {
			fputs(",\n      \"visibility_m\": {", f);
			num(f, "left_edge", v->birdseye.vis_m[0], "%.1f");
			fputs(", ", f);
			num(f, "right_edge", v->birdseye.vis_m[1], "%.1f");
			fputs("}", f);
		}
		fputs(",\n      \"cases\": [", f);
		for (int k = 0; k < v->n_cases; k++) {
			fputs(k ? ",\n" : "\n", f);
			write_case(f, &v->cases[k]);
		}
		fputs("\n      ],\n      \"series\": [", f);
		for (int k = 0; k < v->n_series; k++) {
			fputs(k ? ",\n" : "\n", f);
			write_series(f, &v->series[k]);
		}
		fputs("\n      ]}", f);
	}
	fputs("\n  ]\n}\n", f);
}

int hl_suite_report_write(const struct hl_suite_result *r, const char *path)
{
	return hl_file_replace(path, write_report, (void *)r);
}

static void attr(FILE *f, const char *name, const char *value)
{
	fprintf(f, " %s=\"", name);
	hl_xml_write_text(f, value);
	fputc('"', f);
}

static void write_junit(void *ctx, FILE *f)
{
	const struct hl_suite_result *r = ctx;

	fputs("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites", f);
	attr(f, "name", r->suite->name);
	fputs(">\n", f);
	for (int i = 0; i < r->n_variants; i++) {
		const struct hl_suite_variant *v = &r->v[i];
		int failures = 0, errors = v->error[0] ? 1 : 0;
		char cls[256];

		for (int k = 0; k < v->n_cases; k++) {
			failures += v->cases[k].judged && !v->cases[k].pass;
			errors += v->cases[k].no_samples;
		}
		snprintf(cls, sizeof(cls), "%s.%s", r->suite->name, v->id);
		fputs("  <testsuite", f);
		attr(f, "name", v->id);
		fprintf(f, " tests=\"%d\" failures=\"%d\" errors=\"%d\" skipped=\"0\">\n",
			v->n_cases + (v->error[0] ? 1 : 0), failures, errors);
		fputs("    <properties>\n      <property name=\"ecu\"", f);
		attr(f, "value", r->ecu[0] ? r->ecu : r->preset);
		fputs("/>\n      <property name=\"title\"", f);
		attr(f, "value", v->title);
		fputs("/>\n    </properties>\n", f);
		if (v->error[0]) {
			fputs("    <testcase", f);
			attr(f, "classname", cls);
			attr(f, "name", "run");
			fputs(">\n      <error", f);
			attr(f, "message", v->error);
			fputs("/>\n    </testcase>\n", f);
		}
		for (int k = 0; k < v->n_cases; k++) {
			const struct hl_suite_case *c = &v->cases[k];
			char msg[512];

			fputs("    <testcase", f);
			attr(f, "classname", cls);
			attr(f, "name", c->name);
			if (c->no_samples) {
				snprintf(
					msg, sizeof(msg),
					"no sample in %.1f-%.1f m: the run never measured this bin",
					c->from_m, c->to_m);
				fputs(">\n      <error", f);
				attr(f, "message", msg);
				fputs("/>\n    </testcase>\n", f);
			} else if (c->judged && !c->pass) {
				snprintf(
					msg, sizeof(msg),
					"maximum %.6g %s (as judged %.6g) at range %.1f m (t %.2f s) "
					"%s the limit %.6g %s",
					c->max_raw, c->unit, c->value, c->at_range_m, c->at_t_s,
					c->limit_is_min ? "below" : "over", c->limit, c->unit);
				fputs(">\n      <failure", f);
				attr(f, "message", msg);
				fputs("/>\n    </testcase>\n", f);
			} else {
				fputs("/>\n", f);
			}
		}
		fputs("  </testsuite>\n", f);
	}
	fputs("</testsuites>\n", f);
}

int hl_suite_junit_write(const struct hl_suite_result *r, const char *path)
{
	return hl_file_replace(path, write_junit, (void *)r);
}
