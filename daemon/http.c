/* SPDX-License-Identifier: MIT */
#include "daemon/http.h"

#include <arpa/inet.h>
#include <errno.h>
#include <math.h>
#include <netdb.h>
#include <netinet/in.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <microhttpd.h>
#include <turbojpeg.h>

#include "daemon/live_html.h"
#include "render/pixel.h"
#include "render/plot.h"

#define BOUNDARY "hlframe"
#define STREAM_WAIT_MS 200 /* a stream checks for shutdown this often while it waits */
#define STREAM_BLOCK 65536 /* bytes MHD asks a stream for at most per call */
#define BODY_START 65536 /* first buffer for /status and /metrics */
#define BODY_MAX (4 << 20) /* and the most they may take */
#define CAPTURE_PATH_MAX 4096

struct hl_http {
	struct MHD_Daemon *mhd;
	struct hl_http_sources src;
	bool allow_capture;
	uint16_t port;
	atomic_bool stopping;
	atomic_uint_fast64_t requests, errors, clients, sent, skipped;
};

/* One MJPEG client: its buffers are made when the stream starts, then only refilled. */
struct stream {
	struct hl_http *h;
	tjhandle tj;
	uint8_t *jpeg; /* tjBufSize bytes */
	unsigned long jpeg_cap, jpeg_len;
	uint8_t *rgb; /* tone-mapped pixels of RGBA16F frames; NULL for RGB8 */
	char head[160]; /* part headers */
	size_t head_len;
	size_t off; /* bytes of the current part sent: head, then jpeg, then tail */
	bool started, have_part;
	uint64_t last_seq;
};

static const char part_tail[] = "\r\n--" BOUNDARY "\r\n";

int hl_http_parse_listen(const char *listen, struct sockaddr_storage *ret_addr, bool *ret_loopback)
{
	struct addrinfo hints = { .ai_socktype = SOCK_STREAM, .ai_flags = AI_NUMERICSERV };
	struct addrinfo *ai = NULL;
	char host[256], *end;
	const char *colon, *port;
	size_t n;
	long p;
	bool loop;

	if (!listen)
		return -EINVAL;
	colon = strrchr(listen, ':');
	if (!colon || colon == listen)
		return -EINVAL;
	port = colon + 1;
	errno = 0;
	p = strtol(port, &end, 10);
	if (!*port || *end || errno || p < 0 || p > 65535 || *port == '-' || *port == '+')
		return -EINVAL;
	n = (size_t)(colon - listen);
	if (listen[0] == '[') {
		if (n < 3 || listen[n - 1] != ']')
			return -EINVAL;
		memcpy(host, listen + 1, n - 2);
		host[n - 2] = '\0';
		hints.ai_family = AF_INET6;
		hints.ai_flags |= AI_NUMERICHOST;
	} else {
		if (n >= sizeof(host) || memchr(listen, ':', n))
			return -EINVAL;
		memcpy(host, listen, n);
		host[n] = '\0';
		/* Only localhost is looked up: any other name must be a literal address. */
		hints.ai_family = strcmp(host, "localhost") == 0 ? AF_INET : AF_UNSPEC;
		if (strcmp(host, "localhost") != 0)
			hints.ai_flags |= AI_NUMERICHOST;
	}
	if (getaddrinfo(host, port, &hints, &ai) != 0 || !ai)
		return -EINVAL;
	if (ai->ai_addrlen > sizeof(*ret_addr)) {
		freeaddrinfo(ai);
		return -EINVAL;
	}
	if (ai->ai_family == AF_INET) {
		const struct sockaddr_in *in = (const struct sockaddr_in *)ai->ai_addr;

		loop = (ntohl(in->sin_addr.s_addr) >> 24) == 127;
	} else {
		const struct sockaddr_in6 *in6 = (const struct sockaddr_in6 *)ai->ai_addr;

		loop = IN6_IS_ADDR_LOOPBACK(&in6->sin6_addr);
	}
	memset(ret_addr, 0, sizeof(*ret_addr));
	memcpy(ret_addr, ai->ai_addr, ai->ai_addrlen);
	freeaddrinfo(ai);
	if (ret_loopback)
		*ret_loopback = loop;
	return 0;
}

/* --- pixels --- */

