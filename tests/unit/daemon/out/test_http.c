/* SPDX-License-Identifier: MIT */
/*
 * The HTTP server against a real frame pool, spoken to over plain sockets: every route's status
 * and type, PNG and EXR that decode to the published frame, an MJPEG stream that follows the
 * publisher, a stalled stream client that delays neither the publisher nor another client,
 * the capture policy, and a prompt shutdown.
 */
#include <errno.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <strings.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>
#include <cmocka.h>

#include <openexr.h>
#include <png.h>
#include <turbojpeg.h>

#include "daemon/out/http.h"
#include "render/pixel.h"
#include "testutil.h"

#define W 320
#define H 240
#define BAR 16 /* width of the moving bar, px */

/* --- frames: every pixel a function of the frame's seq n --- */

static uint8_t noise(int x, int y, uint64_t n)
{
	uint32_t v = (uint32_t)x * 73856093u ^ (uint32_t)y * 19349663u ^ (uint32_t)n * 83492791u;

	v ^= v >> 13;
	v *= 0x5bd1e995u;
	return (uint8_t)((v >> 16) & 63);
}

static int bar_x(uint64_t n)
{
	return (int)((n * 8) % (W - BAR));
}

static void expected_rgb(uint64_t n, uint8_t *rgb)
{
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			uint8_t *p = rgb + ((size_t)y * W + x) * 3;
			const bool bar = x >= bar_x(n) && x < bar_x(n) + BAR;

			p[0] = bar ? 230 : noise(x, y, n);
			p[1] = bar ? 230 : (uint8_t)(y / 4);
			p[2] = bar ? 230 : (uint8_t)(x / 8);
		}
}

static float expected_lux(uint64_t n, int i)
{
	return 0.5f * (float)i + (float)n;
}

static void publish(struct hl_frame_pool *pool)
{
	struct hl_frame_pool_counts c;
	struct hl_frame *f = hl_frame_pool_acquire(pool);
	uint64_t n;

	assert_non_null(f);
	hl_frame_pool_counts(pool, &c);
	n = c.published + 1; /* the only publisher: this frame's seq */
	expected_rgb(n, f->pixels);
	for (int i = 0; i < W * H; i++)
		f->lux[i] = expected_lux(n, i);
	hl_frame_pool_publish(pool, f);
	assert_int_equal(f->hdr.seq, n);
}

struct publisher {
	struct hl_frame_pool *pool;
	int period_ms;
	atomic_bool stop;
	pthread_t thread;
};

static void sleep_ms(int ms)
{
	struct timespec ts = { ms / 1000, (long)(ms % 1000) * 1000000 };

	nanosleep(&ts, NULL);
}

static double now_s(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* Limits for waits on an event: only a hang reaches them, never a busy machine. */
#define WAIT_S 30.0

static void *publisher_main(void *arg)
{
	struct publisher *p = arg;

	while (!atomic_load(&p->stop)) {
		publish(p->pool);
		sleep_ms(p->period_ms);
	}
	return NULL;
}

/* --- the server and its sources --- */

struct fixture {
	struct hl_frame_pool *pool;
	struct hl_http *http;
	uint16_t port;
	atomic_int captures;
	char capture_path[512];
	int capture_rc; /* 0: write capture_path; else fail with this and a reason */
};

static int status_json(void *userdata, char *buf, size_t size)
{
	struct fixture *fx = userdata;
	struct hl_frame_pool_counts c;
	int n;

	hl_frame_pool_counts(fx->pool, &c);
	n = snprintf(buf, size, "{\"published\":%llu}", (unsigned long long)c.published);
	return n < 0 ? -EIO : ((size_t)n >= size ? -ENOBUFS : n);
}

#define METRICS_SIZE 100000 /* more than the server's first buffer: it must grow */

static int metrics(void *userdata, char *buf, size_t size)
{
	static const char line[] = "# HELP x y\n";

	(void)userdata;
	if (size < METRICS_SIZE)
		return -ENOBUFS;
	for (size_t i = 0; i < METRICS_SIZE; i++)
		buf[i] = line[i % (sizeof(line) - 1)];
	return METRICS_SIZE;
}

static int capture(void *userdata, char *path, size_t size)
{
	struct fixture *fx = userdata;
	FILE *f;

	if (fx->capture_rc) {
		snprintf(path, size, "'/c/.tmp-frame-1/hdr.exr': cannot write (\"%s\")",
			 strerror(-fx->capture_rc));
		return fx->capture_rc;
	}
	f = fopen(fx->capture_path, "w");
	if (!f)
		return -errno;
	fprintf(f, "capture %d\n", atomic_fetch_add(&fx->captures, 1) + 1);
	fclose(f);
	snprintf(path, size, "%s", fx->capture_path);
	return 0;
}

static struct fixture *start(bool allow_capture)
{
	const struct hl_frame_shape shape = { .width = W,
					      .height = H,
					      .format = HL_PIXEL_RGB8,
					      .n_lamps = 1,
					      .n_sources = 1,
					      .dist_width = 1,
					      .dist_height = 1 };
	struct fixture *fx = calloc(1, sizeof(*fx));
	struct hl_http_sources src = { 0 };

	assert_non_null(fx);
	assert_int_equal(hl_frame_pool_new(4, &shape, &fx->pool), 0);
	test_path(fx->capture_path, sizeof(fx->capture_path), "capture.txt");
	src.pool = fx->pool;
	src.userdata = fx;
	src.status_json = status_json;
	src.metrics = metrics;
	src.capture = capture;
	assert_int_equal(hl_http_new("127.0.0.1:0", allow_capture, &src, &fx->http), 0);
	assert_int_equal(hl_http_start(fx->http), 0);
	fx->port = hl_http_port(fx->http);
	assert_true(fx->port > 0);
	return fx;
}

static void stop(struct fixture *fx)
{
	hl_http_free(fx->http);
	hl_frame_pool_free(fx->pool);
	unlink(fx->capture_path);
	free(fx);
}

/* --- a plain HTTP/1.0 client --- */

static int connect_to(uint16_t port, int rcvbuf)
{
	struct sockaddr_in a = { .sin_family = AF_INET, .sin_port = htons(port) };
	struct timeval tv = { 10, 0 };
	int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);

	assert_true(fd >= 0);
	if (rcvbuf)
		assert_int_equal(setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof(rcvbuf)), 0);
	assert_int_equal(setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv)), 0);
	a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
	assert_int_equal(connect(fd, (struct sockaddr *)&a, sizeof(a)), 0);
	return fd;
}

