/* SPDX-License-Identifier: MIT */
/*
 * daemon/core/can_input.c with the log source: a candump log written here (HL_TEST_TMPDIR) from
 * cycles encoded with the shipped hd84.dbc, replayed as fast as possible by the CAN thread;
 * this thread pops every snapshot from the ring and checks each one exactly, then the
 * counters. A replay runs on the log's own timeline, so stale times are exact too.
 * SocketCAN cannot run on this host: of the socket input, the kernel filter list is checked
 * (hl_can_input_new builds it without opening the interface).
 */
#include <errno.h>
#include <math.h>
#include <poll.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "can/candump.h"
#include "can/candump_log.h"
#include "daemon/core/can_input.h"
#include "testutil.h"
#include "base/clock.h"

#define MS 1000000LL
#define T0_US 1700000000000000LL /* the log's first timestamp, µs since the epoch */
#define TIMEOUT_MS 100
#define N_SOURCES 95
#define WAIT_MS 20000 /* only a broken input takes this long to push the next snapshot */

static const char *const lamps[2] = { "left", "right" };

static struct hl_dbc *load_db(const char *path)
{
	struct hl_dbc *db = NULL;
	struct hl_dbc_error err;

	if (hl_dbc_parse_file(path, &db, &err) < 0)
		fail_msg("%s:%d:%d: %s", path, err.line, err.column, err.msg);
	return db;
}

static struct hl_dbc *load_shipped(const char *name)
{
	char path[512];

	snprintf(path, sizeof(path), "%s/dbc/%s", getenv("HL_SOURCE_DIR"), name);
	return load_db(path);
}

static struct hl_assembler *new_assembler(const struct hl_dbc *db, int n_lamps)
{
	struct hl_assembler *a = NULL;
	struct hl_asm_error err;

	if (hl_assembler_new(db, lamps, n_lamps, TIMEOUT_MS, 0, &a, &err) < 0)
		fail_msg("%s", err.msg);
	return a;
}

/* --- the log --- */

struct cycle {
	int lamp;
	unsigned counter;
	int64_t t_us; /* its first frame, relative to the log's start */
	uint8_t raw[N_SOURCES]; /* 0..63 per source */
};

static void write_frame(FILE *f, int64_t t_us, const struct canfd_frame *frame, bool fd)
{
	struct hl_candump_frame c = { .t_us = T0_US + t_us, .fd = fd, .frame = *frame };
	char line[HL_CANDUMP_MAX_LINE];

	strcpy(c.iface, "can0");
	assert_true(hl_candump_format(&c, line, sizeof(line)) > 0);
	fprintf(f, "%s\n", line);
}

/* Writes the cycle's frames, 100 µs apart; returns how many. */
static int write_cycle(FILE *f, const struct hl_assembler *a, const struct cycle *c)
{
	struct hl_encoded_frame fr[HL_ASM_MAX_PARTS];
	float in[N_SOURCES];
	int n;

	for (int k = 0; k < N_SOURCES; k++)
		in[k] = (float)c->raw[k] / 63.0f;
	n = hl_assembler_encode(a, c->lamp, in, c->counter, fr, HL_ASM_MAX_PARTS);
	assert_true(n > 0);
	for (int j = 0; j < n; j++)
		write_frame(f, c->t_us + 100 * j, &fr[j].frame, fr[j].fd);
	return n;
}

/* --- the consumer side --- */

/* The next snapshot in order, waiting on the input's eventfd (an event, not a duration). */
static void next_snapshot(struct hl_ring *ring, int wake_fd, struct hl_snapshot *ret)
{
	const int64_t until = hl_clock_monotonic_ns() + (int64_t)WAIT_MS * MS;

	while (!hl_ring_pop(ring, ret)) {
		struct pollfd p = { .fd = wake_fd, .events = POLLIN };
		uint64_t n;

		if (hl_clock_monotonic_ns() > until)
			fail_msg("no snapshot from the CAN thread");
		if (poll(&p, 1, 100) > 0 && read(wake_fd, &n, sizeof(n)) < 0)
			assert_int_equal(errno, EAGAIN);
	}
}

