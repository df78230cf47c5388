/* SPDX-License-Identifier: MIT */
/*
 * The frames between the render thread and the outputs (stream clients, HTTP, captures). The
 * render thread takes a free frame, fills it and publishes it as the newest; readers take a
 * reference to the newest (waiting for one newer than what they had, with a timeout) and
 * release it when sent. A reader never blocks the renderer: if every frame is still held by
 * readers, the renderer's frame is not published and that is counted. Memory is fixed at start.
 *
 * Subscribers (the stream, the GPIO strobe) learn of every published frame from
 * hl_frame_pool_publish itself, on the renderer's thread; after unsubscribe returns, the
 * subscriber is not called again.
 *
 * Thread-safety: all functions from any thread; the lock is held for pointer and count updates
 * and the subscribers' calls only, never while pixels are copied or sent.
 */
#ifndef HL_DAEMON_CORE_FRAME_POOL_H
#define HL_DAEMON_CORE_FRAME_POOL_H

#include <stdint.h>

#include "daemon/core/frame.h"

struct hl_frame_shape {
	int width, height;
	enum hl_pixel_format format;
	int n_lamps, n_sources;
	int dist_width, dist_height;
	int n_results; /* verdict results per frame (daemon/core/verdicts.h), 0: none */
	int n_sets; /* configured verdict sets (the header's n_sets) */
};

struct hl_frame_pool_counts {
	uint64_t published;
	uint64_t no_free_frame; /* frames the renderer could not publish: all frames held */
};

struct hl_frame_pool;

#define HL_FRAME_POOL_MAX_SUBSCRIBERS 4

/*
 * Called on the renderer's thread after f was published, with the pool's lock held: it must not
 * block nor call the pool (a wake-up: an eventfd write, a GPIO toggle). f is the newest frame.
 */
typedef void (*hl_frame_pool_published_fn)(void *userdata, const struct hl_frame *f);

/* n_frames >= 2. 0, -EINVAL, -ENOMEM. */
int hl_frame_pool_new(int n_frames, const struct hl_frame_shape *shape, struct hl_frame_pool **ret);
void hl_frame_pool_free(struct hl_frame_pool *pool);

/* Renderer: a frame nobody holds (not the newest), or NULL when all are held (counted). */
struct hl_frame *hl_frame_pool_acquire(struct hl_frame_pool *pool);
/* Renderer: makes f the newest (sets hdr.seq), wakes waiting readers, calls the subscribers. */
void hl_frame_pool_publish(struct hl_frame_pool *pool, struct hl_frame *f);
/* Adds a subscriber, called after every publish. 0, -ENOSPC. */
int hl_frame_pool_subscribe(struct hl_frame_pool *pool, hl_frame_pool_published_fn fn,
			    void *userdata);
/* Removes the subscriber with this fn and userdata (none: nothing happens). */
void hl_frame_pool_unsubscribe(struct hl_frame_pool *pool, hl_frame_pool_published_fn fn,
			       void *userdata);
/* Renderer: gives back an acquired frame without publishing it. */
void hl_frame_pool_discard(struct hl_frame_pool *pool, struct hl_frame *f);

/*
 * Reader: a reference to the newest frame if its seq > after_seq, waiting up to timeout_ms
 * (0: do not wait, -1: forever) for one; NULL when none came. Release it when done.
 */
struct hl_frame *hl_frame_pool_get(struct hl_frame_pool *pool, uint64_t after_seq, int timeout_ms);
void hl_frame_pool_release(struct hl_frame_pool *pool, struct hl_frame *f);
/* Wakes every waiting reader (for shutdown); later gets do not wait. */
void hl_frame_pool_close(struct hl_frame_pool *pool);

void hl_frame_pool_counts(struct hl_frame_pool *pool, struct hl_frame_pool_counts *ret);
const struct hl_frame_shape *hl_frame_pool_shape(const struct hl_frame_pool *pool);

#endif