static void send_all(int fd, const char *s)
{
	size_t n = strlen(s);

	while (n) {
		ssize_t k = send(fd, s, n, MSG_NOSIGNAL);

		assert_true(k > 0);
		s += k;
		n -= (size_t)k;
	}
}

static void send_request(int fd, const char *method, const char *path)
{
	char req[256];

	snprintf(req, sizeof(req), "%s %s HTTP/1.0\r\nHost: 127.0.0.1\r\n%s\r\n", method, path,
		 strcmp(method, "POST") == 0 ? "Content-Length: 0\r\n" : "");
	send_all(fd, req);
}

struct response {
	int status;
	char head[4096]; /* status line and headers, NUL-terminated */
	uint8_t *body;
	size_t len;
};

/* The value of header name in head, or "" (copied into out). */
static const char *header(const char *head, const char *name, char *out, size_t size)
{
	const size_t n = strlen(name);

	out[0] = '\0';
	for (const char *l = strstr(head, "\r\n"); l && l[2]; l = strstr(l + 2, "\r\n")) {
		const char *s = l + 2, *e = strstr(s, "\r\n");

		if (e && strncasecmp(s, name, n) == 0 && s[n] == ':') {
			s += n + 1;
			while (*s == ' ')
				s++;
			snprintf(out, size, "%.*s", (int)(e - s), s);
			break;
		}
	}
	return out;
}

static void request(uint16_t port, const char *method, const char *path, struct response *r)
{
	int fd = connect_to(port, 0);
	size_t cap = 1 << 16, len = 0;
	uint8_t *buf = malloc(cap);
	uint8_t *end;
	ssize_t k;

	assert_non_null(buf);
	send_request(fd, method, path);
	while ((k = recv(fd, buf + len, cap - len, 0)) > 0) {
		len += (size_t)k;
		if (len == cap) {
			cap *= 2;
			buf = realloc(buf, cap);
			assert_non_null(buf);
		}
	}
	assert_int_equal(k, 0);
	close(fd);
	end = memmem(buf, len, "\r\n\r\n", 4);
	assert_non_null(end);
	assert_true((size_t)(end - buf) + 2 < sizeof(r->head));
	memcpy(r->head, buf, (size_t)(end - buf) + 2);
	r->head[end - buf + 2] = '\0';
	assert_int_equal(sscanf(r->head, "HTTP/1.%*d %d", &r->status), 1);
	r->len = len - (size_t)(end + 4 - buf);
	r->body = malloc(r->len + 1);
	memcpy(r->body, end + 4, r->len);
	r->body[r->len] = 0;
	free(buf);
}

static void check(uint16_t port, const char *method, const char *path, int status, const char *type,
		  struct response *r)
{
	char v[256];