/* RGBA16F luminance (cd/m^2) to display RGB8 as the display view does at exposure 0. */
static void tone_map(const struct hl_frame *f, uint8_t *rgb)
{
	const uint32_t w = f->hdr.width, hgt = f->hdr.height;

	for (uint32_t y = 0; y < hgt; y++) {
		const uint16_t *row = (const uint16_t *)(f->pixels + (size_t)y * f->hdr.stride);

		for (uint32_t x = 0; x < w; x++) {
			for (int c = 0; c < 3; c++)
				rgb[((size_t)y * w + x) * 3 + c] =
					hl_pixel_display8(hl_pixel_half_to_float(row[4 * x + c]));
		}
	}
}

/* The frame's pixels as RGB8 rows: its own, or tone-mapped into scratch. */
static const uint8_t *frame_rgb(const struct hl_frame *f, uint8_t *scratch, size_t *ret_stride)
{
	if (f->hdr.pixel_format == HL_PIXEL_RGB8) {
		*ret_stride = f->hdr.stride;
		return f->pixels;
	}
	tone_map(f, scratch);
	*ret_stride = (size_t)f->hdr.width * 3;
	return scratch;
}

/* --- responses --- */

static enum MHD_Result respond(struct hl_http *h, struct MHD_Connection *c, unsigned int status,
			       const char *type, void *body, size_t len,
			       enum MHD_ResponseMemoryMode mode)
{
	struct MHD_Response *r = MHD_create_response_from_buffer(len, body, mode);
	enum MHD_Result ret;

	if (!r) {
		if (mode == MHD_RESPMEM_MUST_FREE)
			free(body);
		return MHD_NO;
	}
	MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, type);
	MHD_add_response_header(r, MHD_HTTP_HEADER_CACHE_CONTROL, "no-store");
	ret = MHD_queue_response(c, status, r);
	MHD_destroy_response(r);
	atomic_fetch_add(&h->requests, 1);
	if (status >= 400)
		atomic_fetch_add(&h->errors, 1);
	return ret;
}

static enum MHD_Result respond_text(struct hl_http *h, struct MHD_Connection *c,
				    unsigned int status, const char *text)
{
	return respond(h, c, status, "text/plain; charset=utf-8", (void *)text, strlen(text),
		       MHD_RESPMEM_PERSISTENT);
}

/* JSON {"error": msg} with a copied message. */
static enum MHD_Result respond_error(struct hl_http *h, struct MHD_Connection *c,
				     unsigned int status, const char *msg)
{
	char *body = malloc(strlen(msg) + 16);

	if (!body)
		return MHD_NO;
	sprintf(body, "{\"error\":\"%s\"}\n", msg); /* callers pass plain ASCII without quotes */
	return respond(h, c, status, "application/json", body, strlen(body), MHD_RESPMEM_MUST_FREE);
}

static enum MHD_Result no_frame(struct hl_http *h, struct MHD_Connection *c)
{
	return respond_error(h, c, MHD_HTTP_SERVICE_UNAVAILABLE, "no frame published yet");
}

static enum MHD_Result get_page(struct hl_http *h, struct MHD_Connection *c)
{
	return respond(h, c, MHD_HTTP_OK, "text/html; charset=utf-8", (void *)hl_live_html,
		       hl_live_html_size, MHD_RESPMEM_PERSISTENT);
}

static enum MHD_Result respond_frame(struct hl_http *h, struct MHD_Connection *c,
				     const struct hl_frame *f, const char *type, uint8_t *body,
				     size_t len)
{
	struct MHD_Response *r = MHD_create_response_from_buffer(len, body, MHD_RESPMEM_MUST_FREE);
	enum MHD_Result ret;
	char seq[32];

	if (!r) {
		free(body);
		return MHD_NO;
	}
	snprintf(seq, sizeof(seq), "%llu", (unsigned long long)f->hdr.seq);
	MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, type);
	MHD_add_response_header(r, MHD_HTTP_HEADER_CACHE_CONTROL, "no-store");
	MHD_add_response_header(r, "X-Frame-Seq", seq);
	ret = MHD_queue_response(c, MHD_HTTP_OK, r);
	MHD_destroy_response(r);
	atomic_fetch_add(&h->requests, 1);
	return ret;
}