static void check_cycle(const struct hl_snapshot *s, const struct cycle *c, uint64_t seq,
			int64_t t_done_ns)
{
	const struct hl_lamp_snapshot *ls = &s->lamps[c->lamp];

	assert_int_equal(ls->cycle_seq, seq);
	assert_int_equal(ls->counter, c->counter);
	assert_int_equal(ls->t_rx_first_ns, (T0_US + c->t_us) * 1000);
	assert_int_equal(ls->t_complete_ns, t_done_ns);
	assert_int_equal(ls->status, HL_LAMP_VALID);
	assert_int_equal(s->t_event_ns, t_done_ns);
	for (int k = 0; k < N_SOURCES; k++)
		assert_int_equal(lroundf(s->i[c->lamp * N_SOURCES + k] * 63.0f), c->raw[k]);
}

/*
 * Five cycles of both lamps every 20 ms, a 300 ms silence (both go stale exactly 100 ms after
 * their last cycle, on the log's timeline), two more cycles each (both recover). Also an
 * unknown ID and a malformed line, counted; the malformed one logged with its line number.
 */
static void can_input_replay_pushes_exact_cycles_and_stale_events(void **state)
{
	char log_path[256], msg_path[256], text[512], want[512];
	struct hl_dbc *db = load_shipped("hd84.dbc");
	struct hl_assembler *a = new_assembler(db, 2);
	struct cycle cyc[14];
	struct hl_can_input_config cfg = { .replay = log_path, .replay_fast = true };
	struct hl_can_input *in;
	struct hl_input_status st;
	struct hl_ring *ring;
	struct hl_snapshot *s;
	unsigned long long rng = 42;
	int n_cyc = 0, frames = 0, parts, malformed_line;
	int64_t t_done[14];
	FILE *f;
	(void)state;

	test_path(log_path, sizeof(log_path), "replay.log");
	test_path(msg_path, sizeof(msg_path), "replay.msg");
	f = fopen(log_path, "w");
	assert_non_null(f);
	for (int k = 0; k < 7; k++) {
		const int64_t t_us = k * 20000 + (k >= 5 ? 300000 : 0);

		for (int l = 0; l < 2; l++) {
			struct cycle *c = &cyc[n_cyc++];

			c->lamp = l;
			c->counter = (unsigned)k;
			c->t_us = t_us + l * 5000; /* right 5 ms after left */
			for (int j = 0; j < N_SOURCES; j++)
				c->raw[j] = (uint8_t)(test_rand(&rng) % 64);
			parts = write_cycle(f, a, c);
			frames += parts;
			/* complete at its last frame, on the log's timeline from the first */
			t_done[n_cyc - 1] = (c->t_us + 100 * (parts - 1)) * 1000;
		}
	}
	/* an ID no lamp uses, and a malformed line, after the last cycle */
	write_frame(f, 6 * 20000 + 300000 + 20000,
		    &(struct canfd_frame){ .can_id = 0x123, .len = 2, .data = { 1, 2 } }, false);
	malformed_line = frames + 2;
	fprintf(f, "(1700000000.500000) can0 12G#00\n");
	assert_int_equal(fclose(f), 0);
	assert_int_equal(parts, 12); /* hd84: 12 pages per lamp cycle */

	assert_int_equal(hl_ring_new(16, 2, N_SOURCES, &ring), 0);
	assert_int_equal(hl_snapshot_new(ring, &s), 0);
	cfg.log = fopen(msg_path, "w+");
	assert_non_null(cfg.log);
	assert_int_equal(hl_can_input_new(&cfg, a, ring, &in), 0);
	assert_int_equal(hl_can_input_start(in), 0);

	/* cycles 1..5 of each lamp, in the log's order */
	for (int c = 0; c < 10; c++) {
		next_snapshot(ring, hl_can_input_wake_fd(in), s);
		assert_int_equal(s->seq, c);
		assert_int_equal(s->status, HL_INPUT_LINK_UP);
		check_cycle(s, &cyc[c], (uint64_t)c / 2 + 1, t_done[c]);
	}
	/* left, then right, go stale exactly TIMEOUT_MS after their last cycle completed */
	for (int l = 0; l < 2; l++) {
		next_snapshot(ring, hl_can_input_wake_fd(in), s);
		assert_int_equal(s->seq, 10 + l);
		assert_int_equal(s->t_event_ns, t_done[8 + l] + TIMEOUT_MS * MS);
		assert_int_equal(s->lamps[0].status, HL_LAMP_VALID | HL_LAMP_STALE);
		assert_int_equal(s->lamps[1].status, HL_LAMP_VALID | (l == 1 ? HL_LAMP_STALE : 0));
		assert_int_equal(s->lamps[l].cycle_seq, 5);
	}
	/* cycles 6 and 7: each lamp's first one recovers it */
	for (int c = 10; c < 14; c++) {
		next_snapshot(ring, hl_can_input_wake_fd(in), s);
		assert_int_equal(s->seq, c + 2);
		check_cycle(s, &cyc[c], (uint64_t)c / 2 + 1, t_done[c]);
		if (c == 10)
			assert_int_equal(s->lamps[1].status, HL_LAMP_VALID | HL_LAMP_STALE);
	}
	/* the end of the log: one last snapshot */
	next_snapshot(ring, hl_can_input_wake_fd(in), s);
	assert_int_equal(s->seq, 16);
	assert_int_equal(s->status, HL_INPUT_LINK_UP | HL_INPUT_DONE);
	hl_can_input_stop(in);
	assert_false(hl_ring_pop(ring, s));

	hl_can_input_status(in, &st);
	assert_int_equal(st.n_lamps, 2);
	assert_true(st.done && st.link_up && !st.is_socket);
	assert_string_equal(st.bus, "replay");
	for (int l = 0; l < 2; l++) {
		assert_int_equal(st.lamps[l].frames, 7 * 12);
		assert_int_equal(st.lamps[l].cycles, 7);
		assert_int_equal(st.lamps[l].stale_events, 1);
		assert_int_equal(st.lamps[l].recoveries, 1);
		assert_int_equal(st.lamps[l].crc_errors, 0);
		assert_int_equal(st.lamps[l].incomplete, 0);
		assert_int_equal(st.lamps[l].lost_cycles, 0);
		assert_false(st.stale[l]);
	}
	assert_int_equal(st.frames.dbc.decoded, frames);
	assert_int_equal(st.frames.dbc.unknown_id, 1);
	assert_int_equal(st.log.lines, frames + 2);
	assert_int_equal(st.log.malformed, 1);
	assert_int_equal(st.log.passes, 1);
	{
		const struct can_filter *flt = (const struct can_filter *)1;

		assert_int_equal(hl_can_input_filters(in, &flt), 0); /* a replay: no socket */
		assert_null(flt);
	}

	/* the malformed line, logged once with where it is */
	rewind(cfg.log);
	assert_non_null(fgets(text, sizeof(text), cfg.log));
	snprintf(want, sizeof(want), "hdlampd: '%s':%d:", log_path, malformed_line);
	assert_memory_equal(text, want, strlen(want));
	assert_null(fgets(text, sizeof(text), cfg.log));

	/* the report: the same counters as JSON members */
	{
		char *buf = NULL;
		size_t len = 0;
		FILE *m = open_memstream(&buf, &len);

		assert_non_null(m);
		hl_can_input_report(in, m);
		assert_int_equal(fclose(m), 0);
		snprintf(want, sizeof(want),
			 "\"frames\":{\"decoded\":%d,\"unknown_id\":1,\"short\":0,\"other\":0,"
			 "\"error_frames\":0},\"log\":{\"lines\":%d,\"frames\":%d,\"malformed\":1,"
			 "\"backwards\":0,\"passes\":1}",
			 frames, frames + 2, frames + 1);
		assert_string_equal(buf, want);
		free(buf);
	}

	hl_can_input_free(in);
	fclose(cfg.log);
	unlink(log_path);
	unlink(msg_path);
	hl_snapshot_free(s);
	hl_ring_free(ring);
	hl_assembler_free(a);
	hl_dbc_free(db);
}

