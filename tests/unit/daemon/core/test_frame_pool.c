/* SPDX-License-Identifier: MIT */
/*
 * The frame pool: refused shapes, the headers it fills, sequence numbers from 1, the newest
 * never handed back to the renderer, a pool whose every frame is held (counted), subscribers
 * (called with the newest, at most 4, removed exactly), and readers on other threads woken by a
 * publish or by close.
 */
#include <errno.h>
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "daemon/core/frame_pool.h"

static const struct hl_frame_shape shape = {
	.width = 8,
	.height = 4,
	.format = HL_PIXEL_RGB8,
	.n_lamps = 2,
	.n_sources = 5,
	.dist_width = 3,
	.dist_height = 2,
	.n_results = 3,
	.n_sets = 2,
};

static void frame_pool_refuses_bad_shapes(void **state)
{
	struct hl_frame_pool *p = NULL;
	struct hl_frame_shape s;
	(void)state;

	assert_int_equal(hl_frame_pool_new(1, &shape, &p), -EINVAL);
	s = shape, s.width = 0;
	assert_int_equal(hl_frame_pool_new(2, &s, &p), -EINVAL);
	s = shape, s.height = -1;
	assert_int_equal(hl_frame_pool_new(2, &s, &p), -EINVAL);
	s = shape, s.n_lamps = 0;
	assert_int_equal(hl_frame_pool_new(2, &s, &p), -EINVAL);
	s = shape, s.n_lamps = HL_FRAME_MAX_LAMPS + 1;
	assert_int_equal(hl_frame_pool_new(2, &s, &p), -EINVAL);
	s = shape, s.n_sources = 0;
	assert_int_equal(hl_frame_pool_new(2, &s, &p), -EINVAL);
	s = shape, s.n_results = -1;
	assert_int_equal(hl_frame_pool_new(2, &s, &p), -EINVAL);
	s = shape, s.n_sets = 33;
	assert_int_equal(hl_frame_pool_new(2, &s, &p), -EINVAL);
	s = shape, s.format = (enum hl_pixel_format)0;
	assert_int_equal(hl_frame_pool_new(2, &s, &p), -EINVAL);
	s = shape, s.format = (enum hl_pixel_format)3;
	assert_int_equal(hl_frame_pool_new(2, &s, &p), -EINVAL);
	assert_null(p);
	hl_frame_pool_free(NULL);
}

static void frame_pool_fills_the_wire_header_of_each_format(void **state)
{
	(void)state;
	for (int fmt = HL_PIXEL_RGB8; fmt <= HL_PIXEL_RGBA16F; fmt++) {
		const size_t bpp = fmt == HL_PIXEL_RGB8 ? 3 : 8;
		struct hl_frame_shape s = shape;
		struct hl_frame_pool *p;
		struct hl_frame *f;

		s.format = (enum hl_pixel_format)fmt;
		assert_int_equal(hl_frame_pool_new(3, &s, &p), 0);
		assert_memory_equal(hl_frame_pool_shape(p), &s, sizeof(s));
		f = hl_frame_pool_acquire(p);
		assert_non_null(f);
		assert_int_equal(f->hdr.magic, HL_FRAME_MAGIC);
		assert_int_equal(f->hdr.version, HL_FRAME_VERSION);
		assert_int_equal(f->hdr.header_size, HL_FRAME_HEADER_SIZE);
		assert_int_equal(f->hdr.seq, 0);
		assert_int_equal(f->hdr.width, 8);
		assert_int_equal(f->hdr.height, 4);
		assert_int_equal(f->hdr.stride, 8 * bpp);
		assert_int_equal(f->hdr.pixel_format, fmt);
		assert_int_equal(f->hdr.payload_size, 8 * 4 * bpp);
		assert_int_equal(f->hdr.n_lamps, 2);
		assert_int_equal(f->hdr.n_sets, 2);
		assert_int_equal(f->n_results, 3);
		assert_int_equal(f->beam_mode, -1);
		assert_int_equal(f->dist_width, 3);
		assert_int_equal(f->dist_height, 2);
		assert_int_equal(f->n_sources, 5);
		/* every buffer is there and zeroed: the last byte of each written under ASan */
		assert_int_equal(f->pixels[8 * 4 * bpp - 1], 0);
		assert_true(f->lux[8 * 4 - 1] == 0.0f);
		for (int l = 0; l < 2; l++) {
			assert_true(f->dist[l][3 * 2 - 1] == 0.0f);
			assert_int_equal(f->dims[l][4], 0);
		}
		assert_non_null(f->results);
		hl_frame_pool_discard(p, f);
		hl_frame_pool_free(p);
	}
}

