/* SPDX-License-Identifier: MIT */
/* The cycle assembler on the shipped databases: values, counters, E2E faults, timeouts. */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "can/assembler.h"
#include "testutil.h"

#define MS 1000000LL

static const char *const lamps[2] = { "left", "right" };

struct fixture {
	struct hl_dbc *db;
	struct hl_assembler *a;
};

static struct hl_dbc *load_db(const char *name)
{
	char path[512];
	struct hl_dbc *db = NULL;
	struct hl_dbc_error err;

	snprintf(path, sizeof(path), "%s/dbc/%s", getenv("HL_SOURCE_DIR"), name);
	if (hl_dbc_parse_file(path, &db, &err) < 0)
		fail_msg("%s:%d:%d: %s", path, err.line, err.column, err.msg);
	return db;
}

static int setup_db(void **state, const char *name)
{
	struct fixture *f = calloc(1, sizeof(*f));
	struct hl_asm_error err;

	f->db = load_db(name);
	if (hl_assembler_new(f->db, lamps, 2, 100, 0, &f->a, &err) < 0)
		fail_msg("%s", err.msg);
	*state = f;
	return 0;
}

static int setup_classic(void **state)
{
	return setup_db(state, "hd84.dbc");
}

static int setup_fd(void **state)
{
	return setup_db(state, "hd84_fd.dbc");
}

static int teardown(void **state)
{
	struct fixture *f = *state;

	hl_assembler_free(f->a);
	hl_dbc_free(f->db);
	free(f);
	return 0;
}

static void values(unsigned long long *rng, float *i)
{
	for (int k = 0; k < 95; k++)
		i[k] = (float)(test_rand(rng) % 64) / 63.0f;
}

/* Feeds frames; returns the number of cycles completed, the last one in *ret. */
static int feed(struct hl_assembler *a, const struct hl_encoded_frame *fr, int n, int64_t t_ns,
		struct hl_cycle *ret, struct hl_asm_events *ev)
{
	int done = 0;

	for (int j = 0; j < n; j++) {
		struct hl_cycle c;

		if (hl_assembler_feed(a, &fr[j].frame, t_ns, t_ns, &c, ev) == 1) {
			*ret = c;
			done++;
		}
	}
	return done;
}

static void assembler_plans_both_lamps_from_the_dbc(void **state)
{
	struct fixture *f = *state;
	uint32_t ids[8];
	uint32_t first;
	int n;

	assert_int_equal(hl_assembler_n_lamps(f->a), 2);
	assert_int_equal(hl_assembler_n_sources(f->a, 0), 95);
	assert_int_equal(hl_assembler_n_sources(f->a, 1), 95);
	assert_string_equal(hl_assembler_lamp_name(f->a, 1), "right");
	n = hl_assembler_ids(f->a, ids, 8);
	assert_true(n == 2 || n == 4); /* hd84: a message per lamp; hd84_fd: two */
	/* a list too short is filled as far as it goes, and the count says so */
	first = ids[0];
	ids[0] = ids[1] = 0;
	assert_int_equal(hl_assembler_ids(f->a, ids, 1), n);
	assert_int_equal(ids[0], first);
	assert_int_equal(ids[1], 0);
}

static void assembler_names_each_sources_signal(void **state)
{
	struct fixture *f = *state;
	const struct hl_dbc_signal *s = hl_assembler_source_signal(f->a, 0, 0);

	assert_non_null(s);
	assert_string_equal(s->name, "LED_001");
	assert_int_equal(s->length, 6);
	assert_true(s->factor == 1.0 / 63.0 && s->offset == 0.0);
	assert_non_null(hl_assembler_source_signal(f->a, 1, 94));
	assert_null(hl_assembler_source_signal(f->a, 1, 95));
	assert_null(hl_assembler_source_signal(f->a, 2, 0));
	assert_null(hl_assembler_source_signal(f->a, 0, -1));
}

