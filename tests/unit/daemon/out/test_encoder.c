/* SPDX-License-Identifier: MIT */
/*
 * The HTTP image encoder against a real frame pool: one encode per frame and kind however many
 * requests share it, images of the newest frame, a bound on the bytes slow clients hold, bad
 * requests, and a stop that answers every request.
 */
#include <errno.h>
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "daemon/out/encoder.h"

#define W 160
#define H 90
#define BIG 1024 /* side of the frames whose EXRs fill the stale-bytes bound */
/* a bound on a hang only: an ASan build on a loaded machine took over 10 s for one EXR */
#define WAIT_MS 60000
#define REQUESTS 8

static struct hl_frame_pool *pool_new(int side_w, int side_h)
{
	const struct hl_frame_shape shape = { .width = side_w,
					      .height = side_h,
					      .format = HL_PIXEL_RGB8,
					      .n_lamps = 1,
					      .n_sources = 1,
					      .dist_width = 1,
					      .dist_height = 1 };
	struct hl_frame_pool *pool;

	assert_int_equal(hl_frame_pool_new(4, &shape, &pool), 0);
	return pool;
}

/* Publishes a frame whose pixels and lux depend on value only: its seq. */
static uint64_t publish(struct hl_frame_pool *pool, int value)
{
	struct hl_frame *f = hl_frame_pool_acquire(pool);

	assert_non_null(f);
	memset(f->pixels, value, f->hdr.payload_size);
	for (uint32_t i = 0; i < f->hdr.width * f->hdr.height; i++) {
		uint32_t x = i * 2654435761u ^ (uint32_t)value;

		x ^= x >> 13;
		x *= 0x5bd1e995u;
		x ^= x >> 15;
		f->lux[i] = (float)x / 65536.0f; /* noise: the EXR does not compress much */
	}
	hl_frame_pool_publish(pool, f);
	return f->hdr.seq;
}

struct request {
	struct hl_encoder *enc;
	uint64_t want;
	int rc;
	struct hl_image *img;
	pthread_t thread;
};

static void *request(void *arg)
{
	struct request *r = arg;

	r->rc = hl_encoder_get(r->enc, HL_IMAGE_PNG, r->want, WAIT_MS, &r->img);
	return NULL;
}

static void encoder_encodes_each_frame_once_for_every_request(void **state)
{
	struct hl_frame_pool *pool = pool_new(W, H);
	struct hl_encoder *enc;
	struct hl_encoder_counts c;
	struct request r[REQUESTS];
	struct hl_image *img, *jpeg, *exr;

	(void)state;
	assert_int_equal(hl_encoder_new(pool, NULL, &enc), 0);
	assert_int_equal(hl_encoder_newest(enc), 0);
	assert_int_equal(publish(pool, 10), 1);
	assert_int_equal(hl_encoder_newest(enc), 1);
	for (int i = 0; i < REQUESTS; i++) {
		r[i] = (struct request){ .enc = enc, .want = 1 };
		assert_int_equal(pthread_create(&r[i].thread, NULL, request, &r[i]), 0);
	}
	for (int i = 0; i < REQUESTS; i++) {
		pthread_join(r[i].thread, NULL);
		assert_int_equal(r[i].rc, 0);
		assert_ptr_equal(r[i].img, r[0].img); /* one image, shared */
	}
	img = r[0].img;
	assert_int_equal(img->seq, 1);
	assert_int_equal(img->kind, HL_IMAGE_PNG);
	assert_memory_equal(img->data, "\x89PNG\r\n\x1a\n", 8);
	hl_encoder_counts(enc, &c);
	assert_int_equal(c.encoded[HL_IMAGE_PNG], 1);
	assert_int_equal(c.encoded[HL_IMAGE_JPEG] + c.encoded[HL_IMAGE_EXR], 0);
	for (int i = 0; i < REQUESTS; i++)
		hl_encoder_release(r[i].img);
	/* the same frame again: the same image, no encode */
	assert_int_equal(hl_encoder_get(enc, HL_IMAGE_PNG, 1, WAIT_MS, &img), 0);
	assert_ptr_equal(img, r[0].img);
	hl_encoder_release(img);
	/* a newer frame: a new image of it; the other kinds only when asked */
	assert_int_equal(publish(pool, 20), 2);
	assert_int_equal(hl_encoder_get(enc, HL_IMAGE_PNG, 2, WAIT_MS, &img), 0);
	assert_int_equal(img->seq, 2);
	assert_int_equal(hl_encoder_get(enc, HL_IMAGE_JPEG, 2, WAIT_MS, &jpeg), 0);
	assert_memory_equal(jpeg->data, "\xff\xd8\xff", 3);
	assert_int_equal(hl_encoder_get(enc, HL_IMAGE_EXR, 1, WAIT_MS, &exr), 0);
	assert_int_equal(exr->seq, 2); /* at least as new as asked: the newest */
	assert_memory_equal(exr->data, "\x76\x2f\x31\x01", 4);
	hl_encoder_counts(enc, &c);
	assert_int_equal(c.encoded[HL_IMAGE_PNG], 2);
	assert_int_equal(c.encoded[HL_IMAGE_JPEG], 1);
	assert_int_equal(c.encoded[HL_IMAGE_EXR], 1);
	assert_int_equal(c.busy + c.timeouts + c.failed, 0);
	hl_encoder_release(img);
	hl_encoder_release(jpeg);
	hl_encoder_release(exr);
	hl_encoder_release(NULL);
	hl_encoder_free(enc);
	hl_frame_pool_free(pool);
}

