/* SPDX-License-Identifier: MIT */
/*
 * The daemon's threads put themselves at their real-time priority when they start, and say so
 * in the log (base/sched.h explains the policy and the refusals).
 *
 * Thread-safety: acts on the calling thread only.
 */
#ifndef HL_DAEMON_CORE_SCHED_START_H
#define HL_DAEMON_CORE_SCHED_START_H

#include <stdio.h>

/*
 * The threads' start: with priority > 0, sets SCHED_FIFO and logs one line to log, naming the
 * thread ("render", "CAN"): the policy it now has, or the one it keeps and why. Nothing with
 * priority 0. Returns hl_sched_realtime's result (0 with priority 0).
 */
int hl_sched_start_thread(const char *thread, int priority, FILE *log);

#endif
