/* SPDX-License-Identifier: MIT */
/*
 * daemon/core/sched_start.c: a thread's start at SCHED_FIFO sets that thread only and logs
 * one line saying what it got. Each case runs on a thread of its own.
 */
#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <cmocka.h>

#include "daemon/core/sched_start.h"

struct run {
	int priority;
	int rc;
	int policy, got_priority; /* the thread's, after the call */
	int main_policy; /* the creating thread's, after the call */
	char *log;
	size_t log_size;
};

static void *start_thread(void *arg)
{
	struct run *r = arg;
	struct sched_param sp;
	FILE *f = open_memstream(&r->log, &r->log_size);

	r->rc = hl_sched_start_thread("test", r->priority, f);
	fclose(f);
	pthread_getschedparam(pthread_self(), &r->policy, &sp);
	r->got_priority = sp.sched_priority;
	return NULL;
}

static struct run run_in_thread(int priority)
{
	struct run r = { .priority = priority };
	struct sched_param sp;
	pthread_t t;

	assert_int_equal(pthread_create(&t, NULL, start_thread, &r), 0);
	assert_int_equal(pthread_join(t, NULL), 0);
	pthread_getschedparam(pthread_self(), &r.main_policy, &sp);
	return r;
}

static void sched_start_thread_priority_0_does_nothing(void **state)
{
	struct run r = run_in_thread(0);
	(void)state;

	assert_int_equal(r.rc, 0);
	assert_int_equal(r.policy, SCHED_OTHER);
	assert_int_equal(r.log_size, 0);
	free(r.log);
}

/* Allowed (root with CAP_SYS_NICE, or RLIMIT_RTPRIO >= 10) or not, the log says what happened. */
static void sched_start_thread_sets_fifo_on_that_thread_only(void **state)
{
	struct run r = run_in_thread(10);
	(void)state;

	assert_int_equal(r.main_policy, SCHED_OTHER);
	if (r.rc == 0) {
		assert_int_equal(r.policy, SCHED_FIFO);
		assert_int_equal(r.got_priority, 10);
		assert_string_equal(r.log,
				    "hdlampd: sched: the test thread runs at SCHED_FIFO 10\n");
	} else {
		assert_int_equal(r.rc, -EPERM);
		assert_int_equal(r.policy, SCHED_OTHER);
		assert_non_null(strstr(r.log, "hdlampd: sched: warning: the test thread stays at "
					      "SCHED_OTHER: SCHED_FIFO 10 refused: Operation not "
					      "permitted"));
	}
	free(r.log);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(sched_start_thread_priority_0_does_nothing),
		cmocka_unit_test(sched_start_thread_sets_fifo_on_that_thread_only),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
