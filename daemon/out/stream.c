/* SPDX-License-Identifier: MIT */
#include "daemon/out/stream.h"

#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <poll.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/uio.h>
#include <sys/un.h>
#include <unistd.h>

#include "base/clock.h"
#include "base/addr.h"
#include "base/sched.h"
#include "daemon/core/sched_start.h"

#define MAX_CLIENTS HL_STREAM_MAX_CLIENTS
#define POLL_MS 100 /* the longest poll: stalls are judged at least this often */

/*
 * A client sends straight from the pool frame it holds (no copy) as long as the socket takes
 * the bytes; when it would block with part of the frame unsent, the rest is copied into buf and
 * the frame released at once, so a slow or stalled client never holds a pool frame.
 */
struct client {
	int fd;
	struct hl_frame *frame; /* the frame being sent, held, or NULL: the rest is in buf */
	struct hl_frame_header hdr; /* its header as sent (t_sent_ns set) */
	uint8_t *buf; /* the frame as sent, header + pixels (raw: pixels only), when copied */
	size_t len, off;
	uint64_t last_seq;
	uint64_t sent, skipped;
	int64_t t_progress_ns; /* the last byte it took, or when its frame was loaded */
	bool eof; /* the client shut down its sending side: no longer polled for input */
};

struct hl_stream {
	struct hl_frame_pool *pool;
	bool subscribed; /* to the pool's published frames */
	bool raw;
	int max_clients;
	int64_t stall_ns; /* a client with a frame to take and no byte taken this long goes */
	int tcp_fd, unix_fd, wake_fd, tcp_port;
	char unix_path[108];
	size_t frame_bytes;
	struct client clients[MAX_CLIENTS];
	pthread_t thread;
	bool started;
	int rt_priority; /* SCHED_FIFO of the stream thread; 0: SCHED_OTHER */
	atomic_int stop;
	pthread_mutex_t lock; /* counts */
	struct hl_stream_counts c;
};

/* HOST:PORT as http.listen takes it (hl_addr_parse: IPv4, [IPv6] or localhost). */
static int listen_tcp(const char *spec, int *ret_port, char *err, size_t err_size)
{
	struct sockaddr_storage addr, ss;
	socklen_t sl = sizeof(ss);
	const int one = 1;
	int fd, rc;

	if (hl_addr_parse(spec, &addr, NULL) < 0) {
		/* config.c checks the value at load and says more */
		snprintf(err, err_size, "stream.tcp '%s': expected host:port", spec);
		return -EINVAL;
	}
	fd = socket(addr.ss_family, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
	if (fd < 0 || setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one)) < 0 ||
	    bind(fd, (const struct sockaddr *)&addr,
		 addr.ss_family == AF_INET6 ? sizeof(struct sockaddr_in6) :
					      sizeof(struct sockaddr_in)) < 0 ||
	    listen(fd, 8) < 0 || getsockname(fd, (struct sockaddr *)&ss, &sl) < 0) {
		rc = -errno;
		snprintf(err, err_size, "stream.tcp '%s': %s", spec, strerror(errno));
		if (fd >= 0)
			close(fd);
		return rc;
	}
	*ret_port = ntohs(ss.ss_family == AF_INET6 ? ((struct sockaddr_in6 *)&ss)->sin6_port :
						     ((struct sockaddr_in *)&ss)->sin_port);
	return fd;
}

/*
 * What is at the socket's path goes only when it is a socket nobody listens on (a stale one of
 * an earlier run): anything else - a file, a directory, a socket in use - is refused, never
 * deleted.
 */
static int remove_stale_socket(const struct sockaddr_un *sa, char *err, size_t err_size)
{
	struct stat st;
	int fd, rc;

	if (lstat(sa->sun_path, &st) < 0) {
		if (errno == ENOENT)
			return 0;
		rc = -errno;
		snprintf(err, err_size, "stream.unix '%s': %s", sa->sun_path, strerror(errno));
		return rc;
	}
	if (!S_ISSOCK(st.st_mode)) {
		snprintf(err, err_size,
			 "stream.unix '%s': exists and is not a socket; refusing to replace it",
			 sa->sun_path);
		return -EEXIST;
	}
	fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
	if (fd < 0) {
		rc = -errno;
		snprintf(err, err_size, "stream.unix: socket: %s", strerror(errno));
		return rc;
	}
	rc = connect(fd, (const struct sockaddr *)sa, sizeof(*sa)) == 0 ? -EADDRINUSE : -errno;
	close(fd);
	if (rc == -EADDRINUSE) {
		snprintf(err, err_size, "stream.unix '%s': another process listens on it",
			 sa->sun_path);
		return rc;
	}
	if (rc != -ECONNREFUSED) {
		snprintf(err, err_size, "stream.unix '%s': %s", sa->sun_path, strerror(-rc));
		return rc;
	}
	if (unlink(sa->sun_path) < 0) { /* stale: nobody listens */
		rc = -errno;
		snprintf(err, err_size, "stream.unix '%s': %s", sa->sun_path, strerror(errno));
		return rc;
	}
	return 0;
}

