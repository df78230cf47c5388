/* SPDX-License-Identifier: MIT */
#include "daemon/out/capture_queue.h"

#include <errno.h>
#include <limits.h>
#include <malloc.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "base/sched.h"

#define MSG_SIZE (PATH_MAX + 512) /* a directory, or a file and a reason */

enum slot_state {
	SLOT_FREE,
	SLOT_FILLING, /* a request copies the frame into it */
	SLOT_QUEUED,
	SLOT_WRITING,
	SLOT_DONE, /* written or failed; its requester takes the result */
};

struct slot {
	struct hl_frame frame; /* the copy: buffers owned by the slot, no pixels */
	enum slot_state state;
	uint64_t order; /* requests are written in this order */
	bool waited; /* a requester waits for the result (else the writer frees the slot) */
	int rc;
	char msg[MSG_SIZE];
};

struct hl_capture_queue {
	char dir[PATH_MAX];
	struct hl_frame_pool *pool;
	struct hl_capture_scene scene;
	FILE *log;
	pthread_t thread;
	bool started;
	pthread_mutex_t lock; /* guards what follows */
	pthread_cond_t queued; /* the writer waits on it */
	pthread_cond_t done; /* requesters wait on it */
	bool stopping;
	uint64_t next_order;
	int n;
	struct slot *slots;
	struct hl_capture_queue_counts c;
};

static void free_frame(struct hl_frame *f)
{
	free(f->lux);
	free(f->results);
	for (int l = 0; l < HL_FRAME_MAX_LAMPS; l++) {
		free(f->dist[l]);
		free(f->dims[l]);
	}
}

/* malloc'd and touched: the memory is the daemon's from the start, not from a first burst. */
static void *alloc_touched(size_t size)
{
	void *p = malloc(size ? size : 1);

	if (p)
		memset(p, 0, size);
	return p;
}

static int alloc_frame(struct hl_frame *f, const struct hl_frame_shape *s)
{
	*f = (struct hl_frame){ .n_results = s->n_results };
	f->lux = alloc_touched(sizeof(float) * s->width * s->height);
	if (!f->lux)
		return -ENOMEM;
	for (int l = 0; l < s->n_lamps; l++) {
		f->dist[l] = alloc_touched(sizeof(float) * s->dist_width * s->dist_height);
		f->dims[l] = alloc_touched(s->n_sources);
		if (!f->dist[l] || !f->dims[l])
			return -ENOMEM;
	}
	if (s->n_results > 0) {
		f->results = alloc_touched(sizeof(*f->results) * s->n_results);
		if (!f->results)
			return -ENOMEM;
	}
	return 0;
}

/* What a capture reads of src, into the slot's buffers (dst->pixels stays NULL). */
static void copy_frame(struct hl_frame *dst, const struct hl_frame *src,
		       const struct hl_frame_shape *s)
{
	dst->hdr = src->hdr;
	memcpy(dst->lux, src->lux, sizeof(float) * s->width * s->height);
	for (int l = 0; l < s->n_lamps; l++) {
		memcpy(dst->dist[l], src->dist[l], sizeof(float) * s->dist_width * s->dist_height);
		memcpy(dst->dims[l], src->dims[l], s->n_sources);
	}
	if (s->n_results > 0)
		memcpy(dst->results, src->results, sizeof(*dst->results) * s->n_results);
	dst->dist_width = src->dist_width;
	dst->dist_height = src->dist_height;
	dst->n_sources = src->n_sources;
	dst->n_results = src->n_results;
	dst->beam_mode = src->beam_mode;
}