/*
 * Two passes of a log (replay_loop, replay_passes 2) whose counters start again at 0: no lost
 * cycle and no repeated frame at the wrap; a malformed line and a timestamp going backwards are
 * reported with their line in the file in both passes, and counted.
 */
static void can_input_loop_passes_with_lines_per_pass(void **state)
{
	char log_path[256], msg_path[256], text[512], want[512];
	struct hl_dbc *db = load_shipped("hd84.dbc");
	struct hl_assembler *a = new_assembler(db, 2);
	struct hl_can_input_config cfg = {
		.replay = log_path, .replay_fast = true, .replay_loop = true, .replay_passes = 2
	};
	struct hl_can_input *in;
	struct hl_input_status st;
	struct hl_ring *ring;
	struct hl_snapshot *s;
	int lines = 2, back_line;
	FILE *f;
	(void)state;

	test_path(log_path, sizeof(log_path), "loop.log");
	test_path(msg_path, sizeof(msg_path), "loop.msg");
	f = fopen(log_path, "w");
	assert_non_null(f);
	fprintf(f, "# two lamps, counters 0..2\n(1700000000.000000) can0 32G#00\n");
	for (int k = 0; k < 3; k++)
		for (int l = 0; l < 2; l++) {
			struct cycle c = { .lamp = l,
					   .counter = (unsigned)k,
					   .t_us = k * 20000 + l * 5000 };

			lines += write_cycle(f, a, &c);
		}
	/* an ID no lamp uses, stamped 1 ms before the frame above it (right's last, 46.1 ms) */
	write_frame(f, 2 * 20000 + 5000 + 100,
		    &(struct canfd_frame){ .can_id = 0x123, .len = 2, .data = { 1, 2 } }, false);
	back_line = ++lines;
	assert_int_equal(fclose(f), 0);

	assert_int_equal(hl_ring_new(64, 2, N_SOURCES, &ring), 0);
	assert_int_equal(hl_snapshot_new(ring, &s), 0);
	cfg.log = fopen(msg_path, "w+");
	assert_non_null(cfg.log);
	assert_int_equal(hl_can_input_new(&cfg, a, ring, &in), 0);
	assert_int_equal(hl_can_input_start(in), 0);
	do
		next_snapshot(ring, hl_can_input_wake_fd(in), s);
	while (!(s->status & HL_INPUT_DONE));
	hl_can_input_stop(in);

	hl_can_input_status(in, &st);
	assert_int_equal(st.log.passes, 2);
	assert_int_equal(st.log.lines, 2 * lines);
	assert_int_equal(st.log.malformed, 2);
	assert_int_equal(st.log.backwards, 2);
	assert_int_equal(st.frames.dbc.unknown_id, 2); /* replayed, not dropped */
	for (int l = 0; l < 2; l++) {
		assert_int_equal(st.lamps[l].cycles, 6);
		assert_int_equal(st.lamps[l].lost_cycles, 0);
		assert_int_equal(st.lamps[l].repeated_frames, 0);
		assert_int_equal(st.lamps[l].incomplete, 0);
	}
	/* the same lines of the file in both passes */
	rewind(cfg.log);
	for (int pass = 0; pass < 2; pass++) {
		assert_non_null(fgets(text, sizeof(text), cfg.log));
		snprintf(want, sizeof(want),
			 "hdlampd: '%s':2:26: malformed candump line: ", log_path);
		assert_memory_equal(text, want, strlen(want));
		assert_non_null(fgets(text, sizeof(text), cfg.log));
		snprintf(want, sizeof(want),
			 "hdlampd: '%s':%d:1: timestamp 1700000000.045100 is 1000 us before the "
			 "previous frame's; expected times that never decrease (replayed at the "
			 "previous frame's time)\n",
			 log_path, back_line);
		assert_string_equal(text, want);
	}
	assert_null(fgets(text, sizeof(text), cfg.log));

	hl_can_input_free(in);
	fclose(cfg.log);
	unlink(log_path);
	unlink(msg_path);
	hl_snapshot_free(s);
	hl_ring_free(ring);
	hl_assembler_free(a);
	hl_dbc_free(db);
}

