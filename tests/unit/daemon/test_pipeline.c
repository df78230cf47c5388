/* SPDX-License-Identifier: MIT */
/*
 * daemon/pipeline.c: ring -> render thread -> frame pool with the CPU renderer, a tiny frame
 * and the HD84 model. Each case pushes hand-made snapshots, one at a time (or several before the
 * render thread starts, as a late pass finds them), waits for the frame each one makes and
 * checks its header, raw values and flags, then the counts after stop.
 * (The waits have a generous bound only so that a hang fails; nothing here measures time.)
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

#include "base/clock.h"
#include "daemon/core/glare_live.h"
#include "daemon/pipeline.h"
#include "lamp/model.h"

#define W 64
#define H 36
#define LAMPS 2
#define SOURCES HL_HD84_SOURCES
#define WAIT_MS 60000 /* a hang, not a speed limit */

struct fixture {
	struct hl_config cfg;
	struct hl_lid *lids[LAMPS];
	struct hl_ring *ring;
	struct hl_frame_pool *pool;
	struct hl_pipeline *p;
	struct hl_snapshot *s;
	struct hl_source_scale scale[LAMPS][SOURCES];
	uint64_t last_frame;
};

static int group_setup(void **state)
{
	static struct fixture f;

	if (hl_model_hd84(HL_SIDE_LEFT, &f.lids[0]) < 0 ||
	    hl_model_hd84(HL_SIDE_RIGHT, &f.lids[1]) < 0)
		return -1;
	*state = &f;
	return 0;
}

static int group_teardown(void **state)
{
	struct fixture *f = *state;

	hl_lid_free(f->lids[0]);
	hl_lid_free(f->lids[1]);
	return 0;
}

/* The DBC's scale of a 6-bit signal: raw / 63. */
static void scale_hd84(struct fixture *f)
{
	for (int l = 0; l < LAMPS; l++)
		for (int k = 0; k < SOURCES; k++)
			f->scale[l][k] = (struct hl_source_scale){ 1.0 / 63.0, 0.0 };
}

/* Makes the ring, pool and pipeline (ring of 8 slots: catch-up up to 4 snapshots behind). */
static void make(struct fixture *f, enum hl_failsafe mode, const uint8_t *const dims[LAMPS])
{
	const struct hl_lid_grid *g = hl_lid_grid(f->lids[0]);
	const struct hl_frame_shape shape = {
		.width = W,
		.height = H,
		.format = HL_PIXEL_RGB8,
		.n_lamps = LAMPS,
		.n_sources = SOURCES,
		.dist_width = g->width,
		.dist_height = g->height,
	};
	const struct hl_source_scale *scales[LAMPS] = { f->scale[0], f->scale[1] };

	hl_config_defaults(&f->cfg);
	f->cfg.width = W;
	f->cfg.height = H;
	snprintf(f->cfg.combine, sizeof(f->cfg.combine), "cpu");
	snprintf(f->cfg.headlight, sizeof(f->cfg.headlight), "cpu");
	f->cfg.render_threads = 1;
	f->cfg.rate_hz = 0; /* a frame for every new snapshot */
	f->cfg.coalesce_ms = 0;
	f->cfg.failsafe = mode;
	f->last_frame = 0;
	assert_int_equal(hl_ring_new(8, LAMPS, SOURCES, &f->ring), 0);
	assert_int_equal(hl_snapshot_new(f->ring, &f->s), 0);
	assert_int_equal(hl_frame_pool_new(4, &shape, &f->pool), 0);
	assert_int_equal(hl_pipeline_new(&f->cfg, f->lids, LAMPS, scales, dims, f->ring, f->pool,
					 NULL, NULL, &f->p),
			 0);
}

static void run(struct fixture *f)
{
	char err[512];

	if (hl_pipeline_start(f->p, err, sizeof(err)) < 0)
		fail_msg("%s", err);
}