int hl_capture_queue_new(const struct hl_capture_queue_config *cfg, struct hl_capture_queue **ret)
{
	const struct hl_frame_shape *shape;
	struct hl_capture_queue *q;
	pthread_condattr_t ca;

	if (!cfg->dir || !cfg->pool || cfg->slots < 1 || cfg->slots > HL_CAPTURE_QUEUE_MAX ||
	    strlen(cfg->dir) >= sizeof(q->dir))
		return -EINVAL;
	q = calloc(1, sizeof(*q));
	if (!q)
		return -ENOMEM;
	strcpy(q->dir, cfg->dir);
	q->pool = cfg->pool;
	q->scene = cfg->scene;
	q->log = cfg->log;
	if (hl_mutex_init_pi(&q->lock) < 0) {
		free(q);
		return -ENOTSUP;
	}
	pthread_condattr_init(&ca);
	pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
	pthread_cond_init(&q->queued, NULL);
	pthread_cond_init(&q->done, &ca);
	pthread_condattr_destroy(&ca);
	q->n = cfg->slots;
	q->slots = calloc(q->n, sizeof(*q->slots));
	if (!q->slots) {
		hl_capture_queue_free(q);
		return -ENOMEM;
	}
	shape = hl_frame_pool_shape(q->pool);
	for (int i = 0; i < q->n; i++) {
		if (alloc_frame(&q->slots[i].frame, shape) < 0) {
			hl_capture_queue_free(q);
			return -ENOMEM;
		}
	}
	*ret = q;
	return 0;
}

/* The writer: the oldest queued capture, one at a time, until stopped with nothing queued. */
static void *writer_main(void *arg)
{
	struct hl_capture_queue *q = arg;

	pthread_mutex_lock(&q->lock);
	for (;;) {
		struct slot *s = NULL;
		char *msg;
		int rc;

		for (int i = 0; i < q->n; i++)
			if (q->slots[i].state == SLOT_QUEUED &&
			    (!s || q->slots[i].order < s->order))
				s = &q->slots[i];
		if (!s) {
			if (q->stopping)
				break;
			pthread_cond_wait(&q->queued, &q->lock);
			continue;
		}
		s->state = SLOT_WRITING;
		msg = s->msg;
		pthread_mutex_unlock(&q->lock);

		{
			char path[PATH_MAX + 64];

			rc = hl_capture_write(q->dir, &s->frame, &q->scene, path, sizeof(path), msg,
					      MSG_SIZE);
			if (rc == 0)
				snprintf(msg, MSG_SIZE, "%s", path);
		}
		if (q->log) {
			if (rc == 0)
				fprintf(q->log, "hdlampd: capture written to '%s'\n", msg);
			else
				fprintf(q->log, "hdlampd: capture failed: %s\n", msg);
		}
		malloc_trim(0); /* what the EXR files took goes back now, not at the next burst */

		pthread_mutex_lock(&q->lock);
		if (rc == 0)
			q->c.written++;
		else
			q->c.failed++;
		s->rc = rc;
		s->state = s->waited ? SLOT_DONE : SLOT_FREE;
		pthread_cond_broadcast(&q->done);
	}
	pthread_mutex_unlock(&q->lock);
	return NULL;
}

int hl_capture_queue_start(struct hl_capture_queue *q)
{
	const int rc = pthread_create(&q->thread, NULL, writer_main, q);

	if (rc != 0)
		return -rc;
	q->started = true;
	return 0;
}

void hl_capture_queue_stop(struct hl_capture_queue *q)
{
	pthread_mutex_lock(&q->lock);
	q->stopping = true;
	pthread_cond_signal(&q->queued);
	pthread_mutex_unlock(&q->lock);
	if (q->started)
		pthread_join(q->thread, NULL);
	q->started = false;
	/* never started: what was queued is not written, but counted */
	pthread_mutex_lock(&q->lock);
	for (int i = 0; i < q->n; i++) {
		if (q->slots[i].state == SLOT_QUEUED) {
			q->slots[i].state = SLOT_FREE;
			q->c.failed++;
		}
	}
	pthread_mutex_unlock(&q->lock);
}