static void frame_pool_publish_numbers_from_1_and_readers_see_the_newest(void **state)
{
	struct hl_frame_pool *p;
	struct hl_frame *a, *b, *r;
	struct hl_frame_pool_counts c;
	(void)state;

	assert_int_equal(hl_frame_pool_new(3, &shape, &p), 0);
	assert_null(hl_frame_pool_get(p, 0, 0)); /* nothing published */
	a = hl_frame_pool_acquire(p);
	hl_frame_pool_publish(p, a);
	assert_int_equal(a->hdr.seq, 1);
	b = hl_frame_pool_acquire(p);
	assert_ptr_not_equal(b, a); /* the newest is never the renderer's */
	hl_frame_pool_publish(p, b);
	assert_int_equal(b->hdr.seq, 2);
	r = hl_frame_pool_get(p, 0, 0);
	assert_ptr_equal(r, b);
	assert_null(hl_frame_pool_get(p, 2, 0)); /* nothing newer than seq 2 */
	hl_frame_pool_release(p, r);
	hl_frame_pool_release(p, NULL);
	hl_frame_pool_counts(p, &c);
	assert_int_equal(c.published, 2);
	assert_int_equal(c.no_free_frame, 0);
	hl_frame_pool_free(p);
}

static void frame_pool_every_frame_held_then_none_to_acquire(void **state)
{
	struct hl_frame_pool *p;
	struct hl_frame *f, *held[2], *g;
	struct hl_frame_pool_counts c;
	(void)state;

	assert_int_equal(hl_frame_pool_new(2, &shape, &p), 0);
	f = hl_frame_pool_acquire(p);
	hl_frame_pool_publish(p, f);
	held[0] = hl_frame_pool_get(p, 0, 0); /* a reader holds seq 1 */
	assert_ptr_equal(held[0], f);
	held[1] = hl_frame_pool_acquire(p); /* the renderer fills the other */
	assert_non_null(held[1]);
	assert_null(hl_frame_pool_acquire(p));
	assert_null(hl_frame_pool_acquire(p));
	hl_frame_pool_counts(p, &c);
	assert_int_equal(c.no_free_frame, 2);
	/* a discarded frame is free again; the newest, even released, is not handed out */
	hl_frame_pool_discard(p, held[1]);
	hl_frame_pool_release(p, held[0]);
	g = hl_frame_pool_acquire(p);
	assert_ptr_equal(g, held[1]);
	assert_null(hl_frame_pool_acquire(p));
	hl_frame_pool_publish(p, g);
	assert_int_equal(g->hdr.seq, 2);
	/* now the first is no longer the newest and free */
	assert_ptr_equal(hl_frame_pool_acquire(p), f);
	hl_frame_pool_counts(p, &c);
	assert_int_equal(c.no_free_frame, 3);
	assert_int_equal(c.published, 2);
	hl_frame_pool_free(p);
}

struct sub {
	int calls;
	uint64_t last_seq;
};

static void on_publish(void *userdata, const struct hl_frame *f)
{
	struct sub *s = userdata;

	s->calls++;
	s->last_seq = f->hdr.seq;
}

static void on_publish_other(void *userdata, const struct hl_frame *f)
{
	(void)f;
	((struct sub *)userdata)->calls += 100;
}

static void frame_pool_subscribers_called_until_unsubscribed(void **state)
{
	struct hl_frame_pool *p;
	struct sub s[5] = { { 0, 0 } };
	(void)state;

	assert_int_equal(hl_frame_pool_new(2, &shape, &p), 0);
	for (int i = 0; i < HL_FRAME_POOL_MAX_SUBSCRIBERS; i++)
		assert_int_equal(hl_frame_pool_subscribe(p, on_publish, &s[i]), 0);
	assert_int_equal(hl_frame_pool_subscribe(p, on_publish, &s[4]), -ENOSPC);
	hl_frame_pool_publish(p, hl_frame_pool_acquire(p));
	for (int i = 0; i < 4; i++) {
		assert_int_equal(s[i].calls, 1);
		assert_int_equal(s[i].last_seq, 1);
	}
	assert_int_equal(s[4].calls, 0);
	/* a different fn with the same userdata, or one never added: nothing removed */
	hl_frame_pool_unsubscribe(p, on_publish_other, &s[1]);
	hl_frame_pool_unsubscribe(p, on_publish, &s[4]);
	hl_frame_pool_unsubscribe(p, on_publish, &s[1]);
	assert_int_equal(hl_frame_pool_subscribe(p, on_publish_other, &s[4]), 0);
	hl_frame_pool_publish(p, hl_frame_pool_acquire(p));
	assert_int_equal(s[0].calls, 2);
	assert_int_equal(s[1].calls, 1); /* removed */
	assert_int_equal(s[2].calls, 2);
	assert_int_equal(s[3].calls, 2);
	assert_int_equal(s[3].last_seq, 2);
	assert_int_equal(s[4].calls, 100);
	hl_frame_pool_free(p);
}

