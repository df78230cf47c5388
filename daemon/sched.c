/* SPDX-License-Identifier: MIT */
#include "daemon/sched.h"

#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <stdbool.h>
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
static int current_policy(int *ret_priority)
{
	struct sched_param sp = { 0 };
	int policy = SCHED_OTHER;

	pthread_getschedparam(pthread_self(), &policy, &sp);
	*ret_priority = sp.sched_priority;
	return policy;
}

static const char *policy_name(int policy)
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
	current_policy(&cur_priority);
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

int hl_sched_start_thread(const char *thread, int priority, FILE *log)
{
	char why[256];
	int rc, policy, cur_priority;

	if (priority == 0)
		return 0;
	rc = hl_sched_realtime(priority);
	if (rc == 0) {
		fprintf(log, "hdlampd: sched: the %s thread runs at SCHED_FIFO %d\n", thread,
			priority);
		return 0;
	}
	hl_sched_explain(rc, priority, why, sizeof(why));
	policy = current_policy(&cur_priority);
	if (policy == SCHED_FIFO || policy == SCHED_RR)
		snprintf(why + strlen(why), sizeof(why) - strlen(why), "; it keeps %s %d",
			 policy_name(policy), cur_priority);
	fprintf(log,
		"hdlampd: sched: warning: the %s thread stays at %s: SCHED_FIFO %d refused: %s\n",
		thread, policy_name(policy), priority, why);
	return rc;
}
