/* SPDX-License-Identifier: MIT */
/*
 * base/clock.c: CLOCK_MONOTONIC in ns, and the sleep to an absolute deadline that a signal does
 * not cut short unless the stop flag is set. Only "not before the deadline" is checked, never
 * how late: the tests cannot flake under load.
 */
#include <errno.h>
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <sys/time.h>
#include <time.h>
#include <cmocka.h>

#include "base/clock.h"

static int64_t now_ns(void)
{
	struct timespec ts;

	assert_int_equal(clock_gettime(CLOCK_MONOTONIC, &ts), 0);
	return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

static volatile sig_atomic_t alarms;
static volatile int stop_flag;
static volatile sig_atomic_t set_stop; /* the handler sets stop_flag */

static void on_alarm(int sig)
{
	(void)sig;
	alarms++;
	if (set_stop)
		stop_flag = 1;
}

/* SIGALRM every interval_us (no SA_RESTART: the sleep sees EINTR), until disarm(). */
static void arm(long interval_us)
{
	struct sigaction sa;
	struct itimerval it = { { 0, interval_us }, { 0, interval_us } };

	memset(&sa, 0, sizeof(sa));
	sa.sa_handler = on_alarm;
	sigemptyset(&sa.sa_mask);
	assert_int_equal(sigaction(SIGALRM, &sa, NULL), 0);
	alarms = 0;
	assert_int_equal(setitimer(ITIMER_REAL, &it, NULL), 0);
}

static void disarm(void)
{
	struct itimerval off = { { 0, 0 }, { 0, 0 } };

	assert_int_equal(setitimer(ITIMER_REAL, &off, NULL), 0);
	signal(SIGALRM, SIG_DFL);
}

/* The value is CLOCK_MONOTONIC's, in ns: between two direct reads taken around it. */
static void clock_monotonic_is_clock_monotonic_in_ns(void **state)
{
	(void)state;
	for (int i = 0; i < 1000; i++) {
		const int64_t before = now_ns();
		const int64_t t = hl_clock_monotonic_ns();
		const int64_t after = now_ns();

		assert_true(before <= t);
		assert_true(t <= after);
	}
}

static void clock_monotonic_never_goes_back(void **state)
{
	int64_t prev = hl_clock_monotonic_ns();

	(void)state;
	assert_true(prev > 0);
	for (int i = 0; i < 100000; i++) {
		const int64_t t = hl_clock_monotonic_ns();

		assert_true(t >= prev);
		prev = t;
	}
}

/* A deadline 30 ms ahead, one not on a whole second (tv_nsec used): not back before it. */
static void clock_sleep_until_returns_not_before_the_deadline(void **state)
{
	(void)state;
	for (int i = 0; i < 3; i++) {
		const int64_t deadline = hl_clock_monotonic_ns() + 30000000 + 123457 * i;

		hl_clock_sleep_until_ns(deadline, NULL);
		assert_true(hl_clock_monotonic_ns() >= deadline);
	}
}

/* A deadline already past (or at 0, or negative) returns without sleeping for ever. */
static void clock_sleep_until_a_past_deadline_returns(void **state)
{
	const int64_t t0 = hl_clock_monotonic_ns();

	(void)state;
	hl_clock_sleep_until_ns(t0 - 1000000000, NULL);
	hl_clock_sleep_until_ns(t0, NULL);
	hl_clock_sleep_until_ns(0, NULL);
	hl_clock_sleep_until_ns(-1, NULL);
	assert_true(hl_clock_monotonic_ns() >= t0);
}

/* Signals every 5 ms during a 100 ms sleep: interrupted, it sleeps on to the deadline, with no
 * stop flag and with a stop flag that stays 0. */
static void clock_sleep_until_is_not_cut_short_by_signals(void **state)
{
	(void)state;
	set_stop = 0;
	stop_flag = 0;
	for (int with_flag = 0; with_flag < 2; with_flag++) {
		int64_t deadline;

		arm(5000);
		deadline = hl_clock_monotonic_ns() + 100000000;
		hl_clock_sleep_until_ns(deadline, with_flag ? &stop_flag : NULL);
		assert_true(hl_clock_monotonic_ns() >= deadline);
		disarm();
		assert_true(alarms > 0);
		assert_int_equal(stop_flag, 0);
	}
}

/* The handler sets the stop flag: the sleep to a deadline an hour ahead returns at the next
 * signal (the timer repeats, so a signal before the sleep starts cannot hang the test). */
static void clock_sleep_until_returns_early_when_a_signal_sets_stop(void **state)
{
	const int64_t deadline = hl_clock_monotonic_ns() + 3600 * (int64_t)1000000000;

	(void)state;
	stop_flag = 0;
	set_stop = 1;
	arm(10000);
	hl_clock_sleep_until_ns(deadline, &stop_flag);
	disarm();
	set_stop = 0;
	assert_int_equal(stop_flag, 1);
	assert_true(alarms > 0);
	assert_true(hl_clock_monotonic_ns() < deadline);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(clock_monotonic_is_clock_monotonic_in_ns),
		cmocka_unit_test(clock_monotonic_never_goes_back),
		cmocka_unit_test(clock_sleep_until_returns_not_before_the_deadline),
		cmocka_unit_test(clock_sleep_until_a_past_deadline_returns),
		cmocka_unit_test(clock_sleep_until_is_not_cut_short_by_signals),
		cmocka_unit_test(clock_sleep_until_returns_early_when_a_signal_sets_stop),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
