/* SPDX-License-Identifier: MIT */
#include "daemon/sched.h"

#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <stdbool.h>
#include <string.h>
#include <sys/resource.h>

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

void hl_sched_explain(int rc, int priority, char *buf, size_t size)
{
	struct rlimit rl;

	if (rc != -EPERM) {
		snprintf(buf, size, "%s", strerror(-rc));
		return;
	}
	if (getrlimit(RLIMIT_RTPRIO, &rl) == 0 && rl.rlim_cur < (rlim_t)priority) {
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
	int rc;

	if (priority == 0)
		return 0;
	rc = hl_sched_realtime(priority);
	if (rc == 0) {
		fprintf(log, "hdlampd: sched: the %s thread runs at SCHED_FIFO %d\n", thread,
			priority);
		return 0;
	}
	hl_sched_explain(rc, priority, why, sizeof(why));
	fprintf(log,
		"hdlampd: sched: warning: the %s thread stays at SCHED_OTHER: SCHED_FIFO %d "
		"refused: %s\n",
		thread, priority, why);
	return rc;
}
