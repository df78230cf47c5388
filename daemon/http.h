/* SPDX-License-Identifier: MIT */
/*
 * The HTTP live view (libmicrohttpd): a page, an MJPEG stream and stills of the newest frame,
 * the daemon's status and metrics, and captures on request (docs/daemon.md, "HTTP live view").
 *
 *   GET /             the live page (HTML and JS built into the binary)
 *   GET /stream.mjpg  multipart/x-mixed-replace, one JPEG part per new published frame
 *   GET /frame.png    the newest frame's pixels
 *   GET /frame.exr    the newest frame's lux image: one FLOAT channel "E", lux
 *   GET /status       application/json from sources->status_json
 *   GET /metrics      Prometheus text (version 0.0.4) from sources->metrics
 *   POST /capture     sources->capture, only when allowed (else 403)
 * HEAD works wherever GET does; another method is 405 (with Allow), another path 404, and a
 * frame route before the first published frame 503.
 *
 * RGBA16F frames (the hdr view, linear cd/m^2) are tone-mapped for JPEG and PNG the way the
 * display view is at exposure 0: L / pi through x / (1 + x), then the sRGB curve.
 *
 * Each connection has its own thread. A stream client gets the newest frame whenever it has
 * taken the previous one: a slow client skips frames (counted), holds a frame only while it
 * is encoded, and keeps one preallocated JPEG buffer; it never delays the renderer or another
 * client. A client that takes nothing for HL_HTTP_IDLE_TIMEOUT_S is disconnected; closing the
 * pool (hl_frame_pool_close) ends every stream.
 *
 * Thread-safety: hl_http_new/hl_http_free from one thread; hl_http_counts and hl_http_port
 * from any. The source callbacks are called from the server's threads, several at once.
 */
#ifndef HL_DAEMON_HTTP_H
#define HL_DAEMON_HTTP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/socket.h>

#include "daemon/frame_pool.h"
#include "render/frame_exr.h"

#define HL_HTTP_MAX_CLIENTS 64 /* connections at once, streams included */
#define HL_HTTP_IDLE_TIMEOUT_S 30 /* a connection that takes nothing for this long is closed */
#define HL_HTTP_JPEG_QUALITY 85

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
	uint64_t mjpeg_clients; /* streams open now */
	uint64_t mjpeg_frames_sent; /* JPEG parts sent, all streams */
	uint64_t mjpeg_frames_skipped; /* published frames a stream did not get: it was slower */
};

struct hl_http;

/*
 * Starts the server on listen, "HOST:PORT": HOST an IPv4 address, [IPv6] or localhost (to
 * listen on every interface, say 0.0.0.0 or [::]); PORT 0 takes a free port (hl_http_port).
 * allow_capture enables POST /capture (it also needs src->capture). src is copied.
 * 0, -EINVAL (bad listen or src), -EADDRINUSE / -EACCES / -EIO (cannot listen), -ENOMEM.
 */
int hl_http_new(const char *listen, bool allow_capture, const struct hl_http_sources *src,
		struct hl_http **ret);
/* Stops the server: streams end within ~0.2 s, every connection is closed. NULL is fine. */
void hl_http_free(struct hl_http *h);

/* The TCP port listened on. */
uint16_t hl_http_port(const struct hl_http *h);
void hl_http_counts(struct hl_http *h, struct hl_http_counts *ret);

/*
 * Parses "HOST:PORT" as hl_http_new does. 0 or -EINVAL. ret_loopback: the address is a
 * loopback one (127.0.0.0/8, ::1); the daemon may warn when it is not.
 */
int hl_http_parse_listen(const char *listen, struct sockaddr_storage *ret_addr, bool *ret_loopback);

#endif
