/* SPDX-License-Identifier: MIT */
/*
 * world/osi_replay.c: OSI traces written here (frames encoded with hl_osi_encode(), framed with
 * hl_osi_trace_write()) loaded as scenarios: a clean trace as a track at the messages' own
 * times; a trace with one fault of each kind counted by reason with the first message and why;
 * the message kind from the file name and the refusals; a road from the base scenario; world
 * source names.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "osi_fixture.h"
#include "scenario_util.h"
#include "testutil.h"
#include "world/osi_msg.h"
#include "world/osi_replay.h"
#include "world/osi_trace.h"
#include "world/scenario.h"
#include "world/track.h"
#include "world/world.h"

#define MS 1000000LL /* ns */

static void put(FILE *fp, const struct hl_osi_frame *f, enum hl_osi_kind kind)
{
	uint8_t *buf = NULL;
	size_t len = 0;

	assert_int_equal(hl_osi_encode(f, kind, &buf, &len), 0);
	assert_int_equal(hl_osi_trace_write(fp, buf, len), 0);
	free(buf);
}

/* A message at t_ns: the host dx along the road at 20 m/s, a preceding car 30 m ahead of it. */
static struct hl_osi_frame *moving(int64_t t_ns, double dx, bool boundaries)
{
	struct hl_osi_frame *f = osi_message(t_ns);

	f->object[0].pos_m[0] += dx;
	f->object[0].vel_mps[0] = 20.0;
	osi_add_vehicle(f, 2, HL_OSI_VEHICLE_MEDIUM_CAR, 30.0 + dx, -1.75, 0.0);
	if (!boundaries) {
		f->n_boundaries = 0;
		f->n_points = 0;
	}
	return f;
}

/* A trace of n messages from t0_ns every 20 ms, of kind, at path. */
static void write_clean(const char *path, int n, int64_t t0_ns, enum hl_osi_kind kind,
			bool boundaries)
{
	FILE *fp = fopen(path, "wb");

	assert_non_null(fp);
	for (int i = 0; i < n; i++) {
		struct hl_osi_frame *f = moving(t0_ns + 20 * MS * i, 0.4 * i, boundaries);

		put(fp, f, kind);
		hl_osi_frame_free(f);
	}
	assert_int_equal(fclose(fp), 0);
}

static void expect_has(const char *s, const char *part)
{
	if (!strstr(s, part))
		fail_msg("'%s' lacks '%s'", s, part);
}

static void osi_replay_clean_trace(void **state)
{
	(void)state;
	struct hl_osi_replay_report rep;
	struct hl_scenario *sc = NULL;
	struct hl_world_state st;
	char path[512], err[512] = "";

	test_path(path, sizeof(path), "20260101T000000Z_gt_3.7.0_3.21.12_5_clean.osi");
	write_clean(path, 5, 10000 * MS, HL_OSI_GROUND_TRUTH, true);
	if (hl_osi_replay_load(path, NULL, NULL, &sc, &rep, err, sizeof(err)) < 0)
		fail_msg("%s", err);
	assert_int_equal(rep.kind, HL_OSI_GROUND_TRUTH);
	assert_int_equal(rep.messages, 5);
	assert_int_equal(rep.taken, 5);
	assert_int_equal(rep.counts[HL_OSI_OK], 5);
	for (int r = 1; r < HL_OSI_REASONS; r++)
		assert_int_equal(rep.counts[r], 0);
	assert_int_equal(rep.t0_ns, 10000 * MS);
	/* scenario time 0 at the first message; the scenario lasts until the last */
	assert_float_equal(sc->duration_s, 0.08, 1e-12);
	assert_non_null(sc->track);
	assert_int_equal(hl_world_track_count(sc->track), 5);
	assert_int_equal(sc->n_actors, 1);
	assert_string_equal(sc->actor[0].id, "osi-2");
	assert_int_equal(sc->road.lanes, 2);
	assert_float_equal(sc->road.lane_width_m, 3.5, 1e-12);
	for (int i = 0; i < 5; i++)
		assert_float_equal(hl_world_track_state(sc->track, (size_t)i)->t_s, 0.02 * i,
				   1e-12);
	/* at the third message: its poses; halfway to the fourth: halfway between */
	hl_world_at(sc, 0.05, &st);
	assert_float_equal(st.t_s, 0.05, 0.0);
	assert_float_equal(st.ego.pos_m[0], 1.0, 1e-9);
	hl_world_at(sc, 0.04, &st);
	assert_float_equal(st.t_s, 0.04, 0.0);
	assert_float_equal(st.ego.pos_m[0], 0.8, 1e-9);
	assert_float_equal(st.ego.pos_m[1], -1.75, 1e-12);
	assert_float_equal(st.ego.speed_mps, 20.0, 1e-12);
	assert_true(hl_world_present(&st, 0));
	assert_float_equal(st.actor[0].pos_m[0], 32.25 + 0.8, 1e-9);
	hl_scenario_free(sc);
	unlink(path);
}

