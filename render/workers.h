/* SPDX-License-Identifier: MIT */
/*
 * A small pool of helper threads that share one job with the calling thread: run fn(ctx, i)
 * for every i in 0..n-1, each index claimed by whichever thread is free (an atomic counter),
 * the caller included. The caller starts on the job at once and never waits for a helper to
 * wake up; it waits only, at the end, for indices a helper has already claimed. With no helpers
 * (threads = 1) hl_workers_run() is a plain loop.
 *
 * Used by the render path to spread the headlight pass and the display view of a frame over
 * the cores: the pass is bound by memory (performance.md), and two cores keep twice the misses in
 * flight.
 *
 * The helpers are created with the caller's scheduling policy and priority (the render thread's
 * SCHED_FIFO in hdlampd, base/sched.h) and named hl-render-1, hl-render-2, ...
 *
 * Thread-safety: hl_workers_run() from one thread at a time (the render thread); fn runs on the
 * caller and the helpers at once and must only write what index i owns.
 */
#ifndef HL_RENDER_WORKERS_H
#define HL_RENDER_WORKERS_H

#include <stddef.h>

#define HL_WORKERS_MAX_THREADS 16

struct hl_workers;

/* threads: 1..HL_WORKERS_MAX_THREADS, the caller included. 0, -EINVAL, -ENOMEM, -EAGAIN. */
int hl_workers_new(int threads, struct hl_workers **ret);
/* Stops and joins the helpers. NULL is fine. */
void hl_workers_free(struct hl_workers *w);

int hl_workers_threads(const struct hl_workers *w);

/* Runs fn(ctx, i) for i in 0..n-1 on the caller and the helpers; returns when all are done. */
void hl_workers_run(struct hl_workers *w, size_t n, void (*fn)(void *ctx, size_t i), void *ctx);

#endif