	request(port, method, path, r);
	assert_int_equal(r->status, status);
	assert_string_equal(header(r->head, "Content-Type", v, sizeof(v)), type);
}

/* --- stream parts --- */

struct reader {
	int fd;
	uint8_t buf[1 << 18];
	size_t start, end;
};

/* Reads until delim is buffered; returns its offset from start. */
static size_t read_until(struct reader *rd, const char *delim)
{
	for (;;) {
		uint8_t *p = memmem(rd->buf + rd->start, rd->end - rd->start, delim, strlen(delim));
		ssize_t k;

		if (p)
			return (size_t)(p - (rd->buf + rd->start));
		if (rd->start > 0) {
			memmove(rd->buf, rd->buf + rd->start, rd->end - rd->start);
			rd->end -= rd->start;
			rd->start = 0;
		}
		assert_true(rd->end < sizeof(rd->buf));
		k = recv(rd->fd, rd->buf + rd->end, sizeof(rd->buf) - rd->end, 0);
		assert_true(k > 0);
		rd->end += (size_t)k;
	}
}

static void read_n(struct reader *rd, size_t n)
{
	if (rd->start + n > sizeof(rd->buf)) {
		memmove(rd->buf, rd->buf + rd->start, rd->end - rd->start);
		rd->end -= rd->start;
		rd->start = 0;
	}
	assert_true(n <= sizeof(rd->buf));
	while (rd->end - rd->start < n) {
		ssize_t k = recv(rd->fd, rd->buf + rd->end, sizeof(rd->buf) - rd->end, 0);

		assert_true(k > 0);
		rd->end += (size_t)k;
	}
}

static struct reader *open_stream(uint16_t port, int rcvbuf, bool read_head)
{
	struct reader *rd = calloc(1, sizeof(*rd));
	char head[1024], v[128];
	size_t n;

	assert_non_null(rd);
	rd->fd = connect_to(port, rcvbuf);
	send_request(rd->fd, "GET", "/stream.mjpg");
	if (!read_head)
		return rd;
	n = read_until(rd, "\r\n\r\n");
	assert_true(n < sizeof(head) - 3);
	memcpy(head, rd->buf + rd->start, n + 2);
	head[n + 2] = '\0';
	rd->start += n + 4;
	assert_memory_equal(head, "HTTP/1.", 7);
	assert_memory_equal(head + 8, " 200", 4);
	assert_string_equal(header(head, "Content-Type", v, sizeof(v)),
			    "multipart/x-mixed-replace; boundary=hlframe");
	/* The body opens with the first boundary. */
	read_n(rd, 11);
	assert_memory_equal(rd->buf + rd->start, "--hlframe\r\n", 11);
	rd->start += 11;
	return rd;
}

/* The next part: its seq, its JPEG copied into jpeg (size in *len). */
static uint64_t read_part(struct reader *rd, uint8_t *jpeg, size_t cap, size_t *len)
{
	char head[512], v[64];
	size_t n = read_until(rd, "\r\n\r\n");
	unsigned long long seq;

	assert_true(n < sizeof(head) - 3);
	memcpy(head, "\r\n", 2); /* header() looks for lines after a line break */
	memcpy(head + 2, rd->buf + rd->start, n + 2);
	head[n + 4] = '\0';
	rd->start += n + 4;
	assert_string_equal(header(head, "Content-Type", v, sizeof(v)), "image/jpeg");
	*len = strtoul(header(head, "Content-Length", v, sizeof(v)), NULL, 10);
	assert_true(*len > 4 && *len <= cap);
	seq = strtoull(header(head, "X-Frame-Seq", v, sizeof(v)), NULL, 10);
	read_n(rd, *len + 13);
	memcpy(jpeg, rd->buf + rd->start, *len);
	assert_memory_equal(rd->buf + rd->start + *len, "\r\n--hlframe\r\n", 13);
	rd->start += *len + 13;
	/* SOI and EOI markers */
	assert_int_equal(jpeg[0], 0xff);
	assert_int_equal(jpeg[1], 0xd8);
	assert_int_equal(jpeg[*len - 2], 0xff);
	assert_int_equal(jpeg[*len - 1], 0xd9);
	return seq;
}

static void close_stream(struct reader *rd)
{
	close(rd->fd);
	free(rd);
}

/* Mean of the red channel over columns x0..x0+BAR of a decoded image. */
static double column_mean(const uint8_t *rgb, int x0)
{
	double sum = 0;

	for (int y = 0; y < H; y++)
		for (int x = x0; x < x0 + BAR; x++)
			sum += rgb[((size_t)y * W + x) * 3];
	return sum / (H * BAR);
}

/* --- tests --- */

