/* SPDX-License-Identifier: MIT */
/* A suite run's plan and its files: see verdict/suite_plan.h. */
#include "verdict/suite_plan.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/make_dirs.h"
#include "verdict/suite_report.h"
#include "verdict/suite_scenario.h"

static bool selected(const char *only, const struct hl_suite_scenario *d, const char *id)
{
	return !only || !strcmp(only, d->id) || !strcmp(only, id);
}

int hl_suite_plan(const struct hl_suite *s, const char *only, int samples,
		  struct hl_suite_result *r, char *msg, size_t msg_size)
{
	int n = 0;

	r->suite = s;
	for (int pass = 0; pass < 2; pass++) {
		for (int i = 0; i < s->n_scenarios; i++) {
			const struct hl_suite_scenario *d = &s->scenario[i];

			for (int k = 0; k < hl_suite_variant_count(d, samples); k++) {
				struct hl_suite_variant v = { .scenario_index = i,
							      .variant_index = k };

				hl_suite_variant_params(d, samples, k, &v.speed_mph, &v.radius_m,
							v.id, sizeof(v.id));
				if (!selected(only, d, v.id))
					continue;
				if (pass == 1) {
					snprintf(v.scenario_id, sizeof(v.scenario_id), "%s", d->id);
					v.road = d->road;
					v.range_m[0] = d->range_m[0];
					v.range_m[1] = d->range_m[1];
					r->v[r->n_variants++] = v;
				} else {
					n++;
				}
			}
		}
		if (pass == 0) {
			if (n == 0) {
				snprintf(msg, msg_size,
					 "--only '%s': no scenario or variant of %s has that id",
					 only ? only : "", s->name);
				return -EINVAL;
			}
			r->v = calloc((size_t)n, sizeof(*r->v));
			if (!r->v)
				return -ENOMEM;
			r->n_variants = 0;
		}
	}
	return n;
}

int hl_suite_plan_dirs(const char *dir, bool traces, char *msg, size_t msg_size)
{
	static const char *const sub[] = { "", "/scenarios", "/plots", "/traces" };
	char p[4096];

	for (size_t i = 0; i < sizeof(sub) / sizeof(sub[0]); i++) {
		int rc;

		if (!traces && !strcmp(sub[i], "/traces"))
			continue;
		snprintf(p, sizeof(p), "%s%s", dir, sub[i]);
		rc = hl_make_dirs(p);
		if (rc < 0) {
			snprintf(msg, msg_size, "'%s': cannot make the directory: %s", p,
				 strerror(-rc));
			return rc;
		}
	}
	return 0;
}

int hl_suite_plan_scenario(const struct hl_suite *s, struct hl_suite_variant *v, const char *dir,
			   char *ret_path, size_t path_size, char *msg, size_t msg_size)
{
	const struct hl_suite_scenario *d = &s->scenario[v->scenario_index];
	char *text = NULL;
	FILE *f;
	int rc;

	rc = hl_suite_variant_scenario(s, d, v->speed_mph, v->radius_m, &text, msg, msg_size);
	if (rc < 0)
		return rc;
	hl_suite_variant_title(d, v->speed_mph, v->radius_m, v->title, sizeof(v->title));
	snprintf(v->scenario_file, sizeof(v->scenario_file), "scenarios/%s.json", v->id);
	snprintf(v->plot_file, sizeof(v->plot_file), "plots/%s.svg", v->id);
	snprintf(ret_path, path_size, "%s/%s", dir, v->scenario_file);
	f = fopen(ret_path, "we");
	rc = f ? 0 : -errno;
	if (f && fputs(text, f) == EOF)
		rc = -EIO;
	if (f && fclose(f) != 0 && rc == 0)
		rc = -errno;
	if (rc < 0)
		snprintf(msg, msg_size, "'%s': %s", ret_path, strerror(-rc));
	free(text);
	return rc;
}

int hl_suite_plan_plot(const struct hl_suite_result *r, const struct hl_suite_variant *v,
		       const char *dir)
{
	char path[4096];
	FILE *f;
	int rc = 0;

	snprintf(path, sizeof(path), "%s/%s", dir, v->plot_file);
	f = fopen(path, "we");
	if (!f)
		return -errno;
	if (hl_suite_plot_svg(r, v, f) < 0)
		rc = -EIO;
	if (fclose(f) != 0 && rc == 0)
		rc = -errno;
	return rc;
}

int hl_suite_plan_write(const struct hl_suite_result *r, const char *dir, char *msg,
			size_t msg_size)
{
	static const char *const names[] = { "report.json", "junit.xml", "index.html" };
	int first = 0;

	for (int i = 0; i < 3; i++) {
		char path[4096];
		int rc;

		snprintf(path, sizeof(path), "%s/%s", dir, names[i]);
		rc = i == 0 ? hl_suite_report_write(r, path) :
		     i == 1 ? hl_suite_junit_write(r, path) :
			      hl_suite_html_write(r, path);
		if (rc < 0 && first == 0) {
			first = rc;
			snprintf(msg, msg_size, "'%s': %s", path, strerror(-rc));
		}
	}
	return first;
}