static void assembler_cycles_round_trip_exactly(void **state)
{
	struct fixture *f = *state;
	struct hl_encoded_frame fr[2][64];
	unsigned long long rng = 5;
	float in[2][95];
	int n[2];

	for (int cyc = 0; cyc < 40; cyc++) {
		const unsigned counter = (unsigned)cyc % (hl_assembler_counter_max(f->a, 0) + 1);

		for (int l = 0; l < 2; l++) {
			values(&rng, in[l]);
			n[l] = hl_assembler_encode(f->a, l, in[l], counter, fr[l], 64);
			assert_true(n[l] >= 2);
		}
		/* the lamps' frames interleave on the bus */
		for (int j = 0; j < n[0] || j < n[1]; j++) {
			for (int l = 0; l < 2; l++) {
				struct hl_cycle c;
				struct hl_asm_events ev;
				int done;

				if (j >= n[l])
					continue;
				done = hl_assembler_feed(f->a, &fr[l][j].frame, cyc * 20 * MS + j,
							 cyc * 20 * MS + j, &c, &ev);
				assert_int_equal(done, j == n[l] - 1);
				if (!done)
					continue;
				assert_int_equal(c.lamp, l);
				assert_true(c.seq == (uint64_t)cyc + 1);
				assert_int_equal(c.counter, counter);
				assert_int_equal(c.n_sources, 95);
				assert_memory_equal(c.i, in[l], sizeof(in[l]));
			}
		}
	}
	for (int l = 0; l < 2; l++) {
		const struct hl_lamp_counters *lc = hl_assembler_lamp_counters(f->a, l);

		assert_true(lc->cycles == 40 && lc->crc_errors == 0 && lc->incomplete == 0 &&
			    lc->lost_cycles == 0 && lc->repeated_frames == 0 &&
			    lc->stale_events == 0);
	}
}

/* One fault each: a CRC error, a missing page, a counter jump, a repeated cycle. */
static void assembler_counts_each_injected_fault_once(void **state)
{
	struct fixture *f = *state;
	struct hl_encoded_frame fr[64];
	struct hl_asm_events ev;
	struct hl_cycle c = { 0 }; /* feed() fills it only when a cycle completes */
	float in[95];
	unsigned long long rng = 11;
	const struct hl_lamp_counters *lc = hl_assembler_lamp_counters(f->a, 0);
	int n;

	values(&rng, in);
	n = hl_assembler_encode(f->a, 0, in, 0, fr, 64);
	assert_int_equal(feed(f->a, fr, n, 0, &c, &ev), 1);

	/* counter 1: one frame's payload bit flipped: CRC error, cycle cannot complete */
	n = hl_assembler_encode(f->a, 0, in, 1, fr, 64);
	fr[1].frame.data[3] ^= 0x10;
	assert_int_equal(feed(f->a, fr, n, 20 * MS, &c, &ev), 0);
	assert_true(lc->crc_errors == 1);

	/* counter 2 completes; counter 1 was abandoned, so nothing is "lost" */
	n = hl_assembler_encode(f->a, 0, in, 2, fr, 64);
	assert_int_equal(feed(f->a, fr, n, 40 * MS, &c, &ev), 1);
	assert_true(lc->incomplete == 1 && lc->lost_cycles == 0 && c.counter == 2);

	/* counter 3 misses its last page; counter 4 completes */
	n = hl_assembler_encode(f->a, 0, in, 3, fr, 64);
	assert_int_equal(feed(f->a, fr, n - 1, 60 * MS, &c, &ev), 0);
	n = hl_assembler_encode(f->a, 0, in, 4, fr, 64);
	assert_int_equal(feed(f->a, fr, n, 80 * MS, &c, &ev), 1);
	assert_true(lc->incomplete == 2 && lc->lost_cycles == 0);

	/* counter jumps from 4 to 8: three cycles lost */
	n = hl_assembler_encode(f->a, 0, in, 8, fr, 64);
	assert_int_equal(feed(f->a, fr, n, 100 * MS, &c, &ev), 1);
	assert_true(lc->lost_cycles == 3 && c.counter == 8);

	/* the same cycle again: every frame ignored, counted */
	assert_int_equal(feed(f->a, fr, n, 120 * MS, &c, &ev), 0);
	assert_true(lc->repeated_frames == (uint64_t)n);
	assert_true(lc->cycles == 4 && lc->crc_errors == 1 && lc->incomplete == 2 &&
		    lc->lost_cycles == 3);
	assert_true(hl_assembler_lamp_counters(f->a, 1)->frames == 0);
}