static void http_new_rejects_bad_input_and_a_busy_port(void **state)
{
	struct fixture *fx = start(false);
	struct hl_http_sources src = { .pool = fx->pool };
	struct hl_http *h = NULL;
	char listen[32];

	(void)state;
	assert_int_equal(hl_http_new("nowhere", false, &src, &h), -EINVAL);
	src.pool = NULL;
	assert_int_equal(hl_http_new("127.0.0.1:0", false, &src, &h), -EINVAL);
	src.pool = fx->pool;
	snprintf(listen, sizeof(listen), "127.0.0.1:%u", fx->port);
	assert_int_equal(hl_http_new(listen, false, &src, &h), 0);
	assert_int_equal(hl_http_start(h), -EADDRINUSE);
	hl_http_free(h);
	hl_http_free(NULL);
	stop(fx);
}

static void http_routes_answer_with_status_and_type(void **state)
{
	struct fixture *fx = start(false);
	struct hl_http_counts c;
	struct response r;
	char v[64];

	(void)state;
	/* Before the first frame, the frame routes have nothing to show. */
	check(fx->port, "GET", "/frame.png", 503, "application/json", &r);
	assert_string_equal((char *)r.body, "{\"error\":\"no frame published yet\"}\n");
	free(r.body);
	publish(fx->pool);

	check(fx->port, "GET", "/", 200, "text/html; charset=utf-8", &r);
	assert_non_null(strstr((char *)r.body, "<img id=\"live\""));
	assert_non_null(strstr((char *)r.body, "/stream.mjpg"));
	assert_non_null(strstr((char *)r.body, "fetch(\"/status\""));
	assert_null(strstr((char *)r.body, "http://")); /* nothing from elsewhere */
	free(r.body);
	check(fx->port, "HEAD", "/", 200, "text/html; charset=utf-8", &r);
	assert_int_equal(r.len, 0);
	free(r.body);
	check(fx->port, "GET", "/status", 200, "application/json", &r);
	assert_string_equal((char *)r.body, "{\"published\":1}");
	free(r.body);
	check(fx->port, "GET", "/metrics", 200, "text/plain; version=0.0.4; charset=utf-8", &r);
	assert_int_equal(r.len, METRICS_SIZE);
	assert_memory_equal(r.body, "# HELP x y\n# HELP x y\n", 22);
	free(r.body);
	check(fx->port, "GET", "/frame.png", 200, "image/png", &r);
	assert_string_equal(header(r.head, "X-Frame-Seq", v, sizeof(v)), "1");
	free(r.body);
	check(fx->port, "GET", "/frame.exr", 200, "image/x-exr", &r);
	free(r.body);

	check(fx->port, "GET", "/nothing", 404, "text/plain; charset=utf-8", &r);
	free(r.body);
	check(fx->port, "GET", "/frame.png/x", 404, "text/plain; charset=utf-8", &r);
	free(r.body);
	check(fx->port, "POST", "/status", 405, "text/plain; charset=utf-8", &r);
	assert_string_equal(header(r.head, "Allow", v, sizeof(v)), "GET, HEAD");
	free(r.body);
	check(fx->port, "DELETE", "/frame.png", 405, "text/plain; charset=utf-8", &r);
	free(r.body);
	check(fx->port, "GET", "/capture", 405, "text/plain; charset=utf-8", &r);
	assert_string_equal(header(r.head, "Allow", v, sizeof(v)), "POST");
	free(r.body);

	hl_http_counts(fx->http, &c);
	assert_int_equal(c.requests, 12);
	assert_int_equal(c.errors, 6); /* 503, 404 x2, 405 x3 */
	assert_int_equal(c.mjpeg_clients, 0);
	stop(fx);
}

struct png_src {
	const uint8_t *data;
	size_t len, pos;
};

static void png_read_mem(png_structp png, png_bytep out, png_size_t n)
{
	struct png_src *s = png_get_io_ptr(png);

	if (s->pos + n > s->len)
		png_error(png, "truncated");
	memcpy(out, s->data + s->pos, n);
	s->pos += n;
}