static void start(struct fixture *f, enum hl_failsafe mode, const uint8_t *const dims[LAMPS])
{
	make(f, mode, dims);
	run(f);
}

static void stop(struct fixture *f, struct hl_pipeline_counts *ret)
{
	hl_pipeline_stop(f->p);
	hl_pipeline_counts(f->p, ret);
	hl_pipeline_free(f->p);
	hl_frame_pool_free(f->pool);
	hl_snapshot_free(f->s);
	hl_ring_free(f->ring);
}

/* Sets lamp l of the snapshot: cycle seq, alive counter, status and raw values raw(k). */
static void set_lamp(struct fixture *f, int l, uint64_t seq, uint32_t status, unsigned raw_mul)
{
	struct hl_lamp_snapshot *ls = &f->s->lamps[l];

	ls->cycle_seq = seq;
	ls->counter = (uint8_t)(seq % 15);
	ls->status = status;
	ls->t_rx_first_ns = (int64_t)(1000 * seq + l);
	ls->t_complete_ns = (int64_t)(1000 * seq + 500 + l); /* the newest: the one done last */
	ls->t_complete_mono_ns = (int64_t)(2000 * seq + l);
	for (int k = 0; k < SOURCES; k++) {
		const struct hl_source_scale *sc = &f->scale[l][k];
		const unsigned raw = (k * raw_mul + (unsigned)seq) % 64;

		f->s->i[(size_t)l * SOURCES + k] = (float)(raw * sc->factor + sc->offset);
	}
}

static unsigned raw_at(unsigned raw_mul, uint64_t seq, int k)
{
	return (k * raw_mul + (unsigned)seq) % 64;
}

/* Pushes the snapshot and takes the frame it makes (release it). */
static struct hl_frame *push_and_take(struct fixture *f)
{
	struct hl_frame *fr;

	hl_ring_push(f->ring, f->s);
	fr = hl_frame_pool_get(f->pool, f->last_frame, WAIT_MS);
	assert_non_null(fr);
	assert_int_equal(fr->hdr.seq, f->last_frame + 1);
	f->last_frame = fr->hdr.seq;
	return fr;
}

static void assert_raw(const struct hl_frame *fr, int l, unsigned raw_mul, uint64_t seq)
{
	for (int k = 0; k < SOURCES; k++)
		if (fr->dims[l][k] != raw_at(raw_mul, seq, k))
			fail_msg("lamp %d source %d: raw %u, expected %u", l, k, fr->dims[l][k],
				 raw_at(raw_mul, seq, k));
}

static void pipeline_publishes_each_cycle_with_its_seqs_and_raw_values(void **state)
{
	struct fixture *f = *state;
	struct hl_pipeline_counts pc;
	struct hl_frame *fr;

	scale_hd84(f);
	start(f, HL_FAILSAFE_HOLD, NULL);
	for (uint64_t seq = 1; seq <= 3; seq++) {
		set_lamp(f, 0, seq, HL_LAMP_VALID, 5);
		set_lamp(f, 1, seq, HL_LAMP_VALID, 7);
		fr = push_and_take(f);
		assert_int_equal(fr->hdr.cycle_seq[0], seq);
		assert_int_equal(fr->hdr.cycle_seq[1], seq);
		assert_int_equal(fr->hdr.counter[0], seq % 15);
		assert_int_equal(fr->hdr.t_lamp_done_ns[1], 2000 * seq + 1);
		assert_int_equal(fr->hdr.t_cycle_rx_ns, 1000 * seq + 1); /* the newest lamp's */
		assert_int_equal(fr->hdr.flags, 0);
		assert_int_equal(fr->hdr.n_lamps, LAMPS);
		assert_raw(fr, 0, 5, seq);
		assert_raw(fr, 1, 7, seq);
		hl_frame_pool_release(f->pool, fr);
	}
	stop(f, &pc);
	assert_int_equal(pc.frames, 3);
	assert_int_equal(pc.not_published, 0);
	assert_int_equal(pc.cycles_not_rendered[0], 0);
	assert_int_equal(pc.cycles_not_rendered[1], 0);
	assert_int_equal(pc.failsafe_frames[0], 0);
	assert_int_equal(pc.failsafe_frames[1], 0);
	assert_int_equal(pc.render_seconds.count, 3);
}

