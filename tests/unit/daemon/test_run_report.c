/* SPDX-License-Identifier: MIT */
/*
 * daemon/run_report.c: the closed-loop run's report and exit code from the parts' counters, on
 * parts made but never started (a renderer that rendered nothing, an input that read nothing):
 * the report's JSON, the verdict "no frame rendered", where it is written and the exit codes.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "daemon/run_report.h"
#include "lamp/model.h"
#include "testutil.h"

struct fixture {
	char scenario[4096], log[256];
	struct hl_scenario *sc;
	struct hl_dbc *db;
	struct hl_assembler *a;
	struct hl_lid *lids[2];
	struct hl_ring *ring;
	struct hl_frame_pool *pool;
	struct hl_pipeline *pipe;
	struct hl_can_input *in;
	struct hl_loop_latency *loop;
	struct hl_run_report_sources src;
};

static const char *const lamps[2] = { "left", "right" };

static int setup(void **state)
{
	static struct fixture f;
	struct hl_source_scale *scales[2];
	struct hl_json_error jerr;
	struct hl_dbc_error derr;
	struct hl_asm_error aerr;
	char path[4096];
	FILE *log;
	int n_src;

	memset(&f, 0, sizeof(f));
	snprintf(f.scenario, sizeof(f.scenario), "%s/scenarios/preceding-car.json",
		 getenv("HL_SOURCE_DIR"));
	assert_int_equal(hl_scenario_read(f.scenario, &f.sc, &jerr), 0);
	snprintf(path, sizeof(path), "%s/dbc/hd84.dbc", getenv("HL_SOURCE_DIR"));
	assert_int_equal(hl_dbc_parse_file(path, &f.db, &derr), 0);
	assert_int_equal(hl_assembler_new(f.db, lamps, 2, 100, 0, &f.a, &aerr), 0);
	n_src = hl_assembler_n_sources(f.a, 0);
	assert_int_equal(hl_model_hd84(HL_SIDE_LEFT, &f.lids[0]), 0);
	assert_int_equal(hl_model_hd84(HL_SIDE_RIGHT, &f.lids[1]), 0);
	assert_int_equal(hl_ring_new(8, 2, n_src, &f.ring), 0);
	{
		const struct hl_lid_grid *g = hl_lid_grid(f.lids[0]);
		const struct hl_frame_shape shape = {
			.width = 64,
			.height = 36,
			.format = HL_PIXEL_RGB8,
			.n_lamps = 2,
			.n_sources = n_src,
			.dist_width = g->width,
			.dist_height = g->height,
		};
		struct hl_config cfg;

		hl_config_defaults(&cfg);
		cfg.width = 64;
		cfg.height = 36;
		assert_int_equal(hl_frame_pool_new(2, &shape, &f.pool), 0);
		for (int l = 0; l < 2; l++) {
			scales[l] = calloc(n_src, sizeof(*scales[l]));
			assert_non_null(scales[l]);
		}
		assert_int_equal(hl_pipeline_new(&cfg, f.lids, 2,
						 (const struct hl_source_scale *const *)scales,
						 NULL, f.ring, f.pool, NULL, NULL, &f.pipe),
				 0);
		free(scales[0]);
		free(scales[1]);
	}
	test_path(f.log, sizeof(f.log), "run-report.log");
	log = fopen(f.log, "w"); /* one frame no lamp uses: an empty log is -ENODATA */
	assert_non_null(log);
	fputs("(1700000000.000000) can0 123#00\n", log);
	fclose(log);
	{
		const struct hl_can_input_config icfg = { .replay = f.log, .replay_fast = true };

		assert_int_equal(hl_can_input_new(&icfg, f.a, f.ring, &f.in), 0);
	}
	{
		const struct hl_loop_latency_config lc = { .sc = f.sc,
							   .ecu_cycle_ms = 20.0,
							   .reaction_ms = 60.0 };

		assert_int_equal(hl_loop_latency_new(&lc, &f.loop), 0);
	}
	f.src = (struct hl_run_report_sources){
		.scenario_path = f.scenario,
		.sc = f.sc,
		.glare_set = "unece-r149-01-adb-glare",
		.n_lamps = 2,
		.lamp_names = lamps,
		.in = f.in,
		.ring = f.ring,
		.pipe = f.pipe,
		.loop = f.loop,
		.end = "signal",
	};
	*state = &f;
	return 0;
}

static int teardown(void **state)
{
	struct fixture *f = *state;

	hl_loop_latency_free(f->loop);
	hl_can_input_free(f->in);
	hl_pipeline_free(f->pipe);
	hl_frame_pool_free(f->pool);
	hl_ring_free(f->ring);
	hl_lid_free(f->lids[0]);
	hl_lid_free(f->lids[1]);
	hl_assembler_free(f->a);
	hl_dbc_free(f->db);
	hl_scenario_free(f->sc);
	unlink(f->log);
	return 0;
}