static void http_frame_png_is_the_newest_frame_losslessly(void **state)
{
	struct fixture *fx = start(false);
	static uint8_t want[W * H * 3], got[W * H * 3];
	struct png_src src;
	struct response r;
	png_structp png;
	png_infop info;
	char v[64];

	(void)state;
	publish(fx->pool);
	publish(fx->pool);
	publish(fx->pool);
	check(fx->port, "GET", "/frame.png", 200, "image/png", &r);
	assert_string_equal(header(r.head, "X-Frame-Seq", v, sizeof(v)), "3");
	assert_memory_equal(r.body, "\x89PNG\r\n\x1a\n", 8);
	/* IHDR first: width, height, depth 8, colour type 2 (RGB) */
	assert_memory_equal(r.body + 12, "IHDR", 4);
	assert_int_equal(ntohl(*(uint32_t *)(r.body + 16)), W);
	assert_int_equal(ntohl(*(uint32_t *)(r.body + 20)), H);
	assert_int_equal(r.body[24], 8);
	assert_int_equal(r.body[25], 2);

	src = (struct png_src){ r.body, r.len, 0 };
	png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
	info = png_create_info_struct(png);
	assert_int_equal(setjmp(png_jmpbuf(png)), 0);
	png_set_read_fn(png, &src, png_read_mem);
	png_read_info(png, info);
	for (int y = 0; y < H; y++)
		png_read_row(png, got + (size_t)y * W * 3, NULL);
	png_read_end(png, NULL);
	png_destroy_read_struct(&png, &info, NULL);
	expected_rgb(3, want);
	assert_memory_equal(got, want, sizeof(want));
	free(r.body);
	stop(fx);
}

/* PNG bytes of a decoded 8-bit RGB image into rgb (w * h * 3). */
static void decode_png(const struct response *r, uint8_t *rgb, int w, int h)
{
	struct png_src src = { r->body, r->len, 0 };
	png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
	png_infop info = png_create_info_struct(png);

	assert_int_equal(setjmp(png_jmpbuf(png)), 0);
	png_set_read_fn(png, &src, png_read_mem);
	png_read_info(png, info);
	assert_int_equal(png_get_image_width(png, info), w);
	assert_int_equal(png_get_image_height(png, info), h);
	for (int y = 0; y < h; y++)
		png_read_row(png, rgb + (size_t)y * w * 3, NULL);
	png_read_end(png, NULL);
	png_destroy_read_struct(&png, &info, NULL);
}

static void http_hdr_frames_are_tone_mapped(void **state)
{
	/* L in cd/m^2 -> x = L / pi -> x / (1 + x) -> sRGB -> 8 bit (values worked out by hand) */
	static const float lum[4] = { 0.0f, 1.0f, 1e4f, 0.05f };
	static const uint8_t want[4] = { 0, 135, 255, 34 };
	const struct hl_frame_shape shape = { .width = 4,
					      .height = 2,
					      .format = HL_PIXEL_RGBA16F,
					      .n_lamps = 1,
					      .n_sources = 1,
					      .dist_width = 1,
					      .dist_height = 1 };
	struct hl_http_sources src = { 0 };
	struct hl_frame_pool *pool;
	struct hl_http *http;
	struct hl_frame *f;
	struct response r;
	uint8_t rgb[4 * 2 * 3];

	(void)state;
	assert_int_equal(hl_frame_pool_new(2, &shape, &pool), 0);
	src.pool = pool;
	assert_int_equal(hl_http_new("127.0.0.1:0", false, &src, &http), 0);
	assert_int_equal(hl_http_start(http), 0);
	f = hl_frame_pool_acquire(pool);
	assert_non_null(f);
	for (int i = 0; i < 8; i++) {
		uint16_t *px = (uint16_t *)f->pixels + 4 * i;

		for (int c = 0; c < 3; c++)
			px[c] = hl_pixel_half_from_float(lum[i % 4]);
		px[3] = hl_pixel_half_from_float(1.0f);
	}
	hl_frame_pool_publish(pool, f);
	check(hl_http_port(http), "GET", "/frame.png", 200, "image/png", &r);
	decode_png(&r, rgb, 4, 2);
	free(r.body);
	for (int i = 0; i < 8; i++)
		for (int c = 0; c < 3; c++)
			assert_int_equal(rgb[3 * i + c], want[i % 4]);
	/* Status and metrics without callbacks: not there. */
	check(hl_http_port(http), "GET", "/status", 404, "text/plain; charset=utf-8", &r);
	free(r.body);
	hl_http_free(http);
	hl_frame_pool_free(pool);
}