static void osi_replay_counts_by_reason(void **state)
{
	(void)state;
	static const uint8_t malformed[] = { 0x0a, 0x50, 0x01 }; /* 80 bytes promised, 1 there */
	static const uint8_t cut[] = { 100, 0, 0, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10 };
	struct hl_osi_replay_report rep;
	struct hl_scenario *sc = NULL;
	struct hl_osi_frame *f;
	char path[512], err[512] = "";
	FILE *fp;
	long end;

	test_path(path, sizeof(path), "20260101T000000Z_gt_3.7.0_3.21.12_9_faults.osi");
	fp = fopen(path, "wb");
	assert_non_null(fp);
	/* 0: malformed */
	assert_int_equal(hl_osi_trace_write(fp, malformed, sizeof(malformed)), 0);
	/* 1: no timestamp */
	f = moving(500 * MS, 0.0, true);
	f->has_timestamp = false;
	put(fp, f, HL_OSI_GROUND_TRUTH);
	hl_osi_frame_free(f);
	/* 2: no host */
	f = moving(600 * MS, 0.0, true);
	f->has_host = false;
	put(fp, f, HL_OSI_GROUND_TRUTH);
	hl_osi_frame_free(f);
	/* 3, 4: taken */
	for (int i = 0; i < 2; i++) {
		f = moving(1000 * MS + 20 * MS * i, 0.0, true);
		put(fp, f, HL_OSI_GROUND_TRUTH);
		hl_osi_frame_free(f);
	}
	/* 5: past (the time of 3) */
	f = moving(1000 * MS, 0.0, true);
	put(fp, f, HL_OSI_GROUND_TRUTH);
	hl_osi_frame_free(f);
	/* 6: 1.48 s after 4: a time jump, taken; 7 after it, taken */
	for (int i = 0; i < 2; i++) {
		f = moving(2500 * MS + 20 * MS * i, 0.0, true);
		put(fp, f, HL_OSI_GROUND_TRUTH);
		hl_osi_frame_free(f);
	}
	/* 8: a host with a NaN position: bad_value */
	f = moving(2600 * MS, 0.0, true);
	f->object[0].pos_m[1] = NAN;
	put(fp, f, HL_OSI_GROUND_TRUTH);
	hl_osi_frame_free(f);
	/* 9: the preceding car NaN (taken; the object counted), then a cut message */
	f = moving(2620 * MS, 0.0, true);
	f->object[1].pos_m[0] = NAN;
	put(fp, f, HL_OSI_GROUND_TRUTH);
	hl_osi_frame_free(f);
	end = ftell(fp);
	assert_int_equal(fwrite(cut, 1, sizeof(cut), fp), sizeof(cut));
	assert_int_equal(fclose(fp), 0);

	if (hl_osi_replay_load(path, NULL, NULL, &sc, &rep, err, sizeof(err)) < 0)
		fail_msg("%s", err);
	assert_int_equal(rep.messages, 10);
	assert_int_equal(rep.taken, 5);
	assert_int_equal(rep.counts[HL_OSI_OK], 5);
	assert_int_equal(rep.t0_ns, 1000 * MS);
	assert_float_equal(sc->duration_s, 1.62, 1e-12);
	assert_int_equal(hl_world_track_count(sc->track), 5);
	{
		static const struct {
			enum hl_osi_reason r;
			uint64_t count;
			size_t first;
			const char *why;
		} want[] = {
			{ HL_OSI_MALFORMED, 1, 0, "" },
			{ HL_OSI_NO_TIMESTAMP, 1, 1, "no timestamp" },
			{ HL_OSI_NO_HOST, 1, 2, "no host_vehicle_id" },
			{ HL_OSI_PAST, 1, 5,
			  "timestamp 1.000000000 s: not after the last taken message's "
			  "1.020000000 s" },
			{ HL_OSI_TIME_JUMP, 1, 6,
			  "1.480000000 s after the message before: over 1 s" },
			{ HL_OSI_BAD_VALUE, 1, 8, "object 1: base.position.y nan" },
			{ HL_OSI_OBJECT_BAD_VALUE, 1, 0, NULL }, /* an object: no message's fault */
			{ HL_OSI_TRUNCATED, 1, 10, "the file ends in a message" },
		};

		for (size_t i = 0; i < sizeof(want) / sizeof(want[0]); i++) {
			const enum hl_osi_reason r = want[i].r;

			if (rep.counts[r] != want[i].count)
				fail_msg("%s: %llu, expected %llu", hl_osi_reason_name(r),
					 (unsigned long long)rep.counts[r],
					 (unsigned long long)want[i].count);
			if (!want[i].why)
				continue;
			assert_int_equal(rep.first[r], want[i].first);
			expect_has(rep.why[r], want[i].why);
			assert_true(rep.why[r][0] != '\0');
		}
		for (int r = 1; r < HL_OSI_REASONS; r++) {
			bool listed = false;

			for (size_t i = 0; i < sizeof(want) / sizeof(want[0]); i++)
				listed |= want[i].r == (enum hl_osi_reason)r;
			if (!listed && rep.counts[r])
				fail_msg("%s: %llu, expected 0", hl_osi_reason_name(r),
					 (unsigned long long)rep.counts[r]);
		}
	}
	{
		char where[128];

		snprintf(where, sizeof(where), "at byte %ld expected 104 bytes, found 14", end);
		expect_has(rep.why[HL_OSI_TRUNCATED], where);
	}
	/* the message with the NaN car: taken, the car absent */
	{
		const struct hl_world_state *st = hl_world_track_state(sc->track, 4);

		assert_float_equal(st->t_s, 1.62, 1e-12);
		assert_false(hl_world_present(st, 0));
		assert_true(hl_world_present(hl_world_track_state(sc->track, 3), 0));
	}
	hl_scenario_free(sc);
	unlink(path);
}

