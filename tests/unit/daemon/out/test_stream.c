/* SPDX-License-Identifier: MIT */
/*
 * daemon/out/stream.c: a real stream server (TCP on 127.0.0.1:0 or a Unix socket in the test
 * directory) fed from a frame pool by this thread, the publisher. Every check is on exact
 * bytes, sequence numbers and the stream's counters; waits are for events, with a generous
 * limit that only a broken stream reaches, never for "long enough".
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <sys/un.h>
#include <time.h>
#include <unistd.h>
#include <cmocka.h>

#include "can/candump_log.h"
#include "daemon/core/frame_pool.h"
#include "daemon/out/stream.h"
#include "testutil.h"
#include "base/clock.h"

#define WAIT_MS 20000 /* only a broken stream takes this long to reach an expected count */
#define NO_STALL_MS 600000 /* stall timeout of the cases that do not test it */
#define HDR sizeof(struct hl_frame_header)

struct fixture {
	struct hl_frame_pool *pool;
	struct hl_stream *stream;
	char unix_path[108];
	int port;
};

static struct fixture *start_with(const struct hl_frame_shape *shape, int n_frames, bool raw,
				  int max_clients, int stall_timeout_ms)
{
	struct fixture *fx = calloc(1, sizeof(*fx));
	char err[256] = "";

	assert_non_null(fx);
	assert_int_equal(hl_frame_pool_new(n_frames, shape, &fx->pool), 0);
	test_path(fx->unix_path, sizeof(fx->unix_path), "stream.sock");
	if (hl_stream_new("127.0.0.1:0", fx->unix_path, raw, max_clients, stall_timeout_ms,
			  fx->pool, &fx->stream, err, sizeof(err)) < 0)
		fail_msg("hl_stream_new: %s", err);
	fx->port = hl_stream_tcp_port(fx->stream);
	assert_true(fx->port > 0);
	assert_int_equal(hl_stream_start(fx->stream, 0), 0);
	return fx;
}

static struct fixture *start(const struct hl_frame_shape *shape, int n_frames, bool raw,
			     int max_clients)
{
	return start_with(shape, n_frames, raw, max_clients, NO_STALL_MS);
}

static void stop(struct fixture *fx)
{
	hl_stream_free(fx->stream);
	hl_frame_pool_free(fx->pool);
	free(fx);
}

static const struct hl_frame_shape small = { .width = 7,
					     .height = 5,
					     .format = HL_PIXEL_RGB8,
					     .n_lamps = 2,
					     .n_sources = 1,
					     .dist_width = 1,
					     .dist_height = 1 };

/* Far larger than any socket buffer, so a client that does not read stalls mid-frame. */
static const struct hl_frame_shape big = { .width = 1024,
					   .height = 512,
					   .format = HL_PIXEL_RGBA16F,
					   .n_lamps = 1,
					   .n_sources = 1,
					   .dist_width = 1,
					   .dist_height = 1 };

static uint8_t pixel(uint64_t seq, size_t i)
{
	return (uint8_t)(seq * 31 + i * 7 + (i >> 8));
}

/* Publishes frame number seq (the pool numbers them 1, 2, ...) with known contents. */
static void publish(struct fixture *fx, uint64_t seq)
{
	struct hl_frame *f = hl_frame_pool_acquire(fx->pool);

	assert_non_null(f); /* the publisher never waits for a stream client */
	for (size_t i = 0; i < f->hdr.payload_size; i++)
		f->pixels[i] = pixel(seq, i);
	f->hdr.flags = (uint32_t)seq & 0xf;
	f->hdr.t_cycle_rx_ns = 1700000000000000000 + (int64_t)seq;
	f->hdr.t_cycle_done_ns = 1000 + (int64_t)seq;
	f->hdr.t_render_start_ns = 2000 + (int64_t)seq;
	f->hdr.t_render_done_ns = 3000 + (int64_t)seq;
	f->hdr.cycle_seq[0] = seq * 2;
	f->hdr.cycle_seq[1] = seq * 3;
	f->hdr.counter[0] = (uint8_t)(seq % 15);
	f->hdr.counter[1] = (uint8_t)((seq + 1) % 15);
	f->hdr.t_lamp_done_ns[0] = 4000 + (int64_t)seq;
	f->hdr.t_lamp_done_ns[1] = 5000 + (int64_t)seq;
	hl_frame_pool_publish(fx->pool, f);
	assert_int_equal(f->hdr.seq, seq);
	hl_stream_wake(fx->stream);
}