/* A database whose signals have another factor and an offset: the frame still carries the
 * raw values the ECU sent (a fixed 63 would have re-quantised them). */
static void pipeline_raw_values_follow_the_dbc_scale(void **state)
{
	struct fixture *f = *state;
	struct hl_pipeline_counts pc;
	struct hl_frame *fr;

	for (int k = 0; k < SOURCES; k++) {
		f->scale[0][k] = (struct hl_source_scale){ 1.0 / 100.0, 0.0 };
		f->scale[1][k] = (struct hl_source_scale){ 0.0125, 0.2 };
	}
	start(f, HL_FAILSAFE_HOLD, NULL);
	set_lamp(f, 0, 1, HL_LAMP_VALID, 3);
	set_lamp(f, 1, 1, HL_LAMP_VALID, 11);
	fr = push_and_take(f);
	assert_raw(fr, 0, 3, 1);
	assert_raw(fr, 1, 11, 1);
	hl_frame_pool_release(f->pool, fr);
	stop(f, &pc);
	assert_int_equal(pc.frames, 1);
}

static void pipeline_counts_cycles_no_frame_showed(void **state)
{
	struct fixture *f = *state;
	struct hl_pipeline_counts pc;
	struct hl_frame *fr;

	scale_hd84(f);
	start(f, HL_FAILSAFE_HOLD, NULL);
	/* cycles before the first frame: left's 1 and 2 were never shown */
	set_lamp(f, 0, 3, HL_LAMP_VALID, 1);
	set_lamp(f, 1, 1, HL_LAMP_VALID, 1);
	fr = push_and_take(f);
	assert_int_equal(fr->hdr.cycle_seq[0], 3);
	hl_frame_pool_release(f->pool, fr);
	/* the next frame: left moved by one (nothing lost), right by four (three lost) */
	set_lamp(f, 0, 4, HL_LAMP_VALID, 1);
	set_lamp(f, 1, 5, HL_LAMP_VALID, 1);
	fr = push_and_take(f);
	assert_int_equal(fr->hdr.cycle_seq[0], 4);
	assert_int_equal(fr->hdr.cycle_seq[1], 5);
	hl_frame_pool_release(f->pool, fr);
	/* a status-only snapshot (same cycles) renders again and loses nothing */
	fr = push_and_take(f);
	hl_frame_pool_release(f->pool, fr);
	stop(f, &pc);
	assert_int_equal(pc.frames, 3);
	assert_int_equal(pc.cycles_not_rendered[0], 2);
	assert_int_equal(pc.cycles_not_rendered[1], 3);
}

/*
 * Waits for frame number `frame` (the pool hands out only the newest, so the ones before may
 * pass unseen) and checks both lamps show cycle seq in it.
 */
static void wait_frame(struct fixture *f, uint64_t frame, uint64_t seq)
{
	struct hl_frame *fr = NULL;

	while (!fr || fr->hdr.seq < frame) {
		if (fr)
			hl_frame_pool_release(f->pool, fr);
		fr = hl_frame_pool_get(f->pool, fr ? fr->hdr.seq : 0, WAIT_MS);
		assert_non_null(fr);
	}
	assert_int_equal(fr->hdr.seq, frame);
	assert_int_equal(fr->hdr.cycle_seq[0], seq);
	assert_int_equal(fr->hdr.cycle_seq[1], seq);
	assert_raw(fr, 0, 5, seq);
	hl_frame_pool_release(f->pool, fr);
}

/*
 * A render pass that ran late: the cycles that came meanwhile (at most half the ring, here 4
 * snapshots) are each shown in a frame, in order: four frames, the last with cycle 4, and no
 * cycle not rendered (a frame out of order or a skipped one would count one).
 */
