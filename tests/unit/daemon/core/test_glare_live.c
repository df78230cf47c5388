/* SPDX-License-Identifier: MIT */
/*
 * The live glare of a scenario (the shipped ADB glare set): refusals, a frame's glare and header
 * fields equal to verdict/glare.h's own evaluation, the bounded history oldest first with
 * what it dropped counted, per road user fail counts, /glare.json too small (-ENOBUFS), the
 * /status part with and without a frame and the /metrics families.
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "daemon/core/glare_live.h"

/* An oncoming car 50 m ahead in lane 2 (limited), a pedestrian at the roadside (no limit). */
static const char scenario_json[] =
	"{\"version\": 1, \"duration_s\": 10, \"title\": \"two \\\"users\\\"\","
	" \"road\": {\"segments\": [{\"kind\": \"straight\", \"length_m\": 400}]},"
	" \"ego\": {\"start_s_m\": 0, \"speed_mps\": 0},"
	" \"actors\": ["
	"  {\"id\": \"car\", \"kind\": \"car\", \"role\": \"oncoming\","
	"   \"path\": {\"lane\": 2, \"start_s_m\": 50, \"speed_mps\": 0}},"
	"  {\"id\": \"walker\", \"kind\": \"pedestrian\", \"role\": \"roadside\","
	"   \"path\": {\"waypoints\": [{\"t_s\": 0, \"x_m\": 30, \"y_m\": -5}], \"heading_deg\": 90}}"
	" ]}";

static const struct hl_lid_grid grid = { 201, 101, HL_ANGLES_A, -20.0f, 20.0f, -10.0f, 10.0f };
static struct hl_scenario *sc;
static struct hl_regulation *reg;
static float *bright, *dark; /* 20000 cd and 1 cd everywhere */

static struct hl_regulation *read_set(const char *name)
{
	char path[4096];
	struct hl_regulation *r = NULL;
	struct hl_regulation_error err;

	snprintf(path, sizeof(path), "%s/regulations/%s.json", getenv("HL_SOURCE_DIR"), name);
	if (hl_regulation_read(path, &r, &err) < 0) {
		fprintf(stderr, "%s\n", err.msg);
		return NULL;
	}
	return r;
}

static int setup(void **state)
{
	struct hl_json_error err;

	(void)state;
	if (hl_scenario_parse(scenario_json, "two.json", &sc, &err) < 0)
		return -1;
	reg = read_set("unece-r149-01-adb-glare");
	bright = malloc(sizeof(float) * 201 * 101);
	dark = malloc(sizeof(float) * 201 * 101);
	if (!reg || !bright || !dark)
		return -1;
	for (int i = 0; i < 201 * 101; i++) {
		bright[i] = 20000.0f;
		dark[i] = 1.0f;
	}
	return 0;
}

static int teardown(void **state)
{
	(void)state;
	free(bright);
	free(dark);
	hl_regulation_free(reg);
	hl_scenario_free(sc);
	return 0;
}

static const struct hl_lid_grid *const grids[2] = { &grid, &grid };

static void glare_live_refuses_no_history_and_a_set_without_glare_rows(void **state)
{
	struct hl_glare_live *gl = NULL;
	struct hl_regulation *driving = read_set("unece-r149-01-driving-a");
	(void)state;

	assert_non_null(driving);
	assert_int_equal(hl_glare_live_new(sc, reg, grids, 0, &gl), -EINVAL);
	assert_int_equal(hl_glare_live_new(sc, reg, grids, -5, &gl), -EINVAL);
	assert_int_equal(hl_glare_live_new(sc, driving, grids, 4, &gl), -EINVAL);
	assert_null(gl);
	assert_int_equal(hl_glare_live_new(sc, reg, grids, 1, &gl), 0);
	assert_ptr_equal(hl_glare_live_scenario(gl), sc);
	assert_ptr_equal(hl_glare_live_regulation(gl), reg);
	hl_glare_live_free(gl);
	hl_glare_live_free(NULL);
	hl_regulation_free(driving);
	assert_string_equal(hl_scene_source_name(HL_SCENE_CLOCK), "clock");
	assert_string_equal(hl_scene_source_name(HL_SCENE_LOG), "log");
	assert_string_equal(hl_scene_source_name(HL_SCENE_POSE), "pose");
	assert_string_equal(hl_scene_source_name(HL_SCENE_NONE), "none");
	assert_string_equal(hl_scene_source_name((enum hl_scene_source)77), "none");
}

static struct hl_frame *new_frame(void)
{
	struct hl_frame *f = calloc(1, sizeof(*f));

	assert_non_null(f);
	return f;
}

