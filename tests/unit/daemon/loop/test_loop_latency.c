/* SPDX-License-Identifier: MIT */
/*
 * The loop's judge on a hand-made timeline (times in whole milliseconds, so every value below is
 * worked out by hand): frames every 20 ms of scenario time whose lamps' cycles completed 1 ms
 * before and whose render ended 5 ms after that, camera cycles every 40 ms sent 1 ms after
 * their deadline, one road user in the camera's view from the cycle at 120 ms to the one at
 * 320 ms, over its glare limit on chosen frames.
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

#include "daemon/loop/loop_latency.h"

#define T0_NS 1000000000LL /* CLOCK_MONOTONIC of scenario time 0 */
#define MS 1000000LL

static struct hl_scenario *scenario(void)
{
	struct hl_scenario *sc = calloc(1, sizeof(*sc));

	assert_non_null(sc);
	sc->duration_s = 1.0;
	sc->n_actors = 2;
	strcpy(sc->actor[0].id, "car");
	strcpy(sc->actor[1].id, "far-car"); /* never in view, over its limit at 100 ms */
	return sc;
}

/* The frame at scenario time t_ms; over: the road users over their limit (bit mask). */
static void frame_at(struct hl_loop_latency *ll, int t_ms, uint32_t over, uint64_t seq)
{
	struct hl_frame f;

	memset(&f, 0, sizeof(f));
	f.hdr.seq = seq;
	f.hdr.scene_t_s = t_ms / 1000.0;
	f.hdr.n_lamps = 2;
	f.hdr.t_lamp_done_ns[0] = T0_NS + (t_ms - 2) * MS; /* the left lamp 1 ms earlier */
	f.hdr.t_lamp_done_ns[1] = T0_NS + (t_ms - 1) * MS;
	f.hdr.t_render_done_ns = T0_NS + (t_ms + 4) * MS;
	f.hdr.n_actors = 2;
	f.hdr.glare_failed = over;
	f.glare[0].illuminance_lx = over & 1 ? 2.5 : 0.5;
	f.glare[1].illuminance_lx = over & 2 ? 1.5 : 0.25;
	hl_loop_latency_frame(ll, &f);
}

/* frames 0..400 ms; the car (bit 0) over its limit on [over_from, over_to) ms */
static void run(struct hl_loop_latency *ll, int over_from, int over_to)
{
	uint64_t seq = 1;

	for (int t = 0; t <= 400; t += 20)
		frame_at(ll, t, (t >= over_from && t < over_to ? 1u : 0u) | (t == 100 ? 2u : 0u),
			 seq++);
	for (int t = 0; t <= 400; t += 40) {
		const bool in_view = t >= 120 && t < 320;

		hl_loop_latency_camera(ll, T0_NS + t * MS, t / 1000.0, in_view ? 1u : 0u,
				       T0_NS + (t + 1) * MS);
	}
	hl_loop_latency_finish(ll);
}

static struct hl_loop_latency *make(struct hl_scenario *sc, bool camera)
{
	const struct hl_loop_latency_config cfg = {
		.sc = sc, .ecu_cycle_ms = 20, .reaction_ms = 60, .camera = camera
	};
	struct hl_loop_latency *ll = NULL;

	assert_int_equal(hl_loop_latency_new(&cfg, &ll), 0);
	return ll;
}

static void loop_masked_within_reaction_passes(void **state)
{
	struct hl_scenario *sc = scenario();
	struct hl_loop_latency *ll = make(sc, true);
	struct hl_loop_counts c;
	struct hl_loop_event e;

	(void)state;
	/* over at 100 (not in view yet: unseen), 120, 140, 160 (in view, <= 60 ms after 120) */
	run(ll, 100, 180);
	hl_loop_latency_counts(ll, &c);
	assert_int_equal(c.frames_in, 21);
	assert_int_equal(c.frames_judged, 21);
	assert_int_equal(c.frames_dropped, 0);
	assert_int_equal(c.camera_cycles, 11);
	assert_int_equal(c.actor[0].frames_over, 4);
	assert_int_equal(c.actor[0].frames_over_unseen, 1);
	assert_int_equal(c.actor[0].frames_over_in_reaction, 3);
	assert_int_equal(c.actor[0].frames_over_late, 0);
	assert_true(fabs(c.actor[0].glare_s - 0.060) < 1e-9);
	assert_true(fabs(c.actor[0].glare_total_s - 0.080) < 1e-9);
	assert_true(fabs(c.actor[0].max_lux - 2.5) < 1e-6);
	assert_int_equal(c.actor[0].entries, 1);
	assert_int_equal(c.actor[0].leaves, 1);
	assert_int_equal(c.actor[1].frames_over_unseen, 1);
	assert_true(hl_loop_latency_passed(ll));
	/* enter (masked by the frame at 180 ms), then the leave at 320 ms */
	assert_int_equal(c.events, 2);
	assert_true(hl_loop_latency_event(ll, 0, &e));
	assert_true(e.enter && e.masked);
	assert_int_equal(e.actor, 0);
	assert_int_equal(e.t_enter_ns, T0_NS + 120 * MS);
	assert_int_equal(e.t_input_ns - e.t_enter_ns, 1 * MS);
	assert_int_equal(e.t_mask_ns - e.t_enter_ns, 59 * MS); /* the later lamp's cycle */
	assert_int_equal(e.t_frame_ns - e.t_enter_ns, 64 * MS);
	assert_int_equal(e.frame_seq, 10); /* 180 ms: the tenth frame */
	assert_int_equal(c.latency_s[1].count, 1);
	assert_true(hl_loop_latency_event(ll, 1, &e));
	assert_false(e.enter);
	assert_int_equal(e.t_enter_ns, T0_NS + 320 * MS);
	assert_true(fabs(e.glare_s - 0.060) < 1e-9);
	assert_int_equal(e.frames_over, 3);
	assert_false(hl_loop_latency_event(ll, 2, &e));
	hl_loop_latency_free(ll);
	free(sc);
}

