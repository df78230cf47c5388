/* SPDX-License-Identifier: MIT */
/* A suite's scenarios made concrete: see verdict/suite_scenario.h. */
#include "verdict/suite_scenario.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/json_write.h"
#include "verdict/photometer.h"
#include "world/world.h"

#define LEAD_M 10.0 /* the straight before a curve */
#define FAR_MARGIN_M 5.0 /* beyond the measured range at the start */
#define NEAR_MARGIN_M 1.0 /* inside its near end at the end */
#define STEP_S 0.01
#define IIHS_DURATION_S 1.0

int hl_suite_variant_count(const struct hl_suite_scenario *d, int samples)
{
	const int ns = d->speed_mph[0] == d->speed_mph[1] ? 1 : samples;
	const int nr = d->road == HL_SUITE_STRAIGHT || d->radius_m[0] == d->radius_m[1] ? 1 :
											  samples;

	return ns * nr;
}

static double sample(const double r[2], int n, int k)
{
	return n <= 1 ? r[0] : r[0] + (r[1] - r[0]) * k / (n - 1);
}

void hl_suite_variant_params(const struct hl_suite_scenario *d, int samples, int k,
			     double *ret_speed_mph, double *ret_radius_m, char *ret_id,
			     size_t id_size)
{
	const int ns = d->speed_mph[0] == d->speed_mph[1] ? 1 : samples;
	const int nr = d->road == HL_SUITE_STRAIGHT || d->radius_m[0] == d->radius_m[1] ? 1 :
											  samples;

	*ret_speed_mph = sample(d->speed_mph, ns, k / nr);
	*ret_radius_m = d->road == HL_SUITE_STRAIGHT ? 0.0 : sample(d->radius_m, nr, k % nr);
	if (d->road == HL_SUITE_STRAIGHT)
		snprintf(ret_id, id_size, "%s-%gmph", d->id, *ret_speed_mph);
	else
		snprintf(ret_id, id_size, "%s-%gmph-r%gm", d->id, *ret_speed_mph, *ret_radius_m);
}

void hl_suite_variant_title(const struct hl_suite_scenario *d, double speed_mph, double radius_m,
			    char *buf, size_t size)
{
	if (d->road == HL_SUITE_STRAIGHT)
		snprintf(buf, size, "%s at %g mph", d->title, speed_mph);
	else
		snprintf(buf, size, "%s at %g mph, radius %g m", d->title, speed_mph, radius_m);
}

/* The JSON text for a stimulus vehicle gap_m ahead (centre-line s) and a duration. */
static char *write_json(const struct hl_suite_scenario *d, double speed_mph, double radius_m,
			double gap_m, double duration_s)
{
	const double v = speed_mph * HL_SUITE_MPH_MPS;
	const double ego_s = LEAD_M;
	char *text = NULL, title[HL_SUITE_TEXT_MAX + 64];
	size_t n = 0;
	FILE *f = open_memstream(&text, &n);

	if (!f)
		return NULL;
	hl_suite_variant_title(d, speed_mph, radius_m, title, sizeof(title));
	fprintf(f, "{\n  \"version\": 1,\n  \"title\": ");
	hl_json_write_str(f, title);
	fprintf(f, ",\n  \"duration_s\": %.3f,\n  \"road\": {\n    \"segments\": [\n", duration_s);
	if (d->road == HL_SUITE_STRAIGHT)
		fprintf(f, "      {\"kind\": \"straight\", \"length_m\": %.3f}\n",
			LEAD_M + gap_m + 200.0);
	else
		fprintf(f,
			"      {\"kind\": \"straight\", \"length_m\": %.3f},\n"
			"      {\"kind\": \"arc\", \"length_m\": %.3f, \"radius_m\": %.3f, "
			"\"turn\": \"%s\"}\n",
			LEAD_M, fmin(gap_m + 400.0, 1.9 * M_PI * radius_m), radius_m,
			d->road == HL_SUITE_LEFT ? "left" : "right");
	fprintf(f, "    ],\n    \"lanes\": {\"count\": 2, \"width_m\": 3.5}\n  },\n");
	fprintf(f, "  \"ego\": {\"start_s_m\": %.3f, \"lane\": 1, \"speed_mps\": %.6f}", ego_s, v);
	if (d->has_role)
		fprintf(f,
			",\n  \"actors\": [\n    {\"id\": \"stimulus\", \"kind\": \"car\", \"role\": "
			"\"%s\",\n     \"path\": {\"lane\": %d, \"start_s_m\": %.3f, "
			"\"speed_mps\": 0}}\n  ]",
			hl_actor_role_name(d->role), d->role == HL_ROLE_ONCOMING ? 2 : 1,
			ego_s + gap_m);
	fprintf(f, "\n}\n");
	if (fclose(f) != 0) {
		free(text);
		return NULL;
	}
	return text;
}

