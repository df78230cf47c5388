/* SPDX-License-Identifier: MIT */
#include "daemon/core/frame_pool.h"

#include <errno.h>
#include <stddef.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "base/sched.h"

struct entry {
	struct hl_frame frame;
	int refs; /* readers holding it, +1 while the renderer fills it */
};

struct hl_frame_pool {
	pthread_mutex_t lock;
	pthread_cond_t newer;
	struct hl_frame_shape shape;
	int n;
	struct entry *e;
	struct entry *newest;
	uint64_t seq;
	bool closed;
	struct hl_frame_pool_counts c;
	int n_subs;
	struct {
		hl_frame_pool_published_fn fn;
		void *userdata;
	} subs[HL_FRAME_POOL_MAX_SUBSCRIBERS];
};

static size_t pixel_bytes(const struct hl_frame_shape *s)
{
	return (size_t)s->width * s->height * (s->format == HL_PIXEL_RGBA16F ? 8 : 3);
}

int hl_frame_pool_new(int n_frames, const struct hl_frame_shape *shape, struct hl_frame_pool **ret)
{
	struct hl_frame_pool *p;

	if (n_frames < 2 || shape->width < 1 || shape->height < 1 || shape->n_lamps < 1 ||
	    shape->n_lamps > HL_FRAME_MAX_LAMPS || shape->n_sources < 1 || shape->n_results < 0 ||
	    shape->n_sets < 0 || shape->n_sets > 32 ||
	    (shape->format != HL_PIXEL_RGB8 && shape->format != HL_PIXEL_RGBA16F))
		return -EINVAL;
	p = calloc(1, sizeof(*p));
	if (!p)
		return -ENOMEM;
	if (hl_mutex_init_pi(&p->lock) < 0) {
		free(p);
		return -ENOTSUP;
	}
	pthread_cond_init(&p->newer, NULL);
	p->shape = *shape;
	p->n = n_frames;
	p->e = calloc(n_frames, sizeof(*p->e));
	if (!p->e)
		goto err;
	for (int i = 0; i < n_frames; i++) {
		struct hl_frame *f = &p->e[i].frame;

		f->pixels = calloc(1, pixel_bytes(shape));
		f->lux = calloc((size_t)shape->width * shape->height, sizeof(float));
		if (!f->pixels || !f->lux)
			goto err;
		for (int l = 0; l < shape->n_lamps; l++) {
			f->dist[l] = calloc((size_t)shape->dist_width * shape->dist_height + 1,
					    sizeof(float));
			f->dims[l] = calloc(shape->n_sources, 1);
			if (!f->dist[l] || !f->dims[l])
				goto err;
		}
		if (shape->n_results > 0) {
			f->results = calloc(shape->n_results, sizeof(*f->results));
			if (!f->results)
				goto err;
		}
		f->n_results = shape->n_results;
		f->beam_mode = -1;
		f->dist_width = shape->dist_width;
		f->dist_height = shape->dist_height;
		f->n_sources = shape->n_sources;
		f->hdr = (struct hl_frame_header){
			.magic = HL_FRAME_MAGIC,
			.version = HL_FRAME_VERSION,
			.header_size = sizeof(struct hl_frame_header),
			.width = (uint32_t)shape->width,
			.height = (uint32_t)shape->height,
			.stride = (uint32_t)(pixel_bytes(shape) / shape->height),
			.pixel_format = shape->format,
			.payload_size = (uint32_t)pixel_bytes(shape),
			.n_lamps = (uint8_t)shape->n_lamps,
			.n_sets = (uint8_t)shape->n_sets,
		};
	}
	*ret = p;
	return 0;
err:
	hl_frame_pool_free(p);
	return -ENOMEM;
}

void hl_frame_pool_free(struct hl_frame_pool *p)
{
	if (!p)
		return;
	for (int i = 0; p->e && i < p->n; i++) {
		free(p->e[i].frame.pixels);
		free(p->e[i].frame.lux);
		free(p->e[i].frame.results);
		for (int l = 0; l < HL_FRAME_MAX_LAMPS; l++) {
			free(p->e[i].frame.dist[l]);
			free(p->e[i].frame.dims[l]);
		}
	}
	free(p->e);
	pthread_cond_destroy(&p->newer);
	pthread_mutex_destroy(&p->lock);
	free(p);
}

static struct entry *entry_of(struct hl_frame_pool *p, struct hl_frame *f)
{
	(void)p;
	return (struct entry *)((char *)f - offsetof(struct entry, frame));
}