static enum MHD_Result get_png(struct hl_http *h, struct MHD_Connection *c)
{
	struct hl_frame *f = hl_frame_pool_get(h->src.pool, 0, 0);
	uint8_t *scratch = NULL, *png = NULL;
	const uint8_t *rgb;
	size_t stride, len = 0;
	enum MHD_Result ret;
	int rc;

	if (!f)
		return no_frame(h, c);
	if (f->hdr.pixel_format != HL_PIXEL_RGB8) {
		scratch = malloc((size_t)f->hdr.width * f->hdr.height * 3);
		if (!scratch) {
			hl_frame_pool_release(h->src.pool, f);
			return respond_error(h, c, MHD_HTTP_INTERNAL_SERVER_ERROR, "out of memory");
		}
	}
	rgb = frame_rgb(f, scratch, &stride);
	rc = hl_png_encode_rgb(rgb, (int)f->hdr.width, (int)f->hdr.height, stride, &png, &len);
	free(scratch);
	if (rc < 0) {
		hl_frame_pool_release(h->src.pool, f);
		return respond_error(h, c, MHD_HTTP_INTERNAL_SERVER_ERROR, "PNG encoding failed");
	}
	ret = respond_frame(h, c, f, "image/png", png, len);
	hl_frame_pool_release(h->src.pool, f);
	return ret;
}

static enum MHD_Result get_exr(struct hl_http *h, struct MHD_Connection *c)
{
	struct hl_frame *f = hl_frame_pool_get(h->src.pool, 0, 0);
	struct hl_lid_error err;
	uint8_t *exr = NULL;
	size_t len = 0;
	enum MHD_Result ret;
	int rc;

	if (!f)
		return no_frame(h, c);
	rc = hl_frame_exr_encode_lux((int)f->hdr.width, (int)f->hdr.height, f->lux, h->src.exr_info,
				     &exr, &len, &err);
	if (rc < 0) {
		hl_frame_pool_release(h->src.pool, f);
		return respond_error(h, c, MHD_HTTP_INTERNAL_SERVER_ERROR, "EXR encoding failed");
	}
	ret = respond_frame(h, c, f, "image/x-exr", exr, len);
	hl_frame_pool_release(h->src.pool, f);
	return ret;
}

/* /status and /metrics: the callback fills a buffer that grows while it says -ENOBUFS. */
static enum MHD_Result get_text(struct hl_http *h, struct MHD_Connection *c,
				int (*fill)(void *, char *, size_t), const char *type)
{
	size_t size = BODY_START;
	char *buf = NULL;
	int n;

	if (!fill)
		return respond_text(h, c, MHD_HTTP_NOT_FOUND, "not found\n");
	for (;;) {
		char *b = realloc(buf, size);

		if (!b) {
			free(buf);
			return respond_error(h, c, MHD_HTTP_INTERNAL_SERVER_ERROR, "out of memory");
		}
		buf = b;
		n = fill(h->src.userdata, buf, size);
		if (n != -ENOBUFS || size >= BODY_MAX)
			break;
		size *= 2;
	}
	if (n < 0 || (size_t)n > size) {
		free(buf);
		return respond_error(h, c, MHD_HTTP_INTERNAL_SERVER_ERROR,
				     n == -ENOBUFS ? "response too large" : "source failed");
	}
	return respond(h, c, MHD_HTTP_OK, type, buf, (size_t)n, MHD_RESPMEM_MUST_FREE);
}

static enum MHD_Result get_status(struct hl_http *h, struct MHD_Connection *c)
{
	return get_text(h, c, h->src.status_json, "application/json");
}

static enum MHD_Result get_metrics(struct hl_http *h, struct MHD_Connection *c)
{
	return get_text(h, c, h->src.metrics, "text/plain; version=0.0.4; charset=utf-8");
}

/* JSON string body of s into out (size >= 6 * strlen + 1 is always enough). */
static void json_escape(const char *s, char *out)
{
	for (; *s; s++) {
		const unsigned char ch = (unsigned char)*s;

		if (ch == '"' || ch == '\\') {
			*out++ = '\\';
			*out++ = (char)ch;
		} else if (ch < 0x20) {
			out += sprintf(out, "\\u%04x", ch);
		} else {
			*out++ = (char)ch;
		}
	}
	*out = '\0';
}