static void pipeline_catches_up_in_order_after_a_late_pass(void **state)
{
	struct fixture *f = *state;
	struct hl_pipeline_counts pc;
	struct hl_ring_counts rc;

	scale_hd84(f);
	make(f, HL_FAILSAFE_HOLD, NULL);
	for (uint64_t seq = 1; seq <= 4; seq++) {
		set_lamp(f, 0, seq, HL_LAMP_VALID, 5);
		set_lamp(f, 1, seq, HL_LAMP_VALID, 7);
		hl_ring_push(f->ring, f->s);
	}
	run(f);
	wait_frame(f, 4, 4);
	hl_ring_counts(f->ring, &rc);
	stop(f, &pc);
	assert_int_equal(pc.frames, 4);
	assert_int_equal(pc.cycles_not_rendered[0], 0);
	assert_int_equal(pc.cycles_not_rendered[1], 0);
	assert_int_equal(rc.consumed, 4);
	assert_int_equal(rc.superseded, 0);
}

/* Further behind than the catch-up: the newest is shown and the cycles between are counted. */
static void pipeline_takes_the_newest_when_far_behind(void **state)
{
	struct fixture *f = *state;
	struct hl_pipeline_counts pc;
	struct hl_ring_counts rc;

	scale_hd84(f);
	make(f, HL_FAILSAFE_HOLD, NULL);
	for (uint64_t seq = 1; seq <= 6; seq++) {
		set_lamp(f, 0, seq, HL_LAMP_VALID, 5);
		set_lamp(f, 1, seq, HL_LAMP_VALID, 7);
		hl_ring_push(f->ring, f->s);
	}
	run(f);
	wait_frame(f, 1, 6);
	hl_ring_counts(f->ring, &rc);
	stop(f, &pc);
	assert_int_equal(pc.frames, 1);
	assert_int_equal(pc.cycles_not_rendered[0], 5);
	assert_int_equal(pc.cycles_not_rendered[1], 5);
	assert_int_equal(rc.consumed, 1);
	assert_int_equal(rc.superseded, 5);
}

static void pipeline_applies_each_failsafe_mode_to_a_stale_lamp(void **state)
{
	struct fixture *f = *state;
	uint8_t preset[LAMPS][SOURCES];
	const uint8_t *dims[LAMPS] = { preset[0], preset[1] };
	struct hl_pipeline_counts pc;
	struct hl_frame *fr;

	for (int k = 0; k < SOURCES; k++) {
		preset[0][k] = (uint8_t)(63 - k % 64);
		preset[1][k] = (uint8_t)(k % 32);
	}
	scale_hd84(f);
	start(f, HL_FAILSAFE_HOLD, NULL);
	/* hold: the stale lamp keeps its last values, flagged stale and fail-safe */
	set_lamp(f, 0, 1, HL_LAMP_VALID, 5);
	set_lamp(f, 1, 1, HL_LAMP_VALID | HL_LAMP_STALE, 7);
	fr = push_and_take(f);
	assert_int_equal(fr->hdr.flags, HL_FRAME_STALE(1) | HL_FRAME_FAILSAFE(1));
	assert_raw(fr, 0, 5, 1);
	assert_raw(fr, 1, 7, 1);
	hl_frame_pool_release(f->pool, fr);
	/* dark: the stale lamp's values are 0 */
	hl_pipeline_set_failsafe(f->p, HL_FAILSAFE_DARK, NULL);
	fr = push_and_take(f);
	assert_int_equal(fr->hdr.flags, HL_FRAME_STALE(1) | HL_FRAME_FAILSAFE(1));
	assert_raw(fr, 0, 5, 1);
	for (int k = 0; k < SOURCES; k++)
		assert_int_equal(fr->dims[1][k], 0);
	hl_frame_pool_release(f->pool, fr);
	/* preset: the preset's raw values; a lamp never valid counts as stale too */
	hl_pipeline_set_failsafe(f->p, HL_FAILSAFE_PRESET, dims);
	set_lamp(f, 0, 0, 0, 5);
	fr = push_and_take(f);
	assert_int_equal(fr->hdr.flags, HL_FRAME_STALE(0) | HL_FRAME_FAILSAFE(0) |
						HL_FRAME_STALE(1) | HL_FRAME_FAILSAFE(1));
	assert_memory_equal(fr->dims[0], preset[0], SOURCES);
	assert_memory_equal(fr->dims[1], preset[1], SOURCES);
	hl_frame_pool_release(f->pool, fr);
	/* recovered: live values again, no flags */
	set_lamp(f, 0, 2, HL_LAMP_VALID, 5);
	set_lamp(f, 1, 2, HL_LAMP_VALID, 7);
	fr = push_and_take(f);
	assert_int_equal(fr->hdr.flags, 0);
	assert_raw(fr, 0, 5, 2);
	assert_raw(fr, 1, 7, 2);
	hl_frame_pool_release(f->pool, fr);
	stop(f, &pc);
	assert_int_equal(pc.frames, 4);
	assert_int_equal(pc.failsafe_frames[0], 1);
	assert_int_equal(pc.failsafe_frames[1], 3);
}