static void http_frame_exr_is_the_lux_image(void **state)
{
	struct fixture *fx = start(false);
	static float back[W * H];
	char path[512], v[64];
	struct response r;
	exr_context_t ctxt;
	const exr_attr_chlist_t *cl;
	const char *unit = NULL;
	exr_chunk_info_t ci;
	exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
	FILE *f;
	int lines;

	(void)state;
	publish(fx->pool);
	publish(fx->pool);
	check(fx->port, "GET", "/frame.exr", 200, "image/x-exr", &r);
	assert_string_equal(header(r.head, "X-Frame-Seq", v, sizeof(v)), "2");
	assert_memory_equal(r.body, "\x76\x2f\x31\x01", 4); /* EXR magic */
	test_path(path, sizeof(path), "frame.exr");
	f = fopen(path, "wb");
	assert_non_null(f);
	assert_int_equal(fwrite(r.body, 1, r.len, f), r.len);
	fclose(f);
	free(r.body);

	assert_int_equal(exr_start_read(&ctxt, path, NULL), EXR_ERR_SUCCESS);
	assert_int_equal(exr_get_channels(ctxt, 0, &cl), EXR_ERR_SUCCESS);
	assert_int_equal(cl->num_channels, 1);
	assert_string_equal(cl->entries[0].name.str, "E");
	assert_int_equal(cl->entries[0].pixel_type, EXR_PIXEL_FLOAT);
	assert_int_equal(exr_attr_get_string(ctxt, 0, "hdlamp:unit", NULL, &unit), EXR_ERR_SUCCESS);
	assert_string_equal(unit, "lx");
	assert_int_equal(exr_get_scanlines_per_chunk(ctxt, 0, &lines), EXR_ERR_SUCCESS);
	for (int y = 0; y < H; y += lines) {
		assert_int_equal(exr_read_scanline_chunk_info(ctxt, 0, y, &ci), EXR_ERR_SUCCESS);
		if (y == 0)
			assert_int_equal(exr_decoding_initialize(ctxt, 0, &ci, &dec),
					 EXR_ERR_SUCCESS);
		else
			assert_int_equal(exr_decoding_update(ctxt, 0, &ci, &dec), EXR_ERR_SUCCESS);
		dec.channels[0].decode_to_ptr = (uint8_t *)(back + y * W);
		dec.channels[0].user_pixel_stride = 4;
		dec.channels[0].user_line_stride = 4 * W;
		dec.channels[0].user_bytes_per_element = 4;
		dec.channels[0].user_data_type = EXR_PIXEL_FLOAT;
		if (y == 0)
			assert_int_equal(exr_decoding_choose_default_routines(ctxt, 0, &dec),
					 EXR_ERR_SUCCESS);
		assert_int_equal(exr_decoding_run(ctxt, 0, &dec), EXR_ERR_SUCCESS);
	}
	exr_decoding_destroy(ctxt, &dec);
	exr_finish(&ctxt);
	unlink(path);
	for (int i = 0; i < W * H; i++)
		if (back[i] != expected_lux(2, i))
			fail_msg("lux[%d] = %g, expected %g", i, back[i], expected_lux(2, i));
	stop(fx);
}

static void http_mjpeg_stream_follows_the_publisher(void **state)
{
	struct fixture *fx = start(false);
	struct publisher pub = { .pool = fx->pool, .period_ms = 40 };
	static uint8_t jpeg[1 << 18], rgb[W * H * 3];
	tjhandle tj = tjInitDecompress();
	struct reader *rd;
	struct hl_http_counts c;
	uint64_t seq, last = 0;
	size_t len;

	(void)state;
	assert_non_null(tj);
	assert_int_equal(pthread_create(&pub.thread, NULL, publisher_main, &pub), 0);
	rd = open_stream(fx->port, 0, true);
	for (int part = 0; part < 5; part++) {
		int w, h, sub, cs;

		seq = read_part(rd, jpeg, sizeof(jpeg), &len);
		assert_true(seq > last); /* each part a newer frame */
		last = seq;
		assert_int_equal(tjDecompressHeader3(tj, jpeg, len, &w, &h, &sub, &cs), 0);
		assert_int_equal(w, W);
		assert_int_equal(h, H);
		assert_int_equal(tjDecompress2(tj, jpeg, len, rgb, W, 0, H, TJPF_RGB, 0), 0);
		/* The bright bar sits where frame seq put it, not where the next one would. */
		assert_true(column_mean(rgb, bar_x(seq)) > 200.0);
		assert_true(column_mean(rgb, bar_x(seq + 16)) < 80.0);
	}
	hl_http_counts(fx->http, &c);
	assert_int_equal(c.mjpeg_clients, 1);
	assert_true(c.mjpeg_frames_sent >= 5);
	close_stream(rd);
	atomic_store(&pub.stop, true);
	pthread_join(pub.thread, NULL);
	tjDestroy(tj);
	/* The server notices the closed client at its next part (waited for, not timed). */
	for (double until = now_s() + WAIT_S; now_s() < until;) {
		publish(fx->pool);
		hl_http_counts(fx->http, &c);
		if (c.mjpeg_clients == 0)
			break;
		sleep_ms(20);
	}
	assert_int_equal(c.mjpeg_clients, 0);
	stop(fx);
}

