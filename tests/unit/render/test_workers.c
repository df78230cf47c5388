/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include <cmocka.h>

#include "render/workers.h"

#define MAX_N 512

struct job {
	atomic_int runs[MAX_N]; /* how often each index ran */
	atomic_int other_thread; /* indices a helper ran */
	pthread_t caller;
	int tag; /* which job this is: an index of an older job must never run with it */
	atomic_int wrong_tag;
	int expect_tag;
	int slow_every; /* every slow_every-th index sleeps 50 us (0: none) */
};

static void run_index(void *ctx, size_t i)
{
	struct job *j = ctx;

	if (j->tag != j->expect_tag)
		atomic_fetch_add(&j->wrong_tag, 1);
	if (j->slow_every && i % (size_t)j->slow_every == 0) {
		const struct timespec ts = { 0, 50000 };

		nanosleep(&ts, NULL);
	}
	atomic_fetch_add(&j->runs[i], 1);
	if (!pthread_equal(pthread_self(), j->caller))
		atomic_fetch_add(&j->other_thread, 1);
}

static void check_once(struct job *j, size_t n)
{
	for (size_t i = 0; i < MAX_N; i++)
		assert_int_equal(atomic_load(&j->runs[i]), i < n ? 1 : 0);
	assert_int_equal(atomic_load(&j->wrong_tag), 0);
}

static struct job *job_new(int tag, int slow_every)
{
	struct job *j = calloc(1, sizeof(*j));

	assert_non_null(j);
	j->caller = pthread_self();
	j->tag = j->expect_tag = tag;
	j->slow_every = slow_every;
	return j;
}

static void workers_run_every_index_exactly_once(void **state)
{
	(void)state;
	for (int threads = 1; threads <= 4; threads++) {
		struct hl_workers *w = NULL;
		const size_t sizes[] = { 0, 1, 2, 3, 57, MAX_N };

		assert_int_equal(hl_workers_new(threads, &w), 0);
		assert_int_equal(hl_workers_threads(w), threads);
		for (size_t s = 0; s < sizeof(sizes) / sizeof(sizes[0]); s++) {
			struct job *j = job_new(1, 7);

			hl_workers_run(w, sizes[s], run_index, j);
			check_once(j, sizes[s]);
			if (threads == 1)
				assert_int_equal(atomic_load(&j->other_thread), 0);
			free(j);
		}
		hl_workers_free(w);
	}
}

/*
 * Jobs back to back: a helper that finished an index of the previous job must not claim one
 * of the next (it would run it with the old function and context).
 */
static void workers_back_to_back_jobs_never_mix(void **state)
{
	struct hl_workers *w = NULL;
	unsigned long long helped = 0;

	(void)state;
	assert_int_equal(hl_workers_new(3, &w), 0);
	for (int r = 0; r < 3000; r++) {
		struct job *j = job_new(r, r % 3 == 0 ? 5 : 0);
		const size_t n = 2 + (size_t)(r * 37) % 60;

		hl_workers_run(w, n, run_index, j);
		/* once returned, nothing of this job may run any more */
		j->expect_tag = -1;
		check_once(j, n);
		helped += (unsigned)atomic_load(&j->other_thread);
		/* a late helper touching j now would count a wrong tag or a second run */
		free(j);
	}
	/* how much the helpers took is the scheduler's business; that they do is shown below */
	print_message("helpers ran %llu indices of 3000 jobs\n", helped);
	hl_workers_free(w);
}

#define WAIT_NS 20000000000LL /* only broken helpers take this long to claim an index */

static int64_t now_ns(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

struct cpus {
	pthread_t caller;
	int caller_cpu; /* the only CPU the caller may run on */
	atomic_int helped; /* indices helpers ran */
	atomic_int on_caller_cpu; /* of those, by a helper allowed on the caller's CPU */
	atomic_int timed_out;
};

/*
 * The caller's first index waits until a helper has run one (an event: so helpers take part
 * whatever the load); every helper index checks the CPUs it may run on.
 */
static void note_cpu(void *ctx, size_t i)
{
	struct cpus *c = ctx;

	(void)i;
	if (pthread_equal(pthread_self(), c->caller)) {
		const int64_t until = now_ns() + WAIT_NS;

		while (atomic_load(&c->helped) == 0 && !atomic_load(&c->timed_out))
			if (now_ns() > until)
				atomic_store(&c->timed_out, 1);
			else
				sched_yield();
	} else {
		cpu_set_t mine;

		if (sched_getaffinity(0, sizeof(mine), &mine) == 0 &&
		    CPU_ISSET(c->caller_cpu, &mine))
			atomic_fetch_add(&c->on_caller_cpu, 1);
		atomic_fetch_add(&c->helped, 1);
	}
}

/*
 * Helpers are kept off the caller's CPU (else the scheduler's wake-affine placement often
 * parks a woken helper behind the caller). Judged by the mechanism, not by where a busy
 * scheduler happened to place threads: with the caller pinned to each allowed CPU in turn,
 * every helper index of a job runs on a helper whose affinity excludes that CPU.
 */
static void workers_helpers_avoid_the_callers_cpu(void **state)
{
	struct hl_workers *w = NULL;
	cpu_set_t allowed;
	int tried = 0;

	(void)state;
	assert_int_equal(sched_getaffinity(0, sizeof(allowed), &allowed), 0);
	if (CPU_COUNT(&allowed) < 2) {
		printf("one CPU allowed: nothing to avoid\n");
		return;
	}
	/* made before the caller is pinned: the helpers may use every allowed CPU */
	assert_int_equal(hl_workers_new(2, &w), 0);
	for (int cpu = 0; cpu < CPU_SETSIZE && tried < 4; cpu++) {
		struct cpus *c;
		cpu_set_t one;

		if (!CPU_ISSET(cpu, &allowed))
			continue;
		CPU_ZERO(&one);
		CPU_SET(cpu, &one);
		assert_int_equal(pthread_setaffinity_np(pthread_self(), sizeof(one), &one), 0);
		for (int r = 0; r < 20; r++) {
			c = calloc(1, sizeof(*c));
			assert_non_null(c);
			c->caller = pthread_self();
			c->caller_cpu = cpu;
			hl_workers_run(w, 16, note_cpu, c);
			assert_int_equal(atomic_load(&c->timed_out), 0);
			assert_true(atomic_load(&c->helped) > 0);
			assert_int_equal(atomic_load(&c->on_caller_cpu), 0);
			free(c);
		}
		tried++;
	}
	assert_int_equal(pthread_setaffinity_np(pthread_self(), sizeof(allowed), &allowed), 0);
	hl_workers_free(w);
}

static void workers_reject_bad_thread_counts(void **state)
{
	struct hl_workers *w = NULL;

	(void)state;
	assert_int_equal(hl_workers_new(0, &w), -EINVAL);
	assert_int_equal(hl_workers_new(HL_WORKERS_MAX_THREADS + 1, &w), -EINVAL);
	assert_null(w);
	hl_workers_free(NULL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(workers_run_every_index_exactly_once),
		cmocka_unit_test(workers_back_to_back_jobs_never_mix),
		cmocka_unit_test(workers_helpers_avoid_the_callers_cpu),
		cmocka_unit_test(workers_reject_bad_thread_counts),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
