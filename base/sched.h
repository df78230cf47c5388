/* SPDX-License-Identifier: MIT */
/*
 * Real-time scheduling for the two threads on the 20 ms path (docs/design.md §2): the CAN
 * thread and the render thread put themselves at SCHED_FIFO (sched.realtime_priority) when they
 * start; the render thread does it before it creates its helpers, so they inherit it. The frame
 * stream thread runs one step below them (it never delays them; a busy machine's other jobs
 * cannot delay the frames to the clients). Every other thread (main, HTTP, encoder, captures)
 * stays at SCHED_OTHER.
 *
 * Unprivileged, this needs RLIMIT_RTPRIO >= the priority (the unit's LimitRTPRIO=, ulimit -r,
 * prlimit --rtprio) and no sandbox that forbids it (RestrictRealtime=, a SystemCallFilter=
 * without sched_setscheduler). A refusal is logged with its likely reason and the thread runs
 * on at SCHED_OTHER: the daemon works, only its latency under load is worse.
 *
 * Thread-safety: each function acts on, or describes, the calling thread only.
 */
#ifndef HL_BASE_SCHED_H
#define HL_BASE_SCHED_H

#include <pthread.h>
#include <stddef.h>

#define HL_SCHED_MAX_PRIORITY 99 /* SCHED_FIFO's range on Linux: 1..99 */

/* Puts the calling thread at SCHED_FIFO priority (1..99). 0, -EINVAL, -errno (-EPERM). */
int hl_sched_realtime(int priority);

/*
 * Why hl_sched_realtime(priority) returned rc, as a phrase for a log line: the calling
 * process's RLIMIT_RTPRIO when it is below the priority (and the thread has no real-time
 * priority that high already, which the kernel would let it keep), else a seccomp filter if
 * one is on.
 */
void hl_sched_explain(int rc, int priority, char *buf, size_t size);

/* The calling thread's policy (SCHED_OTHER, SCHED_FIFO, ...) and its priority. */
int hl_sched_current_policy(int *ret_priority);
/* "SCHED_FIFO", "SCHED_OTHER", ... for a policy. */
const char *hl_sched_policy_name(int policy);

/*
 * A mutex with priority inheritance (PTHREAD_PRIO_INHERIT): while a SCHED_FIFO thread waits on
 * it, its holder runs at the waiter's priority until it unlocks. Every lock the CAN and render
 * threads share with the SCHED_OTHER threads (stream, HTTP, encoder, captures) is one, so a
 * reader that is preempted while it holds a lock cannot keep the 20 ms path waiting behind the
 * other jobs of a busy machine (priority inversion). 0 or -errno (-ENOTSUP: the kernel has no
 * PI futexes; the mutex is then not initialised).
 */
int hl_mutex_init_pi(pthread_mutex_t *m);

#endif
