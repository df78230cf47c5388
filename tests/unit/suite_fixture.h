/* SPDX-License-Identifier: MIT */
/*
 * A suite and a suite run built by hand for the verdict/suite_* tests (header-only): the FMVSS
 * 108 ADB oncoming bins (15.0-29.9 m 3.1 lx, 30.0-59.9 1.8, 60.0-119.9 0.6, 120.0-220 0.3), a
 * preceding bin without a limit, and one variant whose cases follow the bins.
 */
#ifndef HL_TESTS_SUITE_FIXTURE_H
#define HL_TESTS_SUITE_FIXTURE_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "verdict/suite_result.h"

static const struct {
	double from_m, to_m, max_lx;
} fixture_bins[] = { { 15.0, 29.9, 3.1 },
		     { 30.0, 59.9, 1.8 },
		     { 60.0, 119.9, 0.6 },
		     { 120.0, 220.0, 0.3 } };
#define FIXTURE_N_BINS 4

static inline struct hl_suite *fixture_suite(void)
{
	struct hl_suite *s = calloc(1, sizeof(*s));

	if (!s)
		abort();
	snprintf(s->name, sizeof(s->name), "fmvss108-adb");
	snprintf(s->title, sizeof(s->title), "FMVSS 108 ADB track test");
	s->procedure = HL_SUITE_FMVSS108_ADB;
	snprintf(s->source, sizeof(s->source), "49 CFR 571.108 S14.9.3.11, Table XXI");
	s->has_rounding = true;
	s->decimals = 1;
	s->rounding = HL_SUITE_HALF_EVEN;
	snprintf(s->rounding_source, sizeof(s->rounding_source), "S14.9.3.11.4");
	for (int i = 0; i < FIXTURE_N_BINS; i++) {
		struct hl_suite_bin *b = &s->bin[s->n_bins++];

		b->role = HL_ROLE_ONCOMING;
		b->from_m = fixture_bins[i].from_m;
		b->to_m = fixture_bins[i].to_m;
		b->max_lx = fixture_bins[i].max_lx;
		snprintf(b->source, sizeof(b->source), "Table XXI row %d", i + 1);
	}
	s->bin[s->n_bins] = (struct hl_suite_bin){
		.role = HL_ROLE_PRECEDING, .from_m = 15.0, .to_m = 29.9, .max_lx = NAN
	};
	s->n_bins++;
	s->n_defaults = 1;
	snprintf(s->def[0].what, sizeof(s->def[0].what), "photometer height");
	snprintf(s->def[0].value, sizeof(s->def[0].value), "1.1 m");
	snprintf(s->def[0].why, sizeof(s->def[0].why), "driver's eye, a <guess> & \"typical\"");
	return s;
}

/* A case for bin b of the fixture with the given maximum (NAN: never reached). */
static inline struct hl_suite_case fixture_case(int b, double max_raw, double at_range_m)
{
	struct hl_suite_case k = { 0 };

	snprintf(k.name, sizeof(k.name), "oncoming %.1f-%.1f m, photometer driver",
		 fixture_bins[b].from_m, fixture_bins[b].to_m);
	snprintf(k.photometer, sizeof(k.photometer), "driver");
	k.from_m = fixture_bins[b].from_m;
	k.to_m = fixture_bins[b].to_m;
	k.unit = "lx";
	k.n_samples = isnan(max_raw) ? 0 : 10;
	k.max_raw = max_raw;
	k.value = isnan(max_raw) ? NAN : round(max_raw * 10.0) / 10.0;
	k.at_range_m = at_range_m;
	k.at_t_s = 1.0;
	k.limit = fixture_bins[b].max_lx;
	k.margin = k.limit - k.value;
	k.judged = !isnan(max_raw);
	k.pass = !k.judged || k.value <= k.limit;
	k.no_samples = isnan(max_raw);
	snprintf(k.source, sizeof(k.source), "Table XXI row %d", b + 1);
	return k;
}

/* A variant with the fixture's four bins judged, every one passing. */
static inline void fixture_variant(struct hl_suite_variant *v, const char *id)
{
	memset(v, 0, sizeof(*v));
	snprintf(v->id, sizeof(v->id), "%s", id);
	snprintf(v->scenario_id, sizeof(v->scenario_id), "oncoming-straight");
	snprintf(v->title, sizeof(v->title), "Oncoming, straight (%s)", id);
	v->road = HL_SUITE_STRAIGHT;
	v->speed_mph = 25.0;
	v->range_m[0] = 15.0;
	v->range_m[1] = 220.0;
	v->cases = calloc(FIXTURE_N_BINS, sizeof(*v->cases));
	if (!v->cases)
		abort();
	v->n_cases = FIXTURE_N_BINS;
	for (int b = 0; b < FIXTURE_N_BINS; b++)
		v->cases[b] = fixture_case(b, fixture_bins[b].max_lx / 2.0, fixture_bins[b].from_m);
	snprintf(v->series[0].label, sizeof(v->series[0].label), "driver");
	v->series[0].role = HL_ROLE_ONCOMING;
	v->n_series = 1;
	snprintf(v->scenario_file, sizeof(v->scenario_file), "%s.json", id);
	snprintf(v->trace_file, sizeof(v->trace_file), "%s.log", id);
	snprintf(v->plot_file, sizeof(v->plot_file), "%s.svg", id);
	v->n_frames = 300;
}

/* A result of n variants on suite s (all passing). */
static inline void fixture_result(struct hl_suite_result *r, const struct hl_suite *s, int n)
{
	memset(r, 0, sizeof(*r));
	r->suite = s;
	snprintf(r->ecu, sizeof(r->ecu), "reference");
	r->v = calloc((size_t)n, sizeof(*r->v));
	if (!r->v)
		abort();
	r->n_variants = n;
	for (int i = 0; i < n; i++) {
		char id[32];

		snprintf(id, sizeof(id), "oncoming-straight-%d", i);
		fixture_variant(&r->v[i], id);
	}
}

#endif
