/* SPDX-License-Identifier: MIT */
/*
 * verdict/suite_scenario.c: the FMVSS 108 suite's eight Table XXII rows give 28 variants (the
 * ends of each speed and radius range) with the ids and titles the reports use; each variant's
 * scenario is one the scenario reader accepts, with the test vehicle at the variant's speed in
 * lane 1 and the stimulus vehicle standing where the table's role puts it; at t 0 every
 * photometer is at least 5 m beyond the measured range, and at the scenario's end every one is
 * 1 m inside its near end; more samples on request; a road too tight for the range is refused.
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "verdict/photometer.h"
#include "verdict/suite_scenario.h"
#include "world/world.h"
#include "suite_util.h"

/* The nearest and farthest photometer of the stimulus vehicle from the lamps' midpoint. */
static void ranges(const struct hl_suite *s, const struct hl_scenario *sc, double t, double *lo,
		   double *hi)
{
	struct hl_world_state w;
	struct hl_lamp_pose lamps[2];

	hl_world_at(sc, t, &w);
	hl_world_ego_lamps(sc, &w.ego, lamps);
	*lo = INFINITY;
	*hi = -INFINITY;
	for (int p = 0; p < s->n_photometers; p++) {
		double pt[3], n[3], r;

		if (s->photometer[p].role != sc->actor[0].role)
			continue;
		hl_photometer_place(&w.actor[0], s->photometer[p].pos_m, s->photometer[p].normal,
				    pt, n);
		r = hypot(pt[0] - 0.5 * (lamps[0].pos_m[0] + lamps[1].pos_m[0]),
			  pt[1] - 0.5 * (lamps[0].pos_m[1] + lamps[1].pos_m[1]));
		*lo = fmin(*lo, r);
		*hi = fmax(*hi, r);
	}
}

static void scenario_fmvss_variants(void **state)
{
	(void)state;
	struct hl_suite *s = read_shipped("fmvss108-adb");
	int total = 0;

	for (int i = 0; i < s->n_scenarios; i++) {
		const struct hl_suite_scenario *d = &s->scenario[i];
		const int n = hl_suite_variant_count(d, 2);

		assert_int_equal(n, d->road == HL_SUITE_STRAIGHT ? 2 : 4);
		for (int k = 0; k < n; k++) {
			struct hl_scenario *sc = NULL;
			struct hl_json_error err;
			double speed, radius, lo, hi;
			char id[96], want[96], msg[1024], *text = NULL;

			hl_suite_variant_params(d, 2, k, &speed, &radius, id, sizeof(id));
			/* speed outer, radius inner: lo/lo, lo/hi, hi/lo, hi/hi */
			assert_true(speed ==
				    d->speed_mph[d->road == HL_SUITE_STRAIGHT ? k : k / 2]);
			if (d->road == HL_SUITE_STRAIGHT) {
				assert_true(radius == 0.0);
				snprintf(want, sizeof(want), "%s-%gmph", d->id, speed);
			} else {
				assert_true(radius == d->radius_m[k % 2]);
				snprintf(want, sizeof(want), "%s-%gmph-r%gm", d->id, speed, radius);
			}
			assert_string_equal(id, want);
			if (hl_suite_variant_scenario(s, d, speed, radius, &text, msg,
						      sizeof(msg)) < 0)
				fail_msg("%s: %s", id, msg);
			if (hl_scenario_parse(text, id, &sc, &err) < 0)
				fail_msg("%s: %s", id,
					 hl_json_error_format(&err, msg, sizeof(msg)));
			assert_int_equal(sc->ego.path.speed.n, 1);
			assert_true(fabs(sc->ego.path.speed.v_mps[0] - speed * 0.44704) < 1e-6);
			assert_int_equal(sc->ego.path.lane, 1);
			assert_int_equal(sc->n_actors, 1);
			assert_int_equal(sc->actor[0].role, d->role);
			ranges(s, sc, 0.0, &lo, &hi);
			assert_true(lo >= d->range_m[1] + 5.0);
			ranges(s, sc, sc->duration_s, &lo, &hi);
			assert_true(hi <= d->range_m[0] - 1.0);
			/* the step before the end was not yet inside */
			ranges(s, sc, sc->duration_s - 0.01, &lo, &hi);
			assert_true(hi > d->range_m[0] - 1.0);
			hl_scenario_free(sc);
			free(text);
			total++;
		}
	}
	assert_int_equal(total, 28);
	hl_suite_free(s);
}

static void scenario_titles_and_samples(void **state)
{
	(void)state;
	struct hl_suite *s = read_shipped("fmvss108-adb");
	const struct hl_suite_scenario *curve = &s->scenario[1]; /* oncoming left 85-115 m */
	double speed, radius;
	char id[96], title[600];

	assert_int_equal(curve->road, HL_SUITE_LEFT);
	hl_suite_variant_title(curve, 25, 85, title, sizeof(title));
	assert_true(strstr(title, " at 25 mph, radius 85 m") != NULL);
	/* three samples: 25, 27.5, 30 mph by 85, 100, 115 m */
	assert_int_equal(hl_suite_variant_count(curve, 3), 9);
	hl_suite_variant_params(curve, 3, 4, &speed, &radius, id, sizeof(id));
	assert_true(speed == 27.5 && radius == 100.0);
	assert_string_equal(id, "oncoming-left-85m-27.5mph-r100m");
	hl_suite_free(s);
}

static void scenario_refuses_what_the_geometry_cannot_give(void **state)
{
	(void)state;
	struct hl_suite *s = read_shipped("fmvss108-adb");
	struct hl_suite_scenario d = s->scenario[1];
	char msg[1024] = "", *text = NULL;

	/* 400 m of range on a 20 m radius: no start puts the car that far away */
	d.range_m[1] = 400.0;
	assert_int_equal(hl_suite_variant_scenario(s, &d, 25, 20, &text, msg, sizeof(msg)),
			 -EINVAL);
	assert_null(text);
	assert_non_null(strstr(msg, "no start gives a range of 400 m"));
	/* a standing test vehicle never closes the range */
	d = s->scenario[0];
	assert_int_equal(hl_suite_variant_scenario(s, &d, 0, 0, &text, msg, sizeof(msg)), -EINVAL);
	assert_non_null(strstr(msg, "needs a speed above 0"));
	hl_suite_free(s);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(scenario_fmvss_variants),
		cmocka_unit_test(scenario_titles_and_samples),
		cmocka_unit_test(scenario_refuses_what_the_geometry_cannot_give),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
