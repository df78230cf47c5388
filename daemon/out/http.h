/* SPDX-License-Identifier: MIT */
/*
 * The HTTP live view (libmicrohttpd): a page, an MJPEG stream and stills of the newest frame,
 * the daemon's status and metrics, and captures on request (docs/outputs.md, "HTTP live view").
 *
 *   GET /             the live page (HTML and JS built into the binary)
 *   GET /stream.mjpg  multipart/x-mixed-replace, one JPEG part per new published frame
 *   GET /frame.png    the newest frame's pixels
 *   GET /frame.exr    the newest frame's lux image: one FLOAT channel "E", lux
 *   GET /status       application/json from sources->status_json
 *   GET /metrics      Prometheus text (version 0.0.4) from sources->metrics
 *   GET /glare.json   application/json from sources->glare_json (404 without a scenario)
 *   POST /capture     sources->capture, only when allowed (else 403)
 * HEAD works wherever GET does; another method is 405 (with Allow), another path 404, and a
 * frame route before the first published frame 503.
 *
 * RGBA16F frames (the hdr view, linear cd/m^2) are tone-mapped for JPEG and PNG the way the
 * display view is at exposure 0: L / pi through x / (1 + x), then the sRGB curve.
 *
 * Images are encoded on the encoder's thread (daemon/out/encoder.h), once per published frame and
 * kind for any number of requests, which share the bytes; a request that would wait behind
 * HL_ENCODER_MAX_WAITING others, or longer than HL_HTTP_ENCODE_WAIT_MS, is answered 503 with
 * Retry-After (counted). No server thread encodes, holds a frame while it sends, or runs at the
 * daemon's real-time priority: they run at SCHED_OTHER, nice HL_HTTP_NICE.
 *
 * Each connection has its own thread. A stream client gets the newest frame's JPEG whenever it
 * has taken the previous one: a slow client skips frames (counted) and holds one shared JPEG;
 * it never delays the renderer or another client. Limits, each refusal counted: at most
 * HL_HTTP_MAX_CONNECTIONS connections, HL_HTTP_MAX_PER_ADDRESS from one address,
 * HL_HTTP_MAX_STREAMS streams; a connection whose request (headers and any body) is not
 * complete HL_HTTP_HEADER_TIMEOUT_S after it opened (or after its previous answer) is closed
 * when the next connection is accepted; one that takes nothing for HL_HTTP_IDLE_TIMEOUT_S is closed by
 * libmicrohttpd. Closing the pool (hl_frame_pool_close) ends every stream.
 *
 * Thread-safety: hl_http_new, hl_http_start, hl_http_free from one thread; hl_http_counts,
 * hl_http_port and hl_http_loopback from any. The source callbacks are called from the server's
 * threads, several at once.
 */
#ifndef HL_DAEMON_OUT_HTTP_H
#define HL_DAEMON_OUT_HTTP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/socket.h>

#include "daemon/out/encoder.h"
#include "daemon/core/frame_pool.h"
#include "render/frame_exr.h"

#define HL_HTTP_MAX_CONNECTIONS 512 /* connections at once, streams included */
/* from one address: above what a local slowloris of 200 takes, so that /status still gets in */
#define HL_HTTP_MAX_PER_ADDRESS 256
#define HL_HTTP_MAX_STREAMS 16 /* MJPEG streams at once (<= HL_ENCODER_MAX_WAITING) */
#define HL_HTTP_HEADER_TIMEOUT_S 10 /* to send a whole request: headers and any body */
#define HL_HTTP_IDLE_TIMEOUT_S 30 /* a connection that takes nothing for this long is closed */
#define HL_HTTP_ENCODE_WAIT_MS 2000 /* longest a request waits for its image */
#define HL_HTTP_NICE 19 /* the server threads' nice value */
#define HL_HTTP_JPEG_QUALITY HL_ENCODER_JPEG_QUALITY

_Static_assert(HL_HTTP_MAX_STREAMS <= HL_ENCODER_MAX_WAITING, "a stream never waits in vain");

struct hl_http_sources {
	struct hl_frame_pool *pool; /* frames to serve; must outlive the server */
	/* Attributes of /frame.exr (camera, lamp poses); NULL: unit only. Must outlive. */
	const struct hl_frame_exr_info *exr_info;
	void *userdata;
	/*
	 * Fill buf with the daemon's JSON status / Prometheus metrics text: return the length,
	 * -ENOBUFS when size is too small (the server retries with more, up to 4 MiB), or another
	 * -errno (answered 500). NULL: the route answers 404.
	 */
	int (*status_json)(void *userdata, char *buf, size_t size);
	int (*metrics)(void *userdata, char *buf, size_t size);
	int (*glare_json)(void *userdata, char *buf, size_t size); /* the same; NULL: 404 */
	/*
	 * Write a capture now: 0 and the directory or file written, NUL-terminated, in path; or
	 * -errno and why in path (answered as {"error": path}): -EBUSY, -EAGAIN, -ESHUTDOWN 503;
	 * -ETIMEDOUT 504; -ENOSPC, -EDQUOT, -EFBIG 507; others 500. NULL: captures are off (403).
	 */
	int (*capture)(void *userdata, char *path, size_t size);
};

struct hl_http_counts {
	uint64_t requests; /* answered, any status */
	uint64_t errors; /* answered 4xx or 5xx */
	/* answered 503 with Retry-After: an image's waiters or wait, or the streams, at their limit */
	uint64_t overloaded;
	uint64_t connections; /* open now */
	uint64_t connections_refused; /* closed at once: a connection limit was reached */
	uint64_t header_timeouts; /* closed: no whole request within HL_HTTP_HEADER_TIMEOUT_S */
	uint64_t encoded[HL_IMAGE_KINDS]; /* images encoded, by kind */
	uint64_t encode_failures;
	uint64_t mjpeg_clients; /* streams open now */
	uint64_t mjpeg_frames_sent; /* JPEG parts sent, all streams */
	uint64_t mjpeg_frames_skipped; /* published frames a stream did not get: it was slower */
};

struct hl_http;

/*
 * A server for listen, "HOST:PORT": HOST an IPv4 address, [IPv6] or localhost (to listen on
 * every interface, say 0.0.0.0 or [::]); PORT 0 takes a free port (hl_http_port). Starts the
 * encoder thread, does not listen yet. allow_capture enables POST /capture (it also needs
 * src->capture). src is copied. 0, -EINVAL (bad listen or src), -ENOMEM, -errno.
 */
int hl_http_new(const char *listen, bool allow_capture, const struct hl_http_sources *src,
		struct hl_http **ret);
/* Listens and serves. 0, -EADDRINUSE / -EACCES / -EIO (cannot listen), -ENOMEM. */
int hl_http_start(struct hl_http *h);
/*
 * Stops the server: no new connection, requests waiting for an image answered 503, streams
 * end within ~0.2 s, every connection is closed. The counters stay readable. Once is enough.
 */
void hl_http_stop(struct hl_http *h);
/* Stops it and frees it. NULL is fine. */
void hl_http_free(struct hl_http *h);

/* The TCP port listened on (after hl_http_start). */
uint16_t hl_http_port(const struct hl_http *h);
/* Whether the listen address is a loopback one: the daemon warns when it is not. */
bool hl_http_loopback(const struct hl_http *h);
void hl_http_counts(struct hl_http *h, struct hl_http_counts *ret);

#endif
