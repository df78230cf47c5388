/* SPDX-License-Identifier: MIT */
#include "daemon/out/encoder.h"

#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include <turbojpeg.h>

#include "render/pixel.h"
#include "render/plot.h"

#include "base/sched.h"

struct hl_encoder {
	struct hl_frame_pool *pool;
	const struct hl_frame_exr_info *exr_info;
	pthread_t thread;
	bool started, subscribed;
	atomic_uint_fast64_t newest; /* the newest published seq, set on the renderer's thread */
	tjhandle tj;
	/* the frame's copy, made at start at the pool's shape */
	int width, height;
	enum hl_pixel_format format;
	uint8_t *pixels; /* the frame's pixels as published */
	uint8_t *rgb; /* display RGB8, tightly packed */
	float *lux;

	pthread_mutex_t lock; /* guards what follows */
	pthread_cond_t work; /* a request wants an encode, or stop */
	pthread_cond_t done; /* an image (or a failure) was installed, or stop */
	bool stopping;
	struct hl_image *cur[HL_IMAGE_KINDS]; /* the newest image of each kind */
	uint64_t want[HL_IMAGE_KINDS]; /* the newest seq a request waits for */
	uint64_t failed_seq[HL_IMAGE_KINDS]; /* the newest seq whose encode failed */
	int waiting[HL_IMAGE_KINDS];
	size_t stale_bytes; /* of images a newer one replaced, still being sent */
	struct hl_encoder_counts c;
};

/* RGBA16F luminance (cd/m^2) to display RGB8 as the display view does at exposure 0. */
static void tone_map(const struct hl_encoder *e)
{
	const size_t n = (size_t)e->width * e->height;
	const uint16_t *px = (const uint16_t *)e->pixels;

	for (size_t i = 0; i < n; i++)
		for (int c = 0; c < 3; c++)
			e->rgb[i * 3 + c] =
				hl_pixel_display8(hl_pixel_half_to_float(px[4 * i + c]));
}

static void image_free(struct hl_image *img)
{
	if (!img)
		return;
	img->free_data((void *)img->data);
	free(img);
}

static void jpeg_free(void *p)
{
	tjFree(p);
}

/* Encodes one kind from the copy: the image, or NULL on failure. */
static struct hl_image *encode(struct hl_encoder *e, enum hl_image_kind kind, uint64_t seq)
{
	struct hl_image *img = calloc(1, sizeof(*img));
	const uint8_t *rgb = e->format == HL_PIXEL_RGB8 ? e->pixels : e->rgb;
	uint8_t *data = NULL;
	size_t len = 0;
	int rc = -EIO;

	if (!img)
		return NULL;
	/* one reference: the encoder's, while it is the newest of its kind */
	*img = (struct hl_image){
		.seq = seq, .kind = kind, .refs = 1, .free_data = free, .owner = e
	};
	if (kind == HL_IMAGE_JPEG) {
		unsigned long jlen = 0;

		rc = tjCompress2(e->tj, rgb, e->width, e->width * 3, e->height, TJPF_RGB, &data,
				 &jlen, TJSAMP_420, HL_ENCODER_JPEG_QUALITY, TJFLAG_FASTDCT) == 0 ?
			     0 :
			     -EIO;
		len = jlen;
		img->free_data = jpeg_free;
		if (rc < 0)
			tjFree(data);
	} else if (kind == HL_IMAGE_PNG) {
		rc = hl_png_encode_rgb(rgb, e->width, e->height, (size_t)e->width * 3, &data, &len);
	} else {
		struct hl_lid_error err;

		rc = hl_frame_exr_encode_lux(e->width, e->height, e->lux, e->exr_info, &data, &len,
					     &err);
	}
	if (rc < 0) {
		free(img);
		return NULL;
	}
	img->data = data;
	img->len = len;
	return img;
}

/* The kinds a request waits for that are not encoded yet (caller holds the lock). */
static unsigned pending(const struct hl_encoder *e)
{
	unsigned mask = 0;

	for (int k = 0; k < HL_IMAGE_KINDS; k++) {
		const uint64_t have = e->cur[k] ? e->cur[k]->seq : 0;

		if (e->want[k] > have && e->want[k] > e->failed_seq[k])
			mask |= 1u << k;
	}
	return mask;
}