static void assembler_lamp_goes_stale_after_timeout_and_recovers(void **state)
{
	struct fixture *f = *state;
	struct hl_encoded_frame fr[64];
	struct hl_asm_events ev;
	struct hl_cycle c;
	float in[95] = { 0 };
	int n;

	/* no cycle at all since start (t = 0): stale at exactly 100 ms */
	assert_int_equal(hl_assembler_expire(f->a, 99 * MS), 0);
	assert_true(hl_assembler_next_deadline(f->a) == 100 * MS);
	assert_int_equal(hl_assembler_expire(f->a, 100 * MS), 3);
	assert_true(hl_assembler_stale(f->a, 0) && hl_assembler_stale(f->a, 1));
	assert_int_equal(hl_assembler_expire(f->a, 200 * MS), 0); /* once */

	n = hl_assembler_encode(f->a, 0, in, 0, fr, 64);
	assert_int_equal(feed(f->a, fr, n, 210 * MS, &c, &ev), 1);
	assert_int_equal(ev.recovered, 1);
	assert_false(hl_assembler_stale(f->a, 0));
	assert_true(hl_assembler_next_deadline(f->a) == 310 * MS);
	assert_int_equal(hl_assembler_expire(f->a, 309 * MS), 0);
	assert_int_equal(hl_assembler_expire(f->a, 310 * MS), 1);
	assert_true(hl_assembler_lamp_counters(f->a, 0)->stale_events == 2);
	assert_true(hl_assembler_lamp_counters(f->a, 0)->recoveries == 1);
}

static void assembler_counts_error_short_and_unknown_frames(void **state)
{
	struct fixture *f = *state;
	struct hl_encoded_frame fr[64];
	struct canfd_frame g = { 0 };
	struct hl_asm_events ev;
	struct hl_cycle c;
	float in[95] = { 0 };
	int n;

	g.can_id = CAN_ERR_FLAG | 0x4; /* controller problem */
	g.len = 8;
	assert_int_equal(hl_assembler_feed(f->a, &g, 0, 0, &c, &ev), 0);
	g.can_id = 0x7ff;
	assert_int_equal(hl_assembler_feed(f->a, &g, 0, 0, &c, &ev), 0);
	n = hl_assembler_encode(f->a, 0, in, 0, fr, 64);
	assert_true(n > 0);
	fr[0].frame.len = 3; /* short */
	assert_int_equal(hl_assembler_feed(f->a, &fr[0].frame, 0, 0, &c, &ev), 0);
	assert_true(hl_assembler_counters(f->a)->error_frames == 1);
	assert_true(hl_assembler_counters(f->a)->dbc.unknown_id == 1);
	assert_true(hl_assembler_counters(f->a)->dbc.short_frame == 1);
	assert_true(hl_assembler_lamp_counters(f->a, 0)->frames == 0);
}

static void assembler_rejects_a_dbc_that_does_not_fit_the_lamps(void **state)
{
	struct hl_dbc *db = load_db("hd84.dbc");
	static const char *const one[1] = { "left" };
	static const char *const three[3] = { "left", "right", "centre" };
	struct hl_assembler *a = NULL;
	struct hl_asm_error err;
	(void)state;

	assert_int_equal(hl_assembler_new(db, one, 1, 100, 0, &a, &err), -EINVAL);
	assert_non_null(strstr(err.msg, "HdlLamp \"right\" is not a configured lamp"));
	assert_int_equal(hl_assembler_new(db, three, 3, 100, 0, &a, &err), -EINVAL);
	assert_string_equal(
		err.msg,
		"lamp 'centre' has no message with HdlLamp \"centre\" and HdlSource signals");
	assert_null(a);
	hl_dbc_free(db);
}

