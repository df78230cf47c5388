/* SPDX-License-Identifier: MIT */
/*
 * daemon/status.c: the /status JSON and /metrics text from the parts' counters, and a reload
 * (main thread) racing status reads (HTTP threads): run under ThreadSanitizer by tools/test.
 */
#include <errno.h>
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "daemon/status.h"

#define RELOADS 20000
#define READS 2000

static const char *const names[2] = { "left", "right" };

static struct hl_status *new_status(struct hl_ring **ret_ring)
{
	struct hl_status_sources src = {
		.input_name = "drive.log",
		.n_lamps = 2,
		.lamp_names = names,
	};
	struct hl_status *st;

	assert_int_equal(hl_ring_new(4, 2, 3, ret_ring), 0);
	src.ring = *ret_ring;
	assert_int_equal(hl_status_new(&src, HL_FAILSAFE_HOLD, &st), 0);
	return st;
}

static uint64_t number_after(const char *text, const char *key)
{
	const char *p = strstr(text, key);

	assert_non_null(p);
	return strtoull(p + strlen(key), NULL, 10);
}

static void status_rejects_no_lamps(void **state)
{
	const struct hl_status_sources src = { .input_name = "x", .lamp_names = names };
	struct hl_status *st = NULL;

	(void)state;
	assert_int_equal(hl_status_new(&src, HL_FAILSAFE_HOLD, &st), -EINVAL);
	assert_null(st);
	hl_status_free(NULL);
}

static void status_json_with_the_renderer_off(void **state)
{
	struct hl_ring *ring;
	struct hl_status *st = new_status(&ring);
	char buf[4096];
	const char *lamp = "{\"name\":\"%s\",\"stale\":false,\"failsafe\":false,\"cycles\":0,"
			   "\"crc_errors\":0,\"incomplete\":0,\"lost_cycles\":0,"
			   "\"repeated_frames\":0,\"stale_events\":0,\"failsafe_frames\":0,"
			   "\"cycles_not_rendered\":0}";
	char want[4096], l[512], r[512];
	int n;

	(void)state;
	hl_status_reloaded(st, HL_FAILSAFE_DARK);
	snprintf(l, sizeof(l), lamp, "left");
	snprintf(r, sizeof(r), lamp, "right");
	snprintf(want, sizeof(want),
		 "{\"renderer\":\"off\",\"input\":{\"source\":\"drive.log\",\"link\":\"down\","
		 "\"bus\":\"\"},\"lamps\":[%s,%s],\"failsafe_mode\":\"dark\",\"frames\":{"
		 "\"rendered\":0,\"published\":0,\"not_published\":0,\"render_ms_last\":0.000,"
		 "\"render_ms_max\":0.000},\"ring\":{\"pushed\":0,\"consumed\":0,\"superseded\":0,"
		 "\"dropped\":0},\"stream\":{\"clients\":0,\"clients_behind\":0,\"accepted\":0,"
		 "\"refused\":0,\"dropped\":{\"disconnected\":0,\"stalled\":0,\"evicted\":0,"
		 "\"input\":0},\"frames_sent\":0,\"frames_skipped\":0,\"bytes_sent\":0,"
		 "\"input_reads\":0},"
		 "\"captures\":0,\"captures_failed\":0,\"captures_refused\":0,\"reloads\":1}",
		 l, r);
	n = hl_status_json(st, buf, sizeof(buf));
	assert_string_equal(buf, want);
	assert_int_equal(n, (int)strlen(want));
	assert_int_equal(hl_status_json(st, buf, 64), -ENOBUFS);
	hl_status_free(st);
	hl_ring_free(ring);
}