/* The nearest and farthest of the stimulus vehicle's photometers at t. */
static void ranges_at(const struct hl_suite *s, const struct hl_scenario *sc, double t,
		      double *ret_min, double *ret_max)
{
	struct hl_world_state w;
	struct hl_lamp_pose lamps[2];
	double mid[2];

	hl_world_at(sc, t, &w);
	hl_world_ego_lamps(sc, &w.ego, lamps);
	mid[0] = 0.5 * (lamps[0].pos_m[0] + lamps[1].pos_m[0]);
	mid[1] = 0.5 * (lamps[0].pos_m[1] + lamps[1].pos_m[1]);
	*ret_min = INFINITY;
	*ret_max = -INFINITY;
	for (int p = 0; p < s->n_photometers; p++) {
		double pt[3], n[3], r;

		if (s->photometer[p].role != sc->actor[0].role)
			continue;
		hl_photometer_place(&w.actor[0], s->photometer[p].pos_m, s->photometer[p].normal,
				    pt, n);
		r = hypot(pt[0] - mid[0], pt[1] - mid[1]);
		*ret_min = fmin(*ret_min, r);
		*ret_max = fmax(*ret_max, r);
	}
}

static int parse(const char *text, struct hl_scenario **ret, char *msg, size_t msg_size)
{
	struct hl_json_error err;
	char buf[768];
	const int rc = hl_scenario_parse(text, "(generated scenario)", ret, &err);

	if (rc < 0)
		snprintf(msg, msg_size, "%s", hl_json_error_format(&err, buf, sizeof(buf)));
	return rc;
}

int hl_suite_variant_scenario(const struct hl_suite *s, const struct hl_suite_scenario *d,
			      double speed_mph, double radius_m, char **ret, char *msg,
			      size_t msg_size)
{
	const double v = speed_mph * HL_SUITE_MPH_MPS;
	double gap = d->range_m[1] + FAR_MARGIN_M + 10.0, duration = 0.0;
	struct hl_scenario *sc = NULL;
	char *text;
	int rc, tries;

	if (!d->has_role) {
		text = write_json(d, speed_mph, radius_m, 0.0, IIHS_DURATION_S);
		if (!text)
			return -ENOMEM;
		rc = parse(text, &sc, msg, msg_size);
		hl_scenario_free(sc);
		if (rc < 0) {
			free(text);
			return rc;
		}
		*ret = text;
		return 0;
	}
	if (!(v > 0.0)) {
		snprintf(msg, msg_size, "%s: a stimulus vehicle's scenario needs a speed above 0",
			 d->id);
		return -EINVAL;
	}
	/* the gap (along the centre line) that puts every photometer beyond the range */
	for (tries = 0; tries < 400; tries++, gap += 2.0) {
		double lo, hi;

		/* on a curve the stimulus vehicle stands on the arc, not on the road after it */
		if (d->road != HL_SUITE_STRAIGHT && gap > 1.9 * M_PI * radius_m - 50.0)
			break;

		text = write_json(d, speed_mph, radius_m, gap, 1.0);
		if (!text)
			return -ENOMEM;
		rc = parse(text, &sc, msg, msg_size);
		free(text);
		if (rc < 0)
			return rc;
		ranges_at(s, sc, 0.0, &lo, &hi);
		if (!isfinite(lo)) {
			hl_scenario_free(sc);
			snprintf(msg, msg_size, "%s: the suite has no photometer on a %s vehicle",
				 d->id, hl_actor_role_name(d->role));
			return -EINVAL;
		}
		if (lo >= d->range_m[1] + FAR_MARGIN_M)
			break;
		hl_scenario_free(sc);
		sc = NULL;
	}
	if (!sc) {
		snprintf(msg, msg_size, "%s: no start gives a range of %g m on a %g m radius",
			 d->id, d->range_m[1], radius_m);
		return -EINVAL;
	}
	/* the end: every photometer inside the near end */
	for (int k = 1;; k++) {
		const double t = k * STEP_S;
		double lo, hi;

		if (v * t > gap + 50.0) {
			hl_scenario_free(sc);
			snprintf(msg, msg_size, "%s: the range never falls below %g m", d->id,
				 d->range_m[0]);
			return -EINVAL;
		}
		ranges_at(s, sc, t, &lo, &hi);
		if (hi <= d->range_m[0] - NEAR_MARGIN_M) {
			duration = t;
			break;
		}
	}
	hl_scenario_free(sc);
	text = write_json(d, speed_mph, radius_m, gap, duration);
	if (!text)
		return -ENOMEM;
	*ret = text;
	return 0;
}
