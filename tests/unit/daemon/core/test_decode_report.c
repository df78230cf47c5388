/* SPDX-License-Identifier: MIT */
/*
 * hdlampd --no-render's JSON lines, captured from stdout: link and bus events only when they
 * change (with the errno's text), each lamp's cycle only with --print-cycles and only when its
 * seq moves (every source, %.9g), stale and recovered events, true only on the replay's last
 * snapshot, and the summary's counters of a fresh input.
 */
#include <errno.h>
#include <fcntl.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "daemon/core/decode_report.h"
#include "testutil.h"

#define N_SOURCES 95

static const char *const lamps[2] = { "left", "right" };
static struct hl_dbc *db;
static struct hl_assembler *as;

static int setup(void **state)
{
	char path[512];
	struct hl_dbc_error derr;
	struct hl_asm_error aerr;

	(void)state;
	snprintf(path, sizeof(path), "%s/dbc/hd84.dbc", getenv("HL_SOURCE_DIR"));
	if (hl_dbc_parse_file(path, &db, &derr) < 0 ||
	    hl_assembler_new(db, lamps, 2, 100, 0, &as, &aerr) < 0)
		return -1;
	return 0;
}

static int teardown(void **state)
{
	(void)state;
	hl_assembler_free(as);
	hl_dbc_free(db);
	return 0;
}

/* stdout into a scratch file between begin and end; end returns what was written (static). */
static int saved_fd = -1;
static char captured[65536];
static char cap_path[512];