struct hl_frame *hl_frame_pool_acquire(struct hl_frame_pool *p)
{
	struct hl_frame *f = NULL;

	pthread_mutex_lock(&p->lock);
	for (int i = 0; i < p->n; i++) {
		if (p->e[i].refs == 0 && &p->e[i] != p->newest) {
			p->e[i].refs = 1;
			f = &p->e[i].frame;
			break;
		}
	}
	if (!f)
		p->c.no_free_frame++;
	pthread_mutex_unlock(&p->lock);
	return f;
}

void hl_frame_pool_publish(struct hl_frame_pool *p, struct hl_frame *f)
{
	struct entry *e = entry_of(p, f);

	pthread_mutex_lock(&p->lock);
	f->hdr.seq = ++p->seq;
	e->refs--;
	p->newest = e;
	p->c.published++;
	pthread_cond_broadcast(&p->newer);
	for (int i = 0; i < p->n_subs; i++)
		p->subs[i].fn(p->subs[i].userdata, f);
	pthread_mutex_unlock(&p->lock);
}

int hl_frame_pool_subscribe(struct hl_frame_pool *p, hl_frame_pool_published_fn fn, void *userdata)
{
	int rc = -ENOSPC;

	pthread_mutex_lock(&p->lock);
	if (p->n_subs < HL_FRAME_POOL_MAX_SUBSCRIBERS) {
		p->subs[p->n_subs].fn = fn;
		p->subs[p->n_subs].userdata = userdata;
		p->n_subs++;
		rc = 0;
	}
	pthread_mutex_unlock(&p->lock);
	return rc;
}

void hl_frame_pool_unsubscribe(struct hl_frame_pool *p, hl_frame_pool_published_fn fn,
			       void *userdata)
{
	pthread_mutex_lock(&p->lock);
	for (int i = 0; i < p->n_subs; i++) {
		if (p->subs[i].fn != fn || p->subs[i].userdata != userdata)
			continue;
		memmove(&p->subs[i], &p->subs[i + 1], sizeof(p->subs[0]) * (p->n_subs - i - 1));
		p->n_subs--;
		break;
	}
	pthread_mutex_unlock(&p->lock);
}

void hl_frame_pool_discard(struct hl_frame_pool *p, struct hl_frame *f)
{
	pthread_mutex_lock(&p->lock);
	entry_of(p, f)->refs--;
	pthread_mutex_unlock(&p->lock);
}

struct hl_frame *hl_frame_pool_get(struct hl_frame_pool *p, uint64_t after_seq, int timeout_ms)
{
	struct hl_frame *f = NULL;
	struct timespec until;

	if (timeout_ms > 0) {
		clock_gettime(CLOCK_REALTIME, &until);
		until.tv_sec += timeout_ms / 1000;
		until.tv_nsec += (long)(timeout_ms % 1000) * 1000000;
		if (until.tv_nsec >= 1000000000) {
			until.tv_sec++;
			until.tv_nsec -= 1000000000;
		}
	}
	pthread_mutex_lock(&p->lock);
	while (!p->closed && (!p->newest || p->newest->frame.hdr.seq <= after_seq) &&
	       timeout_ms != 0) {
		if (timeout_ms < 0)
			pthread_cond_wait(&p->newer, &p->lock);
		else if (pthread_cond_timedwait(&p->newer, &p->lock, &until) == ETIMEDOUT)
			break;
	}
	if (p->newest && p->newest->frame.hdr.seq > after_seq) {
		p->newest->refs++;
		f = &p->newest->frame;
	}
	pthread_mutex_unlock(&p->lock);
	return f;
}

void hl_frame_pool_release(struct hl_frame_pool *p, struct hl_frame *f)
{
	if (!f)
		return;
	pthread_mutex_lock(&p->lock);
	entry_of(p, f)->refs--;
	pthread_mutex_unlock(&p->lock);
}

void hl_frame_pool_close(struct hl_frame_pool *p)
{
	pthread_mutex_lock(&p->lock);
	p->closed = true;
	pthread_cond_broadcast(&p->newer);
	pthread_mutex_unlock(&p->lock);
}

void hl_frame_pool_counts(struct hl_frame_pool *p, struct hl_frame_pool_counts *ret)
{
	pthread_mutex_lock(&p->lock);
	*ret = p->c;
	pthread_mutex_unlock(&p->lock);
}

const struct hl_frame_shape *hl_frame_pool_shape(const struct hl_frame_pool *p)
{
	return &p->shape;
}