/* hd84.dbc text with HdlSource defined as CANdb++ writes it when the range excludes 0. */
static struct hl_dbc *load_db_default_1(void)
{
	char path[512], *text, *at;
	struct hl_dbc *db = NULL;
	struct hl_dbc_error err;
	FILE *f;
	long n;

	snprintf(path, sizeof(path), "%s/dbc/hd84.dbc", getenv("HL_SOURCE_DIR"));
	f = fopen(path, "re");
	assert_non_null(f);
	fseek(f, 0, SEEK_END);
	n = ftell(f);
	rewind(f);
	text = calloc(1, n + 1);
	assert_non_null(text);
	assert_int_equal(fread(text, 1, n, f), n);
	fclose(f);
	at = strstr(text, "\"HdlSource\" INT 0 4096;");
	assert_non_null(at);
	at[strlen("\"HdlSource\" INT ")] = '1';
	at = strstr(text, "BA_DEF_DEF_  \"HdlSource\" 0;");
	assert_non_null(at);
	at[strlen("BA_DEF_DEF_  \"HdlSource\" ")] = '1';
	if (hl_dbc_parse(text, n, &db, &err) < 0)
		fail_msg("%d:%d: %s", err.line, err.column, err.msg);
	free(text);
	return db;
}

/* Sources come from explicit BA_ only: a default of 1 (INT 1 4096) gives the same cycles. */
static void assembler_hdl_source_default_1_assembles_the_same_cycles(void **state)
{
	struct fixture *f = *state;
	struct hl_dbc *db1 = load_db_default_1();
	struct hl_assembler *a1 = NULL;
	struct hl_asm_error err;
	unsigned long long rng = 11;
	struct hl_encoded_frame fr[64];
	float in[95];
	const struct hl_dbc_message *m = hl_dbc_find_message(db1, "HL_Dim_L");
	struct hl_dbc_attr_value v;

	/* the CRC, counter and page signals read the default 1, yet carry no source */
	assert_non_null(m);
	for (int s = 0; s < m->n_signals; s++)
		if (m->signals[s].is_multiplexor)
			assert_int_equal(
				hl_dbc_signal_attr(db1, m, &m->signals[s], "HdlSource", &v), 1);
	assert_int_equal(v.i, 1);
	assert_int_equal(hl_assembler_new(db1, lamps, 2, 100, 0, &a1, &err), 0);
	for (int l = 0; l < 2; l++)
		assert_int_equal(hl_assembler_n_sources(a1, l), hl_assembler_n_sources(f->a, l));
	for (int cyc = 0; cyc < 12; cyc++) {
		for (int l = 0; l < 2; l++) {
			struct hl_cycle c0 = { 0 }, c1 = { 0 };
			struct hl_asm_events ev;
			int n;

			values(&rng, in);
			/* encoded with the default-0 database, assembled with both */
			n = hl_assembler_encode(f->a, l, in, (unsigned)cyc % 15, fr, 64);
			assert_true(n >= 2);
			assert_int_equal(feed(f->a, fr, n, cyc * 20 * MS, &c0, &ev), 1);
			assert_int_equal(feed(a1, fr, n, cyc * 20 * MS, &c1, &ev), 1);
			assert_int_equal(c1.lamp, c0.lamp);
			assert_true(c1.seq == c0.seq);
			assert_int_equal(c1.counter, c0.counter);
			assert_int_equal(c1.n_sources, c0.n_sources);
			assert_memory_equal(c1.i, c0.i, sizeof(float) * c0.n_sources);
			assert_memory_equal(c1.i, in, sizeof(in));
		}
	}
	hl_assembler_free(a1);
	hl_dbc_free(db1);
}

/* The text of a file of the source tree (malloc'd, NUL-terminated), its length in *ret_n. */
static char *read_text(const char *rel, long *ret_n)
{
	char path[512], *text;
	FILE *f;
	long n;

	snprintf(path, sizeof(path), "%s/%s", getenv("HL_SOURCE_DIR"), rel);
	f = fopen(path, "re");
	assert_non_null(f);
	fseek(f, 0, SEEK_END);
	n = ftell(f);
	rewind(f);
	text = calloc(1, n + 1);
	assert_non_null(text);
	assert_int_equal(fread(text, 1, n, f), n);
	fclose(f);
	*ret_n = n;
	return text;
}