/* --- the kernel filter --- */

static void check_filters(const struct hl_assembler *a, const struct hl_dbc *db,
			  struct hl_ring *ring, int want)
{
	struct hl_can_input_config cfg = { .iface = "hltest0", .log = stderr };
	const struct can_filter *flt = NULL;
	struct hl_can_input *in;
	int n, found = 0;

	/* the interface is opened by the CAN thread, not here: this works without one */
	assert_int_equal(hl_can_input_new(&cfg, (struct hl_assembler *)a, ring, &in), 0);
	n = hl_can_input_filters(in, &flt);
	assert_int_equal(n, want);
	assert_non_null(flt);
	/* every lamp message of the database, exactly once, with the mask of its ID's width */
	for (int i = 0; i < hl_dbc_n_messages(db); i++) {
		const struct hl_dbc_message *m = hl_dbc_message(db, i);
		const uint32_t id = m->id | (m->extended ? CAN_EFF_FLAG : 0);
		const uint32_t mask = CAN_EFF_FLAG | CAN_RTR_FLAG |
				      (m->extended ? CAN_EFF_MASK : CAN_SFF_MASK);
		struct hl_dbc_attr_value lamp;
		int hits = 0;

		if (hl_dbc_message_attr(db, m, "HdlLamp", &lamp) < 0 || !lamp.s || !lamp.s[0])
			continue;
		for (int k = 0; k < n; k++)
			if (flt[k].can_id == id) {
				assert_int_equal(flt[k].can_mask, mask);
				hits++;
			}
		assert_int_equal(hits, 1);
		found++;
	}
	assert_int_equal(found, want);
	hl_can_input_free(in);
}