/* Copies what the kinds in mask need out of the newest frame and releases it: its seq, or 0. */
static uint64_t copy_newest(struct hl_encoder *e, unsigned mask)
{
	struct hl_frame *f = hl_frame_pool_get(e->pool, 0, 0);
	uint64_t seq;

	if (!f)
		return 0;
	seq = f->hdr.seq;
	if (mask & ((1u << HL_IMAGE_JPEG) | (1u << HL_IMAGE_PNG)))
		memcpy(e->pixels, f->pixels, f->hdr.payload_size);
	if (mask & (1u << HL_IMAGE_EXR))
		memcpy(e->lux, f->lux, (size_t)e->width * e->height * sizeof(float));
	hl_frame_pool_release(e->pool, f);
	return seq;
}

/* SCHED_OTHER at nice HL_ENCODER_NICE (lowering one's priority needs no privilege). */
static void lower_priority(void)
{
	const struct sched_param sp = { .sched_priority = 0 };
	const id_t tid = (id_t)gettid();

	pthread_setschedparam(pthread_self(), SCHED_OTHER, &sp);
	errno = 0;
	if (getpriority(PRIO_PROCESS, tid) < HL_ENCODER_NICE)
		setpriority(PRIO_PROCESS, tid, HL_ENCODER_NICE);
}

static void *run(void *arg)
{
	struct hl_encoder *e = arg;

	lower_priority();
	pthread_mutex_lock(&e->lock);
	for (;;) {
		struct hl_image *img[HL_IMAGE_KINDS] = { NULL }, *old[HL_IMAGE_KINDS] = { NULL };
		unsigned mask;
		uint64_t seq;

		while (!e->stopping && !(mask = pending(e)))
			pthread_cond_wait(&e->work, &e->lock);
		if (e->stopping)
			break;
		pthread_mutex_unlock(&e->lock);
		seq = copy_newest(e, mask);
		if (seq && (mask & ((1u << HL_IMAGE_JPEG) | (1u << HL_IMAGE_PNG))) &&
		    e->format == HL_PIXEL_RGBA16F)
			tone_map(e);
		for (int k = 0; seq && k < HL_IMAGE_KINDS; k++)
			if (mask & (1u << k))
				img[k] = encode(e, (enum hl_image_kind)k, seq);
		pthread_mutex_lock(&e->lock);
		for (int k = 0; k < HL_IMAGE_KINDS; k++) {
			if (!(mask & (1u << k)))
				continue;
			if (!img[k]) {
				/* no frame (cannot be: a request saw it published) or a failure */
				e->failed_seq[k] = seq ? seq : e->want[k];
				e->c.failed++;
				continue;
			}
			e->c.encoded[k]++;
			old[k] = e->cur[k];
			e->cur[k] = img[k];
			if (old[k] && --old[k]->refs > 0) {
				e->stale_bytes += old[k]->len;
				old[k] = NULL; /* still sent: its last release frees it */
			}
		}
		pthread_cond_broadcast(&e->done);
		pthread_mutex_unlock(&e->lock);
		for (int k = 0; k < HL_IMAGE_KINDS; k++)
			image_free(old[k]);
		pthread_mutex_lock(&e->lock);
	}
	pthread_mutex_unlock(&e->lock);
	return NULL;
}

/* On the renderer's thread, with the pool's lock held: one store, nothing that could block. */
static void published(void *userdata, const struct hl_frame *f)
{
	struct hl_encoder *e = userdata;

	atomic_store_explicit(&e->newest, f->hdr.seq, memory_order_release);
}

uint64_t hl_encoder_newest(struct hl_encoder *e)
{
	return atomic_load_explicit(&e->newest, memory_order_acquire);
}

int hl_encoder_new(struct hl_frame_pool *pool, const struct hl_frame_exr_info *exr_info,
		   struct hl_encoder **ret)
{
	const struct hl_frame_shape *s = hl_frame_pool_shape(pool);
	const size_t n = (size_t)s->width * s->height;
	struct hl_encoder *e = calloc(1, sizeof(*e));
	int rc;

	if (!e)
		return -ENOMEM;
	e->pool = pool;
	e->exr_info = exr_info;
	e->width = s->width;
	e->height = s->height;
	e->format = s->format;
	rc = hl_mutex_init_pi(&e->lock);
	if (rc < 0) {
		free(e);
		return rc;
	}
	pthread_cond_init(&e->work, NULL);
	pthread_cond_init(&e->done, NULL);
	e->tj = tjInitCompress();
	e->pixels = malloc(n * (s->format == HL_PIXEL_RGBA16F ? 8 : 3));
	e->rgb = malloc(n * 3);
	e->lux = malloc(n * sizeof(float));
	if (!e->tj || !e->pixels || !e->rgb || !e->lux) {
		hl_encoder_free(e);
		return -ENOMEM;
	}
	rc = hl_frame_pool_subscribe(pool, published, e);
	e->subscribed = rc == 0;
	if (rc == 0) {
		struct hl_frame *f = hl_frame_pool_get(pool, 0, 0); /* one published before */

		if (f)
			atomic_store(&e->newest, f->hdr.seq);
		hl_frame_pool_release(pool, f);
		rc = -pthread_create(&e->thread, NULL, run, e);
	}
	if (rc < 0) {
		hl_encoder_free(e);
		return rc;
	}
	e->started = true;
	*ret = e;
	return 0;
}

