/* SPDX-License-Identifier: MIT */
/*
 * base/sched.c: SCHED_FIFO for the calling thread only, the range check, and the reasons a
 * refusal is logged with. Each case that changes a policy does it on a thread of its own.
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

#include "base/sched.h"

static void sched_priority_out_of_range_is_einval(void **state)
{
	int policy;
	struct sched_param sp;
	(void)state;

	assert_int_equal(hl_sched_realtime(0), -EINVAL);
	assert_int_equal(hl_sched_realtime(HL_SCHED_MAX_PRIORITY + 1), -EINVAL);
	assert_int_equal(hl_sched_realtime(-1), -EINVAL);
	pthread_getschedparam(pthread_self(), &policy, &sp);
	assert_int_equal(policy, SCHED_OTHER);
}

static void sched_current_policy_and_its_name(void **state)
{
	int priority = -1;
	(void)state;

	assert_int_equal(hl_sched_current_policy(&priority), SCHED_OTHER);
	assert_int_equal(priority, 0);
	assert_string_equal(hl_sched_policy_name(SCHED_OTHER), "SCHED_OTHER");
	assert_string_equal(hl_sched_policy_name(SCHED_FIFO), "SCHED_FIFO");
	assert_string_equal(hl_sched_policy_name(SCHED_RR), "SCHED_RR");
}

static void sched_explain_names_rlimit_rtprio(void **state)
{
	struct rlimit old, rl;
	char buf[256];
	(void)state;

	assert_int_equal(getrlimit(RLIMIT_RTPRIO, &old), 0);
	rl = (struct rlimit){ .rlim_cur = 3, .rlim_max = old.rlim_max };
	if (old.rlim_max < 3)
		rl.rlim_cur = old.rlim_max;
	assert_int_equal(setrlimit(RLIMIT_RTPRIO, &rl), 0);
	{
		char want[256];

		snprintf(want, sizeof(want),
			 "Operation not permitted: RLIMIT_RTPRIO is %llu, below 10, and no "
			 "CAP_SYS_NICE (raise it with LimitRTPRIO= in the unit, ulimit -r or "
			 "prlimit --rtprio)",
			 (unsigned long long)rl.rlim_cur);
		hl_sched_explain(-EPERM, 10, buf, sizeof(buf));
		assert_string_equal(buf, want);
	}
	/* the limit is high enough: no word about it */
	hl_sched_explain(-EPERM, (int)rl.rlim_cur, buf, sizeof(buf));
	assert_null(strstr(buf, "RLIMIT_RTPRIO is"));
	assert_int_equal(strncmp(buf, "Operation not permitted", 23), 0);
	assert_int_equal(setrlimit(RLIMIT_RTPRIO, &old), 0);
}

static void sched_explain_other_errors_by_name(void **state)
{
	char buf[256];
	(void)state;

	hl_sched_explain(-EINVAL, 10, buf, sizeof(buf));
	assert_string_equal(buf, "Invalid argument");
	hl_sched_explain(-ESRCH, 10, buf, sizeof(buf));
	assert_string_equal(buf, "No such process");
}

/* A thread already at FIFO 10 may keep 10 whatever RLIMIT_RTPRIO says: not the reason then. */
static void *explain_at_fifo(void *arg)
{
	char *buf = arg;

	if (hl_sched_realtime(10) < 0)
		snprintf(buf, 256, "(not allowed here)");
	else
		hl_sched_explain(-EPERM, 10, buf, 256);
	return NULL;
}

static void sched_explain_skips_rlimit_for_a_priority_already_held(void **state)
{
	struct rlimit old, rl;
	char buf[256];
	pthread_t t;
	(void)state;

	assert_int_equal(getrlimit(RLIMIT_RTPRIO, &old), 0);
	rl = (struct rlimit){ .rlim_cur = 0, .rlim_max = old.rlim_max };
	assert_int_equal(setrlimit(RLIMIT_RTPRIO, &rl), 0);
	assert_int_equal(pthread_create(&t, NULL, explain_at_fifo, buf), 0);
	assert_int_equal(pthread_join(t, NULL), 0);
	assert_int_equal(setrlimit(RLIMIT_RTPRIO, &old), 0);
	if (strcmp(buf, "(not allowed here)") == 0)
		skip(); /* neither CAP_SYS_NICE nor RLIMIT_RTPRIO >= 10 to get there */
	assert_null(strstr(buf, "RLIMIT_RTPRIO is"));
	assert_int_equal(strncmp(buf, "Operation not permitted", 23), 0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(sched_priority_out_of_range_is_einval),
		cmocka_unit_test(sched_current_policy_and_its_name),
		cmocka_unit_test(sched_explain_names_rlimit_rtprio),
		cmocka_unit_test(sched_explain_other_errors_by_name),
		cmocka_unit_test(sched_explain_skips_rlimit_for_a_priority_already_held),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
