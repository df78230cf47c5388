/* SPDX-License-Identifier: MIT */
/* A run's verdicts as JUnit XML: see daemon/loop/loop_junit.h. */
#include "daemon/loop/loop_junit.h"
#include "base/file_replace.h"
#include "base/xml_write.h"

#include <inttypes.h>
#include <stdio.h>
#include <string.h>

static void testcase(FILE *f, const char *classname, const char *name, const char *failure)
{
	fputs("    <testcase classname=\"", f);
	hl_xml_write_text(f, classname);
	fputs("\" name=\"", f);
	hl_xml_write_text(f, name);
	if (!failure) {
		fputs("\"/>\n", f);
		return;
	}
	fputs("\">\n      <failure message=\"", f);
	hl_xml_write_text(f, failure);
	fputs("\"/>\n    </testcase>\n", f);
}

static void write_cases(const struct hl_loop_report *r, const char *ecu_error, FILE *f,
			int *ret_tests, int *ret_failures, bool count_only)
{
	const bool strict = hl_loop_latency_strict(r->loop);
	struct hl_loop_counts lc;
	char cls[512], name[256], why[512];
	int tests = 0, failures = 0;

	hl_loop_latency_counts(r->loop, &lc);
	snprintf(cls, sizeof(cls), "%s", r->scenario_path);
	if (ecu_error) {
		tests++;
		failures++;
		if (!count_only)
			testcase(f, cls, "ecu", ecu_error);
	}
	tests++;
	why[0] = '\0';
	if (r->frames == 0)
		snprintf(why, sizeof(why), "no frame judged");
	else if (lc.frames_dropped || lc.frames_judged != lc.frames_in)
		snprintf(why, sizeof(why), "%" PRIu64 " of %" PRIu64 " frames not judged",
			 lc.frames_in - lc.frames_judged, lc.frames_in);
	failures += why[0] != '\0';
	if (!count_only)
		testcase(f, cls, "frames", why[0] ? why : NULL);
	for (int i = 0; r->verdicts && i < hl_verdicts_n_sets(r->verdicts); i++) {
		tests++;
		snprintf(name, sizeof(name), "verdict set %s", hl_verdicts_set(r->verdicts, i)->id);
		why[0] = '\0';
		if (r->verdict_failed_frames[i])
			snprintf(why, sizeof(why), "failed on %" PRIu64 " of %" PRIu64 " frames",
				 r->verdict_failed_frames[i], r->verdict_frames[i]);
		failures += why[0] != '\0';
		if (!count_only)
			testcase(f, cls, name, why[0] ? why : NULL);
	}
	for (int a = 0; a < lc.n_actors && a < r->sc->n_actors; a++) {
		const struct hl_loop_actor *ac = &lc.actor[a];

		tests++;
		snprintf(name, sizeof(name), "glare at %s", r->sc->actor[a].id);
		why[0] = '\0';
		if (strict && ac->frames_over)
			snprintf(why, sizeof(why),
				 "over its limit on %" PRIu64
				 " frames (%.3f s), highest %.4g lx (no "
				 "restbus, no camera: every frame counts)",
				 ac->frames_over, ac->glare_total_s, ac->max_lux);
		else if (!strict && ac->frames_over_late)
			snprintf(why, sizeof(why),
				 "over its limit in view after the reaction time on %" PRIu64
				 " frames (%.3f s), highest %.4g lx",
				 ac->frames_over_late, ac->glare_late_s, ac->max_lux);
		failures += why[0] != '\0';
		if (!count_only)
			testcase(f, cls, name, why[0] ? why : NULL);
	}
	*ret_tests = tests;
	*ret_failures = failures;
}

struct junit {
	const struct hl_loop_report *r;
	const char *ecu_error;
};

static void write_file(void *ctx, FILE *f)
{
	const struct junit *j = ctx;
	int tests, failures;

	write_cases(j->r, j->ecu_error, NULL, &tests, &failures, true);
	fputs("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites>\n  <testsuite name=\"", f);
	hl_xml_write_text(f, j->r->scenario_path);
	fprintf(f, "\" tests=\"%d\" failures=\"%d\" errors=\"0\" skipped=\"0\">\n", tests,
		failures);
	fputs("    <properties>\n      <property name=\"ecu\" value=\"", f);
	hl_xml_write_text(f, j->r->ecu ? j->r->ecu : "");
	fputs("\"/>\n    </properties>\n", f);
	write_cases(j->r, j->ecu_error, f, &tests, &failures, false);
	fputs("  </testsuite>\n</testsuites>\n", f);
}

int hl_loop_junit_write(const struct hl_loop_report *r, const char *ecu_error, const char *path)
{
	struct junit j = { r, ecu_error };

	return hl_file_replace(path, write_file, &j);
}