static void osi_replay_kind_from_the_name(void **state)
{
	(void)state;
	const enum hl_osi_kind gt = HL_OSI_GROUND_TRUTH, sv = HL_OSI_SENSOR_VIEW;
	struct hl_osi_replay_report rep;
	struct hl_scenario *sc = NULL;
	char path[512], err[1024] = "";

	/* _sv_: sensor views */
	test_path(path, sizeof(path), "20260101T000000Z_sv_3.7.0_3.21.12_3_view.osi");
	write_clean(path, 3, 0, HL_OSI_SENSOR_VIEW, true);
	if (hl_osi_replay_load(path, NULL, NULL, &sc, &rep, err, sizeof(err)) < 0)
		fail_msg("%s", err);
	assert_int_equal(rep.kind, HL_OSI_SENSOR_VIEW);
	assert_int_equal(rep.taken, 3);
	assert_int_equal(rep.t0_ns, 0);
	assert_float_equal(sc->duration_s, 0.04, 1e-12);
	hl_scenario_free(sc);
	sc = NULL;
	/* the kind given overrides the name */
	if (hl_osi_replay_load(path, &sv, NULL, &sc, &rep, err, sizeof(err)) < 0)
		fail_msg("%s", err);
	assert_int_equal(rep.taken, 3);
	hl_scenario_free(sc);
	sc = NULL;
	unlink(path);

	/* no convention in the name: the kind must be given */
	test_path(path, sizeof(path), "recording.osi");
	write_clean(path, 2, 0, HL_OSI_GROUND_TRUTH, true);
	assert_int_equal(hl_osi_replay_load(path, NULL, NULL, &sc, &rep, err, sizeof(err)),
			 -EINVAL);
	assert_null(sc);
	expect_has(err, path);
	expect_has(err, "the file name does not say the message");
	if (hl_osi_replay_load(path, &gt, NULL, &sc, &rep, err, sizeof(err)) < 0)
		fail_msg("%s", err);
	assert_int_equal(rep.taken, 2);
	hl_scenario_free(sc);
	sc = NULL;
	unlink(path);

	/* another type of OSI's naming (sensor data): not ours to read */
	test_path(path, sizeof(path), "20260101T000000Z_sd_3.7.0_3.21.12_2_data.osi");
	write_clean(path, 2, 0, HL_OSI_GROUND_TRUTH, true);
	assert_int_equal(hl_osi_replay_load(path, NULL, NULL, &sc, &rep, err, sizeof(err)),
			 -EINVAL);
	assert_null(sc);
	unlink(path);

	/* a missing file */
	test_path(path, sizeof(path), "20260101T000000Z_gt_3.7.0_3.21.12_0_none.osi");
	assert_int_equal(hl_osi_replay_load(path, NULL, NULL, &sc, &rep, err, sizeof(err)),
			 -ENOENT);
	assert_null(sc);
	expect_has(err, path);
	expect_has(err, "No such file");

	/* an empty file: no message */
	test_path(path, sizeof(path), "20260101T000000Z_gt_3.7.0_3.21.12_0_empty.osi");
	write_clean(path, 0, 0, HL_OSI_GROUND_TRUTH, true);
	assert_int_equal(hl_osi_replay_load(path, NULL, NULL, &sc, &rep, err, sizeof(err)),
			 -EINVAL);
	assert_null(sc);
	{
		char want[600];

		snprintf(want, sizeof(want), "%s: no message in the file", path);
		assert_string_equal(err, want);
	}
	unlink(path);
}