static void loop_glare_after_reaction_fails(void **state)
{
	struct hl_scenario *sc = scenario();
	struct hl_loop_latency *ll = make(sc, true);
	struct hl_loop_counts c;
	struct hl_loop_event e;

	(void)state;
	/* in view and over at 120..200: 180 is 60 ms after entering (allowed), 200 is 80 (not) */
	run(ll, 120, 220);
	hl_loop_latency_counts(ll, &c);
	assert_int_equal(c.actor[0].frames_over_in_reaction, 4);
	assert_int_equal(c.actor[0].frames_over_late, 1);
	assert_true(fabs(c.actor[0].glare_late_s - 0.020) < 1e-9);
	assert_false(hl_loop_latency_passed(ll));
	assert_true(hl_loop_latency_event(ll, 0, &e));
	assert_int_equal(e.t_mask_ns - e.t_enter_ns, 99 * MS); /* the frame at 220 ms */
	hl_loop_latency_free(ll);
	free(sc);
}

static void loop_never_masked_is_reported_unmasked(void **state)
{
	struct hl_scenario *sc = scenario();
	struct hl_loop_latency *ll = make(sc, true);
	struct hl_loop_counts c;
	struct hl_loop_event e;

	(void)state;
	run(ll, 0, 1000); /* the whole high beam on it, as an ECU ignoring the objects would */
	hl_loop_latency_counts(ll, &c);
	assert_int_equal(c.unmasked, 1);
	assert_int_equal(c.latency_s[1].count, 0);
	assert_true(hl_loop_latency_event(ll, 0, &e));
	assert_true(e.enter);
	assert_false(e.masked);
	/* in view 120..300: 10 frames over, 120..180 within the reaction time */
	assert_int_equal(c.actor[0].frames_over_in_reaction, 4);
	assert_int_equal(c.actor[0].frames_over_late, 6);
	assert_false(hl_loop_latency_passed(ll));
	hl_loop_latency_free(ll);
	free(sc);
}

static void loop_without_camera_is_strict(void **state)
{
	struct hl_scenario *sc = scenario();
	struct hl_loop_latency *ll = make(sc, false);
	struct hl_loop_counts c;

	(void)state;
	for (int t = 0; t <= 100; t += 20)
		frame_at(ll, t, t == 100 ? 2u : 0u, (uint64_t)t / 20 + 1);
	hl_loop_latency_drain(ll, INFINITY);
	hl_loop_latency_finish(ll);
	hl_loop_latency_counts(ll, &c);
	assert_int_equal(c.frames_judged, 6);
	assert_int_equal(c.actor[1].frames_over, 1);
	assert_false(hl_loop_latency_passed(ll)); /* no camera: no frame may be over */
	hl_loop_latency_free(ll);
	free(sc);
}

static void loop_full_ring_counts_dropped_frames(void **state)
{
	struct hl_scenario *sc = scenario();
	struct hl_loop_latency *ll = make(sc, true);
	struct hl_loop_counts c;

	(void)state;
	for (int k = 0; k < HL_LOOP_FRAME_SLOTS + 3; k++)
		frame_at(ll, k, 0, (uint64_t)k + 1);
	hl_loop_latency_finish(ll);
	hl_loop_latency_counts(ll, &c);
	assert_int_equal(c.frames_in, HL_LOOP_FRAME_SLOTS);
	assert_int_equal(c.frames_dropped, 3);
	assert_int_equal(c.frames_judged, HL_LOOP_FRAME_SLOTS);
	hl_loop_latency_free(ll);
	free(sc);
}

static void loop_new_refuses_bad_config(void **state)
{
	struct hl_scenario *sc = scenario();
	struct hl_loop_latency_config cfg = { .sc = sc, .ecu_cycle_ms = 20, .reaction_ms = 0 };
	struct hl_loop_latency *ll = NULL;

	(void)state;
	assert_int_equal(hl_loop_latency_new(&cfg, &ll), -EINVAL);
	cfg.reaction_ms = 60;
	cfg.ecu_cycle_ms = 0;
	assert_int_equal(hl_loop_latency_new(&cfg, &ll), -EINVAL);
	assert_null(ll);
	hl_loop_latency_free(NULL);
	free(sc);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(loop_masked_within_reaction_passes),
		cmocka_unit_test(loop_glare_after_reaction_fails),
		cmocka_unit_test(loop_never_masked_is_reported_unmasked),
		cmocka_unit_test(loop_without_camera_is_strict),
		cmocka_unit_test(loop_full_ring_counts_dropped_frames),
		cmocka_unit_test(loop_new_refuses_bad_config),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