void hl_encoder_stop(struct hl_encoder *e)
{
	pthread_mutex_lock(&e->lock);
	e->stopping = true;
	pthread_cond_broadcast(&e->work);
	pthread_cond_broadcast(&e->done);
	pthread_mutex_unlock(&e->lock);
	if (e->started)
		pthread_join(e->thread, NULL);
	e->started = false;
}

void hl_encoder_free(struct hl_encoder *e)
{
	if (!e)
		return;
	hl_encoder_stop(e);
	if (e->subscribed)
		hl_frame_pool_unsubscribe(e->pool, published, e);
	for (int k = 0; k < HL_IMAGE_KINDS; k++)
		image_free(e->cur[k]);
	if (e->tj)
		tjDestroy(e->tj);
	free(e->pixels);
	free(e->rgb);
	free(e->lux);
	pthread_cond_destroy(&e->done);
	pthread_cond_destroy(&e->work);
	pthread_mutex_destroy(&e->lock);
	free(e);
}

static void deadline(int timeout_ms, struct timespec *ret)
{
	clock_gettime(CLOCK_REALTIME, ret);
	ret->tv_sec += timeout_ms / 1000;
	ret->tv_nsec += (long)(timeout_ms % 1000) * 1000000;
	if (ret->tv_nsec >= 1000000000) {
		ret->tv_sec++;
		ret->tv_nsec -= 1000000000;
	}
}

int hl_encoder_get(struct hl_encoder *e, enum hl_image_kind kind, uint64_t want_seq, int timeout_ms,
		   struct hl_image **ret)
{
	struct timespec until;
	bool waits = false;
	int rc = 0;

	/* nothing newer to encode would ever come for it: the encoder would spin */
	if (want_seq < 1 || want_seq > hl_encoder_newest(e) || kind >= HL_IMAGE_KINDS)
		return -EINVAL;
	deadline(timeout_ms, &until);
	pthread_mutex_lock(&e->lock);
	for (;;) {
		struct hl_image *img = e->cur[kind];

		if (e->stopping) {
			rc = -ESHUTDOWN;
			break;
		}
		if (img && img->seq >= want_seq) {
			img->refs++;
			*ret = img;
			break;
		}
		if (e->failed_seq[kind] >= want_seq) {
			rc = -EIO;
			break;
		}
		if (!waits) {
			/* slow clients holding old images: no new one until they let go */
			if (e->waiting[kind] >= HL_ENCODER_MAX_WAITING ||
			    e->stale_bytes > HL_ENCODER_MAX_STALE_BYTES) {
				e->c.busy++;
				rc = -EBUSY;
				break;
			}
			e->waiting[kind]++;
			waits = true;
		}
		if (e->want[kind] < want_seq) {
			e->want[kind] = want_seq;
			pthread_cond_signal(&e->work);
		}
		if (pthread_cond_timedwait(&e->done, &e->lock, &until) == ETIMEDOUT) {
			img = e->cur[kind];
			if (img && img->seq >= want_seq)
				continue; /* it came at the last moment */
			e->c.timeouts++;
			rc = -ETIMEDOUT;
			break;
		}
	}
	if (waits)
		e->waiting[kind]--;
	pthread_mutex_unlock(&e->lock);
	return rc;
}

void hl_encoder_release(struct hl_image *img)
{
	struct hl_encoder *e;
	bool last;

	if (!img)
		return;
	e = img->owner;
	pthread_mutex_lock(&e->lock);
	last = --img->refs == 0;
	if (last)
		e->stale_bytes -= img->len; /* the newest is never freed here: it holds a ref */
	pthread_mutex_unlock(&e->lock);
	if (last)
		image_free(img);
}

void hl_encoder_counts(struct hl_encoder *e, struct hl_encoder_counts *ret)
{
	pthread_mutex_lock(&e->lock);
	*ret = e->c;
	pthread_mutex_unlock(&e->lock);
}