/* A standing ego and an oncoming car at 50 m, a pedestrian beside the road; 10 s long. */
static const char scene_json[] =
	"{\"version\": 1, \"title\": \"t\", \"duration_s\": 10,\n"
	" \"road\": {\"segments\": [{\"kind\": \"straight\", \"length_m\": 400}],\n"
	"          \"lanes\": {\"count\": 2, \"width_m\": 3.5}},\n"
	" \"ego\": {\"start_s_m\": 0, \"lane\": 1, \"speed_mps\": 0},\n"
	" \"actors\": [\n"
	"  {\"id\": \"car\", \"kind\": \"car\", \"role\": \"oncoming\",\n"
	"   \"path\": {\"lane\": 2, \"start_s_m\": 150, \"speed_mps\": 10}},\n"
	"  {\"id\": \"walker\", \"kind\": \"pedestrian\", \"role\": \"roadside\",\n"
	"   \"path\": {\"waypoints\": [{\"t_s\": 0, \"x_m\": 30, \"y_m\": -5}]}}]}\n";

/*
 * The scenario clock: with a replay, the newest lamp cycle's time on the log's timeline from
 * the start of its pass, held at the scenario's end; live, CLOCK_MONOTONIC since the start.
 * Each frame's glare is the one of that instant's world state.
 */