/* A shipped database's text without its beam-mode signal (every line naming HL_Mode_). */
static struct hl_dbc *load_db_without_mode(const char *name)
{
	char rel[64], *text, *line, *out;
	struct hl_dbc *db = NULL;
	struct hl_dbc_error err;
	long n;
	size_t len = 0;

	snprintf(rel, sizeof(rel), "dbc/%s", name);
	text = read_text(rel, &n);
	out = calloc(1, n + 1);
	assert_non_null(out);
	for (line = strtok(text, "\n"); line; line = strtok(NULL, "\n"))
		if (!strstr(line, "HL_Mode_"))
			len += (size_t)sprintf(out + len, "%s\n", line);
	if (hl_dbc_parse(out, (long)len, &db, &err) < 0)
		fail_msg("%s without HL_Mode_:%d:%d: %s", name, err.line, err.column, err.msg);
	free(text);
	free(out);
	return db;
}

/*
 * hd84_fd.dbc with a 4-bit HL_Mode_L/_R in the last byte of each lamp's second message
 * (tests/data/dbc/hd84_fd_beam_mode.dbc): its value rides with the lamp's cycle.
 */
static void assembler_beam_mode_signal_rides_with_the_cycle(void **state)
{
	struct hl_dbc *db, *plain = load_db_without_mode("hd84_fd.dbc");
	struct hl_assembler *a, *ap;
	struct hl_asm_error err;
	struct hl_encoded_frame fr[64];
	struct hl_asm_events ev;
	struct hl_dbc_error derr;
	const struct hl_dbc_signal *sg;
	unsigned long long rng = 5;
	float in[95];
	long n;
	char *text = read_text("tests/data/dbc/hd84_fd_beam_mode.dbc", &n), *at;
	(void)state;

	assert_int_equal(hl_dbc_parse(text, n, &db, &derr), 0);
	assert_int_equal(hl_assembler_new(db, lamps, 2, 100, 0, &a, &err), 0);
	assert_int_equal(hl_assembler_new(plain, lamps, 2, 100, 0, &ap, &err), 0);
	sg = hl_assembler_mode_signal(a, 0);
	assert_non_null(sg);
	assert_string_equal(sg->name, "HL_Mode_L");
	assert_int_equal(sg->n_values, 3);
	assert_string_equal(sg->values[2].desc, "glarefree");
	assert_string_equal(hl_assembler_mode_signal(a, 1)->name, "HL_Mode_R");
	assert_null(hl_assembler_mode_signal(ap, 0));
	assert_int_equal(hl_assembler_n_sources(a, 0), 95); /* the mode is no source */
	for (int cyc = 0; cyc < 6; cyc++) {
		struct hl_cycle c = { 0 };
		const int64_t mode = cyc % 3;
		int k;

		values(&rng, in);
		k = hl_assembler_encode_mode(a, 0, in, (unsigned)cyc, mode, fr, 64);
		assert_int_equal(k, 2);
		assert_int_equal(feed(a, fr, k, cyc * 20 * MS, &c, &ev), 1);
		assert_true(c.mode == mode);
		assert_memory_equal(c.i, in, sizeof(in));
		/* the plain database's lamps carry no mode; its frames are the same size */
		k = hl_assembler_encode(ap, 0, in, (unsigned)cyc, fr, 64);
		assert_int_equal(feed(ap, fr, k, cyc * 20 * MS, &c, &ev), 1);
		assert_true(c.mode == -1);
	}
	hl_assembler_free(a);
	hl_assembler_free(ap);
	hl_dbc_free(db);

	/* without VAL_ names the modes have none: refused */
	for (int l = 0; l < 2; l++) { /* both lamps' VAL_ statements blanked */
		at = strstr(text, l ? "VAL_ 819 HL_Mode_R" : "VAL_ 817 HL_Mode_L");
		assert_non_null(at);
		memset(at, ' ', strcspn(at, ";") + 1);
	}
	assert_int_equal(hl_dbc_parse(text, n, &db, &derr), 0);
	assert_int_equal(hl_assembler_new(db, lamps, 2, 100, 0, &a, &err), -EINVAL);
	assert_non_null(strstr(err.msg, "signal HL_Mode_L of message HL_DimB_L (line "));
	assert_non_null(
		strstr(err.msg, "): HdlBeamMode needs the modes' names as VAL_ descriptions"));
	hl_dbc_free(db);
	hl_dbc_free(plain);
	free(text);
}