void hl_capture_queue_free(struct hl_capture_queue *q)
{
	if (!q)
		return;
	hl_capture_queue_stop(q);
	for (int i = 0; q->slots && i < q->n; i++)
		free_frame(&q->slots[i].frame);
	free(q->slots);
	pthread_cond_destroy(&q->done);
	pthread_cond_destroy(&q->queued);
	pthread_mutex_destroy(&q->lock);
	free(q);
}

/* Takes a free slot (FILLING), or NULL: counted as refused. Locked. */
static struct slot *take_slot(struct hl_capture_queue *q)
{
	for (int i = 0; i < q->n; i++) {
		if (q->slots[i].state == SLOT_FREE) {
			q->slots[i].state = SLOT_FILLING;
			return &q->slots[i];
		}
	}
	q->c.refused++;
	return NULL;
}

/* Waits until s is done or wait_ms passed; its result, or -ETIMEDOUT (it is let go). Locked. */
static int wait_done(struct hl_capture_queue *q, struct slot *s, int wait_ms, char *ret_msg,
		     size_t size)
{
	struct timespec until;
	int rc;

	clock_gettime(CLOCK_MONOTONIC, &until);
	until.tv_sec += wait_ms / 1000;
	until.tv_nsec += (long)(wait_ms % 1000) * 1000000;
	if (until.tv_nsec >= 1000000000) {
		until.tv_sec++;
		until.tv_nsec -= 1000000000;
	}
	while (s->state != SLOT_DONE)
		if (pthread_cond_timedwait(&q->done, &q->lock, &until) == ETIMEDOUT)
			break;
	if (s->state != SLOT_DONE) {
		s->waited = false; /* the writer frees it when done */
		snprintf(ret_msg, size,
			 "the capture is still being written after %d ms; the log will say where",
			 wait_ms);
		return -ETIMEDOUT;
	}
	rc = s->rc;
	snprintf(ret_msg, size, "%s", s->msg);
	s->state = SLOT_FREE;
	return rc;
}

int hl_capture_queue_submit(struct hl_capture_queue *q, int wait_ms, char *ret_msg, size_t size)
{
	struct hl_frame *f;
	struct slot *s;
	bool stopping;
	int rc = 0;

	pthread_mutex_lock(&q->lock);
	stopping = q->stopping;
	s = stopping ? NULL : take_slot(q);
	pthread_mutex_unlock(&q->lock);
	if (stopping || !s) {
		if (stopping)
			snprintf(ret_msg, size, "the daemon is stopping");
		else
			snprintf(ret_msg, size, "%d captures are queued (capture.queue); try again",
				 q->n);
		if (wait_ms == 0 && q->log)
			fprintf(q->log, "hdlampd: capture refused: %s\n", ret_msg);
		return stopping ? -ESHUTDOWN : -EBUSY;
	}
	/* the pool frame is held for this copy only */
	f = hl_frame_pool_get(q->pool, 0, HL_CAPTURE_FIRST_FRAME_MS);
	if (f) {
		copy_frame(&s->frame, f, hl_frame_pool_shape(q->pool));
		hl_frame_pool_release(q->pool, f);
	}
	pthread_mutex_lock(&q->lock);
	if (!f) {
		q->c.failed++;
		s->state = SLOT_FREE;
		snprintf(ret_msg, size, "no frame rendered yet");
		rc = -EAGAIN;
	} else {
		s->order = ++q->next_order;
		s->waited = wait_ms > 0;
		s->state = SLOT_QUEUED;
		pthread_cond_signal(&q->queued);
		if (wait_ms > 0)
			rc = wait_done(q, s, wait_ms, ret_msg, size);
		else
			snprintf(ret_msg, size, "capture queued");
	}
	pthread_mutex_unlock(&q->lock);
	if (rc == -EAGAIN && q->log)
		fprintf(q->log, "hdlampd: capture failed: %s\n", ret_msg);
	return rc;
}

void hl_capture_queue_counts(struct hl_capture_queue *q, struct hl_capture_queue_counts *ret)
{
	pthread_mutex_lock(&q->lock);
	*ret = q->c;
	pthread_mutex_unlock(&q->lock);
}