static enum MHD_Result post_capture(struct hl_http *h, struct MHD_Connection *c)
{
	char path[CAPTURE_PATH_MAX] = "";
	unsigned int status = MHD_HTTP_OK;
	char *body;
	int rc;

	if (!h->allow_capture || !h->src.capture)
		return respond_error(h, c, MHD_HTTP_FORBIDDEN,
				     "captures are disabled (config: http.capture = false)");
	rc = h->src.capture(h->src.userdata, path, sizeof(path));
	path[sizeof(path) - 1] = '\0';
	if (rc == -EBUSY || rc == -EAGAIN || rc == -ESHUTDOWN)
		status = MHD_HTTP_SERVICE_UNAVAILABLE;
	else if (rc == -ETIMEDOUT)
		status = MHD_HTTP_GATEWAY_TIMEOUT;
	else if (rc == -ENOSPC || rc == -EDQUOT || rc == -EFBIG)
		status = MHD_HTTP_INSUFFICIENT_STORAGE;
	else if (rc < 0)
		status = MHD_HTTP_INTERNAL_SERVER_ERROR;
	/* {"path": the directory} or {"error": why, naming the file}; path is the callback's text */
	body = malloc(strlen(path) * 6 + 16);
	if (!body)
		return respond_error(h, c, MHD_HTTP_INTERNAL_SERVER_ERROR, "out of memory");
	strcpy(body, rc < 0 ? "{\"error\":\"" : "{\"path\":\"");
	json_escape(path, body + strlen(body));
	strcat(body, "\"}\n");
	return respond(h, c, status, "application/json", body, strlen(body), MHD_RESPMEM_MUST_FREE);
}

/* --- the MJPEG stream --- */

static void stream_free(void *cls)
{
	struct stream *s = cls;

	atomic_fetch_sub(&s->h->clients, 1);
	if (s->tj)
		tjDestroy(s->tj);
	tjFree(s->jpeg);
	free(s->rgb);
	free(s);
}

/* Waits for a frame newer than the last one sent and encodes it as the next part. */
static int next_part(struct stream *s)
{
	struct hl_http *h = s->h;
	struct hl_frame *f = NULL;
	const uint8_t *rgb;
	size_t stride;
	int rc;

	while (!f) {
		struct timespec t0, t1;

		if (atomic_load(&h->stopping))
			return -ESHUTDOWN;
		clock_gettime(CLOCK_MONOTONIC, &t0);
		f = hl_frame_pool_get(h->src.pool, s->last_seq, STREAM_WAIT_MS);
		clock_gettime(CLOCK_MONOTONIC, &t1);
		/* Nothing, long before the timeout: the pool was closed, no frame will come. */
		if (!f && (t1.tv_sec - t0.tv_sec) * 1000 + (t1.tv_nsec - t0.tv_nsec) / 1000000 <
				  STREAM_WAIT_MS / 2)
			return -ESHUTDOWN;
	}
	rgb = frame_rgb(f, s->rgb, &stride);
	s->jpeg_len = s->jpeg_cap;
	rc = tjCompress2(s->tj, rgb, (int)f->hdr.width, (int)stride, (int)f->hdr.height, TJPF_RGB,
			 &s->jpeg, &s->jpeg_len, TJSAMP_420, HL_HTTP_JPEG_QUALITY,
			 TJFLAG_NOREALLOC | TJFLAG_FASTDCT);
	if (s->last_seq && f->hdr.seq > s->last_seq + 1)
		atomic_fetch_add(&h->skipped, f->hdr.seq - s->last_seq - 1);
	s->last_seq = f->hdr.seq;
	hl_frame_pool_release(h->src.pool, f);
	if (rc != 0)
		return -EIO;
	s->head_len = (size_t)snprintf(s->head, sizeof(s->head),
				       "Content-Type: image/jpeg\r\nContent-Length: %lu\r\n"
				       "X-Frame-Seq: %llu\r\n\r\n",
				       s->jpeg_len, (unsigned long long)s->last_seq);
	s->off = 0;
	s->have_part = true;
	atomic_fetch_add(&h->sent, 1);
	return 0;
}