/*
 * The shipped databases' HL_Mode_L / HL_Mode_R (0 unset, 1 low, 2 high, 3 glarefree): hd84.dbc
 * on page 11 (bits 58..63, the slot after source 95), hd84_fd.dbc in frame B (bits 114..119).
 * Each cycle carries the value given; hl_assembler_encode (no mode) sends 0, "unset".
 */
static void assembler_shipped_databases_carry_the_beam_mode(void **state)
{
	static const char *const files[] = { "hd84.dbc", "hd84_fd.dbc" };
	static const char *const mode_msg[] = { "HL_Dim_L", "HL_DimB_L" };
	static const int start[] = { 58, 114 }, parts[] = { 12, 2 };
	static const char *const names[] = { "unset", "low", "high", "glarefree" };
	(void)state;

	for (int f = 0; f < 2; f++) {
		struct hl_dbc *db = load_db(files[f]);
		struct hl_assembler *a;
		struct hl_asm_error err;
		struct hl_encoded_frame fr[64];
		struct hl_asm_events ev;
		const struct hl_dbc_signal *sg;
		unsigned long long rng = 11;
		float in[95];
		int64_t v;

		assert_int_equal(hl_assembler_new(db, lamps, 2, 100, 0, &a, &err), 0);
		for (int l = 0; l < 2; l++) {
			sg = hl_assembler_mode_signal(a, l);
			assert_non_null(sg);
			assert_string_equal(sg->name, l ? "HL_Mode_R" : "HL_Mode_L");
			assert_int_equal(sg->start_bit, start[f]);
			assert_int_equal(sg->length, 6);
			assert_int_equal(sg->n_values, 4);
			for (int k = 0; k < 4; k++) {
				assert_int_equal(sg->values[k].value, k);
				assert_string_equal(sg->values[k].desc, names[k]);
				assert_int_equal(hl_assembler_mode_value(a, l, names[k], &v), 0);
				assert_true(v == k);
			}
			assert_int_equal(hl_assembler_mode_value(a, l, "GlareFree", &v), 0);
			assert_true(v == 3);
			assert_int_equal(hl_assembler_mode_value(a, l, "fog", &v), -ENOENT);
			assert_int_equal(hl_assembler_n_sources(a, l),
					 95); /* the mode is no source */
		}
		sg = hl_assembler_mode_signal(a, 0);
		assert_ptr_equal(sg, hl_dbc_find_signal(hl_dbc_find_message(db, mode_msg[f]),
							"HL_Mode_L"));
		if (f == 0) /* a page-11 signal, as the sources 89..95 */
			assert_true(sg->mux_parent >= 0 && sg->n_mux_ranges == 1 &&
				    sg->mux_ranges[0].lo == 11 && sg->mux_ranges[0].hi == 11);
		for (int cyc = 0; cyc < 8; cyc++) {
			struct hl_cycle c = { 0 };
			const int64_t mode = cyc % 4;
			int k;

			values(&rng, in);
			k = hl_assembler_encode_mode(a, 0, in, (unsigned)cyc, mode, fr, 64);
			assert_int_equal(k, parts[f]);
			assert_int_equal(feed(a, fr, k, cyc * 20 * MS, &c, &ev), 1);
			assert_true(c.mode == mode);
			assert_memory_equal(c.i, in, sizeof(in));
		}
		/* no mode given: the bits stay 0, unset */
		{
			struct hl_cycle c = { 0 };
			int k;

			k = hl_assembler_encode(a, 0, in, 8, fr, 64);
			assert_int_equal(feed(a, fr, k, 8 * 20 * MS, &c, &ev), 1);
			assert_true(c.mode == 0);
		}
		hl_assembler_free(a);
		hl_dbc_free(db);
	}
}

