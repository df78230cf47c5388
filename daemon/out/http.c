/* SPDX-License-Identifier: MIT */
#include "daemon/out/http.h"

#include <arpa/inet.h>
#include <errno.h>
#include <netdb.h>
#include <netinet/in.h>
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include <microhttpd.h>

#include "base/addr.h"
#include "daemon/out/live_html.h"
#include "base/sched.h"
#include "base/json_write.h"
#include "base/clock.h"

#define BOUNDARY "hlframe"
#define STREAM_WAIT_MS 200 /* a stream checks for shutdown this often while it waits */
#define STREAM_BLOCK 65536 /* bytes MHD asks a stream for at most per call */
#define BODY_START 65536 /* first buffer for /status and /metrics */
#define BODY_MAX (4 << 20) /* and the most they may take */
#define CAPTURE_PATH_MAX 4096
#define STACK_SIZE (512 << 10) /* bytes per server thread: they encode nothing */

/* An open connection, for the limits and the header deadline. */
struct conn {
	bool used;
	bool awaiting; /* waits for a request's headers (since since_ns) */
	int fd; /* MHD's: checked against peer before it is shut down */
	uint8_t addr[16]; /* the peer's IPv4 or IPv6 address */
	struct sockaddr_storage peer; /* and port */
	int64_t since_ns;
};

struct hl_http {
	struct MHD_Daemon *mhd;
	struct hl_encoder *enc;
	struct hl_http_sources src;
	struct sockaddr_storage addr;
	bool allow_capture, loopback;
	uint16_t port;
	atomic_bool stopping;
	atomic_uint_fast64_t requests, errors, overloaded, clients, sent, skipped;
	pthread_mutex_t lock; /* guards what follows: MHD's listen and connection threads */
	struct conn conns[HL_HTTP_MAX_CONNECTIONS];
	uint64_t refused, header_timeouts, open;
};

/* One MJPEG client: the shared JPEG of the part it sends, held until the part is sent. */
struct stream {
	struct hl_http *h;
	struct hl_image *jpeg;
	char head[160]; /* part headers */
	size_t head_len;
	size_t off; /* bytes of the current part sent: head, then jpeg, then tail */
	bool started;
	uint64_t last_seq;
};

static const char part_tail[] = "\r\n--" BOUNDARY "\r\n";

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

/* 503 with Retry-After, counted as an overload. */
static enum MHD_Result overloaded(struct hl_http *h, struct MHD_Connection *c, const char *msg)
{
	static const char fmt[] = "{\"error\":\"%s\"}\n";
	struct MHD_Response *r;
	enum MHD_Result ret;
	char body[256];
	int n = snprintf(body, sizeof(body), fmt, msg);

	r = MHD_create_response_from_buffer((size_t)n, body, MHD_RESPMEM_MUST_COPY);
	if (!r)
		return MHD_NO;
	MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, "application/json");
	MHD_add_response_header(r, MHD_HTTP_HEADER_CACHE_CONTROL, "no-store");
	MHD_add_response_header(r, MHD_HTTP_HEADER_RETRY_AFTER, "1");
	ret = MHD_queue_response(c, MHD_HTTP_SERVICE_UNAVAILABLE, r);
	MHD_destroy_response(r);
	atomic_fetch_add(&h->requests, 1);
	atomic_fetch_add(&h->errors, 1);
	atomic_fetch_add(&h->overloaded, 1);
	return ret;
}

static void image_release(void *img)
{
	hl_encoder_release(img);
}

/* The newest frame as an image of kind: the encoder's bytes, shared with every request. */
static enum MHD_Result get_image(struct hl_http *h, struct MHD_Connection *c,
				 enum hl_image_kind kind, const char *type)
{
	const uint64_t seq = hl_encoder_newest(h->enc);
	struct MHD_Response *r;
	struct hl_image *img;
	enum MHD_Result ret;
	char v[32];
	int rc;

