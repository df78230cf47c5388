/* SPDX-License-Identifier: MIT */
/* A thread's start at its real-time priority, logged (base/sched.c does the work and never logs). */
#include "daemon/core/sched_start.h"

#include <sched.h>
#include <string.h>

#include "base/sched.h"

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
	policy = hl_sched_current_policy(&cur_priority);
	if (policy == SCHED_FIFO || policy == SCHED_RR)
		snprintf(why + strlen(why), sizeof(why) - strlen(why), "; it keeps %s %d",
			 hl_sched_policy_name(policy), cur_priority);
	fprintf(log,
		"hdlampd: sched: warning: the %s thread stays at %s: SCHED_FIFO %d refused: %s\n",
		thread, hl_sched_policy_name(policy), priority, why);
	return rc;
}