static void can_input_filters_every_lamp_message_of_hd84(void **state)
{
	struct hl_dbc *db = load_shipped("hd84_fd.dbc");
	struct hl_assembler *a = new_assembler(db, 2);
	struct hl_ring *ring;
	(void)state;

	assert_int_equal(hl_ring_new(4, 2, hl_assembler_n_sources(a, 0), &ring), 0);
	check_filters(a, db, ring, 4);
	hl_ring_free(ring);
	hl_assembler_free(a);
	hl_dbc_free(db);
}

/*
 * A database with more lamp messages than the old fixed list of 64: 2 lamps of 50 messages
 * (one source each; the odd ones with 29-bit IDs) and one message of no lamp. Every one of
 * the 100 must be in the kernel filter, or its frames would never arrive.
 */
static void can_input_filters_more_than_64_messages(void **state)
{
	const int per_lamp = 50;
	struct hl_assembler *a;
	struct hl_ring *ring;
	struct hl_dbc *db;
	char path[256];
	FILE *f;
	(void)state;

	test_path(path, sizeof(path), "many.dbc");
	f = fopen(path, "w");
	assert_non_null(f);
	fprintf(f,
		"VERSION \"\"\n\nNS_ :\n\tBA_DEF_\n\tBA_\n\tBA_DEF_DEF_\n\nBS_:\n\nBU_: ECU HL\n\n");
	for (int l = 0; l < 2; l++)
		for (int m = 0; m < per_lamp; m++) {
			const int k = l * per_lamp + m;
			const unsigned id = (m & 1) ? 0x80000000u | (0x18000000u + (unsigned)k) :
						      0x400u + (unsigned)k;

			fprintf(f, "BO_ %u M%d: 8 ECU\n SG_ S%d : 0|6@1+ (1,0) [0|63] \"\" HL\n\n",
				id, k, k);
		}
	fprintf(f, "BO_ 1 Other: 8 ECU\n SG_ X : 0|8@1+ (1,0) [0|255] \"\" HL\n\n");
	fprintf(f, "BA_DEF_ BO_ \"HdlLamp\" STRING ;\nBA_DEF_ BO_ \"HdlE2E\" STRING ;\n"
		   "BA_DEF_ SG_ \"HdlSource\" INT 0 4096;\nBA_DEF_DEF_ \"HdlLamp\" \"\";\n"
		   "BA_DEF_DEF_ \"HdlE2E\" \"none\";\nBA_DEF_DEF_ \"HdlSource\" 0;\n");
	for (int l = 0; l < 2; l++)
		for (int m = 0; m < per_lamp; m++) {
			const int k = l * per_lamp + m;
			const unsigned id = (m & 1) ? 0x80000000u | (0x18000000u + (unsigned)k) :
						      0x400u + (unsigned)k;

			fprintf(f, "BA_ \"HdlLamp\" BO_ %u \"%s\";\n", id, lamps[l]);
			fprintf(f, "BA_ \"HdlSource\" SG_ %u S%d %d;\n", id, k, m + 1);
		}
	assert_int_equal(fclose(f), 0);
	db = load_db(path);
	a = new_assembler(db, 2);
	assert_int_equal(hl_assembler_n_sources(a, 0), per_lamp);
	assert_int_equal(hl_ring_new(4, 2, per_lamp, &ring), 0);
	check_filters(a, db, ring, 2 * per_lamp);
	hl_ring_free(ring);
	hl_assembler_free(a);
	hl_dbc_free(db);
	unlink(path);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(can_input_replay_pushes_exact_cycles_and_stale_events),
		cmocka_unit_test(can_input_loop_passes_with_lines_per_pass),
		cmocka_unit_test(can_input_filters_every_lamp_message_of_hd84),
		cmocka_unit_test(can_input_filters_more_than_64_messages),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