static int listen_unix(const char *path, char *err, size_t err_size)
{
	struct sockaddr_un sa = { .sun_family = AF_UNIX };
	int fd, rc;

	if (strlen(path) >= sizeof(sa.sun_path)) {
		snprintf(err, err_size, "stream.unix '%s': path too long", path);
		return -EINVAL;
	}
	strcpy(sa.sun_path, path);
	rc = remove_stale_socket(&sa, err, err_size);
	if (rc < 0)
		return rc;
	fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
	if (fd < 0 || bind(fd, (struct sockaddr *)&sa, sizeof(sa)) < 0 || listen(fd, 8) < 0) {
		rc = -errno;
		snprintf(err, err_size, "stream.unix '%s': %s", path, strerror(errno));
		if (fd >= 0)
			close(fd);
		return rc;
	}
	return fd;
}

/* The pool's subscriber: every published frame wakes the stream thread. */
static void on_published(void *userdata, const struct hl_frame *f)
{
	(void)f;
	hl_stream_wake(userdata);
}

int hl_stream_new(const char *tcp, const char *unix_path, bool raw, int max_clients,
		  int stall_timeout_ms, struct hl_frame_pool *pool, struct hl_stream **ret,
		  char *err, size_t err_size)
{
	const struct hl_frame_shape *sh = hl_frame_pool_shape(pool);
	struct hl_stream *s;

	if (max_clients < 1 || max_clients > MAX_CLIENTS) {
		snprintf(err, err_size, "stream.max_clients: expected 1..%d", MAX_CLIENTS);
		return -EINVAL;
	}
	if (stall_timeout_ms < 1) {
		snprintf(err, err_size, "stream.stall_timeout_ms: expected >= 1, found %d",
			 stall_timeout_ms);
		return -EINVAL;
	}
	s = calloc(1, sizeof(*s));
	if (!s)
		return -ENOMEM;
	s->pool = pool;
	s->raw = raw;
	s->max_clients = max_clients;
	s->stall_ns = (int64_t)stall_timeout_ms * 1000000;
	s->tcp_fd = s->unix_fd = -1;
	for (int i = 0; i < MAX_CLIENTS; i++)
		s->clients[i].fd = -1;
	s->frame_bytes = sizeof(struct hl_frame_header) +
			 (size_t)sh->width * sh->height * (sh->format == HL_PIXEL_RGBA16F ? 8 : 3);
	if (hl_mutex_init_pi(&s->lock) < 0) {
		snprintf(err, err_size, "no priority-inheritance mutex (PI futexes)");
		free(s);
		return -ENOTSUP;
	}
	atomic_init(&s->stop, 0);
	s->wake_fd = eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
	if (s->wake_fd < 0) {
		snprintf(err, err_size, "eventfd: %s", strerror(errno));
		hl_stream_free(s);
		return -EIO;
	}
	if (tcp && tcp[0]) {
		s->tcp_fd = listen_tcp(tcp, &s->tcp_port, err, err_size);
		if (s->tcp_fd < 0) {
			int rc = s->tcp_fd;

			hl_stream_free(s);
			return rc;
		}
	}
	if (unix_path && unix_path[0]) {
		s->unix_fd = listen_unix(unix_path, err, err_size);
		if (s->unix_fd < 0) {
			int rc = s->unix_fd;

			hl_stream_free(s);
			return rc;
		}
		snprintf(s->unix_path, sizeof(s->unix_path), "%s", unix_path);
	}
	if (hl_frame_pool_subscribe(pool, on_published, s) < 0) {
		snprintf(err, err_size, "stream: the frame pool has no room for a subscriber");
		hl_stream_free(s);
		return -ENOSPC;
	}
	s->subscribed = true;
	*ret = s;
	return 0;
}

static void release_frame(struct hl_stream *s, struct client *c)
{
	if (c->frame)
		hl_frame_pool_release(s->pool, c->frame);
	c->frame = NULL;
}

