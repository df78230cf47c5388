/* SPDX-License-Identifier: MIT */
#include "base/sched.h"

#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>

int hl_mutex_init_pi(pthread_mutex_t *m)
{
	pthread_mutexattr_t a;
	int rc = pthread_mutexattr_init(&a);

	if (rc == 0) {
		rc = pthread_mutexattr_setprotocol(&a, PTHREAD_PRIO_INHERIT);
		if (rc == 0)
			rc = pthread_mutex_init(m, &a);
		pthread_mutexattr_destroy(&a);
	}
	return -rc;
}

int hl_sched_realtime(int priority)
{
	const struct sched_param sp = { .sched_priority = priority };

	if (priority < 1 || priority > HL_SCHED_MAX_PRIORITY)
		return -EINVAL;
	return -pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp);
}

/* Whether a seccomp filter is on for this thread (/proc/thread-self/status "Seccomp: 2"). */
static bool seccomp_filtered(void)
{
	FILE *f = fopen("/proc/thread-self/status", "re");
	char line[256];
	int mode = 0;

	if (!f)
		return false;
	while (fgets(line, sizeof(line), f))
		if (sscanf(line, "Seccomp: %d", &mode) == 1)
			break;
	fclose(f);
	return mode == 2;
}

/* The calling thread's policy, and its real-time priority (0 for the others). */
int hl_sched_current_policy(int *ret_priority)
{
	struct sched_param sp = { 0 };
	int policy = SCHED_OTHER;

	pthread_getschedparam(pthread_self(), &policy, &sp);
	*ret_priority = sp.sched_priority;
	return policy;
}

const char *hl_sched_policy_name(int policy)
{
	switch (policy) {
	case SCHED_OTHER:
		return "SCHED_OTHER";
	case SCHED_FIFO:
		return "SCHED_FIFO";
	case SCHED_RR:
		return "SCHED_RR";
	case SCHED_BATCH:
		return "SCHED_BATCH";
	case SCHED_IDLE:
		return "SCHED_IDLE";
	default:
		return "an unknown policy";
	}
}

void hl_sched_explain(int rc, int priority, char *buf, size_t size)
{
	struct rlimit rl;
	int cur_priority;

	if (rc != -EPERM) {
		snprintf(buf, size, "%s", strerror(-rc));
		return;
	}
	/* the kernel lets a thread keep or lower a real-time priority it has, whatever the limit */
	hl_sched_current_policy(&cur_priority);
	if (getrlimit(RLIMIT_RTPRIO, &rl) == 0 && rl.rlim_cur < (rlim_t)priority &&
	    cur_priority < priority) {
		snprintf(buf, size,
			 "%s: RLIMIT_RTPRIO is %llu, below %d, and no CAP_SYS_NICE (raise it with "
			 "LimitRTPRIO= in the unit, ulimit -r or prlimit --rtprio)",
			 strerror(-rc), (unsigned long long)rl.rlim_cur, priority);
		return;
	}
	snprintf(buf, size, "%s%s", strerror(-rc),
		 seccomp_filtered() ? ": RLIMIT_RTPRIO allows it, so the seccomp filter forbids "
				      "it (RestrictRealtime=, SystemCallFilter= without "
				      "sched_setscheduler)" :
				      "");
}