	if (!seq)
		return no_frame(h, c);
	rc = hl_encoder_get(h->enc, kind, seq, HL_HTTP_ENCODE_WAIT_MS, &img);
	if (rc == -EBUSY)
		return overloaded(h, c, "too many requests wait for this image; retry after 1 s");
	if (rc == -ETIMEDOUT)
		return overloaded(h, c, "the image was not encoded in time; retry after 1 s");
	if (rc == -ESHUTDOWN)
		return respond_error(h, c, MHD_HTTP_SERVICE_UNAVAILABLE, "shutting down");
	if (rc < 0)
		return respond_error(h, c, MHD_HTTP_INTERNAL_SERVER_ERROR, "encoding failed");
	r = MHD_create_response_from_buffer_with_free_callback_cls(img->len, (void *)img->data,
								   image_release, img);
	if (!r) {
		hl_encoder_release(img);
		return MHD_NO;
	}
	snprintf(v, sizeof(v), "%llu", (unsigned long long)img->seq);
	MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, type);
	MHD_add_response_header(r, MHD_HTTP_HEADER_CACHE_CONTROL, "no-store");
	MHD_add_response_header(r, "X-Frame-Seq", v);
	ret = MHD_queue_response(c, MHD_HTTP_OK, r);
	MHD_destroy_response(r);
	atomic_fetch_add(&h->requests, 1);
	return ret;
}

static enum MHD_Result get_png(struct hl_http *h, struct MHD_Connection *c)
{
	return get_image(h, c, HL_IMAGE_PNG, "image/png");
}

static enum MHD_Result get_exr(struct hl_http *h, struct MHD_Connection *c)
{
	return get_image(h, c, HL_IMAGE_EXR, "image/x-exr");
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

static enum MHD_Result get_glare(struct hl_http *h, struct MHD_Connection *c)
{
	return get_text(h, c, h->src.glare_json, "application/json");
}

static enum MHD_Result post_capture(struct hl_http *h, struct MHD_Connection *c)
{
	char path[CAPTURE_PATH_MAX] = "";
	unsigned int status = MHD_HTTP_OK;
	char *body = NULL;
	size_t len = 0;
	FILE *f;
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
	f = open_memstream(&body, &len);
	if (!f)
		return respond_error(h, c, MHD_HTTP_INTERNAL_SERVER_ERROR, "out of memory");
	fputs(rc < 0 ? "{\"error\":" : "{\"path\":", f);
	hl_json_write_str(f, path);
	fputs("}\n", f);
	if (fclose(f) != 0 || !body) {
		free(body);
		return respond_error(h, c, MHD_HTTP_INTERNAL_SERVER_ERROR, "out of memory");
	}
	return respond(h, c, status, "application/json", body, len, MHD_RESPMEM_MUST_FREE);
}

/* --- the MJPEG stream --- */

static void stream_free(void *cls)
{
	struct stream *s = cls;

	atomic_fetch_sub(&s->h->clients, 1);
	hl_encoder_release(s->jpeg);
	free(s);
}

/* Waits for a frame newer than the last one sent and takes its JPEG as the next part. */
static int next_part(struct stream *s)
{
	struct hl_http *h = s->h;
	struct hl_image *jpeg = NULL;
	int rc;

	while (!jpeg) {
		struct timespec t0, t1;
		struct hl_frame *f;
		uint64_t seq;

		if (atomic_load(&h->stopping))
			return -ESHUTDOWN;
		clock_gettime(CLOCK_MONOTONIC, &t0);
		f = hl_frame_pool_get(h->src.pool, s->last_seq, STREAM_WAIT_MS);
		clock_gettime(CLOCK_MONOTONIC, &t1);
		/* Nothing, long before the timeout: the pool was closed, no frame will come. */
		if (!f && (t1.tv_sec - t0.tv_sec) * 1000 + (t1.tv_nsec - t0.tv_nsec) / 1000000 <
				  STREAM_WAIT_MS / 2)
			return -ESHUTDOWN;
		if (!f)
			continue;
		seq = f->hdr.seq;
		hl_frame_pool_release(h->src.pool, f); /* the encoder copies the newest itself */
		rc = hl_encoder_get(h->enc, HL_IMAGE_JPEG, seq, HL_HTTP_ENCODE_WAIT_MS, &jpeg);
		if (rc < 0 && rc != -ETIMEDOUT)
			return rc; /* -EBUSY cannot be: streams <= HL_ENCODER_MAX_WAITING */
	}
	if (s->last_seq && jpeg->seq > s->last_seq + 1)
		atomic_fetch_add(&h->skipped, jpeg->seq - s->last_seq - 1);
	s->last_seq = jpeg->seq;
	hl_encoder_release(s->jpeg);
	s->jpeg = jpeg;
	s->head_len = (size_t)snprintf(s->head, sizeof(s->head),
				       "Content-Type: image/jpeg\r\nContent-Length: %zu\r\n"
				       "X-Frame-Seq: %llu\r\n\r\n",
				       jpeg->len, (unsigned long long)s->last_seq);
	s->off = 0;
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
	part_len = s->jpeg ? s->head_len + s->jpeg->len + tail : 0;
	if ((!s->jpeg || s->off >= part_len) && next_part(s) < 0)
		return MHD_CONTENT_READER_END_OF_STREAM;
	n += take(s->head, s->head_len, 0, &s->off, buf + n, max - n);
	n += take(s->jpeg->data, s->jpeg->len, s->head_len, &s->off, buf + n, max - n);
	n += take(part_tail, tail, s->head_len + s->jpeg->len, &s->off, buf + n, max - n);
	return (ssize_t)n;
}

static enum MHD_Result get_stream(struct hl_http *h, struct MHD_Connection *c)
{
	struct MHD_Response *r;
	struct stream *s;
	enum MHD_Result ret;