static void osi_replay_no_usable_message(void **state)
{
	(void)state;
	struct hl_osi_replay_report rep;
	struct hl_scenario *sc = NULL;
	struct hl_osi_frame *f;
	char path[512], err[1024] = "";
	FILE *fp;

	/* every message without a host */
	test_path(path, sizeof(path), "20260101T000000Z_gt_3.7.0_3.21.12_2_nohost.osi");
	fp = fopen(path, "wb");
	assert_non_null(fp);
	for (int i = 0; i < 2; i++) {
		f = moving(20 * MS * i, 0.0, true);
		f->host_id = 77;
		put(fp, f, HL_OSI_GROUND_TRUTH);
		hl_osi_frame_free(f);
	}
	assert_int_equal(fclose(fp), 0);
	assert_int_equal(hl_osi_replay_load(path, NULL, NULL, &sc, &rep, err, sizeof(err)),
			 -EINVAL);
	assert_null(sc);
	expect_has(err, path);
	expect_has(err, "no usable ground-truth message; the first fault: message 0: "
			"host_vehicle_id 77 is none of the 2 moving objects");
	unlink(path);
}

static void osi_replay_road_from_base(void **state)
{
	(void)state;
	struct hl_scenario *base = shipped("preceding-car.json");
	struct hl_osi_replay_report rep;
	struct hl_scenario *sc = NULL;
	char path[512], err[1024] = "";

	test_path(path, sizeof(path), "20260101T000000Z_gt_3.7.0_3.21.12_4_noroad.osi");
	write_clean(path, 4, 0, HL_OSI_GROUND_TRUTH, false);
	/* without lane boundaries and without a base: no road */
	assert_int_equal(hl_osi_replay_load(path, NULL, NULL, &sc, &rep, err, sizeof(err)),
			 -ENOENT);
	assert_null(sc);
	expect_has(err, "no lane boundaries");
	/* with a base: its road */
	if (hl_osi_replay_load(path, NULL, base, &sc, &rep, err, sizeof(err)) < 0)
		fail_msg("%s", err);
	assert_int_equal(rep.taken, 4);
	assert_memory_equal(&sc->road, &base->road, sizeof(base->road));
	assert_memory_equal(sc->ego.lamp, base->ego.lamp, sizeof(base->ego.lamp));
	assert_null(base->track);
	hl_scenario_free(sc);
	hl_scenario_free(base);
	unlink(path);
}