static void status_metrics_are_prometheus_text(void **state)
{
	struct hl_ring *ring;
	struct hl_status *st = new_status(&ring);
	struct hl_snapshot *s;
	char buf[16384];

	(void)state;
	assert_int_equal(hl_snapshot_new(ring, &s), 0);
	hl_ring_push(ring, s);
	hl_ring_push(ring, s);
	assert_true(hl_ring_take_newest(ring, s)); /* one consumed, one superseded */
	assert_true(hl_status_metrics(st, buf, sizeof(buf)) > 0);
	assert_non_null(strstr(buf, "# HELP hdlamp_cycles_total Complete lamp cycles.\n"
				    "# TYPE hdlamp_cycles_total counter\n"
				    "hdlamp_cycles_total{lamp=\"left\"} 0\n"
				    "hdlamp_cycles_total{lamp=\"right\"} 0\n"));
	assert_non_null(strstr(buf, "hdlamp_ring_snapshots_total{fate=\"consumed\"} 1\n"
				    "hdlamp_ring_snapshots_total{fate=\"superseded\"} 1\n"
				    "hdlamp_ring_snapshots_total{fate=\"dropped\"} 0\n"));
	assert_non_null(strstr(buf, "hdlamp_lamp_stale{lamp=\"right\"} 0\n"));
	assert_non_null(strstr(buf, "hdlamp_link_up 0\n"));
	assert_non_null(strstr(buf,
			       "# TYPE hdlamp_stream_clients_dropped_total counter\n"
			       "hdlamp_stream_clients_dropped_total{reason=\"disconnected\"} 0\n"
			       "hdlamp_stream_clients_dropped_total{reason=\"stalled\"} 0\n"
			       "hdlamp_stream_clients_dropped_total{reason=\"evicted\"} 0\n"
			       "hdlamp_stream_clients_dropped_total{reason=\"input\"} 0\n"));
	assert_non_null(strstr(buf, "hdlamp_stream_clients_refused_total 0\n"));
	assert_non_null(strstr(buf, "hdlamp_captures_total{result=\"written\"} 0\n"
				    "hdlamp_captures_total{result=\"failed\"} 0\n"
				    "hdlamp_captures_total{result=\"refused\"} 0\n"));
	assert_null(strstr(buf, "hdlamp_render_seconds")); /* no renderer, no render times */
	assert_int_equal(hl_status_metrics(st, buf, 100), -ENOBUFS);
	hl_snapshot_free(s);
	hl_status_free(st);
	hl_ring_free(ring);
}

struct race {
	struct hl_status *st;
	pthread_barrier_t go;
};

/* The main thread's part: SIGHUP reloads, alternating the fail-safe mode. */
static void *reloader(void *arg)
{
	struct race *r = arg;

	pthread_barrier_wait(&r->go);
	for (int i = 1; i <= RELOADS; i++)
		hl_status_reloaded(r->st, i % 2 ? HL_FAILSAFE_DARK : HL_FAILSAFE_HOLD);
	return NULL;
}

/*
 * Both sides start together and neither waits for the other: without the status lock
 * ThreadSanitizer reports the reload's writes racing the reads (as it did for live.c's
 * unlocked reloads and cfg.failsafe).
 */
static void status_reload_races_status_reads(void **state)
{
	struct hl_ring *ring;
	struct race r = { .st = new_status(&ring) };
	static char buf[16384];
	uint64_t last = 0;
	pthread_t t;

	(void)state;
	assert_int_equal(pthread_barrier_init(&r.go, NULL, 2), 0);
	assert_int_equal(pthread_create(&t, NULL, reloader, &r), 0);
	pthread_barrier_wait(&r.go);
	/* the HTTP threads' part: what they see is always a state the main thread made */
	for (int i = 0; i < READS; i++) {
		uint64_t reloads;

		assert_true(hl_status_json(r.st, buf, sizeof(buf)) > 0);
		reloads = number_after(buf, "\"reloads\":");
		assert_true(reloads >= last && reloads <= RELOADS);
		assert_non_null(strstr(buf, reloads % 2 ? "\"failsafe_mode\":\"dark\"" :
							  "\"failsafe_mode\":\"hold\""));
		assert_true(hl_status_metrics(r.st, buf, sizeof(buf)) > 0);
		last = reloads;
	}
	pthread_join(t, NULL);
	pthread_barrier_destroy(&r.go);
	assert_true(hl_status_json(r.st, buf, sizeof(buf)) > 0);
	assert_int_equal(number_after(buf, "\"reloads\":"), RELOADS);
	assert_non_null(strstr(buf, "\"failsafe_mode\":\"hold\""));
	hl_status_free(r.st);
	hl_ring_free(ring);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(status_rejects_no_lamps),
		cmocka_unit_test(status_json_with_the_renderer_off),
		cmocka_unit_test(status_metrics_are_prometheus_text),
		cmocka_unit_test(status_reload_races_status_reads),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