static void pipeline_scene_time_from_the_log_pass_and_the_clock(void **state)
{
	struct fixture *f = *state;
	const struct hl_lid_grid *grids[2] = { hl_lid_grid(f->lids[0]), hl_lid_grid(f->lids[1]) };
	struct hl_scenario *sc = NULL;
	struct hl_regulation *reg = NULL;
	struct hl_regulation_error rerr;
	struct hl_json_error jerr;
	struct hl_glare_live *gl = NULL;
	struct hl_pipeline_counts pc;
	char dir[1024];
	const double cases[][2] = { { 5e9, 6.25e9 }, { 5e9, 120e9 }, { 0, 3.5e9 } };

	snprintf(dir, sizeof(dir), "%s/regulations", getenv("HL_SOURCE_DIR"));
	assert_int_equal(hl_scenario_parse(scene_json, "t.json", &sc, &jerr), 0);
	assert_int_equal(hl_regulation_load(dir, "unece-r149-01-adb-glare", &reg, &rerr), 0);
	assert_int_equal(hl_glare_live_new(sc, reg, grids, 16, &gl), 0);
	scale_hd84(f);
	for (int live = 0; live < 2; live++) {
		int64_t t0;

		make(f, HL_FAILSAFE_HOLD, NULL);
		hl_pipeline_free(f->p); /* again, with the replay configured */
		if (!live)
			snprintf(f->cfg.replay, sizeof(f->cfg.replay), "x.log");
		{
			const struct hl_source_scale *scales[LAMPS] = { f->scale[0], f->scale[1] };

			assert_int_equal(hl_pipeline_new(&f->cfg, f->lids, LAMPS, scales, NULL,
							 f->ring, f->pool, NULL, NULL, &f->p),
					 0);
		}
		hl_pipeline_set_scene(f->p, sc, gl, NULL);
		t0 = hl_clock_monotonic_ns();
		run(f);
		for (size_t c = 0; c < sizeof(cases) / sizeof(cases[0]); c++) {
			struct hl_frame *fr;
			struct hl_world_state w;
			struct hl_glare_result want[HL_SCN_MAX_ACTORS];
			const float *dist[2];
			double t;

			set_lamp(f, 0, c + 1, HL_LAMP_VALID, 5);
			set_lamp(f, 1, c + 1, HL_LAMP_VALID, 7);
			f->s->t_pass_ns = (int64_t)cases[c][0];
			f->s->lamps[0].t_complete_ns = (int64_t)cases[c][1];
			f->s->lamps[1].t_complete_ns =
				(int64_t)cases[c][1] - 1000; /* lamp 0 newest */
			fr = push_and_take(f);
			t = fr->hdr.scene_t_s;
			if (!live) {
				const double want_t = (cases[c][1] - cases[c][0]) / 1e9;

				assert_int_equal(fr->hdr.scene_source, HL_SCENE_LOG);
				assert_true(t == (want_t > 10.0 ? 10.0 : want_t));
			} else {
				assert_int_equal(fr->hdr.scene_source, HL_SCENE_CLOCK);
				assert_true(t >= 0.0 &&
					    t <= (double)(hl_clock_monotonic_ns() - t0) / 1e9);
			}
			assert_int_equal(fr->hdr.n_actors, 2);
			/* the glare of the world at t, under the frame's own distributions */
			hl_world_at(sc, t, &w);
			dist[0] = fr->dist[0];
			dist[1] = fr->dist[1];
			{
				struct hl_glare *g;

				assert_int_equal(hl_glare_new(sc, reg, grids, &g), 0);
				assert_int_equal(hl_glare_eval_world(g, &w, dist, want),
						 __builtin_popcount(fr->hdr.glare_failed));
				hl_glare_free(g);
			}
			for (int i = 0; i < 2; i++) {
				assert_true(fr->glare[i].distance_m == want[i].distance_m);
				assert_true(fr->glare[i].illuminance_lx == want[i].illuminance_lx);
				assert_true(fr->glare[i].pair_half_cd == want[i].pair_half_cd);
				assert_int_equal(!!(fr->hdr.glare_failed & (1u << i)),
						 !want[i].pass);
			}
			assert_true(fr->hdr.eye_lux_max ==
				    (float)fmax(want[0].illuminance_lx, want[1].illuminance_lx));
			hl_frame_pool_release(f->pool, fr);
		}
		stop(f, &pc);
		assert_int_equal(pc.frames, 3);
	}
	hl_glare_live_free(gl);
	hl_regulation_free(reg);
	hl_scenario_free(sc);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(pipeline_publishes_each_cycle_with_its_seqs_and_raw_values),
		cmocka_unit_test(pipeline_raw_values_follow_the_dbc_scale),
		cmocka_unit_test(pipeline_counts_cycles_no_frame_showed),
		cmocka_unit_test(pipeline_applies_each_failsafe_mode_to_a_stale_lamp),
		cmocka_unit_test(pipeline_catches_up_in_order_after_a_late_pass),
		cmocka_unit_test(pipeline_takes_the_newest_when_far_behind),
		cmocka_unit_test(pipeline_scene_time_from_the_log_pass_and_the_clock),
	};

	return cmocka_run_group_tests(tests, group_setup, group_teardown);
}
