/* SPDX-License-Identifier: MIT */
/*
 * can/candump_log.c: a candump -L log replayed from a real file: due times relative to the first
 * frame, loop passes one gap apart, malformed lines and backward timestamps reported with
 * their line and never silent, files without frames refused at open.
 */
#include <errno.h>
#include <fcntl.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "can/candump_log.h"
#include "testutil.h"

static const char *write_log(char *path, size_t size, const char *name, const char *text)
{
	FILE *f;

	test_path(path, size, name);
	f = fopen(path, "w");
	assert_non_null(f);
	assert_int_equal(fputs(text, f) >= 0, 1);
	assert_int_equal(fclose(f), 0);
	return path;
}

static struct hl_candump_log *open_log(const char *text, uint64_t passes)
{
	struct hl_candump_log *log = NULL;
	char path[4096];

	write_log(path, sizeof(path), "log.txt", text);
	assert_int_equal(hl_candump_log_open(path, passes, &log), 0);
	unlink(path); /* the open file stays readable */
	return log;
}

/* Expects a frame with status rc (1, or 2 for a backward one) due at due_ns with can_id. */
static void expect_frame(struct hl_candump_log *log, int rc, int64_t due_ns, uint32_t can_id)
{
	struct hl_candump_frame f;
	struct hl_candump_log_error err;
	int64_t due = -1;

	assert_int_equal(hl_candump_log_next(log, &f, &due, &err), rc);
	assert_int_equal(due, due_ns);
	assert_int_equal(f.frame.can_id, can_id);
}

static void expect_end(struct hl_candump_log *log)
{
	struct hl_candump_frame f;
	int64_t due = -1;

	assert_int_equal(hl_candump_log_next(log, &f, &due, NULL), 0);
	assert_int_equal(due, -1);
	assert_int_equal(hl_candump_log_next(log, &f, &due, NULL), 0);
}

/* Due times are the timestamps minus the first frame's, in ns; the frames are the lines'. */
static void log_due_times_are_relative_to_the_first_frame(void **state)
{
	struct hl_candump_log *log = open_log("(1700000100.000000) can0 123#11223344\n"
					      "(1700000100.250000) can1 1ABCDEF0#\n"
					      "(1700000101.000001) can0 7FF#0102030405060708\n",
					      1);
	struct hl_candump_log_stats st;
	struct hl_candump_frame f;
	int64_t due = -1;

	(void)state;
	assert_int_equal(hl_candump_log_next(log, &f, &due, NULL), 1);
	assert_int_equal(due, 0);
	assert_int_equal(f.t_us, 1700000100000000LL);
	assert_string_equal(f.iface, "can0");
	assert_int_equal(f.frame.can_id, 0x123);
	assert_int_equal(f.frame.len, 4);
	assert_memory_equal(f.frame.data, "\x11\x22\x33\x44", 4);
	expect_frame(log, 1, 250000000, 0x1ABCDEF0 | 0x80000000u);
	expect_frame(log, 1, 1000001000, 0x7FF);
	expect_end(log);
	hl_candump_log_stats(log, &st);
	assert_int_equal(st.lines, 3);
	assert_int_equal(st.frames, 3);
	assert_int_equal(st.malformed, 0);
	assert_int_equal(st.passes, 1);
	assert_int_equal(st.backwards, 0);
	hl_candump_log_free(log);
	hl_candump_log_free(NULL);
}

/* Comments, blank lines and CRLF are skipped; a malformed line is -EBADMSG with its line and
 * the parser's column and message, and the next call goes on. */
static void log_reports_malformed_lines_and_goes_on(void **state)
{
	static const char bad[] = "(1.000000) can0 12G#00";
	struct hl_candump_log *log = open_log("# a comment\n"
					      "\n"
					      "(1.000000) can0 100#01\r\n"
					      "(1.000000) can0 12G#00\n"
					      "(1.500000) can0 101#02\n",
					      1);
	struct hl_candump_error perr;
	struct hl_candump_log_error err;
	struct hl_candump_log_stats st;
	struct hl_candump_frame f;
	int64_t due = -1;

	(void)state;
	assert_true(hl_candump_parse(bad, strlen(bad), &f, &perr) < 0);
	expect_frame(log, 1, 0, 0x100);
	memset(&err, 0, sizeof(err));
	assert_int_equal(hl_candump_log_next(log, &f, &due, &err), -EBADMSG);
	assert_int_equal(err.line, 4);
	assert_int_equal(err.column, perr.column);
	assert_string_equal(err.msg, perr.msg);
	assert_int_equal(hl_candump_log_next(log, &f, &due, &err), 1);
	assert_int_equal(due, 500000000);
	assert_int_equal(f.frame.can_id, 0x101);
	expect_end(log);
	hl_candump_log_stats(log, &st);
	assert_int_equal(st.lines, 5);
	assert_int_equal(st.frames, 2);
	assert_int_equal(st.malformed, 1);
	hl_candump_log_free(log);
}

/* A timestamp before the previous frame's: status 2, counted, replayed at the previous time,
 * its line and how far back in the message. */