/* --- clients --- */

static void set_timeout(int fd, int rcvbuf)
{
	struct timeval tv = { WAIT_MS / 1000, 0 };

	assert_int_equal(setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv)), 0);
	if (rcvbuf)
		assert_int_equal(setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof(rcvbuf)), 0);
}

static int connect_tcp(const struct fixture *fx)
{
	struct sockaddr_in a = { .sin_family = AF_INET, .sin_port = htons((uint16_t)fx->port) };
	int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);

	assert_true(fd >= 0);
	set_timeout(fd, 0);
	a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
	assert_int_equal(connect(fd, (struct sockaddr *)&a, sizeof(a)), 0);
	return fd;
}

static int connect_unix(const struct fixture *fx, int rcvbuf)
{
	struct sockaddr_un a = { .sun_family = AF_UNIX };
	int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);

	assert_true(fd >= 0);
	set_timeout(fd, rcvbuf);
	snprintf(a.sun_path, sizeof(a.sun_path), "%s", fx->unix_path);
	assert_int_equal(connect(fd, (struct sockaddr *)&a, sizeof(a)), 0);
	return fd;
}

/* Exactly n bytes; 0 when the stream closed the connection before the first. */
static size_t read_exact(int fd, void *buf, size_t n)
{
	size_t got = 0;

	while (got < n) {
		ssize_t k = recv(fd, (uint8_t *)buf + got, n - got, 0);

		if (k == 0 && got == 0)
			return 0;
		if (k <= 0)
			fail_msg("recv: %zd after %zu of %zu bytes (%s)", k, got, n,
				 k < 0 ? strerror(errno) : "closed");
		got += (size_t)k;
	}
	return got;
}

/* The header as the publisher wrote frame seq (t_sent_ns is the stream's). */
static void check_header(const struct hl_frame_header *h, const struct hl_frame_shape *sh,
			 uint64_t seq)
{
	const uint32_t bpp = sh->format == HL_PIXEL_RGBA16F ? 8 : 3;

	assert_int_equal(h->magic, HL_FRAME_MAGIC);
	assert_int_equal(h->version, HL_FRAME_VERSION);
	assert_int_equal(h->header_size, HL_FRAME_HEADER_SIZE);
	assert_int_equal(HL_FRAME_HEADER_SIZE, 192);
	assert_int_equal(HL_FRAME_VERSION, 3);
	assert_int_equal(h->seq, seq);
	assert_int_equal(h->width, sh->width);
	assert_int_equal(h->height, sh->height);
	assert_int_equal(h->stride, sh->width * bpp);
	assert_int_equal(h->pixel_format, sh->format);
	assert_int_equal(h->payload_size, (uint32_t)(sh->width * sh->height) * bpp);
	assert_int_equal(h->flags, seq & 0xf);
	assert_int_equal(h->t_cycle_rx_ns, 1700000000000000000 + (int64_t)seq);
	assert_int_equal(h->t_cycle_done_ns, 1000 + seq);
	assert_int_equal(h->t_render_start_ns, 2000 + seq);
	assert_int_equal(h->t_render_done_ns, 3000 + seq);
	assert_true(h->t_sent_ns > 0);
	assert_int_equal(h->cycle_seq[0], seq * 2);
	assert_int_equal(h->cycle_seq[1], seq * 3);
	assert_int_equal(h->counter[0], seq % 15);
	assert_int_equal(h->counter[1], (seq + 1) % 15);
	assert_int_equal(h->n_lamps, sh->n_lamps);
	assert_int_equal(h->t_lamp_done_ns[0], 4000 + seq);
	assert_int_equal(h->t_lamp_done_ns[1], 5000 + seq);
}