/* Copies what is left of [src, src + len) from position *pos of the part into buf. */
static size_t take(const void *src, size_t len, size_t start, size_t *pos, char *buf, size_t max)
{
	size_t n;

	if (*pos < start || *pos >= start + len)
		return 0;
	n = start + len - *pos;
	if (n > max)
		n = max;
	memcpy(buf, (const char *)src + (*pos - start), n);
	*pos += n;
	return n;
}

static ssize_t stream_read(void *cls, uint64_t pos, char *buf, size_t max)
{
	struct stream *s = cls;
	const size_t tail = sizeof(part_tail) - 1;
	size_t n = 0, part_len;

	(void)pos;
	if (!s->started) {
		static const char first[] = "--" BOUNDARY "\r\n";

		if (max < sizeof(first) - 1)
			return 0;
		s->started = true;
		memcpy(buf, first, sizeof(first) - 1);
		return (ssize_t)(sizeof(first) - 1);
	}
	part_len = s->head_len + s->jpeg_len + tail;
	if ((!s->have_part || s->off >= part_len) && next_part(s) < 0)
		return MHD_CONTENT_READER_END_OF_STREAM;
	n += take(s->head, s->head_len, 0, &s->off, buf + n, max - n);
	n += take(s->jpeg, s->jpeg_len, s->head_len, &s->off, buf + n, max - n);
	n += take(part_tail, tail, s->head_len + s->jpeg_len, &s->off, buf + n, max - n);
	return (ssize_t)n;
}

static enum MHD_Result get_stream(struct hl_http *h, struct MHD_Connection *c)
{
	const struct hl_frame_shape *shape = hl_frame_pool_shape(h->src.pool);
	struct MHD_Response *r;
	struct stream *s = calloc(1, sizeof(*s));
	enum MHD_Result ret;

	if (!s)
		return respond_error(h, c, MHD_HTTP_INTERNAL_SERVER_ERROR, "out of memory");
	s->h = h;
	atomic_fetch_add(&h->clients, 1);
	s->tj = tjInitCompress();
	s->jpeg_cap = tjBufSize(shape->width, shape->height, TJSAMP_420);
	s->jpeg = s->jpeg_cap != (unsigned long)-1 ? tjAlloc((int)s->jpeg_cap) : NULL;
	if (shape->format != HL_PIXEL_RGB8)
		s->rgb = malloc((size_t)shape->width * shape->height * 3);
	if (!s->tj || !s->jpeg || (shape->format != HL_PIXEL_RGB8 && !s->rgb)) {
		stream_free(s);
		return respond_error(h, c, MHD_HTTP_INTERNAL_SERVER_ERROR, "out of memory");
	}
	/* Each part ends with the next boundary, so a browser shows it as soon as it is sent. */
	r = MHD_create_response_from_callback(MHD_SIZE_UNKNOWN, STREAM_BLOCK, stream_read, s,
					      stream_free);
	if (!r) {
		stream_free(s);
		return MHD_NO;
	}
	MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE,
				"multipart/x-mixed-replace; boundary=" BOUNDARY);
	MHD_add_response_header(r, MHD_HTTP_HEADER_CACHE_CONTROL, "no-store");
	ret = MHD_queue_response(c, MHD_HTTP_OK, r);
	MHD_destroy_response(r);
	atomic_fetch_add(&h->requests, 1);
	return ret;
}

/* --- routing --- */

struct route {
	const char *path;
	bool post; /* POST only; else GET and HEAD */
	enum MHD_Result (*fn)(struct hl_http *h, struct MHD_Connection *c);
};

static const struct route routes[] = {
	{ "/", false, get_page },	    { "/stream.mjpg", false, get_stream },
	{ "/frame.png", false, get_png },   { "/frame.exr", false, get_exr },
	{ "/status", false, get_status },   { "/metrics", false, get_metrics },
	{ "/capture", true, post_capture },
};