static void log_backward_timestamp_is_replayed_at_the_previous_time(void **state)
{
	struct hl_candump_log *log = open_log("(5.000000) can0 001#\n"
					      "(5.200000) can0 002#\n"
					      "(5.100000) can0 003#\n"
					      "(5.300000) can0 004#\n",
					      1);
	struct hl_candump_log_error err;
	struct hl_candump_log_stats st;
	struct hl_candump_frame f;
	int64_t due = -1;

	(void)state;
	expect_frame(log, 1, 0, 1);
	expect_frame(log, 1, 200000000, 2);
	assert_int_equal(hl_candump_log_next(log, &f, &due, &err), 2);
	assert_int_equal(f.frame.can_id, 3);
	assert_int_equal(f.t_us, 5200000);
	assert_int_equal(due, 200000000);
	assert_int_equal(err.line, 3);
	assert_int_equal(err.column, 1);
	assert_string_equal(err.msg, "timestamp 5.100000 is 100000 us before the previous frame's; "
				     "expected times that never decrease (replayed at the previous "
				     "frame's time)");
	expect_frame(log, 1, 300000000, 4);
	expect_end(log);
	hl_candump_log_stats(log, &st);
	assert_int_equal(st.frames, 4);
	assert_int_equal(st.backwards, 1);
	hl_candump_log_free(log);
}

/* Passes: each starts HL_LOG_LOOP_GAP_NS after the previous one's last frame, line numbers
 * count from 1 again, the restart is not a backward step; 0 passes go on for ever. */
static void log_loop_passes_continue_the_timeline_one_gap_later(void **state)
{
	static const char text[] = "(10.000000) can0 0A0#\n"
				   "bad line\n"
				   "(10.500000) can0 0A1#\n";
	const int64_t pass = 500000000 + HL_LOG_LOOP_GAP_NS;
	struct hl_candump_log *log = open_log(text, 3);
	struct hl_candump_log_error err;
	struct hl_candump_log_stats st;
	struct hl_candump_frame f;
	int64_t due;

	(void)state;
	for (int p = 0; p < 3; p++) {
		expect_frame(log, 1, p * pass, 0xA0);
		memset(&err, 0, sizeof(err));
		assert_int_equal(hl_candump_log_next(log, &f, &due, &err), -EBADMSG);
		assert_int_equal(err.line, 2);
		expect_frame(log, 1, p * pass + 500000000, 0xA1);
		hl_candump_log_stats(log, &st);
		assert_int_equal(st.passes, (uint64_t)p + 1);
	}
	expect_end(log);
	hl_candump_log_stats(log, &st);
	assert_int_equal(st.passes, 3);
	assert_int_equal(st.frames, 6);
	assert_int_equal(st.malformed, 3);
	assert_int_equal(st.lines, 9);
	assert_int_equal(st.backwards, 0);
	hl_candump_log_free(log);

	log = open_log(text, 0);
	for (int p = 0; p < 50; p++) {
		expect_frame(log, 1, p * pass, 0xA0);
		assert_int_equal(hl_candump_log_next(log, &f, &due, NULL), -EBADMSG);
		expect_frame(log, 1, p * pass + 500000000, 0xA1);
	}
	hl_candump_log_stats(log, &st);
	assert_int_equal(st.passes, 50);
	hl_candump_log_free(log);
}

/* No frame (empty, comments, malformed lines only): -ENODATA at open; a missing file its
 * -errno; stdin only once; a directory opens but reads as -EIO. */
static void log_open_refuses_files_without_frames(void **state)
{
	static const char *const frameless[] = {
		"", "# only a comment\n\n", "not a frame\n(x) can0 123#00\n",
		"(1.000000) can0 123#0\n", /* odd number of hex digits */
	};
	struct hl_candump_log *log = NULL;
	struct hl_candump_frame f;
	char path[4096];
	int64_t due;

	(void)state;
	for (size_t i = 0; i < sizeof(frameless) / sizeof(frameless[0]); i++) {
		write_log(path, sizeof(path), "empty.log", frameless[i]);
		assert_int_equal(hl_candump_log_open(path, 1, &log), -ENODATA);
		assert_null(log);
		unlink(path);
	}
	test_path(path, sizeof(path), "missing.log");
	assert_int_equal(hl_candump_log_open(path, 1, &log), -ENOENT);
	assert_null(log);
	assert_int_equal(hl_candump_log_open("-", 0, &log), -EINVAL);
	assert_int_equal(hl_candump_log_open("-", 2, &log), -EINVAL);
	assert_null(log);
	assert_int_equal(hl_candump_log_open("-", 1, &log), 0);
	hl_candump_log_free(log); /* stdin stays open */
	assert_true(fcntl(STDIN_FILENO, F_GETFD) >= 0);

	test_path(path, sizeof(path), "dir.log");
	assert_int_equal(mkdir(path, 0700), 0);
	log = NULL;
	assert_int_equal(hl_candump_log_open(path, 1, &log), 0);
	assert_int_equal(hl_candump_log_next(log, &f, &due, NULL), -EIO);
	hl_candump_log_free(log);
	assert_int_equal(rmdir(path), 0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(log_due_times_are_relative_to_the_first_frame),
		cmocka_unit_test(log_reports_malformed_lines_and_goes_on),
		cmocka_unit_test(log_backward_timestamp_is_replayed_at_the_previous_time),
		cmocka_unit_test(log_loop_passes_continue_the_timeline_one_gap_later),
		cmocka_unit_test(log_open_refuses_files_without_frames),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