static void glare_live_frame_carries_the_evaluation_and_header_fields(void **state)
{
	struct hl_glare_live *gl;
	struct hl_glare *plan;
	struct hl_world_state w;
	struct hl_glare_result want[HL_SCN_MAX_ACTORS];
	struct hl_frame *f = new_frame();
	const float *const d[2] = { bright, bright };
	(void)state;

	assert_int_equal(hl_glare_live_new(sc, reg, grids, 4, &gl), 0);
	assert_int_equal(hl_glare_new(sc, reg, grids, &plan), 0);
	hl_world_at(sc, 2.5, &w);
	assert_int_equal(hl_glare_eval_world(plan, &w, d, want), 1); /* the car fails */
	hl_glare_live_eval(gl, &w, HL_SCENE_LOG, d, 1, f);
	assert_memory_equal(f->glare, want, sizeof(want[0]) * 2);
	assert_true(f->hdr.scene_t_s == 2.5);
	assert_int_equal(f->hdr.scene_source, HL_SCENE_LOG);
	assert_int_equal(f->hdr.n_actors, 2);
	assert_int_equal(f->hdr.glare_failed, 0x1);
	assert_true(f->hdr.eye_lux_max ==
		    (float)fmax(want[0].illuminance_lx, want[1].illuminance_lx));
	assert_true(f->hdr.eye_lux_max > 0.0f);
	assert_false(want[0].pass);
	assert_true(want[1].pass); /* a roadside user has no limit */
	/* dark: nobody fails */
	hl_glare_live_eval(gl, &w, HL_SCENE_CLOCK, (const float *const[2]){ dark, dark }, 2, f);
	assert_int_equal(f->hdr.glare_failed, 0);
	assert_int_equal(f->hdr.scene_source, HL_SCENE_CLOCK);
	hl_glare_free(plan);
	hl_glare_live_free(gl);
	free(f);
}

static void glare_live_history_keeps_the_last_n_oldest_first(void **state)
{
	struct hl_glare_live *gl;
	struct hl_glare_live_counts c;
	struct hl_world_state w;
	struct hl_frame *f = new_frame();
	char buf[8192];
	int n;
	(void)state;

	assert_int_equal(hl_glare_live_new(sc, reg, grids, 3, &gl), 0);
	/* empty */
	n = hl_glare_live_json(gl, buf, sizeof(buf));
	assert_int_equal(n, (int)strlen(buf));
	assert_string_equal(buf,
			    "{\"history_frames\":3,\"frames_kept\":0,\"frames\":0,"
			    "\"history_overwritten\":0,\"glare_set\":\"unece-r149-01-adb-glare\","
			    "\"actors\":[{\"id\":\"car\",\"kind\":\"car\",\"role\":\"oncoming\"},"
			    "{\"id\":\"walker\",\"kind\":\"pedestrian\",\"role\":\"roadside\"}],"
			    "\"history\":[]}");
	/* five frames, seq 1..5 at t = 0.1 .. 0.5, bright on odd seqs */
	for (int k = 1; k <= 5; k++) {
		const float *dd = k % 2 ? bright : dark;

		hl_world_at(sc, 0.1 * k, &w);
		hl_glare_live_eval(gl, &w, HL_SCENE_POSE, (const float *const[2]){ dd, dd },
				   (uint64_t)k, f);
	}
	hl_glare_live_counts(gl, &c);
	assert_int_equal(c.frames, 5);
	assert_int_equal(c.history_overwritten, 2);
	assert_int_equal(c.fail_frames[0], 3);
	assert_int_equal(c.fail_frames[1], 0);
	n = hl_glare_live_json(gl, buf, sizeof(buf));
	assert_int_equal(n, (int)strlen(buf));
	assert_non_null(strstr(buf, "{\"history_frames\":3,\"frames_kept\":3,\"frames\":5,"
				    "\"history_overwritten\":2,"));
	{
		const char *a =
			strstr(buf, "{\"seq\":3,\"t_s\":0.3,\"source\":\"pose\",\"failed\":1,");
		const char *b =
			strstr(buf, "{\"seq\":4,\"t_s\":0.4,\"source\":\"pose\",\"failed\":0,");
		const char *e =
			strstr(buf, "{\"seq\":5,\"t_s\":0.5,\"source\":\"pose\",\"failed\":1,");

		assert_non_null(a);
		assert_non_null(b);
		assert_non_null(e);
		assert_true(a < b && b < e);
		assert_null(strstr(buf, "\"seq\":2,"));
	}
	/* the last frame's numbers, as the frame has them */
	{
		char want[256];

		snprintf(want, sizeof(want), "\"lux\":[%.7g,%.7g],\"cd\":[%.7g,%.7g]",
			 (double)(float)f->glare[0].illuminance_lx,
			 (double)(float)f->glare[1].illuminance_lx,
			 (double)(float)f->glare[0].pair_half_cd,
			 (double)(float)f->glare[1].pair_half_cd);
		assert_non_null(strstr(buf, want));
	}
	/* too small, by one byte and by much */
	assert_int_equal(hl_glare_live_json(gl, buf, (size_t)n), -ENOBUFS);
	assert_int_equal(hl_glare_live_json(gl, buf, 10), -ENOBUFS);
	assert_int_equal(hl_glare_live_json(gl, buf, (size_t)n + 1), n);
	assert_int_equal(strlen(buf), (size_t)n);
	hl_glare_live_free(gl);
	free(f);
}