static enum MHD_Result handle(void *cls, struct MHD_Connection *c, const char *url,
			      const char *method, const char *version, const char *upload_data,
			      size_t *upload_size, void **req_cls)
{
	static int body_seen; /* marker: the request's first call has passed */
	struct hl_http *h = cls;
	const struct route *r = NULL;
	bool is_post = strcmp(method, MHD_HTTP_METHOD_POST) == 0;
	bool is_get = strcmp(method, MHD_HTTP_METHOD_GET) == 0 ||
		      strcmp(method, MHD_HTTP_METHOD_HEAD) == 0;

	(void)version;
	(void)upload_data;
	/* A request with a body: answer once all of it is read (and dropped). */
	if (!*req_cls) {
		*req_cls = &body_seen;
		if (is_post || *upload_size)
			return MHD_YES;
	}
	if (*upload_size) {
		*upload_size = 0;
		return MHD_YES;
	}
	for (size_t i = 0; i < sizeof(routes) / sizeof(routes[0]); i++)
		if (strcmp(url, routes[i].path) == 0)
			r = &routes[i];
	if (!r)
		return respond_text(h, c, MHD_HTTP_NOT_FOUND, "not found\n");
	if (r->post ? !is_post : !is_get) {
		struct MHD_Response *resp;
		static const char msg[] = "method not allowed\n";
		enum MHD_Result ret;

		resp = MHD_create_response_from_buffer(sizeof(msg) - 1, (void *)msg,
						       MHD_RESPMEM_PERSISTENT);
		if (!resp)
			return MHD_NO;
		MHD_add_response_header(resp, MHD_HTTP_HEADER_CONTENT_TYPE,
					"text/plain; charset=utf-8");
		MHD_add_response_header(resp, MHD_HTTP_HEADER_ALLOW,
					r->post ? "POST" : "GET, HEAD");
		ret = MHD_queue_response(c, MHD_HTTP_METHOD_NOT_ALLOWED, resp);
		MHD_destroy_response(resp);
		atomic_fetch_add(&h->requests, 1);
		atomic_fetch_add(&h->errors, 1);
		return ret;
	}
	return r->fn(h, c);
}

int hl_http_new(const char *listen, bool allow_capture, const struct hl_http_sources *src,
		struct hl_http **ret)
{
	struct sockaddr_storage addr;
	const union MHD_DaemonInfo *info;
	struct hl_http *h;
	unsigned int flags = MHD_USE_INTERNAL_POLLING_THREAD | MHD_USE_THREAD_PER_CONNECTION |
			     MHD_USE_POLL | MHD_USE_ITC;
	int rc;

	if (!src || !src->pool)
		return -EINVAL;
	rc = hl_http_parse_listen(listen, &addr, NULL);
	if (rc < 0)
		return rc;
	if (addr.ss_family == AF_INET6)
		flags |= MHD_USE_IPv6;
	h = calloc(1, sizeof(*h));
	if (!h)
		return -ENOMEM;
	h->src = *src;
	h->allow_capture = allow_capture;
	errno = 0;
	h->mhd = MHD_start_daemon(flags, 0, NULL, NULL, handle, h, MHD_OPTION_SOCK_ADDR, &addr,
				  MHD_OPTION_CONNECTION_LIMIT, (unsigned int)HL_HTTP_MAX_CLIENTS,
				  MHD_OPTION_CONNECTION_TIMEOUT,
				  (unsigned int)HL_HTTP_IDLE_TIMEOUT_S, MHD_OPTION_END);
	if (!h->mhd) {
		rc = errno == EADDRINUSE || errno == EACCES || errno == ENOMEM ? -errno : -EIO;
		free(h);
		return rc;
	}
	info = MHD_get_daemon_info(h->mhd, MHD_DAEMON_INFO_BIND_PORT);
	h->port = info ? info->port : 0;
	*ret = h;
	return 0;
}

void hl_http_free(struct hl_http *h)
{
	if (!h)
		return;
	atomic_store(&h->stopping, true);
	MHD_stop_daemon(h->mhd);
	free(h);
}

uint16_t hl_http_port(const struct hl_http *h)
{
	return h->port;
}

void hl_http_counts(struct hl_http *h, struct hl_http_counts *ret)
{
	*ret = (struct hl_http_counts){
		.requests = atomic_load(&h->requests),
		.errors = atomic_load(&h->errors),
		.mjpeg_clients = atomic_load(&h->clients),
		.mjpeg_frames_sent = atomic_load(&h->sent),
		.mjpeg_frames_skipped = atomic_load(&h->skipped),
	};
}
