/* SPDX-License-Identifier: MIT */
/*
 * world/osi_msg.c: a frame encoded and decoded again is the same bit for bit (GroundTruth and
 * SensorView); truncated buffers are malformed; more than the limits is TOO_MANY (two encoded
 * messages concatenated merge their repeated fields, protobuf's rule, which makes one message
 * beyond what the encoder accepts); absent fields decode as NAN and 0; a SensorView's host
 * falls back to its ground truth's. Hand-written bytes below are protobuf's wire format:
 * tag = field number << 3 | wire type (0 varint, 2 length-delimited).
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

#include "world/osi_msg.h"

/* Equal as stored: both NAN, or the same bits (so -0.0 and 0.0 differ). */
static void same_num(const char *what, int i, double got, double want)
{
	if (isnan(got) && isnan(want))
		return;
	if (memcmp(&got, &want, sizeof(got)) != 0)
		fail_msg("%s[%d]: got %.17g, want %.17g", what, i, got, want);
}

static void same_vec(const char *what, int i, const double got[3], const double want[3])
{
	for (int k = 0; k < 3; k++)
		same_num(what, i * 3 + k, got[k], want[k]);
}

static void same_frame(const struct hl_osi_frame *got, const struct hl_osi_frame *want)
{
	assert_int_equal(got->has_timestamp, want->has_timestamp);
	if (want->has_timestamp)
		assert_int_equal(got->t_ns, want->t_ns);
	assert_int_equal(got->has_host, want->has_host);
	if (want->has_host)
		assert_int_equal(got->host_id, want->host_id);
	assert_int_equal(got->n_objects, want->n_objects);
	for (int i = 0; i < want->n_objects; i++) {
		const struct hl_osi_object *g = &got->object[i], *w = &want->object[i];

		assert_int_equal(g->has_id, w->has_id);
		assert_int_equal(g->id, w->id);
		assert_int_equal(g->type, w->type);
		assert_int_equal(g->has_classification, w->has_classification);
		assert_int_equal(g->vehicle_type, w->vehicle_type);
		assert_int_equal(g->head_light, w->head_light);
		assert_int_equal(g->high_beam, w->high_beam);
		assert_int_equal(g->brake_light, w->brake_light);
		assert_int_equal(g->tail_light, w->tail_light);
		same_vec("dim_m", i, g->dim_m, w->dim_m);
		same_vec("pos_m", i, g->pos_m, w->pos_m);
		same_vec("rpy_rad", i, g->rpy_rad, w->rpy_rad);
		same_vec("vel_mps", i, g->vel_mps, w->vel_mps);
	}
	assert_int_equal(got->n_boundaries, want->n_boundaries);
	for (int i = 0; i < want->n_boundaries; i++) {
		assert_int_equal(got->boundary[i].id, want->boundary[i].id);
		assert_int_equal(got->boundary[i].type, want->boundary[i].type);
		assert_int_equal(got->boundary[i].first, want->boundary[i].first);
		assert_int_equal(got->boundary[i].n, want->boundary[i].n);
	}
	assert_int_equal(got->n_points, want->n_points);
	for (int i = 0; i < want->n_points; i++) {
		same_vec("point", i, got->point[i], want->point[i]);
		same_num("point_width_m", i, got->point_width_m[i], want->point_width_m[i]);
	}
}

static void set3(double v[3], double a, double b, double c)
{
	v[0] = a;
	v[1] = b;
	v[2] = c;
}

/* Values a text format would round: thirds, tiny and huge numbers, -0.0, NAN holes. */
static struct hl_osi_frame *sample(void)
{
	struct hl_osi_frame *f = hl_osi_frame_new();
	struct hl_osi_object *o;

	assert_non_null(f);
	f->has_timestamp = true;
	f->t_ns = -1500000001; /* before zero: seconds -2, nanos 499999999 */
	f->has_host = true;
	f->host_id = UINT64_MAX - 1;

	o = &f->object[f->n_objects++];
	o->has_id = true;
	o->id = 7;
	o->type = HL_OSI_TYPE_VEHICLE;
	o->has_classification = true;
	o->vehicle_type = HL_OSI_VEHICLE_MEDIUM_CAR;
	o->head_light = HL_OSI_LIGHT_ON;
	o->high_beam = HL_OSI_LIGHT_OFF;
	o->brake_light = 4; /* BRAKE_LIGHT_STATE_STRONG */
	o->tail_light = HL_OSI_LIGHT_ON;
	set3(o->dim_m, 4.6, 1.8, 1.45);
	set3(o->pos_m, 1.0 / 3.0, -2.5e-300, 1e300);
	set3(o->rpy_rad, -0.0, 0.01, M_PI);
	set3(o->vel_mps, 22.2, -0.1, 0.0);

