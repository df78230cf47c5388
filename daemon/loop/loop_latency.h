/* SPDX-License-Identifier: MIT */
/*
 * The closed loop's latency and its glare verdict (docs/loop.md): for each road user entering
 * or leaving the front camera's view as the restbus projects it (daemon/loop/restbus_state.h), the
 * times along the loop and how long the user was glared.
 *
 * An enter event of road user i has four times, all CLOCK_MONOTONIC ns:
 *   t_enter: the deadline of the first camera cycle that carried i (its scenario time t_enter_s
 *            = the cycle's; i entered the view at most one camera period before it),
 *   t_input: when the restbus finished sending that cycle's frames (the ECU has the cycle),
 *   t_mask:  the first dimming cycle after t_input whose glare at i's eye is under its limit:
 *            the first frame whose lamps' cycles all completed after t_input (hdr
 *            t_lamp_done_ns) with i's glare passing (daemon/core/glare_live.h); t_mask is the later
 *            lamp's completion,
 *   t_frame: that frame's render end (hdr t_render_done_ns), the first rendered frame under
 *            the limit that shows the ECU's answer.
 * Latencies: each time minus t_enter, in ms and in ECU cycles (ms / ecu_cycle_ms). A leave event
 * has t_enter (the first cycle without i) and t_input only, and closes the visible interval:
 * its glare time (scenario seconds over the limit while visible, each over-limit frame counted
 * until the next frame's scenario time) and over-limit frames.
 *
 * The verdict (per road user, on every frame, by the frame's scenario time t): glare over the
 * limit is allowed while i is in the camera's view and t - t_enter_s <= reaction_ms; over the
 * limit later in the interval is a violation; over the limit while i is not in the view (the
 * ECU was not told) is counted as unseen and is no violation. A frame is judged under the camera
 * state in force at its scenario time: the newest camera cycle at or before t.
 *
 * Threads: the render thread hands each published frame over with hl_loop_latency_frame()
 * through a lock-free single-producer single-consumer ring (never blocks; a full ring drops the
 * frame, counted); the restbus thread (or, without a restbus, the main thread through
 * hl_loop_latency_drain) is the one consumer: hl_loop_latency_camera() takes the frames, judges
 * those before the cycle's time and applies the cycle's entries and leaves. The results are
 * under a priority-inheritance mutex the consumer holds only to update them; the readers (counts,
 * status, metrics, report) copy them under it. JSON lines go to the events file from the
 * consumer, outside the lock.
 */
#ifndef HL_DAEMON_LOOP_LOOP_LATENCY_H
#define HL_DAEMON_LOOP_LOOP_LATENCY_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "daemon/core/frame.h"
#include "daemon/core/prom.h"
#include "world/scenario.h"

#define HL_LOOP_MAX_EVENTS 256 /* kept for the report; more are counted, not kept */
#define HL_LOOP_FRAME_SLOTS 512 /* frames between the render thread and the consumer */

struct hl_loop_latency_config {
	const struct hl_scenario *sc; /* must outlive it */
	double ecu_cycle_ms; /* the ECU's dimming period: 20 */
	double reaction_ms; /* glare allowed this long after entering the view */
	FILE *events; /* JSON lines per event; NULL: none */
	/* false: no restbus tells it of camera cycles; the verdict is then strict (no frame
	 * over any road user's limit) */
	bool camera;
};

struct hl_loop_event {
	int actor; /* index in the scenario */
	bool enter; /* false: leave */
	bool masked; /* enter: a masking frame was found (else the t_mask/t_frame fields are 0) */
	double t_enter_s; /* scenario time of the camera cycle */
	int64_t t_enter_ns, t_input_ns, t_mask_ns, t_frame_ns;
	uint64_t frame_seq; /* the masking frame */
	double glare_s; /* leave (or the end): the closed interval's time over the limit */
	uint64_t frames_over; /* its frames over the limit */
};

struct hl_loop_actor {
	double max_lux; /* the highest illuminance at the eye over judged frames */
	uint64_t frames_over; /* every frame over the limit */
	uint64_t frames_over_in_reaction; /* in view, within reaction_ms of entering */
	uint64_t frames_over_late; /* in view, later: violations */
	uint64_t frames_over_unseen; /* not in the camera's view */
	double glare_s; /* scenario seconds over the limit while in view */
	double glare_late_s; /* of those, after the reaction time */
	double glare_total_s; /* scenario seconds over the limit, in view or not */
	uint64_t entries, leaves;
};

struct hl_loop_counts {
	uint64_t frames_in; /* handed over by the render thread */
	uint64_t frames_dropped; /* the ring was full: not judged */
	uint64_t frames_judged;
	uint64_t camera_cycles;
	uint64_t events; /* every event, kept or not */
	uint64_t events_not_kept; /* beyond HL_LOOP_MAX_EVENTS */
	uint64_t unmasked; /* enter events no frame masked before the user left or the run ended */
	int n_actors;
	struct hl_loop_actor actor[HL_SCN_MAX_ACTORS];
	struct hl_prom_histogram latency_s[3]; /* input, mask, frame (masked enters), s */
};

struct hl_loop_latency;

/* 0, -EINVAL (a period or reaction not > 0), -ENOMEM. */
int hl_loop_latency_new(const struct hl_loop_latency_config *cfg, struct hl_loop_latency **ret);
void hl_loop_latency_free(struct hl_loop_latency *ll);

/* Render thread: frame f was published (hdr.seq set). Never blocks, allocates nothing. */
void hl_loop_latency_frame(struct hl_loop_latency *ll, const struct hl_frame *f);

/*
 * Consumer: the camera cycle with deadline deadline_ns (scenario time t_s) carried the road
 * users of bit mask visible (bit i: scenario index i); its last frame was sent at t_input_ns.
 */
void hl_loop_latency_camera(struct hl_loop_latency *ll, int64_t deadline_ns, double t_s,
			    uint32_t visible, int64_t t_input_ns);
/* Consumer: judges the frames handed over whose scenario time is before t_s (INFINITY: all). */
void hl_loop_latency_drain(struct hl_loop_latency *ll, double t_s);
/*
 * Consumer, at the end (the producer stopped): judges every frame left and closes the open
 * intervals (their glare time reported as an "end" line).
 */
void hl_loop_latency_finish(struct hl_loop_latency *ll);

/* Any thread. */
void hl_loop_latency_counts(struct hl_loop_latency *ll, struct hl_loop_counts *ret);
/* Any thread: event k (k < the kept events); false past them. */
bool hl_loop_latency_event(struct hl_loop_latency *ll, int k, struct hl_loop_event *ret);
/* The verdict: no road user over its limit in view after the reaction time (without a
 * camera: no road user over its limit at all). */
bool hl_loop_latency_passed(struct hl_loop_latency *ll);
/* true: no camera (no restbus), every frame over a road user's limit is a violation */
bool hl_loop_latency_strict(const struct hl_loop_latency *ll);
double hl_loop_latency_reaction_ms(const struct hl_loop_latency *ll);

/* One event as a JSON object (no newline). */
void hl_loop_event_json(const struct hl_loop_latency *ll, const struct hl_loop_event *e, FILE *f);
/* ,"loop":{...} for /status. */
void hl_loop_latency_status_json(struct hl_loop_latency *ll, FILE *f);
/* "loop":{...} for the run's report: per road user and every kept event. */
void hl_loop_latency_report_json(struct hl_loop_latency *ll, FILE *f);
/* hdlamp_loop_latency_seconds (histogram by stage), hdlamp_loop_* counters. */
void hl_loop_latency_metrics(struct hl_loop_latency *ll, struct hl_prom *p);

#endif