static void osi_replay_spec_parse(void **state)
{
	(void)state;
	static const char *const bad[] = {
		"",
		"osi:",
		"osi:file:",
		"osi:udp:",
		"file:/tmp/x.osi",
		"udp:127.0.0.1:48198",
		"osi:tcp:127.0.0.1:1",
		"OSI:file:x",
	};
	struct hl_osi_spec spec;
	char err[256], *long_spec;

	assert_int_equal(hl_osi_spec_parse("osi:file:/data/a_gt_b.osi", &spec, err, sizeof(err)),
			 0);
	assert_false(spec.udp);
	assert_string_equal(spec.path, "/data/a_gt_b.osi");
	assert_string_equal(spec.listen, "");
	assert_int_equal(hl_osi_spec_parse("osi:udp:127.0.0.1:48198", &spec, err, sizeof(err)), 0);
	assert_true(spec.udp);
	assert_string_equal(spec.listen, "udp:127.0.0.1:48198");
	assert_string_equal(spec.path, "");
	for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
		err[0] = '\0';
		assert_int_equal(hl_osi_spec_parse(bad[i], &spec, err, sizeof(err)), -EINVAL);
		expect_has(err, "expected osi:file:PATH (an OSI trace) or osi:udp:HOST:PORT");
	}
	/* a path longer than the spec holds */
	long_spec = malloc(9 + sizeof(spec.path) + 1);
	assert_non_null(long_spec);
	memcpy(long_spec, "osi:file:", 9);
	memset(long_spec + 9, 'a', sizeof(spec.path));
	long_spec[9 + sizeof(spec.path)] = '\0';
	assert_int_equal(hl_osi_spec_parse(long_spec, &spec, err, sizeof(err)), -EINVAL);
	expect_has(err, "the path is too long");
	long_spec[9 + sizeof(spec.path) - 1] = '\0'; /* the longest that fits */
	assert_int_equal(hl_osi_spec_parse(long_spec, &spec, err, sizeof(err)), 0);
	assert_int_equal(strlen(spec.path), sizeof(spec.path) - 1);
	free(long_spec);
	/* no err: still refused */
	assert_int_equal(hl_osi_spec_parse("osi:", &spec, NULL, 0), -EINVAL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(osi_replay_clean_trace),
		cmocka_unit_test(osi_replay_counts_by_reason),
		cmocka_unit_test(osi_replay_kind_from_the_name),
		cmocka_unit_test(osi_replay_no_usable_message),
		cmocka_unit_test(osi_replay_road_from_base),
		cmocka_unit_test(osi_replay_spec_parse),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