static void encoder_rejects_frames_not_published(void **state)
{
	struct hl_frame_pool *pool = pool_new(W, H);
	struct hl_encoder *enc;
	struct hl_image *img = NULL;

	(void)state;
	assert_int_equal(hl_encoder_new(pool, NULL, &enc), 0);
	assert_int_equal(hl_encoder_get(enc, HL_IMAGE_PNG, 1, WAIT_MS, &img), -EINVAL);
	publish(pool, 1);
	assert_int_equal(hl_encoder_get(enc, HL_IMAGE_PNG, 0, WAIT_MS, &img), -EINVAL);
	assert_int_equal(hl_encoder_get(enc, HL_IMAGE_PNG, 2, WAIT_MS, &img), -EINVAL);
	assert_int_equal(hl_encoder_get(enc, HL_IMAGE_KINDS, 1, WAIT_MS, &img), -EINVAL);
	assert_null(img);
	hl_encoder_free(enc);
	hl_frame_pool_free(pool);
}

/*
 * Slow clients that hold the images of older frames: once they hold more than
 * HL_ENCODER_MAX_STALE_BYTES of replaced images, no new image is encoded (-EBUSY, counted);
 * when they let go, encoding resumes.
 */
static void encoder_bounds_the_bytes_slow_clients_hold(void **state)
{
	struct hl_frame_pool *pool = pool_new(BIG, BIG);
	struct hl_image *held[256], *img;
	struct hl_encoder *enc;
	struct hl_encoder_counts c;
	size_t len, expect;
	int n = 0, rc;

	(void)state;
	assert_int_equal(hl_encoder_new(pool, NULL, &enc), 0);
	for (;;) {
		const uint64_t seq = publish(pool, 7); /* the same content: the same size */

		assert_true(n < 256);
		rc = hl_encoder_get(enc, HL_IMAGE_EXR, seq, WAIT_MS, &held[n]);
		if (rc < 0)
			break;
		n++;
	}
	assert_int_equal(rc, -EBUSY);
	len = held[0]->len;
	for (int i = 1; i < n; i++)
		assert_int_equal(held[i]->len, len);
	/* refused at the first request that found more than the bound replaced and held */
	expect = (size_t)HL_ENCODER_MAX_STALE_BYTES / len + 2;
	assert_int_equal(n, expect);
	hl_encoder_counts(enc, &c);
	assert_int_equal(c.busy, 1);
	assert_int_equal(c.encoded[HL_IMAGE_EXR], n);
	for (int i = 0; i < n; i++)
		hl_encoder_release(held[i]);
	assert_int_equal(hl_encoder_get(enc, HL_IMAGE_EXR, hl_encoder_newest(enc), WAIT_MS, &img),
			 0);
	hl_encoder_release(img);
	hl_encoder_free(enc);
	hl_frame_pool_free(pool);
}

static void encoder_stop_answers_every_request(void **state)
{
	struct hl_frame_pool *pool = pool_new(W, H);
	struct hl_encoder *enc;
	struct hl_image *img;

	(void)state;
	assert_int_equal(hl_encoder_new(pool, NULL, &enc), 0);
	publish(pool, 3);
	assert_int_equal(hl_encoder_get(enc, HL_IMAGE_PNG, 1, WAIT_MS, &img), 0);
	hl_encoder_stop(enc);
	assert_int_equal(hl_encoder_get(enc, HL_IMAGE_PNG, 1, WAIT_MS, &img), -ESHUTDOWN);
	hl_encoder_release(img); /* held across the stop: still valid */
	hl_encoder_free(enc);
	hl_encoder_free(NULL);
	hl_frame_pool_free(pool);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(encoder_encodes_each_frame_once_for_every_request),
		cmocka_unit_test(encoder_rejects_frames_not_published),
		cmocka_unit_test(encoder_bounds_the_bytes_slow_clients_hold),
		cmocka_unit_test(encoder_stop_answers_every_request),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