	o = &f->object[f->n_objects++]; /* a pedestrian: no classification, holes */
	o->has_id = true;
	o->id = 0;
	o->type = HL_OSI_TYPE_PEDESTRIAN;
	set3(o->dim_m, 0.3, 0.5, NAN);
	set3(o->pos_m, NAN, NAN, NAN);
	set3(o->rpy_rad, NAN, NAN, -1.25);
	set3(o->vel_mps, NAN, 1.4, NAN);

	o = &f->object[f->n_objects++]; /* classified, later OSI's type numbers, no lights */
	o->type = 2;
	o->has_classification = true;
	o->vehicle_type = 22;
	set3(o->dim_m, NAN, NAN, NAN);
	set3(o->pos_m, 5, 6, 7);
	set3(o->rpy_rad, NAN, NAN, NAN);
	set3(o->vel_mps, NAN, NAN, NAN);

	f->boundary[0] = (struct hl_osi_boundary){
		.id = 100, .type = HL_OSI_BOUNDARY_SOLID_LINE, .first = 0, .n = 3
	};
	f->boundary[1] = (struct hl_osi_boundary){ .id = 101, .type = 0, .first = 3, .n = 0 };
	f->boundary[2] = (struct hl_osi_boundary){
		.id = 102, .type = HL_OSI_BOUNDARY_CURB, .first = 3, .n = 2
	};
	f->n_boundaries = 3;
	for (int i = 0; i < 5; i++) {
		set3(f->point[i], i * 10.1, -1.75, 0.001 * i);
		f->point_width_m[i] = i == 1 ? NAN : 0.15;
	}
	f->point[4][2] = NAN;
	f->n_points = 5;
	return f;
}

static void round_trip(enum hl_osi_kind kind)
{
	struct hl_osi_frame *f = sample(), *g = hl_osi_frame_new();
	uint8_t *buf = NULL;
	size_t len = 0;
	char why[200];

	assert_non_null(g);
	assert_int_equal(hl_osi_encode(f, kind, &buf, &len), 0);
	assert_true(len > 0);
	assert_int_equal(hl_osi_decode(buf, len, kind, g, why, sizeof(why)), HL_OSI_DECODE_OK);
	assert_int_equal(g->kind, kind);
	assert_true(g->has_version);
	assert_int_equal(g->version[0], HL_OSI_VERSION_MAJOR);
	assert_int_equal(g->version[1], HL_OSI_VERSION_MINOR);
	assert_int_equal(g->version[2], HL_OSI_VERSION_PATCH);
	same_frame(g, f);
	free(buf);
	hl_osi_frame_free(f);
	hl_osi_frame_free(g);
}

static void osi_round_trip_ground_truth_exact(void **state)
{
	(void)state;
	round_trip(HL_OSI_GROUND_TRUTH);
}

static void osi_round_trip_sensor_view_exact(void **state)
{
	(void)state;
	round_trip(HL_OSI_SENSOR_VIEW);
}

static void osi_truncated_buffer_is_malformed(void **state)
{
	struct hl_osi_frame *f = sample(), *g = hl_osi_frame_new();
	enum hl_osi_kind kinds[] = { HL_OSI_GROUND_TRUTH, HL_OSI_SENSOR_VIEW };
	char why[200];

	(void)state;
	for (int k = 0; k < 2; k++) {
		uint8_t *buf;
		size_t len;

		assert_int_equal(hl_osi_encode(f, kinds[k], &buf, &len), 0);
		/* The last field is length-delimited: cutting its end leaves it short. */
		assert_int_equal(hl_osi_decode(buf, len - 1, kinds[k], g, why, sizeof(why)),
				 HL_OSI_DECODE_MALFORMED);
		assert_non_null(strstr(why, k ? "osi3.SensorView" : "osi3.GroundTruth"));
		assert_int_equal(g->n_objects, 0);
		assert_int_equal(hl_osi_decode(buf, 3, kinds[k], g, why, sizeof(why)),
				 HL_OSI_DECODE_MALFORMED);
		free(buf);
	}
	hl_osi_frame_free(f);
	hl_osi_frame_free(g);
}