	if (atomic_fetch_add(&h->clients, 1) >= HL_HTTP_MAX_STREAMS) {
		atomic_fetch_sub(&h->clients, 1);
		return overloaded(h, c, "too many streams open; retry after 1 s");
	}
	s = calloc(1, sizeof(*s));
	if (!s) {
		atomic_fetch_sub(&h->clients, 1);
		return respond_error(h, c, MHD_HTTP_INTERNAL_SERVER_ERROR, "out of memory");
	}
	s->h = h;
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

/* --- connections: the limits and the header deadline --- */

static void addr_key(const struct sockaddr *sa, uint8_t key[16])
{
	memset(key, 0, 16);
	if (sa->sa_family == AF_INET)
		memcpy(key, &((const struct sockaddr_in *)sa)->sin_addr, 4);
	else if (sa->sa_family == AF_INET6)
		memcpy(key, &((const struct sockaddr_in6 *)sa)->sin6_addr, 16);
}

/*
 * Shuts the connection down (MHD then closes it). Only if its fd still has this peer: should
 * MHD close an fd before it tells us, a new connection could have its number.
 */
static void shut_down(const struct conn *k)
{
	struct sockaddr_storage peer = { 0 };
	socklen_t len = sizeof(peer);

	if (getpeername(k->fd, (struct sockaddr *)&peer, &len) == 0 &&
	    memcmp(&peer, &k->peer, sizeof(peer)) == 0)
		shutdown(k->fd, SHUT_RDWR);
}

/*
 * MHD's accept policy, on its listen thread before each new connection: first closes the
 * connections past their header deadline (shutdown: MHD then closes them), then refuses this
 * one if the limits are reached. Both counted.
 */
static enum MHD_Result accept_policy(void *cls, const struct sockaddr *sa, socklen_t len)
{
	struct hl_http *h = cls;
	const int64_t now = hl_clock_monotonic_ns();
	uint8_t key[16];
	int open = 0, same = 0;
	bool ok;

	(void)len;
	addr_key(sa, key);
	pthread_mutex_lock(&h->lock);
	for (int i = 0; i < HL_HTTP_MAX_CONNECTIONS; i++) {
		struct conn *k = &h->conns[i];

		if (!k->used)
			continue;
		if (k->awaiting &&
		    now - k->since_ns > (int64_t)HL_HTTP_HEADER_TIMEOUT_S * 1000000000) {
			shut_down(k);
			k->awaiting = false;
			h->header_timeouts++;
		}
		open++;
		same += memcmp(k->addr, key, 16) == 0;
	}
	ok = open < HL_HTTP_MAX_CONNECTIONS && same < HL_HTTP_MAX_PER_ADDRESS;
	if (!ok)
		h->refused++;
	pthread_mutex_unlock(&h->lock);
	return ok ? MHD_YES : MHD_NO;
}

/* Started: takes a slot (the accept policy left one). Closed: frees it. */
static void notify_connection(void *cls, struct MHD_Connection *c, void **socket_context,
			      enum MHD_ConnectionNotificationCode code)
{
	struct hl_http *h = cls;
	struct conn *k = *socket_context;