const char *hl_stream_drop_name(enum hl_stream_drop why)
{
	static const char *const names[HL_STREAM_DROP_N] = {
		[HL_STREAM_DROP_DISCONNECTED] = "disconnected",
		[HL_STREAM_DROP_STALLED] = "stalled",
		[HL_STREAM_DROP_EVICTED] = "evicted",
		[HL_STREAM_DROP_INPUT] = "input",
	};

	return names[why];
}

static void close_client(struct hl_stream *s, struct client *c)
{
	release_frame(s, c);
	close(c->fd);
	free(c->buf);
	*c = (struct client){ .fd = -1 };
	pthread_mutex_lock(&s->lock);
	s->c.clients--;
	pthread_mutex_unlock(&s->lock);
}

/*
 * Dropped by the stream, not by the peer: a reset (SO_LINGER 0), so what the client did not
 * take is discarded now rather than kept by the kernel for a peer that does not read.
 */
static void drop_client(struct hl_stream *s, struct client *c, enum hl_stream_drop why)
{
	if (why != HL_STREAM_DROP_DISCONNECTED) {
		const struct linger reset = { .l_onoff = 1, .l_linger = 0 };

		/* should it fail, a plain close: the client is dropped all the same */
		setsockopt(c->fd, SOL_SOCKET, SO_LINGER, &reset, sizeof(reset));
	}
	close_client(s, c);
	pthread_mutex_lock(&s->lock);
	s->c.dropped[why]++;
	pthread_mutex_unlock(&s->lock);
}

void hl_stream_free(struct hl_stream *s)
{
	if (!s)
		return;
	if (s->subscribed)
		hl_frame_pool_unsubscribe(s->pool, on_published, s);
	hl_stream_stop(s);
	for (int i = 0; i < MAX_CLIENTS; i++)
		if (s->clients[i].fd >= 0)
			close_client(s, &s->clients[i]);
	if (s->tcp_fd >= 0)
		close(s->tcp_fd);
	if (s->unix_fd >= 0) {
		close(s->unix_fd);
		unlink(s->unix_path);
	}
	if (s->wake_fd >= 0)
		close(s->wake_fd);
	pthread_mutex_destroy(&s->lock);
	free(s);
}

/* Has a frame to take and no byte taken for stall_timeout_ms. */
static bool stalled(const struct hl_stream *s, const struct client *c, int64_t now_ns)
{
	return c->off < c->len && now_ns - c->t_progress_ns >= s->stall_ns;
}

/* Still sending a frame HL_STREAM_BEHIND_FRAMES or more older than the newest (newest_seq). */
static bool behind(const struct client *c, uint64_t newest_seq)
{
	return c->off < c->len && c->hdr.seq + HL_STREAM_BEHIND_FRAMES <= newest_seq;
}

static uint64_t newest_seq(struct hl_stream *s)
{
	struct hl_frame_pool_counts pc;

	hl_frame_pool_counts(s->pool, &pc);
	return pc.published; /* the pool numbers its frames 1, 2, ... */
}

/* The client behind that has taken no byte for longest, or NULL: whom a new client replaces. */
static struct client *longest_stalled(struct hl_stream *s)
{
	const uint64_t newest = newest_seq(s);
	struct client *victim = NULL;

	for (int i = 0; i < MAX_CLIENTS; i++) {
		struct client *c = &s->clients[i];

		if (c->fd >= 0 && behind(c, newest) &&
		    (!victim || c->t_progress_ns < victim->t_progress_ns))
			victim = c;
	}
	return victim;
}

static void accept_client(struct hl_stream *s, int lfd)
{
	const int fd = accept4(lfd, NULL, NULL, SOCK_CLOEXEC | SOCK_NONBLOCK);
	struct client *c = NULL;
	int n = 0;

	if (fd < 0)
		return;
	for (int i = 0; i < MAX_CLIENTS; i++) {
		if (s->clients[i].fd >= 0)
			n++;
		else if (!c)
			c = &s->clients[i];
	}
	if (n >= s->max_clients) {
		struct client *victim = longest_stalled(s);

		if (victim) {
			drop_client(s, victim, HL_STREAM_DROP_EVICTED);
			c = victim;
			n--;
		}
	}
	if (n >= s->max_clients || !c || !(c->buf = malloc(s->frame_bytes))) {
		close(fd);
		pthread_mutex_lock(&s->lock);
		s->c.refused++;
		pthread_mutex_unlock(&s->lock);
		return;
	}
	c->fd = fd;
	pthread_mutex_lock(&s->lock);
	s->c.accepted++;
	s->c.clients++;
	pthread_mutex_unlock(&s->lock);
}