/* buf twice, one after the other: one message with the repeated fields of both. */
static enum hl_osi_decode_result decode_twice(const struct hl_osi_frame *f, struct hl_osi_frame *g,
					      char *why, size_t why_size)
{
	uint8_t *buf, *two;
	size_t len;
	enum hl_osi_decode_result r;

	assert_int_equal(hl_osi_encode(f, HL_OSI_GROUND_TRUTH, &buf, &len), 0);
	two = malloc(2 * len);
	assert_non_null(two);
	memcpy(two, buf, len);
	memcpy(two + len, buf, len);
	r = hl_osi_decode(two, 2 * len, HL_OSI_GROUND_TRUTH, g, why, why_size);
	free(two);
	free(buf);
	return r;
}

static void osi_beyond_the_limits_is_too_many(void **state)
{
	struct hl_osi_frame *f = hl_osi_frame_new(), *g = hl_osi_frame_new();
	uint8_t *buf = NULL;
	size_t len = 0;
	char why[200];

	(void)state;
	assert_non_null(f);
	assert_non_null(g);
	/* Exactly the limit: fine; 2 * 129 objects: too many. */
	f->n_objects = HL_OSI_MAX_OBJECTS / 2;
	for (int i = 0; i < f->n_objects; i++) {
		f->object[i].has_id = true;
		f->object[i].id = (uint64_t)i;
	}
	assert_int_equal(decode_twice(f, g, why, sizeof(why)), HL_OSI_DECODE_OK);
	assert_int_equal(g->n_objects, HL_OSI_MAX_OBJECTS);
	f->n_objects++;
	assert_int_equal(decode_twice(f, g, why, sizeof(why)), HL_OSI_DECODE_TOO_MANY);
	assert_string_equal(why, "258 moving objects, more than 256");
	assert_int_equal(g->n_objects, 0);
	f->n_objects = 0;

	f->n_boundaries = HL_OSI_MAX_BOUNDARIES / 2 + 1;
	assert_int_equal(decode_twice(f, g, why, sizeof(why)), HL_OSI_DECODE_TOO_MANY);
	assert_string_equal(why, "130 lane boundaries, more than 128");
	f->n_boundaries = 1;
	f->boundary[0].n = f->n_points = HL_OSI_MAX_POINTS / 2 + 1;
	assert_int_equal(decode_twice(f, g, why, sizeof(why)), HL_OSI_DECODE_TOO_MANY);
	assert_string_equal(why, "16386 lane boundary points, more than 16384");

	/* The encoder refuses what the decoder would not take, and a boundary past the points. */
	f->n_objects = HL_OSI_MAX_OBJECTS + 1;
	assert_int_equal(hl_osi_encode(f, HL_OSI_GROUND_TRUTH, &buf, &len), -EINVAL);
	f->n_objects = 0;
	f->boundary[0].n = f->n_points + 1;
	assert_int_equal(hl_osi_encode(f, HL_OSI_SENSOR_VIEW, &buf, &len), -EINVAL);
	assert_null(buf);
	hl_osi_frame_free(f);
	hl_osi_frame_free(g);
}

static void osi_absent_fields_are_nan_and_zero(void **state)
{
	/* GroundTruth { moving_object (5) { id (1) { value (1): 7 } } country_code (13): 276,
	   lane_boundary (9) { boundary_line (2) { } } } */
	static const uint8_t gt[] = { 0x2a, 0x04, 0x0a, 0x02, 0x08, 0x07, 0x68,
				      0x94, 0x02, 0x4a, 0x02, 0x12, 0x00 };
	struct hl_osi_frame *g = hl_osi_frame_new();
	const struct hl_osi_object *o;
	char why[200];

	(void)state;
	assert_non_null(g);
	assert_int_equal(hl_osi_decode(NULL, 0, HL_OSI_GROUND_TRUTH, g, why, sizeof(why)),
			 HL_OSI_DECODE_OK);
	assert_false(g->has_version);
	assert_false(g->has_timestamp);
	assert_false(g->has_host);
	assert_int_equal(g->n_objects, 0);
	assert_int_equal(g->n_boundaries, 0);

	assert_int_equal(hl_osi_decode(gt, sizeof(gt), HL_OSI_GROUND_TRUTH, g, why, sizeof(why)),
			 HL_OSI_DECODE_OK);
	assert_int_equal(g->n_objects, 1);
	o = &g->object[0];
	assert_true(o->has_id);
	assert_int_equal(o->id, 7);
	assert_int_equal(o->type, 0);
	assert_false(o->has_classification);
	assert_int_equal(o->vehicle_type + o->head_light + o->high_beam + o->brake_light, 0);
	assert_int_equal(o->tail_light, 0);
	for (int k = 0; k < 3; k++) {
		assert_true(isnan(o->dim_m[k]));
		assert_true(isnan(o->pos_m[k]));
		assert_true(isnan(o->rpy_rad[k]));
		assert_true(isnan(o->vel_mps[k]));
	}
	assert_int_equal(g->n_boundaries, 1);
	assert_int_equal(g->boundary[0].id, 0);
	assert_int_equal(g->boundary[0].type, 0);
	assert_int_equal(g->boundary[0].n, 1);
	assert_true(isnan(g->point[0][0]) && isnan(g->point[0][1]) && isnan(g->point[0][2]));
	assert_true(isnan(g->point_width_m[0]));
	hl_osi_frame_free(g);
}