/*
 * A restart (a looped log's next pass) forgets the counters: the same counter again is a new
 * cycle, not repeated frames; a lower one is no jump; a cycle half assembled is incomplete.
 */
static void assembler_restart_forgets_the_alive_counters(void **state)
{
	struct fixture *f = *state;
	struct hl_encoded_frame fr[64];
	struct hl_asm_events ev;
	struct hl_cycle c = { 0 };
	float in[95];
	unsigned long long rng = 5;
	const struct hl_lamp_counters *lc = hl_assembler_lamp_counters(f->a, 0);
	int n;

	values(&rng, in);
	for (unsigned k = 0; k < 3; k++) {
		n = hl_assembler_encode(f->a, 0, in, k, fr, 64);
		assert_int_equal(feed(f->a, fr, n, (int64_t)k * 20 * MS, &c, &ev), 1);
	}
	/* the next pass begins with counter 0 again: no lost cycles, no repeated frames */
	hl_assembler_restart(f->a);
	n = hl_assembler_encode(f->a, 0, in, 0, fr, 64);
	assert_int_equal(feed(f->a, fr, n, 60 * MS, &c, &ev), 1);
	assert_int_equal(c.counter, 0);
	assert_int_equal(c.seq, 4);
	/* a pass ending mid-cycle: the part-assembled cycle is incomplete, the next one whole */
	n = hl_assembler_encode(f->a, 0, in, 1, fr, 64);
	assert_int_equal(feed(f->a, fr, n - 1, 80 * MS, &c, &ev), 0);
	hl_assembler_restart(f->a);
	n = hl_assembler_encode(f->a, 0, in, 1, fr, 64);
	assert_int_equal(feed(f->a, fr, n, 100 * MS, &c, &ev), 1);
	assert_int_equal(lc->cycles, 5);
	assert_int_equal(lc->lost_cycles, 0);
	assert_int_equal(lc->repeated_frames, 0);
	assert_int_equal(lc->incomplete, 1);
	/* without a restart the same counter again is what it always was: repeated frames */
	assert_int_equal(feed(f->a, fr, n, 120 * MS, &c, &ev), 0);
	assert_int_equal(lc->repeated_frames, (uint64_t)n);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test_setup_teardown(assembler_plans_both_lamps_from_the_dbc,
						setup_classic, teardown),
		cmocka_unit_test_setup_teardown(assembler_names_each_sources_signal, setup_classic,
						teardown),
		cmocka_unit_test_setup_teardown(assembler_cycles_round_trip_exactly, setup_classic,
						teardown),
		cmocka_unit_test_setup_teardown(assembler_counts_each_injected_fault_once,
						setup_classic, teardown),
		cmocka_unit_test_setup_teardown(assembler_lamp_goes_stale_after_timeout_and_recovers,
						setup_classic, teardown),
		cmocka_unit_test_setup_teardown(assembler_counts_error_short_and_unknown_frames,
						setup_classic, teardown),
		cmocka_unit_test_setup_teardown(assembler_plans_both_lamps_from_the_dbc, setup_fd,
						teardown),
		cmocka_unit_test_setup_teardown(assembler_cycles_round_trip_exactly, setup_fd,
						teardown),
		cmocka_unit_test_setup_teardown(assembler_counts_each_injected_fault_once, setup_fd,
						teardown),
		cmocka_unit_test_setup_teardown(assembler_restart_forgets_the_alive_counters,
						setup_classic, teardown),
		cmocka_unit_test_setup_teardown(assembler_restart_forgets_the_alive_counters,
						setup_fd, teardown),
		cmocka_unit_test(assembler_rejects_a_dbc_that_does_not_fit_the_lamps),
		cmocka_unit_test_setup_teardown(
			assembler_hdl_source_default_1_assembles_the_same_cycles, setup_classic,
			teardown),
		cmocka_unit_test(assembler_beam_mode_signal_rides_with_the_cycle),
		cmocka_unit_test(assembler_shipped_databases_carry_the_beam_mode),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