struct reader {
	struct hl_frame_pool *p;
	uint64_t after;
	int timeout_ms;
	struct hl_frame *got;
	uint64_t seq;
};

static void *read_one(void *arg)
{
	struct reader *r = arg;

	r->got = hl_frame_pool_get(r->p, r->after, r->timeout_ms);
	r->seq = r->got ? r->got->hdr.seq : 0;
	hl_frame_pool_release(r->p, r->got);
	return NULL;
}

static void frame_pool_waiting_readers_woken_by_publish_and_by_close(void **state)
{
	struct hl_frame_pool *p;
	struct reader r;
	pthread_t t;
	(void)state;

	assert_int_equal(hl_frame_pool_new(3, &shape, &p), 0);
	/* a reader waiting forever for a frame after seq 0 gets the one published */
	r = (struct reader){ p, 0, -1, NULL, 0 };
	assert_int_equal(pthread_create(&t, NULL, read_one, &r), 0);
	hl_frame_pool_publish(p, hl_frame_pool_acquire(p));
	assert_int_equal(pthread_join(t, NULL), 0);
	assert_non_null(r.got);
	assert_int_equal(r.seq, 1);
	/* a timed wait with nothing newer ends without a frame */
	r = (struct reader){ p, 1, 20, NULL, 0 };
	read_one(&r);
	assert_null(r.got);
	/* a reader waiting forever for a frame after seq 1 is woken by close, without one */
	r = (struct reader){ p, 1, -1, NULL, 0 };
	assert_int_equal(pthread_create(&t, NULL, read_one, &r), 0);
	hl_frame_pool_close(p);
	assert_int_equal(pthread_join(t, NULL), 0);
	assert_null(r.got);
	/* after close: no waiting, and what is there is still given */
	assert_null(hl_frame_pool_get(p, 1, -1));
	r.got = hl_frame_pool_get(p, 0, -1);
	assert_non_null(r.got);
	assert_int_equal(r.got->hdr.seq, 1);
	hl_frame_pool_release(p, r.got);
	hl_frame_pool_free(p);
}

/* Two publishers' worth of frames against four readers: each reader sees rising seqs. */
struct stress {
	struct hl_frame_pool *p;
	int bad;
};

static void *stress_reader(void *arg)
{
	struct stress *s = arg;
	uint64_t last = 0;

	for (;;) {
		struct hl_frame *f = hl_frame_pool_get(s->p, last, -1);

		if (!f)
			return NULL;
		if (f->hdr.seq <= last || f->pixels[0] != (uint8_t)f->hdr.seq)
			__atomic_add_fetch(&s->bad, 1, __ATOMIC_RELAXED);
		last = f->hdr.seq;
		hl_frame_pool_release(s->p, f);
	}
}

static void frame_pool_readers_on_threads_see_whole_rising_frames(void **state)
{
	struct stress s = { NULL, 0 };
	struct hl_frame_pool_counts c;
	pthread_t t[4];
	uint64_t published = 0;
	(void)state;

	assert_int_equal(hl_frame_pool_new(3, &shape, &s.p), 0);
	for (int i = 0; i < 4; i++)
		assert_int_equal(pthread_create(&t[i], NULL, stress_reader, &s), 0);
	for (int k = 0; k < 2000; k++) {
		struct hl_frame *f = hl_frame_pool_acquire(s.p);

		if (!f)
			continue;
		/* the pixels carry the seq this frame will get: a reader checks they agree */
		f->pixels[0] = (uint8_t)(published + 1);
		hl_frame_pool_publish(s.p, f);
		published++;
	}
	hl_frame_pool_close(s.p);
	for (int i = 0; i < 4; i++)
		assert_int_equal(pthread_join(t[i], NULL), 0);
	assert_int_equal(s.bad, 0);
	hl_frame_pool_counts(s.p, &c);
	assert_int_equal(c.published, published);
	assert_int_equal(c.published + c.no_free_frame, 2000);
	hl_frame_pool_free(s.p);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(frame_pool_refuses_bad_shapes),
		cmocka_unit_test(frame_pool_fills_the_wire_header_of_each_format),
		cmocka_unit_test(frame_pool_publish_numbers_from_1_and_readers_see_the_newest),
		cmocka_unit_test(frame_pool_every_frame_held_then_none_to_acquire),
		cmocka_unit_test(frame_pool_subscribers_called_until_unsubscribed),
		cmocka_unit_test(frame_pool_waiting_readers_woken_by_publish_and_by_close),
		cmocka_unit_test(frame_pool_readers_on_threads_see_whole_rising_frames),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