static void osi_sensor_view_host_falls_back_to_ground_truth(void **state)
{
	/* SensorView { global_ground_truth (7) { host_vehicle_id (3) { value: 42 },
	   timestamp (2) { seconds: 3 } } } and then its own host_vehicle_id (8) { value: 5 } */
	static const uint8_t sv[] = { 0x3a, 0x08, 0x1a, 0x02, 0x08, 0x2a, 0x12,
				      0x02, 0x08, 0x03, 0x42, 0x02, 0x08, 0x05 };
	struct hl_osi_frame *g = hl_osi_frame_new();
	char why[200];

	(void)state;
	assert_non_null(g);
	assert_int_equal(hl_osi_decode(sv, sizeof(sv) - 4, HL_OSI_SENSOR_VIEW, g, why, sizeof(why)),
			 HL_OSI_DECODE_OK);
	assert_true(g->has_host);
	assert_int_equal(g->host_id, 42);
	assert_true(g->has_timestamp);
	assert_int_equal(g->t_ns, 3000000000LL);
	assert_int_equal(hl_osi_decode(sv, sizeof(sv), HL_OSI_SENSOR_VIEW, g, why, sizeof(why)),
			 HL_OSI_DECODE_OK);
	assert_int_equal(g->host_id, 5);
	/* The same bytes are no GroundTruth: field 7 there is traffic_light, skipped, and 8 is
	   road_marking, whose bytes are no RoadMarking we know either; still well formed. */
	assert_int_equal(hl_osi_decode(sv, sizeof(sv), HL_OSI_GROUND_TRUTH, g, why, sizeof(why)),
			 HL_OSI_DECODE_OK);
	assert_false(g->has_host);
	hl_osi_frame_free(g);
}

static void osi_timestamp_beyond_int64_ns_is_malformed(void **state)
{
	/* GroundTruth { timestamp (2) { seconds (1): INT64_MAX } } */
	static const uint8_t gt[] = { 0x12, 0x0a, 0x08, 0xff, 0xff, 0xff,
				      0xff, 0xff, 0xff, 0xff, 0xff, 0x7f };
	struct hl_osi_frame *g = hl_osi_frame_new();
	char why[200];

	(void)state;
	assert_non_null(g);
	assert_int_equal(hl_osi_decode(gt, sizeof(gt), HL_OSI_GROUND_TRUTH, g, why, sizeof(why)),
			 HL_OSI_DECODE_MALFORMED);
	assert_non_null(strstr(why, "timestamp"));
	assert_false(g->has_timestamp);
	hl_osi_frame_free(g);
}

static void osi_kind_names(void **state)
{
	enum hl_osi_kind k;

	(void)state;
	assert_string_equal(hl_osi_kind_name(HL_OSI_GROUND_TRUTH), "ground-truth");
	assert_string_equal(hl_osi_kind_name(HL_OSI_SENSOR_VIEW), "sensor-view");
	assert_int_equal(hl_osi_kind_parse("sensor-view", &k), 0);
	assert_int_equal(k, HL_OSI_SENSOR_VIEW);
	assert_int_equal(hl_osi_kind_parse("ground-truth", &k), 0);
	assert_int_equal(k, HL_OSI_GROUND_TRUTH);
	assert_int_equal(hl_osi_kind_parse("sensor_view", &k), -EINVAL);
	assert_int_equal(hl_osi_kind_parse(NULL, &k), -EINVAL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(osi_round_trip_ground_truth_exact),
		cmocka_unit_test(osi_round_trip_sensor_view_exact),
		cmocka_unit_test(osi_truncated_buffer_is_malformed),
		cmocka_unit_test(osi_beyond_the_limits_is_too_many),
		cmocka_unit_test(osi_absent_fields_are_nan_and_zero),
		cmocka_unit_test(osi_sensor_view_host_falls_back_to_ground_truth),
		cmocka_unit_test(osi_timestamp_beyond_int64_ns_is_malformed),
		cmocka_unit_test(osi_kind_names),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