/* A client with nothing pending gets the newest frame, if newer than its last. */
static void load_frame(struct hl_stream *s, struct client *c)
{
	struct hl_frame *f = hl_frame_pool_get(s->pool, c->last_seq, 0);
	struct hl_frame_header h;
	uint64_t skipped = 0;

	if (!f)
		return;
	h = f->hdr;
	h.t_sent_ns = hl_clock_monotonic_ns();
	c->t_progress_ns = h.t_sent_ns;
	c->frame = f;
	c->hdr = h;
	c->len = (s->raw ? 0 : sizeof(h)) + h.payload_size;
	if (c->last_seq)
		skipped = h.seq - c->last_seq - 1;
	c->last_seq = h.seq;
	c->off = 0;
	c->skipped += skipped;
	pthread_mutex_lock(&s->lock);
	s->c.frames_skipped += skipped;
	pthread_mutex_unlock(&s->lock);
}

/* Bytes off .. of the frame as sent: the header (not raw), then the pixels. */
static int frame_iov(const struct hl_stream *s, const struct client *c, struct iovec iov[2])
{
	const size_t head = s->raw ? 0 : sizeof(c->hdr);
	int n = 0;

	if (c->off < head)
		iov[n++] = (struct iovec){ (uint8_t *)&c->hdr + c->off, head - c->off };
	iov[n++] = (struct iovec){ c->frame->pixels + (c->off > head ? c->off - head : 0),
				   c->len - (c->off > head ? c->off : head) };
	return n;
}

/* The unsent rest of the held frame into buf (same offsets), and the frame released. */
static void copy_rest(struct hl_stream *s, struct client *c)
{
	struct iovec iov[2];
	const int n = frame_iov(s, c, iov);
	size_t at = c->off;

	for (int i = 0; i < n; i++) {
		memcpy(c->buf + at, iov[i].iov_base, iov[i].iov_len);
		at += iov[i].iov_len;
	}
	release_frame(s, c);
	pthread_mutex_lock(&s->lock);
	s->c.frames_copied++;
	pthread_mutex_unlock(&s->lock);
}

/*
 * The stream takes no input: a byte from the client drops it (input). recv() returning 0 is
 * not an error: the client shut down its sending side and may still read (a half-close), so it
 * stays and is no longer polled for input (a socket at EOF is readable for ever). A client that
 * closed the connection entirely shows as POLLHUP or as a failing send (or recv). false when it
 * is to be dropped, why in *ret_why.
 */
static bool check_input(struct hl_stream *s, struct client *c, enum hl_stream_drop *ret_why)
{
	char b;
	const ssize_t n = recv(c->fd, &b, 1, MSG_DONTWAIT);
	const bool gone = n < 0 && errno != EAGAIN && errno != EINTR;

	if (n == 0)
		c->eof = true;
	pthread_mutex_lock(&s->lock);
	s->c.input_reads++;
	s->c.input_eofs += n == 0;
	pthread_mutex_unlock(&s->lock);
	if (n > 0 || gone)
		*ret_why = n > 0 ? HL_STREAM_DROP_INPUT : HL_STREAM_DROP_DISCONNECTED;
	return n <= 0 && !gone;
}

/* Sends what the socket takes now; false when the client is gone. */
static bool pump(struct hl_stream *s, struct client *c)
{
	while (c->off < c->len) {
		ssize_t n;

		if (c->frame) {
			struct iovec iov[2];
			struct msghdr m = { .msg_iov = iov };

			m.msg_iovlen = (size_t)frame_iov(s, c, iov);
			n = sendmsg(c->fd, &m, MSG_NOSIGNAL | MSG_DONTWAIT);
		} else {
			n = send(c->fd, c->buf + c->off, c->len - c->off,
				 MSG_NOSIGNAL | MSG_DONTWAIT);
		}
		if (n < 0) {
			if (errno != EAGAIN && errno != EINTR)
				return false;
			if (c->frame && errno == EAGAIN)
				copy_rest(s, c);
			return true;
		}
		c->off += (size_t)n;
		c->t_progress_ns = hl_clock_monotonic_ns();
		pthread_mutex_lock(&s->lock);
		s->c.bytes_sent += (uint64_t)n;
		if (c->off == c->len)
			s->c.frames_sent++;
		pthread_mutex_unlock(&s->lock);
	}
	release_frame(s, c);
	return true;
}