static void http_stalled_stream_client_delays_nobody(void **state)
{
	struct fixture *fx = start(false);
	struct publisher pub = { .pool = fx->pool, .period_ms = 20 };
	static uint8_t jpeg[1 << 18];
	struct hl_frame_pool_counts pc0, pc1;
	struct hl_http_counts c;
	struct reader *stalled, *live;
	uint64_t seq, first, prev;
	double t0, dt;
	size_t len;
	int parts = 0;
	bool gap = false;

	(void)state;
	assert_int_equal(pthread_create(&pub.thread, NULL, publisher_main, &pub), 0);
	/* A small receive buffer, and never read: the server's sends to it block. */
	stalled = open_stream(fx->port, 4096, false);
	sleep_ms(1000);
	live = open_stream(fx->port, 0, true);
	hl_frame_pool_counts(fx->pool, &pc0);
	/* 100 parts for the live client, however long a busy machine takes: each a newer frame */
	t0 = now_s();
	first = read_part(live, jpeg, sizeof(jpeg), &len);
	seq = first;
	while (parts < 100) {
		prev = seq;
		seq = read_part(live, jpeg, sizeof(jpeg), &len);
		assert_true(seq > prev);
		parts++;
	}
	dt = now_s() - t0;
	hl_frame_pool_counts(fx->pool, &pc1);
	hl_http_counts(fx->http, &c);
	assert_int_equal(c.mjpeg_clients, 2);
	/* The publisher always found a free frame: the stalled client holds none. How many of
	 * the published frames the live client got depends on the load, so it is only printed. */
	assert_int_equal(pc1.no_free_frame, 0);
	print_message("published %llu in %.2f s; the live client got %d parts, seq %llu..%llu\n",
		      (unsigned long long)(pc1.published - pc0.published), dt, parts,
		      (unsigned long long)first, (unsigned long long)seq);

	/*
	 * The stalled client skipped frames: once it reads, its parts jump in seq (its thread sat
	 * in a blocked send while frames were published, and then took the newest).
	 */
	{
		char head[1024];
		size_t n = read_until(stalled, "\r\n\r\n");

		assert_true(n < sizeof(head));
		stalled->start += n + 4;
		read_n(stalled, 11);
		stalled->start += 11;
	}
	prev = read_part(stalled, jpeg, sizeof(jpeg), &len);
	for (int i = 0; i < 400 && !gap; i++) {
		seq = read_part(stalled, jpeg, sizeof(jpeg), &len);
		gap = seq > prev + 1;
		prev = seq;
	}
	assert_true(gap);
	hl_http_counts(fx->http, &c);
	assert_true(c.mjpeg_frames_skipped > 0);
	close_stream(stalled);
	close_stream(live);
	atomic_store(&pub.stop, true);
	pthread_join(pub.thread, NULL);
	stop(fx);
}

static void http_capture_only_when_allowed(void **state)
{
	struct fixture *fx = start(false);
	struct response r;
	char want[600], text[64];
	FILE *f;

	(void)state;
	check(fx->port, "POST", "/capture", 403, "application/json", &r);
	assert_string_equal(
		(char *)r.body,
		"{\"error\":\"captures are disabled (config: http.capture = false)\"}\n");
	free(r.body);
	assert_int_equal(atomic_load(&fx->captures), 0);
	stop(fx);

	fx = start(true);
	check(fx->port, "POST", "/capture", 200, "application/json", &r);
	snprintf(want, sizeof(want), "{\"path\":\"%s\"}\n", fx->capture_path);
	assert_string_equal((char *)r.body, want);
	free(r.body);
	assert_int_equal(atomic_load(&fx->captures), 1);
	f = fopen(fx->capture_path, "r");
	assert_non_null(f);
	assert_non_null(fgets(text, sizeof(text), f));
	fclose(f);
	assert_string_equal(text, "capture 1\n");
	check(fx->port, "PUT", "/capture", 405, "text/plain; charset=utf-8", &r);
	free(r.body);
	assert_int_equal(atomic_load(&fx->captures), 1);
	stop(fx);
}

/* A capture that failed or was not taken: the status says which, the body why (escaped). */
static void http_capture_failure_says_why(void **state)
{
	static const struct {
		int rc;
		int status;
	} cases[] = { { -ENOSPC, 507 }, { -EFBIG, 507 }, { -EDQUOT, 507 }, { -EIO, 500 },
		      { -EACCES, 500 }, { -EBUSY, 503 }, { -EAGAIN, 503 }, { -ETIMEDOUT, 504 } };
	struct fixture *fx = start(true);
	struct response r;
	char want[600];

	(void)state;
	for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
		fx->capture_rc = cases[i].rc;
		check(fx->port, "POST", "/capture", cases[i].status, "application/json", &r);
		snprintf(want, sizeof(want),
			 "{\"error\":\"'/c/.tmp-frame-1/hdr.exr': cannot write (\\\"%s\\\")\"}\n",
			 strerror(-cases[i].rc));
		assert_string_equal((char *)r.body, want);
		free(r.body);
	}
	stop(fx);
}

