/* SPDX-License-Identifier: MIT */
#include "render/workers.h"

#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

/*
 * The job is published under the mutex (generation + 1, broadcast). Indices are claimed by a
 * compare-and-swap on next, which holds the job's generation in its upper 32 bits and the next
 * index in the lower: a helper still holding an older job can then never claim an index of a
 * newer one (a plain fetch_add would take it and run it with the old function). Every finished
 * index adds one to done; the caller, out of indices, waits on the condition until done == n,
 * and the helper that finishes the last index signals it. A helper that wakes late finds its
 * generation's indices gone and goes back to sleep.
 */
struct hl_workers {
	int threads; /* the caller included */
	pthread_t helpers[HL_WORKERS_MAX_THREADS];
	int n_helpers; /* started */
	pthread_mutex_t lock;
	pthread_cond_t job; /* helpers wait here for a new generation */
	pthread_cond_t finished; /* the caller waits here for done == n */
	uint64_t generation; /* under lock */
	bool stop; /* under lock */
	void (*fn)(void *ctx, size_t i); /* under lock; read by helpers after seeing generation */
	void *ctx;
	size_t n;
	atomic_uint_least64_t next; /* generation << 32 | next index to claim */
	atomic_size_t done; /* indices finished */
	cpu_set_t allowed; /* the CPUs the process may use, at creation */
	int avoid_cpu; /* the caller's CPU the helpers are kept off, -1: none yet */
};

/*
 * Claims and runs indices of generation gen until none is left; true when this thread
 * finished the last one.
 */
static bool drain(struct hl_workers *w, uint64_t gen, void (*fn)(void *, size_t), void *ctx,
		  size_t n)
{
	uint64_t v = atomic_load_explicit(&w->next, memory_order_relaxed);
	bool last = false;

	for (;;) {
		size_t i;

		if (v >> 32 != (gen & 0xffffffffu) || (v & 0xffffffffu) >= n)
			return last;
		if (!atomic_compare_exchange_weak_explicit(
			    &w->next, &v, v + 1, memory_order_relaxed, memory_order_relaxed))
			continue;
		i = (size_t)(v & 0xffffffffu);
		v++;
		fn(ctx, i);
		/* release: what fn wrote is visible to whoever sees done == n (acquire) */
		last = atomic_fetch_add_explicit(&w->done, 1, memory_order_acq_rel) + 1 == n;
	}
}

static void *helper_main(void *arg)
{
	struct hl_workers *w = arg;
	uint64_t seen = 0;

	pthread_mutex_lock(&w->lock);
	for (;;) {
		void (*fn)(void *, size_t);
		void *ctx;
		size_t n;

		while (!w->stop && w->generation == seen)
			pthread_cond_wait(&w->job, &w->lock);
		if (w->stop)
			break;
		seen = w->generation;
		fn = w->fn;
		ctx = w->ctx;
		n = w->n;
		pthread_mutex_unlock(&w->lock);
		if (drain(w, seen, fn, ctx, n)) {
			pthread_mutex_lock(&w->lock);
			pthread_cond_signal(&w->finished);
		} else {
			pthread_mutex_lock(&w->lock);
		}
	}
	pthread_mutex_unlock(&w->lock);
	return NULL;
}

int hl_workers_new(int threads, struct hl_workers **ret)
{
	struct hl_workers *w;

	if (threads < 1 || threads > HL_WORKERS_MAX_THREADS)
		return -EINVAL;
	w = calloc(1, sizeof(*w));
	if (!w)
		return -ENOMEM;
	w->threads = threads;
	pthread_mutex_init(&w->lock, NULL);
	pthread_cond_init(&w->job, NULL);
	pthread_cond_init(&w->finished, NULL);
	atomic_init(&w->next, 0);
	atomic_init(&w->done, 0);
	w->avoid_cpu = -1;
	if (sched_getaffinity(0, sizeof(w->allowed), &w->allowed) < 0)
		CPU_ZERO(&w->allowed);
	for (int t = 0; t < threads - 1; t++) {
		char name[16];

		if (pthread_create(&w->helpers[t], NULL, helper_main, w) != 0) {
			hl_workers_free(w);
			return -EAGAIN;
		}
		w->n_helpers++;
		/* for ps -L and /proc/PID/task/TID/comm: the render thread's helpers */
		snprintf(name, sizeof(name), "hl-render-%d", t + 1);
		pthread_setname_np(w->helpers[t], name);
	}
	*ret = w;
	return 0;
}

void hl_workers_free(struct hl_workers *w)
{
	if (!w)
		return;
	pthread_mutex_lock(&w->lock);
	w->stop = true;
	pthread_cond_broadcast(&w->job);
	pthread_mutex_unlock(&w->lock);
	for (int t = 0; t < w->n_helpers; t++)
		pthread_join(w->helpers[t], NULL);
	pthread_cond_destroy(&w->finished);
	pthread_cond_destroy(&w->job);
	pthread_mutex_destroy(&w->lock);
	free(w);
}

int hl_workers_threads(const struct hl_workers *w)
{
	return w->threads;
}

/*
 * Keeps the helpers off the CPU the caller runs on: a woken thread is often placed on the
 * waker's CPU (the scheduler's wake-affine choice), where it waits for the caller's time slice
 * instead of running beside it. Only when the caller has moved, so this is rarely a syscall.
 */
static void avoid_caller_cpu(struct hl_workers *w)
{
	const int cpu = sched_getcpu();
	cpu_set_t set;

	if (cpu < 0 || cpu == w->avoid_cpu)
		return;
	w->avoid_cpu = cpu;
	set = w->allowed;
	CPU_CLR(cpu, &set);
	if (CPU_COUNT(&set) == 0)
		return; /* one CPU: nowhere else to go */
	for (int t = 0; t < w->n_helpers; t++)
		pthread_setaffinity_np(w->helpers[t], sizeof(set), &set);
}

void hl_workers_run(struct hl_workers *w, size_t n, void (*fn)(void *ctx, size_t i), void *ctx)
{
	if (w->n_helpers == 0 || n < 2 || n > UINT32_MAX) {
		for (size_t i = 0; i < n; i++)
			fn(ctx, i);
		return;
	}
	avoid_caller_cpu(w);
	pthread_mutex_lock(&w->lock);
	w->fn = fn;
	w->ctx = ctx;
	w->n = n;
	w->generation++;
	atomic_store_explicit(&w->done, 0, memory_order_relaxed);
	atomic_store_explicit(&w->next, (w->generation & 0xffffffffu) << 32, memory_order_relaxed);
	pthread_cond_broadcast(&w->job);
	pthread_mutex_unlock(&w->lock);

	drain(w, w->generation, fn, ctx, n);
	if (atomic_load_explicit(&w->done, memory_order_acquire) == n)
		return;
	pthread_mutex_lock(&w->lock);
	while (atomic_load_explicit(&w->done, memory_order_acquire) != n)
		pthread_cond_wait(&w->finished, &w->lock);
	pthread_mutex_unlock(&w->lock);
}