static char *report_text(const struct hl_run_report_sources *s)
{
	char *text = NULL;
	size_t size = 0;
	FILE *f = open_memstream(&text, &size);

	assert_non_null(f);
	hl_run_report_json(s, f);
	assert_int_equal(fclose(f), 0);
	return text;
}

static void run_report_nothing_rendered_fails(void **state)
{
	struct fixture *f = *state;

	hl_loop_latency_finish(f->loop);
	assert_false(hl_run_report_passed(&f->src));
}

static void run_report_json_of_a_run_that_rendered_nothing(void **state)
{
	static const char lamp[] = ":{\"complete\":0,\"rendered\":0,\"not_rendered\":0,\"lost\":0,"
				   "\"incomplete\":0,\"crc_errors\":0,\"failsafe_frames\":0}";
	static const char tail[] =
		",\"verdict\":false,\"failed_because\":[\"no frame rendered\"]}\n";
	struct fixture *f = *state;
	char head[8192];
	char *text;

	hl_loop_latency_finish(f->loop);
	text = report_text(&f->src);
	snprintf(head, sizeof(head),
		 "{\"report\":\"hdlamp closed-loop run\",\"version\":1,\"scenario\":\"%s\","
		 "\"title\":\"%s\",\"duration_s\":11,\"end\":\"signal\",\"frames\":{\"rendered\":0,"
		 "\"not_published\":0,\"render_ms_max\":0.000},\"snapshots\":{\"pushed\":0,"
		 "\"superseded\":0,\"dropped\":0},\"cycles\":{\"left\"%s,\"right\"%s},"
		 "\"verdict_sets\":[],\"glare_set\":\"unece-r149-01-adb-glare\",",
		 f->scenario, f->sc->title, lamp, lamp);
	if (strncmp(text, head, strlen(head)) != 0)
		fail_msg("report:\n%s\nwant it to start:\n%s", text, head);
	assert_true(strlen(text) > strlen(tail));
	assert_string_equal(text + strlen(text) - strlen(tail), tail);
	assert_null(strstr(text, "\"restbus\"")); /* none */
	free(text);
}

static void run_report_write_renames_into_place(void **state)
{
	struct fixture *f = *state;
	char path[256], tmp[300];
	char *want = report_text(&f->src), got[8192];
	FILE *in;
	size_t n;

	test_path(path, sizeof(path), "report.json");
	snprintf(tmp, sizeof(tmp), "%s.tmp", path);
	assert_int_equal(hl_run_report_write(&f->src, path), 0);
	assert_int_equal(access(tmp, F_OK), -1);
	in = fopen(path, "r");
	assert_non_null(in);
	n = fread(got, 1, sizeof(got) - 1, in);
	got[n] = '\0';
	fclose(in);
	assert_string_equal(got, want);
	unlink(path);
	free(want);
}

static void run_report_write_into_a_missing_directory_is_enoent(void **state)
{
	struct fixture *f = *state;
	char path[5000];

	assert_int_equal(hl_run_report_write(&f->src, "/nonexistent-dir/report.json"), -ENOENT);
	memset(path, 'a', sizeof(path) - 1);
	path[sizeof(path) - 1] = '\0';
	assert_int_equal(hl_run_report_write(&f->src, path), -ENAMETOOLONG);
}

/* The exit code: unchanged without a report, a JUnit or an end asked for; 3 for a failed
 * verdict; 1 for a report or a JUnit that cannot be written. */
static void run_report_end_exit_codes(void **state)
{
	struct fixture *f = *state;

	assert_int_equal(hl_run_report_end(&f->src, "", "", false, 0), 0);
	assert_int_equal(hl_run_report_end(&f->src, "", "", false, 7), 7);
	assert_int_equal(hl_run_report_end(&f->src, "", "", true, 0), 3);
	assert_int_equal(hl_run_report_end(&f->src, "", "", true, 1), 1);
	assert_int_equal(hl_run_report_end(&f->src, "/nonexistent-dir/report.json", "", false, 0),
			 1);
	/* a JUnit alone asks for the verdict too; one that cannot be written is exit 1 */
	assert_int_equal(hl_run_report_end(&f->src, "", "/nonexistent-dir/junit.xml", false, 0), 1);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(run_report_nothing_rendered_fails, setup, teardown),
		cmocka_unit_test_setup_teardown(run_report_json_of_a_run_that_rendered_nothing,
						setup, teardown),
		cmocka_unit_test_setup_teardown(run_report_write_renames_into_place, setup,
						teardown),
		cmocka_unit_test_setup_teardown(run_report_write_into_a_missing_directory_is_enoent,
						setup, teardown),
		cmocka_unit_test_setup_teardown(run_report_end_exit_codes, setup, teardown),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