static void check_pixels(const uint8_t *px, size_t n, uint64_t seq)
{
	for (size_t i = 0; i < n; i++)
		if (px[i] != pixel(seq, i))
			fail_msg("frame %llu pixel byte %zu: %u, expected %u",
				 (unsigned long long)seq, i, px[i], pixel(seq, i));
}

/* Reads one whole frame and checks it is frame seq, byte for byte. */
static void read_frame(int fd, const struct hl_frame_shape *sh, uint64_t seq)
{
	struct hl_frame_header h;
	uint8_t *px;

	assert_int_equal(read_exact(fd, &h, HDR), HDR);
	check_header(&h, sh, seq);
	px = malloc(h.payload_size);
	assert_non_null(px);
	assert_int_equal(read_exact(fd, px, h.payload_size), h.payload_size);
	check_pixels(px, h.payload_size, seq);
	free(px);
}

static struct hl_stream_counts counts(struct fixture *fx)
{
	struct hl_stream_counts c;

	hl_stream_counts(fx->stream, &c);
	return c;
}

/* Waits until the stream's counter at offset off reaches want (an event, not a duration). */
#define wait_count(fx, field, want) \
	wait_count_at(fx, offsetof(struct hl_stream_counts, field), #field, want)
static void wait_count_at(struct fixture *fx, size_t off, const char *name, uint64_t want)
{
	const int64_t until = hl_clock_monotonic_ns() + (int64_t)WAIT_MS * 1000000;
	uint64_t v;

	for (;;) {
		struct hl_stream_counts c = counts(fx);

		memcpy(&v, (const char *)&c + off, sizeof(v));
		if (v == want)
			return;
		if (hl_clock_monotonic_ns() > until)
			fail_msg("stream counter %s: %llu, waited for %llu", name,
				 (unsigned long long)v, (unsigned long long)want);
		hl_clock_sleep_until_ns(hl_clock_monotonic_ns() + 1000000, NULL);
	}
}

/* Waits until the stream sent a frame more than sent, or has no client left. */
static void wait_sent_or_gone(struct fixture *fx, uint64_t sent)
{
	const int64_t until = hl_clock_monotonic_ns() + (int64_t)WAIT_MS * 1000000;

	for (;;) {
		struct hl_stream_counts c = counts(fx);

		if (c.frames_sent > sent || c.clients == 0)
			return;
		if (hl_clock_monotonic_ns() > until)
			fail_msg("stream: no frame sent after %llu and %llu clients left",
				 (unsigned long long)sent, (unsigned long long)c.clients);
		hl_clock_sleep_until_ns(hl_clock_monotonic_ns() + 1000000, NULL);
	}
}

/* --- cases --- */

static void stream_reader_gets_exact_headers_and_pixels(void **state)
{
	struct fixture *fx = start(&small, 3, false, 4);
	const size_t frame = HDR + 7 * 5 * 3;
	struct hl_frame_header h;
	struct hl_stream_counts c;
	uint8_t px[7 * 5 * 3];
	int64_t t_before;
	int fd;
	(void)state;

	fd = connect_tcp(fx);
	wait_count(fx, accepted, 1);
	t_before = hl_clock_monotonic_ns();
	publish(fx, 1);
	assert_int_equal(read_exact(fd, &h, HDR), HDR);
	check_header(&h, &small, 1);
	/* t_sent_ns is stamped when the stream takes the frame for this client */
	assert_true(h.t_sent_ns >= t_before && h.t_sent_ns <= hl_clock_monotonic_ns());
	assert_int_equal(read_exact(fd, px, sizeof(px)), sizeof(px));
	check_pixels(px, sizeof(px), 1);
	for (uint64_t seq = 2; seq <= 5; seq++) {
		publish(fx, seq);
		read_frame(fd, &small, seq);
	}
	wait_count(fx, frames_sent, 5);
	c = counts(fx);
	assert_int_equal(c.accepted, 1);
	assert_int_equal(c.refused, 0);
	assert_int_equal(c.clients, 1);
	assert_int_equal(c.frames_skipped, 0);
	assert_int_equal(c.bytes_sent, 5 * frame);
	assert_int_equal(c.input_reads, 0); /* the client sent nothing */
	close(fd);
	stop(fx);
}

static void stream_raw_sends_pixels_only(void **state)
{
	struct fixture *fx = start(&small, 3, true, 4);
	uint8_t px[7 * 5 * 3 + 1];
	int fd;
	(void)state;

	fd = connect_unix(fx, 0);
	wait_count(fx, accepted, 1);
	for (uint64_t seq = 1; seq <= 3; seq++) {
		publish(fx, seq);
		assert_int_equal(read_exact(fd, px, sizeof(px) - 1), sizeof(px) - 1);
		check_pixels(px, sizeof(px) - 1, seq);
	}
	wait_count(fx, frames_sent, 3);
	assert_int_equal(counts(fx).bytes_sent, 3 * (sizeof(px) - 1));
	/* nothing more than the three frames' pixels was sent */
	assert_int_equal(recv(fd, px, sizeof(px), MSG_DONTWAIT), -1);
	assert_int_equal(errno, EAGAIN);
	close(fd);
	stop(fx);
}

/*
 * shutdown(SHUT_WR), as "nc -N" does at the end of its input: the client still reads. The
 * stream reads its EOF once, keeps it and sends every frame; it never reads from it again (a
 * socket at EOF stays readable: polling it for input again would spin the stream thread).
 */
static void half_closed_client(bool tcp, const struct hl_frame_shape *sh)
{
	struct fixture *fx = start(sh, 3, false, 4);
	struct hl_stream_counts c;
	int fd;

	fd = tcp ? connect_tcp(fx) : connect_unix(fx, 0);
	wait_count(fx, accepted, 1);
	publish(fx, 1);
	read_frame(fd, sh, 1);
	assert_int_equal(shutdown(fd, SHUT_WR), 0);
	wait_count(fx, input_eofs, 1);
	for (uint64_t seq = 2; seq <= 20; seq++) {
		publish(fx, seq);
		read_frame(fd, sh, seq);
	}
	wait_count(fx, frames_sent, 20);
	c = counts(fx);
	assert_int_equal(c.input_eofs, 1);
	assert_int_equal(c.input_reads, 1); /* the EOF, and nothing after it */
	assert_int_equal(c.clients, 1);
	assert_int_equal(c.frames_skipped, 0);
	close(fd);
	stop(fx);
}

static void stream_half_closed_unix_client_keeps_receiving(void **state)
{
	(void)state;
	half_closed_client(false, &small);
}

static void stream_half_closed_tcp_client_keeps_receiving(void **state)
{
	(void)state;
	half_closed_client(true, &small);
}

/* Frames larger than the socket buffer: the stream has met EAGAIN before it reads the EOF. */
static void stream_half_closed_client_of_big_frames_keeps_receiving(void **state)
{
	(void)state;
	half_closed_client(false, &big);
}

/*
 * A client that stops reading in the middle of a frame holds no pool frame (its rest is
 * copied), so the publisher always finds a free frame in a pool of two and another client gets
 * every frame; when it reads again it finishes its frame, then gets the newest: the frames in
 * between are skipped and counted exactly.
 */
static void stream_stalled_client_skips_and_never_stalls_the_publisher(void **state)
{
	struct fixture *fx = start(&big, 2, false, 4);
	const size_t payload = (size_t)big.width * big.height * 8;
	const uint64_t last = 12;
	struct hl_frame_pool_counts pc;
	struct hl_frame_header h;
	struct hl_stream_counts c;
	uint8_t *px = malloc(payload);
	int stalled, reader;
	(void)state;

	assert_non_null(px);
	stalled = connect_unix(fx, 4096);
	wait_count(fx, accepted, 1);
	publish(fx, 1);
	/* it has started on frame 1; the rest does not fit its socket: copied, frame released */
	assert_int_equal(read_exact(stalled, &h, HDR), HDR);
	check_header(&h, &big, 1);
	wait_count(fx, frames_copied, 1);

	reader = connect_unix(fx, 0);
	wait_count(fx, accepted, 2);
	read_frame(reader, &big, 1); /* the newest when it came */
	for (uint64_t seq = 2; seq <= last; seq++) {
		publish(fx, seq); /* asserts that a frame was free */
		read_frame(reader, &big, seq);
	}
	hl_frame_pool_counts(fx->pool, &pc);
	assert_int_equal(pc.published, last);
	assert_int_equal(pc.no_free_frame, 0);

	/* the stalled client reads again: the rest of frame 1, then the newest */
	assert_int_equal(read_exact(stalled, px, payload), payload);
	check_pixels(px, payload, 1);
	read_frame(stalled, &big, last);
	wait_count(fx, frames_sent, last + 2); /* the reader's every frame, the stalled one's 2 */
	c = counts(fx);
	assert_int_equal(c.frames_skipped, last - 2);
	assert_int_equal(c.clients, 2);
	assert_int_equal(c.bytes_sent, (last + 2) * (HDR + payload));
	free(px);
	close(stalled);
	close(reader);
	stop(fx);
}

/* A client that goes away is dropped and counted, whether it closes or resets. */
static void stream_disconnects_are_counted(void **state)
{
	struct fixture *fx = start(&small, 3, false, 4);
	const struct linger reset = { .l_onoff = 1, .l_linger = 0 };
	struct hl_stream_counts c;
	uint64_t seq = 0;
	int fd;
	(void)state;

	/* Unix: the stream sees the hang-up at once */
	fd = connect_unix(fx, 0);
	wait_count(fx, accepted, 1);
	publish(fx, ++seq);
	read_frame(fd, &small, seq);
	close(fd);
	wait_count(fx, clients, 0);

	/* TCP reset (SO_LINGER 0): an error on the stream's side at once */
	fd = connect_tcp(fx);
	wait_count(fx, accepted, 2);
	read_frame(fd, &small, seq); /* a new client starts with the newest frame */
	assert_int_equal(setsockopt(fd, SOL_SOCKET, SO_LINGER, &reset, sizeof(reset)), 0);
	close(fd);
	wait_count(fx, clients, 0);

	/* TCP close: a FIN, which alone may be a half-close; the next frames sent find it gone */
	fd = connect_tcp(fx);
	wait_count(fx, accepted, 3);
	read_frame(fd, &small, seq);
	close(fd);
	wait_count(fx, input_eofs, 1);
	for (int i = 0; i < 100 && counts(fx).clients > 0; i++) {
		const uint64_t sent = counts(fx).frames_sent;

		publish(fx, ++seq);
		wait_sent_or_gone(fx, sent);
	}
	c = counts(fx);
	assert_int_equal(c.clients, 0);
	assert_int_equal(c.accepted, 3);
	assert_int_equal(c.refused, 0);
	stop(fx);
}

static void stream_rejects_clients_over_the_limit(void **state)
{
	struct fixture *fx = start(&small, 3, false, 1);
	struct hl_stream_counts c;
	uint8_t b;
	int first, second;
	(void)state;

	first = connect_unix(fx, 0);
	wait_count(fx, accepted, 1);
	second = connect_unix(fx, 0);
	wait_count(fx, refused, 1);
	assert_int_equal(recv(second, &b, 1, 0), 0); /* closed by the stream */
	publish(fx, 1);
	read_frame(first, &small, 1);
	c = counts(fx);
	assert_int_equal(c.accepted, 1);
	assert_int_equal(c.clients, 1);
	close(second);
	close(first);
	stop(fx);
}

/* Reads what is queued until the stream's close: the bytes read (EOF or reset ends it). */
static size_t read_to_close(int fd)
{
	static uint8_t sink[65536];
	size_t total = 0;

	for (;;) {
		const ssize_t k = recv(fd, sink, sizeof(sink), 0);

		if (k == 0 || (k < 0 && errno == ECONNRESET))
			return total;
		if (k < 0)
			fail_msg("recv: %s, expected the stream to close", strerror(errno));
		total += (size_t)k;
	}
}

/*
 * The stream takes no input: a client that sends a byte is dropped at once (over TCP with a
 * reset), counted as input; a reader beside it gets every frame.
 */
static void stream_client_that_sends_is_dropped(void **state)
{
	struct fixture *fx = start(&small, 3, false, 4);
	struct hl_stream_counts c;
	int reader, tcp, unx;
	char b;
	(void)state;

	reader = connect_unix(fx, 0);
	tcp = connect_tcp(fx);
	unx = connect_unix(fx, 0);
	wait_count(fx, accepted, 3);
	publish(fx, 1);
	read_frame(reader, &small, 1);
	read_frame(tcp, &small, 1);
	read_frame(unx, &small, 1);
	assert_int_equal(send(tcp, "x", 1, MSG_NOSIGNAL), 1);
	wait_count(fx, dropped[HL_STREAM_DROP_INPUT], 1);
	assert_int_equal(recv(tcp, &b, 1, 0), -1);
	assert_int_equal(errno, ECONNRESET);
	assert_int_equal(send(unx, "GET / HTTP/1.0\r\n\r\n", 18, MSG_NOSIGNAL), 18);
	wait_count(fx, dropped[HL_STREAM_DROP_INPUT], 2);
	assert_int_equal(read_to_close(unx), 0); /* reset: it closed with input unread */
	for (uint64_t seq = 2; seq <= 4; seq++) {
		publish(fx, seq);
		read_frame(reader, &small, seq);
	}
	wait_count(fx, frames_sent, 6);
	c = counts(fx);
	assert_int_equal(c.clients, 1);
	assert_int_equal(c.accepted, 3);
	assert_int_equal(c.dropped[HL_STREAM_DROP_INPUT], 2);
	assert_int_equal(c.dropped[HL_STREAM_DROP_DISCONNECTED], 0);
	assert_int_equal(c.dropped[HL_STREAM_DROP_STALLED], 0);
	assert_int_equal(c.dropped[HL_STREAM_DROP_EVICTED], 0);
	assert_int_equal(c.input_reads, 2); /* one byte of each: enough to know */
	assert_int_equal(c.frames_skipped, 0);
	close(tcp);
	close(unx);
	close(reader);
	stop(fx);
}

/*
 * A client that takes no byte of its frame for stall_timeout_ms is dropped, no sooner (judged
 * by the stream's own t_sent_ns: its last byte went after that); a client with nothing to take
 * stays however long it waits.
 */
static void stream_stalled_client_is_dropped_after_the_timeout(void **state)
{
	const int64_t stall_ms = 300;
	struct fixture *fx = start_with(&big, 4, false, 4, (int)stall_ms);
	const size_t frame = HDR + (size_t)big.width * big.height * 8;
	struct hl_frame_header h;
	struct hl_stream_counts c;
	int64_t t_dropped;
	size_t got;
	int idle, stalled;
	(void)state;

	idle = connect_unix(fx, 0);
	stalled = connect_unix(fx, 4096);
	wait_count(fx, accepted, 2);
	publish(fx, 1);
	read_frame(idle, &big, 1);
	assert_int_equal(read_exact(stalled, &h, HDR), HDR);
	check_header(&h, &big, 1);
	wait_count(fx, dropped[HL_STREAM_DROP_STALLED], 1);
	t_dropped = hl_clock_monotonic_ns();
	assert_true(t_dropped - h.t_sent_ns >= stall_ms * 1000000);
	got = read_to_close(stalled);
	assert_true(got > 0 && got < frame - HDR); /* what was queued, then the end */
	c = counts(fx);
	assert_int_equal(c.clients, 1);
	assert_int_equal(c.accepted, 2);
	assert_int_equal(c.dropped[HL_STREAM_DROP_STALLED], 1);
	assert_int_equal(c.dropped[HL_STREAM_DROP_DISCONNECTED], 0);
	/* the idle client waited as long with nothing to take: still there */
	publish(fx, 2);
	read_frame(idle, &big, 2);
	assert_int_equal(counts(fx).clients, 1);
	close(stalled);
	close(idle);
	stop(fx);
}

/*
 * All slots taken: a new client replaces the client behind (still sending a frame
 * HL_STREAM_BEHIND_FRAMES older than the newest) that took no byte for longest; with no client
 * behind it is refused, closed at once. The evicted client's connection ends after what was
 * queued; the other one finishes its frame and gets the newest.
 */
static void stream_new_client_replaces_the_client_stalled_longest(void **state)
{
	struct fixture *fx = start(&big, 8, false, 2);
	const size_t frame = HDR + (size_t)big.width * big.height * 8;
	struct hl_stream_counts c;
	int first, second, refused, third;
	size_t got;
	char b;
	(void)state;

	assert_int_equal(HL_STREAM_BEHIND_FRAMES, 3);
	first = connect_unix(fx, 0);
	wait_count(fx, accepted, 1);
	publish(fx, 1);
	wait_count(fx, frames_copied, 1); /* first stalls in frame 1 */
	second = connect_unix(fx, 0);
	wait_count(fx, accepted, 2);
	wait_count(fx, frames_copied, 2); /* second too, later */
	publish(fx, 2);
	publish(fx, 3); /* two newer frames: not behind yet */
	refused = connect_unix(fx, 0);
	wait_count(fx, refused, 1);
	assert_int_equal(recv(refused, &b, 1, 0), 0);
	publish(fx, 4); /* three: both behind, first for longer */
	wait_count(fx, clients_behind, 2);
	third = connect_unix(fx, 0);
	wait_count(fx, dropped[HL_STREAM_DROP_EVICTED], 1);
	read_frame(third, &big, 4);
	got = read_to_close(first);
	assert_true(got > 0 && got < frame);
	read_frame(second, &big, 1);
	read_frame(second, &big, 4);
	wait_count(fx, frames_sent, 3);
	c = counts(fx);
	assert_int_equal(c.accepted, 3);
	assert_int_equal(c.refused, 1);
	assert_int_equal(c.clients, 2);
	assert_int_equal(c.dropped[HL_STREAM_DROP_EVICTED], 1);
	assert_int_equal(c.dropped[HL_STREAM_DROP_STALLED], 0);
	assert_int_equal(c.dropped[HL_STREAM_DROP_DISCONNECTED], 0);
	assert_int_equal(c.frames_skipped, 2); /* second: 2 and 3 */
	close(first);
	close(second);
	close(refused);
	close(third);
	stop(fx);
}

static void stream_new_rejects_bad_addresses(void **state)
{
	struct hl_frame_pool *pool;
	struct hl_stream *s = NULL;
	char err[256] = "";
	(void)state;

	assert_int_equal(hl_frame_pool_new(2, &small, &pool), 0);
	assert_int_equal(hl_stream_new("localhost", "", false, 1, 2000, pool, &s, err, sizeof(err)),
			 -EINVAL);
	assert_string_equal(err, "stream.tcp 'localhost': expected host:port");
	assert_int_equal(hl_stream_new("127.0.0.1:0", "", false, 0, 2000, pool, &s, err,
				       sizeof(err)),
			 -EINVAL);
	assert_string_equal(err, "stream.max_clients: expected 1..64");
	assert_int_equal(hl_stream_new("127.0.0.1:0", "", false, 1, 0, pool, &s, err, sizeof(err)),
			 -EINVAL);
	assert_string_equal(err, "stream.stall_timeout_ms: expected >= 1, found 0");
	assert_null(s);
	hl_frame_pool_free(pool);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(stream_reader_gets_exact_headers_and_pixels),
		cmocka_unit_test(stream_raw_sends_pixels_only),
		cmocka_unit_test(stream_half_closed_unix_client_keeps_receiving),
		cmocka_unit_test(stream_half_closed_tcp_client_keeps_receiving),
		cmocka_unit_test(stream_half_closed_client_of_big_frames_keeps_receiving),
		cmocka_unit_test(stream_stalled_client_skips_and_never_stalls_the_publisher),
		cmocka_unit_test(stream_disconnects_are_counted),
		cmocka_unit_test(stream_rejects_clients_over_the_limit),
		cmocka_unit_test(stream_client_that_sends_is_dropped),
		cmocka_unit_test(stream_stalled_client_is_dropped_after_the_timeout),
		cmocka_unit_test(stream_new_client_replaces_the_client_stalled_longest),
		cmocka_unit_test(stream_new_rejects_bad_addresses),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
