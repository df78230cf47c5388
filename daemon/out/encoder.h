/* SPDX-License-Identifier: MIT */
/*
 * The images the HTTP server sends (JPEG for the MJPEG stream, PNG, EXR), encoded off the render
 * path on one thread of the encoder's own (docs/outputs.md, "HTTP live view").
 *
 * A request asks for an image kind of a frame at least as new as want_seq (the newest published
 * when it came). The encoder encodes each kind at most once per published frame, however many
 * requests want it, and only when one does: it takes the newest frame from the pool, copies the
 * pixels or lux values it needs, releases the frame, and encodes the copy. Every request for that
 * frame shares the encoded bytes (struct hl_image, reference counted); an image is freed when a
 * newer one of its kind replaced it and the last request sending it released it.
 *
 * The thread runs at SCHED_OTHER, nice HL_ENCODER_NICE, whatever the daemon's policy (systemd
 * starts hdlampd at SCHED_FIFO): a busy encoder slows the images, never the renderer.
 *
 * Thread-safety: hl_encoder_get, hl_encoder_release, hl_encoder_counts from any thread, several
 * at once; new, stop and free from one thread. The pool must outlive the encoder.
 */
#ifndef HL_DAEMON_OUT_ENCODER_H
#define HL_DAEMON_OUT_ENCODER_H

#include <stddef.h>
#include <stdint.h>

#include "daemon/core/frame_pool.h"
#include "render/frame_exr.h"

#define HL_ENCODER_NICE 10 /* the encoder thread's nice value */
#define HL_ENCODER_MAX_WAITING 16 /* requests waiting for an encode of one kind, at most */
/* bytes of replaced images that slow clients still hold; beyond it no new image is encoded */
#define HL_ENCODER_MAX_STALE_BYTES (64u << 20)
#define HL_ENCODER_JPEG_QUALITY 85

enum hl_image_kind {
	HL_IMAGE_JPEG, /* display RGB, 4:2:0 */
	HL_IMAGE_PNG, /* display RGB, 8 bit */
	HL_IMAGE_EXR, /* the lux image: one FLOAT channel "E" */
	HL_IMAGE_KINDS
};

struct hl_encoder;

/* An encoded image; read only, valid until released. */
struct hl_image {
	const uint8_t *data;
	size_t len;
	uint64_t seq; /* the frame's hdr.seq */
	enum hl_image_kind kind;
	int refs; /* private: the requests sending it, +1 while it is the newest */
	void (*free_data)(void *); /* private */
	struct hl_encoder *owner; /* private */
};

struct hl_encoder_counts {
	uint64_t encoded[HL_IMAGE_KINDS]; /* images encoded, by kind */
	uint64_t failed; /* encodes that failed (the requests are answered 500) */
	/* requests refused: HL_ENCODER_MAX_WAITING already waited for that kind, or slow clients
	 * held more than HL_ENCODER_MAX_STALE_BYTES of replaced images */
	uint64_t busy;
	uint64_t timeouts; /* requests whose image did not come within their timeout */
};

/*
 * Starts the thread and subscribes to the pool (one of HL_FRAME_POOL_MAX_SUBSCRIBERS).
 * exr_info: attributes of the EXR (NULL: unit only), must outlive. 0, -ENOSPC, -ENOMEM, -errno.
 */
int hl_encoder_new(struct hl_frame_pool *pool, const struct hl_frame_exr_info *exr_info,
		   struct hl_encoder **ret);
/* Wakes every waiting request (-ESHUTDOWN) and ends the thread; later gets fail at once. */
void hl_encoder_stop(struct hl_encoder *enc);
/* Stops it; the images still held must have been released. NULL is fine. */
void hl_encoder_free(struct hl_encoder *enc);

/*
 * The image of kind of a frame with seq >= want_seq (1 <= want_seq <= hl_encoder_newest, else
 * -EINVAL: a frame seen in the pool is always <= it), waiting
 * up to timeout_ms for its encode: 0 and a reference in *ret; -EBUSY (too many waiting, or too
 * many bytes of replaced images still held), -ETIMEDOUT,
 * -EIO (the encode failed), -ESHUTDOWN. Each refusal and timeout is counted.
 */
int hl_encoder_get(struct hl_encoder *enc, enum hl_image_kind kind, uint64_t want_seq,
		   int timeout_ms, struct hl_image **ret);
/*
 * The newest published frame's seq (0: none yet), without the pool's lock: the encoder learns
 * of each publish from the pool (a subscriber), so requests never contend with the renderer.
 */
uint64_t hl_encoder_newest(struct hl_encoder *enc);
/* Gives back a reference from hl_encoder_get, from any thread. NULL is fine. */
void hl_encoder_release(struct hl_image *img);

void hl_encoder_counts(struct hl_encoder *enc, struct hl_encoder_counts *ret);

#endif