/* HL_HTTP_MAX_STREAMS streams share one JPEG per frame; one more is a counted 503. */
static void http_streams_share_one_jpeg_and_are_limited(void **state)
{
	struct fixture *fx = start(false);
	static uint8_t jpeg[1 << 18];
	struct reader *rd[HL_HTTP_MAX_STREAMS];
	struct hl_http_counts c;
	struct response r;
	char v[64];
	size_t len;

	(void)state;
	publish(fx->pool);
	for (int i = 0; i < HL_HTTP_MAX_STREAMS; i++) {
		rd[i] = open_stream(fx->port, 0, true);
		assert_int_equal(read_part(rd[i], jpeg, sizeof(jpeg), &len), 1);
	}
	check(fx->port, "GET", "/stream.mjpg", 503, "application/json", &r);
	assert_string_equal(header(r.head, "Retry-After", v, sizeof(v)), "1");
	free(r.body);
	hl_http_counts(fx->http, &c);
	assert_int_equal(c.mjpeg_clients, HL_HTTP_MAX_STREAMS);
	assert_int_equal(c.overloaded, 1);
	assert_int_equal(c.encoded[HL_IMAGE_JPEG], 1); /* one JPEG for all the streams */
	assert_int_equal(c.connections_refused + c.header_timeouts, 0);
	for (int i = 0; i < HL_HTTP_MAX_STREAMS; i++)
		close_stream(rd[i]);
	stop(fx);
}

static void http_free_ends_streams_promptly(void **state)
{
	struct fixture *fx = start(false);
	static uint8_t jpeg[1 << 18];
	struct reader *rd, *stalled;
	char tail[4096];
	size_t len;
	double t0;
	ssize_t k;

	(void)state;
	publish(fx->pool);
	rd = open_stream(fx->port, 0, true);
	assert_int_equal(read_part(rd, jpeg, sizeof(jpeg), &len), 1);
	stalled = open_stream(fx->port, 4096, false);
	sleep_ms(200);
	/* rd now waits for a frame that never comes; free must not wait for one. */
	t0 = now_s();
	hl_http_free(fx->http);
	fx->http = NULL;
	/* it returns, not waiting for a frame (how fast is the machine's business) */
	assert_true(now_s() - t0 < WAIT_S);
	while ((k = recv(rd->fd, tail, sizeof(tail), 0)) > 0)
		;
	assert_int_equal(k, 0); /* closed, not timed out */
	close_stream(rd);
	close_stream(stalled);
	stop(fx);
}

static void http_closed_pool_ends_streams(void **state)
{
	struct fixture *fx = start(false);
	static uint8_t jpeg[1 << 18];
	struct hl_http_counts c;
	struct reader *rd;
	char tail[4096];
	size_t len;
	double t0;
	ssize_t k;

	(void)state;
	publish(fx->pool);
	rd = open_stream(fx->port, 0, true);
	assert_int_equal(read_part(rd, jpeg, sizeof(jpeg), &len), 1);
	/* The daemon shuts down its renderer first: the stream ends, the server stays up. */
	t0 = now_s();
	hl_frame_pool_close(fx->pool);
	while ((k = recv(rd->fd, tail, sizeof(tail), 0)) > 0)
		;
	assert_int_equal(k, 0);
	assert_true(now_s() - t0 < WAIT_S); /* ended, not left waiting for a frame */
	close_stream(rd);
	for (double until = now_s() + WAIT_S; now_s() < until;) {
		hl_http_counts(fx->http, &c);
		if (c.mjpeg_clients == 0)
			break;
		sleep_ms(20);
	}
	assert_int_equal(c.mjpeg_clients, 0);
	stop(fx);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(http_new_rejects_bad_input_and_a_busy_port),
		cmocka_unit_test(http_routes_answer_with_status_and_type),
		cmocka_unit_test(http_frame_png_is_the_newest_frame_losslessly),
		cmocka_unit_test(http_hdr_frames_are_tone_mapped),
		cmocka_unit_test(http_frame_exr_is_the_lux_image),
		cmocka_unit_test(http_mjpeg_stream_follows_the_publisher),
		cmocka_unit_test(http_stalled_stream_client_delays_nobody),
		cmocka_unit_test(http_capture_only_when_allowed),
		cmocka_unit_test(http_capture_failure_says_why),
		cmocka_unit_test(http_streams_share_one_jpeg_and_are_limited),
		cmocka_unit_test(http_free_ends_streams_promptly),
		cmocka_unit_test(http_closed_pool_ends_streams),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