static char *status(struct hl_glare_live *gl, const struct hl_frame *f, double age)
{
	static char buf[4096];
	FILE *m = fmemopen(buf, sizeof(buf), "w");

	assert_non_null(m);
	hl_glare_live_status_json(gl, f, age, m);
	fclose(m);
	return buf;
}

static void glare_live_status_before_and_after_a_frame(void **state)
{
	struct hl_glare_live *gl;
	struct hl_world_state w;
	struct hl_frame *f = new_frame();
	char want[1024];
	(void)state;

	assert_int_equal(hl_glare_live_new(sc, reg, grids, 2, &gl), 0);
	/* the title's quotes escaped */
	assert_string_equal(status(gl, NULL, -1.0),
			    ",\"scene\":{\"title\":\"two \\\"users\\\"\",\"duration_s\":10,"
			    "\"glare_set\":\"unece-r149-01-adb-glare\",\"frames\":0,"
			    "\"history_overwritten\":0},\"glare\":[]");
	hl_world_at(sc, 1.25, &w);
	hl_glare_live_eval(gl, &w, HL_SCENE_CLOCK, (const float *const[2]){ bright, bright }, 9, f);
	f->hdr.seq = 9;
	snprintf(want, sizeof(want),
		 ",\"scene\":{\"title\":\"two \\\"users\\\"\",\"duration_s\":10,"
		 "\"glare_set\":\"unece-r149-01-adb-glare\",\"frames\":1,"
		 "\"history_overwritten\":0,\"seq\":9,\"t_s\":1.25,\"source\":\"clock\","
		 "\"pose_age_s\":0.250},\"glare\":[{\"id\":\"car\",\"kind\":\"car\","
		 "\"role\":\"oncoming\",\"distance_m\":%.9g,",
		 f->glare[0].distance_m);
	assert_memory_equal(status(gl, f, 0.25), want, strlen(want));
	assert_non_null(strstr(status(gl, f, 0.25), "\"pass\":false,\"fail_frames\":1}"));
	/* the roadside user has no limit: null, and passes */
	assert_non_null(strstr(status(gl, f, 0.25), "\"limit_cd\":null,\"limit_distance_m\":null,"
						    "\"pass\":true,\"fail_frames\":0}]"));
	hl_glare_live_free(gl);
	free(f);
}

static void glare_live_metrics_families_with_and_without_a_frame(void **state)
{
	struct hl_glare_live *gl;
	struct hl_world_state w;
	struct hl_frame *f = new_frame();
	struct hl_prom p;
	char buf[8192];
	(void)state;

	assert_int_equal(hl_glare_live_new(sc, reg, grids, 2, &gl), 0);
	hl_prom_init(&p, buf, sizeof(buf));
	hl_glare_live_metrics(gl, NULL, &p);
	assert_true(hl_prom_end(&p) > 0);
	assert_non_null(strstr(buf, "\nhdlamp_glare_frames_total 0\n"));
	assert_non_null(strstr(buf, "hdlamp_glare_fail_frames_total{actor=\"car\"} 0\n"));
	assert_non_null(strstr(buf, "hdlamp_glare_fail_frames_total{actor=\"walker\"} 0\n"));
	assert_null(strstr(buf, "hdlamp_scene_time_seconds"));
	assert_null(strstr(buf, "hdlamp_glare_lux"));

	hl_world_at(sc, 3.0, &w);
	hl_glare_live_eval(gl, &w, HL_SCENE_CLOCK, (const float *const[2]){ bright, bright }, 1, f);
	hl_prom_init(&p, buf, sizeof(buf));
	hl_glare_live_metrics(gl, f, &p);
	assert_true(hl_prom_end(&p) > 0);
	assert_non_null(strstr(buf, "\nhdlamp_glare_frames_total 1\n"));
	assert_non_null(strstr(buf, "hdlamp_glare_fail_frames_total{actor=\"car\"} 1\n"));
	assert_non_null(strstr(buf, "\nhdlamp_scene_time_seconds 3\n"));
	assert_non_null(strstr(buf, "hdlamp_glare_lux{actor=\"walker\"} "));
	/* a limit only for the car */
	assert_non_null(strstr(buf, "hdlamp_glare_limit_cd{actor=\"car\"} "));
	assert_null(strstr(buf, "hdlamp_glare_limit_cd{actor=\"walker\"}"));
	hl_glare_live_free(gl);
	free(f);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(glare_live_refuses_no_history_and_a_set_without_glare_rows),
		cmocka_unit_test(glare_live_frame_carries_the_evaluation_and_header_fields),
		cmocka_unit_test(glare_live_history_keeps_the_last_n_oldest_first),
		cmocka_unit_test(glare_live_status_before_and_after_a_frame),
		cmocka_unit_test(glare_live_metrics_families_with_and_without_a_frame),
	};

	return cmocka_run_group_tests(tests, setup, teardown);
}