static void begin(void)
{
	int fd;

	fflush(stdout);
	test_path(cap_path, sizeof(cap_path), "stdout.txt");
	fd = open(cap_path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
	assert_true(fd >= 0);
	saved_fd = dup(1);
	assert_true(saved_fd >= 0);
	assert_int_equal(dup2(fd, 1), 1);
	close(fd);
}

static const char *end(void)
{
	FILE *f;
	size_t n;

	fflush(stdout);
	assert_int_equal(dup2(saved_fd, 1), 1);
	close(saved_fd);
	f = fopen(cap_path, "r");
	assert_non_null(f);
	n = fread(captured, 1, sizeof(captured) - 1, f);
	captured[n] = '\0';
	fclose(f);
	unlink(cap_path);
	return captured;
}

struct snap {
	struct hl_snapshot s;
	float i[2 * N_SOURCES];
};

static void init_snap(struct snap *p)
{
	memset(p, 0, sizeof(*p));
	p->s.n_lamps = 2;
	p->s.n_sources = N_SOURCES;
	p->s.i = p->i;
}

static void decode_report_link_and_bus_only_when_they_change(void **state)
{
	struct hl_decode_seen seen;
	struct snap p;
	bool done;
	(void)state;

	memset(&seen, 0, sizeof(seen));
	init_snap(&p);
	p.s.status = HL_INPUT_LINK_UP;
	p.s.bus = HL_CAN_BUS_ACTIVE;
	p.s.t_event_ns = 1234567890123LL;
	begin();
	done = hl_decode_report("vcan0", false, as, &p.s, &seen);
	assert_string_equal(
		end(), "{\"event\":\"link\",\"iface\":\"vcan0\",\"state\":\"up\",\"error\":\"\","
		       "\"t_ns\":1234567890123}\n"
		       "{\"event\":\"bus\",\"iface\":\"vcan0\",\"state\":\"error-active\","
		       "\"t_ns\":1234567890123}\n");
	assert_false(done);
	assert_int_equal(seen.status, HL_INPUT_LINK_UP);
	assert_int_equal(seen.bus, HL_CAN_BUS_ACTIVE);
	/* the same again: nothing */
	begin();
	hl_decode_report("vcan0", true, as, &p.s, &seen);
	assert_string_equal(end(), "");
	/* the link goes down with ENODEV: one line with the errno's text; bus unchanged */
	p.s.status = 0;
	p.s.link_errno = ENODEV;
	p.s.t_event_ns = 5;
	begin();
	hl_decode_report("vcan0", false, as, &p.s, &seen);
	assert_string_equal(end(), "{\"event\":\"link\",\"iface\":\"vcan0\",\"state\":\"down\","
				   "\"error\":\"No such device\",\"t_ns\":5}\n");
	/* another errno while down is news too */
	p.s.link_errno = ENETDOWN;
	begin();
	hl_decode_report("vcan0", false, as, &p.s, &seen);
	assert_string_equal(end(), "{\"event\":\"link\",\"iface\":\"vcan0\",\"state\":\"down\","
				   "\"error\":\"Network is down\",\"t_ns\":5}\n");
	p.s.bus = HL_CAN_BUS_OFF;
	begin();
	hl_decode_report("vcan0", false, as, &p.s, &seen);
	assert_string_equal(end(), "{\"event\":\"bus\",\"iface\":\"vcan0\",\"state\":\"bus-off\","
				   "\"t_ns\":5}\n");
	/* the kernel allows a '"' in an interface name: the line stays JSON */
	p.s.bus = HL_CAN_BUS_WARNING;
	begin();
	hl_decode_report("can\"0", false, as, &p.s, &seen);
	assert_string_equal(end(), "{\"event\":\"bus\",\"iface\":\"can\\\"0\",\"state\":"
				   "\"error-warning\",\"t_ns\":5}\n");
}

static void decode_report_cycles_only_when_asked_and_when_new(void **state)
{
	struct hl_decode_seen seen;
	struct snap p;
	char want[8192];
	size_t o;
	(void)state;

	memset(&seen, 0, sizeof(seen));
	init_snap(&p);
	seen.status = p.s.status = HL_INPUT_LINK_UP;
	p.s.lamps[1].cycle_seq = 7;
	p.s.lamps[1].counter = 14;
	p.s.lamps[1].t_rx_first_ns = -3;
	p.s.lamps[1].t_complete_ns = 9000000000LL;
	for (int k = 0; k < N_SOURCES; k++)
		p.i[N_SOURCES + k] = k == 0 ? 0.123456789f : (float)k / 63.0f;
	/* without --print-cycles: nothing, but the seq is remembered */
	begin();
	hl_decode_report("x", false, as, &p.s, &seen);
	assert_string_equal(end(), "");
	assert_int_equal(seen.cycle_seq[1], 7);
	/* with it: the next cycle of the right lamp, every source */
	p.s.lamps[1].cycle_seq = 8;
	o = (size_t)snprintf(want, sizeof(want),
			     "{\"lamp\":\"right\",\"seq\":8,\"counter\":14,\"t_rx_ns\":-3,"
			     "\"t_done_ns\":9000000000,\"i\":[");
	for (int k = 0; k < N_SOURCES; k++)
		o += (size_t)snprintf(want + o, sizeof(want) - o, "%s%.9g", k ? "," : "",
				      (double)p.i[N_SOURCES + k]);
	snprintf(want + o, sizeof(want) - o, "]}\n");
	begin();
	hl_decode_report("x", true, as, &p.s, &seen);
	assert_string_equal(end(), want);
	assert_non_null(strstr(want, "\"i\":[0.123456791,0.0158730168,")); /* float's 9 digits */
	/* the same seq again: nothing */
	begin();
	hl_decode_report("x", true, as, &p.s, &seen);
	assert_string_equal(end(), "");
}

static void decode_report_stale_recovered_and_the_last_snapshot(void **state)
{
	struct hl_decode_seen seen;
	struct snap p;
	(void)state;

	memset(&seen, 0, sizeof(seen));
	init_snap(&p);
	seen.status = p.s.status = HL_INPUT_LINK_UP;
	p.s.t_event_ns = 42;
	p.s.lamps[0].status = HL_LAMP_STALE;
	begin();
	assert_false(hl_decode_report("x", false, as, &p.s, &seen));
	assert_string_equal(end(), "{\"event\":\"stale\",\"lamp\":\"left\",\"t_ns\":42}\n");
	p.s.lamps[0].status = 0;
	p.s.lamps[1].status = HL_LAMP_STALE;
	p.s.t_event_ns = 43;
	begin();
	hl_decode_report("x", false, as, &p.s, &seen);
	assert_string_equal(end(), "{\"event\":\"recovered\",\"lamp\":\"left\",\"t_ns\":43}\n"
				   "{\"event\":\"stale\",\"lamp\":\"right\",\"t_ns\":43}\n");
	/* the replay's end */
	p.s.status |= HL_INPUT_DONE;
	begin();
	assert_true(hl_decode_report("x", false, as, &p.s, &seen));
	assert_string_equal(end(), "");
}

static void decode_summary_of_an_input_not_started_counts_zero(void **state)
{
	struct hl_ring *ring;
	struct hl_can_input *in;
	struct hl_can_input_config cfg = { 0 };
	char log[512];
	const char *out, *lamp0;
	FILE *f;
	(void)state;

	/* a log of one frame no lamp uses (an empty log is refused) */
	test_path(log, sizeof(log), "one.log");
	f = fopen(log, "w");
	assert_non_null(f);
	fputs("(1700000000.000000) vcan0 7FF#00\n", f);
	fclose(f);
	cfg.replay = log;
	cfg.replay_fast = true;
	assert_int_equal(hl_ring_new(4, 2, N_SOURCES, &ring), 0);
	assert_int_equal(hl_can_input_new(&cfg, as, ring, &in), 0);
	begin();
	hl_decode_summary(as, ring, in);
	out = end();
	lamp0 = "{\"event\":\"summary\",\"lamps\":{\"left\":{\"frames\":0,\"cycles\":0,"
		"\"crc_errors\":0,\"incomplete\":0,\"lost_cycles\":0,\"repeated_frames\":0,"
		"\"out_of_range\":0,\"stale_events\":0,\"recoveries\":0,\"stale\":false},"
		"\"right\":{\"frames\":0,";
	assert_memory_equal(out, lamp0, strlen(lamp0));
	{
		const char *tail = ",\"ring\":{\"pushed\":0,\"consumed\":0,\"superseded\":0,"
				   "\"dropped\":0}}\n";
		const size_t n = strlen(out), m = strlen(tail);

		assert_true(n > m);
		assert_string_equal(out + n - m, tail);
		assert_ptr_equal(strchr(out, '\n'), out + n - 1); /* one line */
	}
	hl_can_input_free(in);
	hl_ring_free(ring);
	unlink(log);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(decode_report_link_and_bus_only_when_they_change),
		cmocka_unit_test(decode_report_cycles_only_when_asked_and_when_new),
		cmocka_unit_test(decode_report_stale_recovered_and_the_last_snapshot),
		cmocka_unit_test(decode_summary_of_an_input_not_started_counts_zero),
	};

	return cmocka_run_group_tests(tests, setup, teardown);
}