/*
 * Drops the clients stalled for stall_timeout_ms, gives each idle client the newest frame and
 * counts the clients behind; the poll set in pfd/who (after the n entries there), its length.
 */
static nfds_t look_at_clients(struct hl_stream *s, struct pollfd *pfd, struct client **who,
			      nfds_t n)
{
	const int64_t now = hl_clock_monotonic_ns();
	const uint64_t newest = newest_seq(s);
	uint64_t n_behind = 0;

	for (int i = 0; i < MAX_CLIENTS; i++) {
		struct client *c = &s->clients[i];

		if (c->fd < 0)
			continue;
		if (stalled(s, c, now)) {
			drop_client(s, c, HL_STREAM_DROP_STALLED);
			continue;
		}
		if (c->off == c->len)
			load_frame(s, c);
		n_behind += behind(c, newest);
		who[n] = c;
		pfd[n++] = (struct pollfd){ .fd = c->fd,
					    .events = (c->eof ? 0 : POLLIN) |
						      (c->off < c->len ? POLLOUT : 0) };
	}
	pthread_mutex_lock(&s->lock);
	s->c.clients_behind = n_behind;
	pthread_mutex_unlock(&s->lock);
	return n;
}

static void *thread_main(void *arg)
{
	struct hl_stream *s = arg;

	pthread_setname_np(pthread_self(), "hl-stream");
	hl_sched_start_thread("stream", s->rt_priority, stderr);
	while (!atomic_load(&s->stop)) {
		struct pollfd pfd[3 + MAX_CLIENTS];
		struct client *who[3 + MAX_CLIENTS];
		nfds_t n = 0, first;
		uint64_t wakes;

		pfd[n++] = (struct pollfd){ .fd = s->wake_fd, .events = POLLIN };
		if (s->tcp_fd >= 0)
			pfd[n++] = (struct pollfd){ .fd = s->tcp_fd, .events = POLLIN };
		if (s->unix_fd >= 0)
			pfd[n++] = (struct pollfd){ .fd = s->unix_fd, .events = POLLIN };
		first = n;
		n = look_at_clients(s, pfd, who, n);
		if (poll(pfd, n, POLL_MS) <= 0)
			continue;
		/* the clients before the listeners: a new client may take an evicted one's slot */
		for (nfds_t i = first; i < n; i++) {
			struct client *c = who[i];
			enum hl_stream_drop why = HL_STREAM_DROP_DISCONNECTED;
			bool alive = true;

			if (!pfd[i].revents)
				continue;
			if (pfd[i].revents & (POLLERR | POLLHUP))
				alive = false;
			if (alive && (pfd[i].revents & POLLIN))
				alive = check_input(s, c, &why);
			if (alive && (pfd[i].revents & POLLOUT))
				alive = pump(s, c);
			if (!alive)
				drop_client(s, c, why);
		}
		for (nfds_t i = 0; i < first; i++) {
			if (!(pfd[i].revents & POLLIN))
				continue;
			if (pfd[i].fd == s->wake_fd) {
				if (read(s->wake_fd, &wakes, sizeof(wakes)) < 0) {
					/* reset lost: we only poll once more */
				}
			} else if (pfd[i].fd == s->tcp_fd || pfd[i].fd == s->unix_fd) {
				accept_client(s, pfd[i].fd);
			}
		}
	}
	return NULL;
}

int hl_stream_start(struct hl_stream *s, int rt_priority)
{
	int rc;

	s->rt_priority = rt_priority;
	rc = pthread_create(&s->thread, NULL, thread_main, s);

	if (rc)
		return -rc;
	s->started = true;
	return 0;
}

void hl_stream_stop(struct hl_stream *s)
{
	if (!s->started)
		return;
	atomic_store(&s->stop, 1);
	hl_stream_wake(s);
	pthread_join(s->thread, NULL);
	s->started = false;
}

void hl_stream_wake(struct hl_stream *s)
{
	const uint64_t one = 1;

	if (write(s->wake_fd, &one, sizeof(one)) < 0) {
		/* the counter is saturated only if nobody reads: the thread polls every POLL_MS */
	}
}

void hl_stream_counts(struct hl_stream *s, struct hl_stream_counts *ret)
{
	pthread_mutex_lock(&s->lock);
	*ret = s->c;
	pthread_mutex_unlock(&s->lock);
}

int hl_stream_tcp_port(const struct hl_stream *s)
{
	return s->tcp_fd >= 0 ? s->tcp_port : 0;
}