	pthread_mutex_lock(&h->lock);
	if (code == MHD_CONNECTION_NOTIFY_STARTED) {
		const union MHD_ConnectionInfo *fd =
			MHD_get_connection_info(c, MHD_CONNECTION_INFO_CONNECTION_FD);
		const union MHD_ConnectionInfo *addr =
			MHD_get_connection_info(c, MHD_CONNECTION_INFO_CLIENT_ADDRESS);

		for (int i = 0; i < HL_HTTP_MAX_CONNECTIONS && !k; i++)
			if (!h->conns[i].used)
				k = &h->conns[i];
		if (k && fd && addr) {
			*k = (struct conn){ .used = true,
					    .awaiting = true,
					    .fd = fd->connect_fd,
					    .since_ns = hl_clock_monotonic_ns() };
			addr_key(addr->client_addr, k->addr);
			if (getpeername(k->fd, (struct sockaddr *)&k->peer,
					&(socklen_t){ sizeof(k->peer) }) < 0)
				k->fd = -1; /* never shut down */
			h->open++;
			*socket_context = k;
		}
	} else if (k) {
		k->used = false;
		h->open--;
		*socket_context = NULL;
	}
	pthread_mutex_unlock(&h->lock);
}

/* A whole request is in (awaiting false), or its answer was sent: the next one's wait starts. */
static void set_awaiting(struct hl_http *h, struct MHD_Connection *c, bool awaiting)
{
	const union MHD_ConnectionInfo *ci =
		MHD_get_connection_info(c, MHD_CONNECTION_INFO_SOCKET_CONTEXT);
	struct conn *k = ci ? ci->socket_context : NULL;

	if (!k)
		return;
	pthread_mutex_lock(&h->lock);
	k->awaiting = awaiting;
	k->since_ns = hl_clock_monotonic_ns();
	pthread_mutex_unlock(&h->lock);
}

static void request_completed(void *cls, struct MHD_Connection *c, void **req_cls,
			      enum MHD_RequestTerminationCode toe)
{
	(void)req_cls;
	(void)toe;
	set_awaiting(cls, c, true);
}

/* --- routing --- */

struct route {
	const char *path;
	bool post; /* POST only; else GET and HEAD */
	enum MHD_Result (*fn)(struct hl_http *h, struct MHD_Connection *c);
};

static const struct route routes[] = {
	{ "/", false, get_page },
	{ "/stream.mjpg", false, get_stream },
	{ "/frame.png", false, get_png },
	{ "/frame.exr", false, get_exr },
	{ "/status", false, get_status },
	{ "/metrics", false, get_metrics },
	{ "/glare.json", false, get_glare },
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
	set_awaiting(h, c, false); /* the whole request is in, body included */
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
	struct hl_http *h;
	int rc;

	if (!src || !src->pool)
		return -EINVAL;
	h = calloc(1, sizeof(*h));
	if (!h)
		return -ENOMEM;
	rc = hl_addr_parse(listen, &h->addr, &h->loopback);
	if (rc < 0) {
		free(h);
		return rc;
	}
	h->src = *src;
	h->allow_capture = allow_capture;
	rc = hl_mutex_init_pi(&h->lock);
	if (rc < 0) {
		free(h);
		return rc;
	}
	rc = hl_encoder_new(src->pool, src->exr_info, &h->enc);
	if (rc < 0) {
		hl_http_free(h);
		return rc;
	}
	*ret = h;
	return 0;
}

/*
 * MHD starts its threads from this one, so that they inherit SCHED_OTHER at nice HL_HTTP_NICE
 * whatever the daemon's policy: the server never competes with the renderer at its priority.
 */
static void *start_server(void *arg)
{
	struct hl_http *h = arg;
	const struct sched_param sp = { .sched_priority = 0 };
	const id_t tid = (id_t)gettid();
	unsigned int flags = MHD_USE_INTERNAL_POLLING_THREAD | MHD_USE_THREAD_PER_CONNECTION |
			     MHD_USE_POLL | MHD_USE_ITC;

	pthread_setschedparam(pthread_self(), SCHED_OTHER, &sp);
	errno = 0;
	if (getpriority(PRIO_PROCESS, tid) < HL_HTTP_NICE)
		setpriority(PRIO_PROCESS, tid, HL_HTTP_NICE);
	if (h->addr.ss_family == AF_INET6)
		flags |= MHD_USE_IPv6;
	errno = 0;
	/* The connection limit is the accept policy's (counted); MHD's is a backstop above it. */
	h->mhd = MHD_start_daemon(
		flags, 0, accept_policy, h, handle, h, MHD_OPTION_SOCK_ADDR, &h->addr,
		MHD_OPTION_CONNECTION_LIMIT, (unsigned int)HL_HTTP_MAX_CONNECTIONS + 16,
		MHD_OPTION_CONNECTION_TIMEOUT, (unsigned int)HL_HTTP_IDLE_TIMEOUT_S,
		MHD_OPTION_THREAD_STACK_SIZE, (size_t)STACK_SIZE, MHD_OPTION_NOTIFY_CONNECTION,
		notify_connection, h, MHD_OPTION_NOTIFY_COMPLETED, request_completed, h,
		MHD_OPTION_END);
	return (void *)(intptr_t)(h->mhd ? 0 : errno);
}

int hl_http_start(struct hl_http *h)
{
	const union MHD_DaemonInfo *info;
	pthread_t t;
	void *err;
	int rc;

	rc = -pthread_create(&t, NULL, start_server, h);
	if (rc < 0)
		return rc;
	pthread_join(t, &err);
	rc = (int)(intptr_t)err;
	if (!h->mhd)
		return rc == EADDRINUSE || rc == EACCES || rc == ENOMEM ? -rc : -EIO;
	info = MHD_get_daemon_info(h->mhd, MHD_DAEMON_INFO_BIND_PORT);
	h->port = info ? info->port : 0;
	return 0;
}

void hl_http_stop(struct hl_http *h)
{
	MHD_socket listen_fd = MHD_INVALID_SOCKET;

	if (!h || !h->mhd)
		return;
	atomic_store(&h->stopping, true);
	/* No new connection; every request waiting for an image is answered at once. */
	listen_fd = MHD_quiesce_daemon(h->mhd);
	hl_encoder_stop(h->enc);
	MHD_stop_daemon(h->mhd);
	h->mhd = NULL;
	if (listen_fd != MHD_INVALID_SOCKET)
		close(listen_fd);
}

void hl_http_free(struct hl_http *h)
{
	if (!h)
		return;
	hl_http_stop(h);
	hl_encoder_free(h->enc);
	pthread_mutex_destroy(&h->lock);
	free(h);
}

bool hl_http_loopback(const struct hl_http *h)
{
	return h->loopback;
}

uint16_t hl_http_port(const struct hl_http *h)
{
	return h->port;
}

void hl_http_counts(struct hl_http *h, struct hl_http_counts *ret)
{
	struct hl_encoder_counts ec;

	*ret = (struct hl_http_counts){
		.requests = atomic_load(&h->requests),
		.errors = atomic_load(&h->errors),
		.overloaded = atomic_load(&h->overloaded),
		.mjpeg_clients = atomic_load(&h->clients),
		.mjpeg_frames_sent = atomic_load(&h->sent),
		.mjpeg_frames_skipped = atomic_load(&h->skipped),
	};
	hl_encoder_counts(h->enc, &ec);
	memcpy(ret->encoded, ec.encoded, sizeof(ret->encoded));
	ret->encode_failures = ec.failed;
	pthread_mutex_lock(&h->lock);
	ret->connections = h->open;
	ret->connections_refused = h->refused;
	ret->header_timeouts = h->header_timeouts;
	pthread_mutex_unlock(&h->lock);
}
