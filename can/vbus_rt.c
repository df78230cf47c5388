/* SPDX-License-Identifier: MIT */
/* The virtual bus in real time: see can/vbus_rt.h. */
#include "can/vbus_rt.h"

#include <errno.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdlib.h>
#include <time.h>

struct hl_vbus_rt {
	struct hl_vbus *bus;
	struct hl_vbus_rt_hook hook;
	pthread_t thread;
	pthread_mutex_t lock;
	pthread_cond_t cond; /* on CLOCK_MONOTONIC */
	bool stop, kicked;
	int error;
	struct hl_vbus_rt_counts c;
};

static int64_t mono_ns(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

/* The bus's notify: a node sent, the next frame's end may have moved. */
static void kick(void *ctx)
{
	struct hl_vbus_rt *rt = ctx;

	pthread_mutex_lock(&rt->lock);
	rt->kicked = true;
	pthread_cond_signal(&rt->cond);
	pthread_mutex_unlock(&rt->lock);
}

static int64_t next_event(struct hl_vbus_rt *rt)
{
	int64_t t = hl_vbus_next(rt->bus);

	if (rt->hook.next) {
		const int64_t h = rt->hook.next(rt->hook.ctx);

		if (h < t)
			t = h;
	}
	return t;
}

static void *thread_main(void *arg)
{
	struct hl_vbus_rt *rt = arg;

	pthread_mutex_lock(&rt->lock);
	while (!rt->stop) {
		const int64_t t = next_event(rt);
		int64_t now = mono_ns();

		if (t > now && !rt->kicked) {
			struct timespec ts = { .tv_sec = 5, .tv_nsec = 0 }; /* idle: look again */

			if (t != INT64_MAX)
				ts = (struct timespec){ .tv_sec = t / 1000000000,
							.tv_nsec = t % 1000000000 };
			else
				ts.tv_sec += now / 1000000000;
			pthread_cond_timedwait(&rt->cond, &rt->lock, &ts);
			rt->c.wakeups++;
			continue;
		}
		rt->kicked = false;
		pthread_mutex_unlock(&rt->lock);
		now = mono_ns();
		hl_vbus_run_until(rt->bus, now);
		if (rt->hook.next) {
			const int64_t h = rt->hook.next(rt->hook.ctx);

			if (h <= now) {
				const int rc = rt->hook.run(rt->hook.ctx, h);

				pthread_mutex_lock(&rt->lock);
				rt->c.events++;
				if (now - h > rt->c.late_max_ns)
					rt->c.late_max_ns = now - h;
				if (rc < 0) {
					rt->error = rc;
					rt->stop = true;
				}
				continue;
			}
		}
		pthread_mutex_lock(&rt->lock);
	}
	pthread_mutex_unlock(&rt->lock);
	return NULL;
}

int hl_vbus_rt_start(struct hl_vbus *b, const struct hl_vbus_rt_hook *hook, struct hl_vbus_rt **ret)
{
	struct hl_vbus_rt *rt = calloc(1, sizeof(*rt));
	pthread_condattr_t ca;
	int rc;

	if (!rt)
		return -ENOMEM;
	rt->bus = b;
	if (hook)
		rt->hook = *hook;
	pthread_mutex_init(&rt->lock, NULL);
	pthread_condattr_init(&ca);
	pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
	pthread_cond_init(&rt->cond, &ca);
	pthread_condattr_destroy(&ca);
	hl_vbus_set_notify(b, kick, rt);
	rc = -pthread_create(&rt->thread, NULL, thread_main, rt);
	if (rc < 0) {
		hl_vbus_set_notify(b, NULL, NULL);
		pthread_cond_destroy(&rt->cond);
		pthread_mutex_destroy(&rt->lock);
		free(rt);
		return rc;
	}
	pthread_setname_np(rt->thread, "hl-vbus");
	*ret = rt;
	return 0;
}

void hl_vbus_rt_stop(struct hl_vbus_rt *rt)
{
	if (!rt)
		return;
	pthread_mutex_lock(&rt->lock);
	rt->stop = true;
	pthread_cond_signal(&rt->cond);
	pthread_mutex_unlock(&rt->lock);
	pthread_join(rt->thread, NULL);
	hl_vbus_set_notify(rt->bus, NULL, NULL);
	pthread_cond_destroy(&rt->cond);
	pthread_mutex_destroy(&rt->lock);
	free(rt);
}

int hl_vbus_rt_error(struct hl_vbus_rt *rt)
{
	int e;

	pthread_mutex_lock(&rt->lock);
	e = rt->error;
	pthread_mutex_unlock(&rt->lock);
	return e;
}

void hl_vbus_rt_counts(struct hl_vbus_rt *rt, struct hl_vbus_rt_counts *ret)
{
	pthread_mutex_lock(&rt->lock);
	*ret = rt->c;
	pthread_mutex_unlock(&rt->lock);
}
