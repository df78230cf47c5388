/* SPDX-License-Identifier: MIT */
/* The live ASAM OSI input: see daemon/loop/osi_input.h. */
#include "daemon/loop/osi_input.h"

#include <errno.h>
#include <netinet/in.h>
#include <poll.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "base/addr.h"
#include "base/clock.h"
#include "base/sched.h"
#include "world/osi_udp_frame.h"

#define POLL_MS 100 /* longest wait for a datagram, so that stop is seen */
#define DGRAM_MAX 65536 /* bytes: any UDP datagram */
#define RCVBUF_BYTES (4 << 20) /* a burst of messages while the thread was not running */
#define LOG_EVERY_NS 1000000000LL /* a reason is logged at most once a second */

struct hl_osi_input {
	const struct hl_scenario *base;
	enum hl_osi_kind kind;
	double timeout_s;
	FILE *log;
	int fd;
	uint16_t port;
	char listen[64];
	pthread_t thread;
	bool started;
	atomic_int stop;
	/* the input thread's (the main thread's before it starts) */
	uint8_t *dgram;
	struct hl_osi_udp_reasm *reasm;
	struct hl_osi_frame *frame;
	struct hl_osi_world *world; /* made of the first usable message */
	int64_t last_ns; /* the newest taken message's timestamp */
	char first_why[256]; /* before the world: why the last message made none */
	int64_t logged_ns[HL_OSI_REASONS];
	uint64_t unlogged[HL_OSI_REASONS];
	uint32_t kernel_drops;

	pthread_mutex_t lock; /* PI: the render thread takes it; guards what follows */
	struct hl_world_state latest;
	struct hl_osi_input_counts c;
};

/* Counts n of reason r; logs it with why unless it was logged less than a second ago. */
static void count(struct hl_osi_input *oi, enum hl_osi_reason r, uint64_t n, const char *why,
		  int64_t now_ns)
{
	pthread_mutex_lock(&oi->lock);
	oi->c.reasons[r] += n;
	pthread_mutex_unlock(&oi->lock);
	if (r == HL_OSI_OK || !oi->log || !n)
		return;
	if (oi->logged_ns[r] && now_ns - oi->logged_ns[r] < LOG_EVERY_NS) {
		oi->unlogged[r] += n;
		return;
	}
	fprintf(oi->log, "hdlampd: scene.world 'osi:%s': %s: %s", oi->listen, hl_osi_reason_name(r),
		why);
	if (oi->unlogged[r])
		fprintf(oi->log, " (and %llu more in the second before)",
			(unsigned long long)oi->unlogged[r]);
	fputc('\n', oi->log);
	oi->logged_ns[r] = now_ns;
	oi->unlogged[r] = 0;
}

/*
 * One whole message: decoded, checked against the last one's time, mapped and published. Before
 * the world exists, a usable message makes it (*ret_first_rc: what hl_osi_world_new said).
 */
static void message(struct hl_osi_input *oi, const uint8_t *buf, size_t len, int64_t now_ns)
{
	uint64_t objects[HL_OSI_REASONS] = { 0 };
	struct hl_osi_frame *f = oi->frame;
	struct hl_world_state st;
	enum hl_osi_reason r;
	char why[256];
	int n = 0;

	switch (hl_osi_decode(buf, len, oi->kind, f, why, sizeof(why))) {
	case HL_OSI_DECODE_OK:
		break;
	case HL_OSI_DECODE_TOO_MANY:
		count(oi, HL_OSI_TOO_MANY, 1, why, now_ns);
		return;
	default:
		count(oi, HL_OSI_MALFORMED, 1, why, now_ns);
		return;
	}
	if (!f->has_timestamp) {
		count(oi, HL_OSI_NO_TIMESTAMP, 1, "no timestamp: expected one on every message",
		      now_ns);
		return;
	}
	if (!oi->world) {
		const int rc = hl_osi_world_new(f, oi->base, &oi->world, why, sizeof(why));

		if (rc < 0) { /* counted; the next message may do */
			count(oi,
			      rc == -EINVAL  ? HL_OSI_NO_HOST :
			      rc == -ENOENT  ? HL_OSI_NO_ROAD :
			      rc == -EBADMSG ? HL_OSI_BAD_VALUE :
					       HL_OSI_MALFORMED,
			      1, why, now_ns);
			snprintf(oi->first_why, sizeof(oi->first_why), "%s", why);
			return;
		}
		oi->last_ns = f->t_ns;
	} else if (f->t_ns <= oi->last_ns) {
		snprintf(why, sizeof(why), "timestamp %.9f s: not after the last good one's %.9f s",
			 f->t_ns / 1e9, oi->last_ns / 1e9);
		count(oi, HL_OSI_PAST, 1, why, now_ns);
		return;
	}
	/* live, the scene's time is the simulator's own: the message's timestamp */
	r = hl_osi_world_map(oi->world, f, (double)f->t_ns / 1e9, &st, objects, why, sizeof(why));
	for (int k = 0; k < HL_OSI_REASONS; k++)
		if (objects[k])
			count(oi, (enum hl_osi_reason)k, objects[k], "in a message: left out",
			      now_ns);
	if (r != HL_OSI_OK) {
		count(oi, r, 1, why, now_ns);
		return;
	}
	if ((double)(f->t_ns - oi->last_ns) / 1e9 > HL_OSI_MAX_JUMP_S) {
		snprintf(why, sizeof(why), "%.3f s after the message before (over %g s): taken",
			 (f->t_ns - oi->last_ns) / 1e9, HL_OSI_MAX_JUMP_S);
		count(oi, HL_OSI_TIME_JUMP, 1, why, now_ns);
	}
	oi->last_ns = f->t_ns;
	for (int k = 0; k < st.n_actors; k++)
		n += hl_world_present(&st, k);
	pthread_mutex_lock(&oi->lock);
	oi->latest = st;
	oi->c.have = true;
	oi->c.t_last_ok_ns = now_ns;
	oi->c.t_s = st.t_s;
	oi->c.objects = n;
	oi->c.reasons[HL_OSI_OK]++;
	pthread_mutex_unlock(&oi->lock);
}

/* Reads one datagram (the socket readable) and feeds it on. */
static void receive(struct hl_osi_input *oi)
{
	char ctl[CMSG_SPACE(sizeof(uint32_t))];
	struct iovec iov = { oi->dgram, DGRAM_MAX };
	struct msghdr mh = {
		.msg_iov = &iov, .msg_iovlen = 1, .msg_control = ctl, .msg_controllen = sizeof(ctl)
	};
	const uint8_t *msg;
	size_t msg_len;
	int64_t now;
	char why[128];
	ssize_t n;

	/* MSG_TRUNC: the datagram's real length, so an over-long one is told apart */
	n = recvmsg(oi->fd, &mh, MSG_TRUNC | MSG_DONTWAIT);
	if (n < 0)
		return; /* EAGAIN, EINTR: nothing to count */
	now = hl_clock_monotonic_ns();
	for (struct cmsghdr *cm = CMSG_FIRSTHDR(&mh); cm; cm = CMSG_NXTHDR(&mh, cm))
		if (cm->cmsg_level == SOL_SOCKET && cm->cmsg_type == SO_RXQ_OVFL) {
			uint32_t drops;

			memcpy(&drops, CMSG_DATA(cm), sizeof(drops));
			pthread_mutex_lock(&oi->lock);
			oi->c.socket_drops = drops; /* the kernel's running count */
			pthread_mutex_unlock(&oi->lock);
		}
	pthread_mutex_lock(&oi->lock);
	oi->c.datagrams++;
	pthread_mutex_unlock(&oi->lock);
	if (n > DGRAM_MAX) {
		snprintf(why, sizeof(why), "a datagram of %zd bytes; at most %d", n, DGRAM_MAX);
		count(oi, HL_OSI_TOO_LARGE, 1, why, now);
		return;
	}
	switch (hl_osi_udp_reasm_feed(oi->reasm, oi->dgram, (size_t)n, &msg, &msg_len)) {
	case HL_OSI_UDP_MESSAGE:
		message(oi, msg, msg_len, now);
		break;
	case HL_OSI_UDP_PART:
		break;
	case HL_OSI_UDP_TOO_LARGE:
		count(oi, HL_OSI_TOO_LARGE, 1, "a message over 16 MiB: dropped", now);
		break;
	case HL_OSI_UDP_BAD_HEADER:
		snprintf(why, sizeof(why),
			 "a datagram of %zd bytes without esmini's header (int32 part counter, "
			 "uint32 size = the bytes after it): ignored",
			 n);
		count(oi, HL_OSI_BAD_FRAMING, 1, why, now);
		break;
	case HL_OSI_UDP_OUT_OF_ORDER:
		count(oi, HL_OSI_BAD_FRAMING, 1,
		      "a part that is not the next of the message in progress (lost, repeated "
		      "or reordered): the message dropped",
		      now);
		break;
	}
}

static void *thread_main(void *arg)
{
	struct hl_osi_input *oi = arg;

	pthread_setname_np(pthread_self(), "hl-osi");
	while (!atomic_load(&oi->stop)) {
		struct pollfd pfd = { .fd = oi->fd, .events = POLLIN };

		if (poll(&pfd, 1, POLL_MS) > 0)
			receive(oi);
	}
	return NULL;
}

int hl_osi_input_new(const char *listen, enum hl_osi_kind kind, const struct hl_scenario *base,
		     double timeout_s, FILE *log, struct hl_osi_input **ret, char *err,
		     size_t err_size)
{
	const int one = 1, rcvbuf = RCVBUF_BYTES;
	struct sockaddr_storage ss;
	struct hl_osi_input *oi;
	socklen_t len;
	int rc;

	if (strncmp(listen, "udp:", 4) != 0 || hl_addr_parse(listen + 4, &ss, NULL) < 0) {
		snprintf(err, err_size, "scene.world 'osi:%s': expected osi:udp:HOST:PORT", listen);
		return -EINVAL;
	}
	oi = calloc(1, sizeof(*oi));
	if (!oi)
		return -ENOMEM;
	oi->base = base;
	oi->kind = kind;
	oi->timeout_s = timeout_s;
	oi->log = log;
	oi->fd = -1;
	snprintf(oi->listen, sizeof(oi->listen), "%s", listen);
	atomic_init(&oi->stop, 0);
	oi->dgram = malloc(DGRAM_MAX);
	oi->frame = hl_osi_frame_new();
	rc = oi->dgram && oi->frame ? hl_osi_udp_reasm_new(HL_OSI_UDP_MSG_DEFAULT, &oi->reasm) :
				      -ENOMEM;
	if (rc == 0)
		rc = hl_mutex_init_pi(&oi->lock);
	if (rc < 0) {
		snprintf(err, err_size, "scene.world 'osi:%s': %s", listen, strerror(-rc));
		hl_osi_udp_reasm_free(oi->reasm);
		hl_osi_frame_free(oi->frame);
		free(oi->dgram);
		free(oi);
		return rc;
	}
	oi->fd = socket(ss.ss_family, SOCK_DGRAM | SOCK_CLOEXEC, 0);
	len = ss.ss_family == AF_INET6 ? sizeof(struct sockaddr_in6) : sizeof(struct sockaddr_in);
	if (oi->fd < 0 || bind(oi->fd, (struct sockaddr *)&ss, len) < 0 ||
	    getsockname(oi->fd, (struct sockaddr *)&ss, &len) < 0) {
		rc = -errno;
		snprintf(err, err_size, "scene.world 'osi:%s': %s", listen, strerror(errno));
		hl_osi_input_free(oi);
		return rc;
	}
	/* best effort: a larger buffer and the kernel's drop count; neither is fatal */
	(void)setsockopt(oi->fd, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof(rcvbuf));
	(void)setsockopt(oi->fd, SOL_SOCKET, SO_RXQ_OVFL, &one, sizeof(one));
	oi->port = ntohs(ss.ss_family == AF_INET6 ? ((struct sockaddr_in6 *)&ss)->sin6_port :
						    ((struct sockaddr_in *)&ss)->sin_port);
	*ret = oi;
	return 0;
}

int hl_osi_input_first(struct hl_osi_input *oi, double wait_s, char *err, size_t err_size)
{
	const int64_t end = hl_clock_monotonic_ns() + (int64_t)(wait_s * 1e9);

	while (!oi->world) {
		const int64_t left_ms = (end - hl_clock_monotonic_ns()) / 1000000;
		struct pollfd pfd = { .fd = oi->fd, .events = POLLIN };

		if (left_ms <= 0) {
			snprintf(err, err_size,
				 "scene.world 'osi:%s': no usable OSI message in %g s on port %u "
				 "(a host vehicle, a timestamp and, without scene.scenario, lane "
				 "boundaries)%s%s",
				 oi->listen, wait_s, oi->port,
				 oi->first_why[0] ? "; the last: " : "", oi->first_why);
			return -ETIMEDOUT;
		}
		if (poll(&pfd, 1, left_ms > 1000 ? 1000 : (int)left_ms) > 0)
			receive(oi);
	}
	return 0;
}

const struct hl_scenario *hl_osi_input_scenario(const struct hl_osi_input *oi)
{
	return oi->world ? hl_osi_world_scenario(oi->world) : NULL;
}

int hl_osi_input_start(struct hl_osi_input *oi)
{
	const int rc = pthread_create(&oi->thread, NULL, thread_main, oi);

	if (rc)
		return -rc;
	oi->started = true;
	return 0;
}

void hl_osi_input_stop(struct hl_osi_input *oi)
{
	if (!oi || !oi->started)
		return;
	atomic_store(&oi->stop, 1);
	pthread_join(oi->thread, NULL);
	oi->started = false;
}

void hl_osi_input_free(struct hl_osi_input *oi)
{
	if (!oi)
		return;
	hl_osi_input_stop(oi);
	if (oi->fd >= 0)
		close(oi->fd);
	pthread_mutex_destroy(&oi->lock);
	hl_osi_world_free(oi->world);
	hl_osi_udp_reasm_free(oi->reasm);
	hl_osi_frame_free(oi->frame);
	free(oi->dgram);
	free(oi);
}

uint16_t hl_osi_input_port(const struct hl_osi_input *oi)
{
	return oi->port;
}

double hl_osi_input_timeout_s(const struct hl_osi_input *oi)
{
	return oi->timeout_s;
}

bool hl_osi_input_latest(struct hl_osi_input *oi, struct hl_world_state *ret, int64_t *ret_rx_ns)
{
	const int64_t now = hl_clock_monotonic_ns();
	bool have;

	pthread_mutex_lock(&oi->lock);
	have = oi->c.have;
	if (have) {
		*ret = oi->latest;
		*ret_rx_ns = oi->c.t_last_ok_ns;
	}
	pthread_mutex_unlock(&oi->lock);
	if (have && (double)(now - *ret_rx_ns) / 1e9 > oi->timeout_s)
		ret->present = ret->lamps_on = 0; /* no world: the ego held, nobody else */
	return have;
}

void hl_osi_input_counts(struct hl_osi_input *oi, struct hl_osi_input_counts *ret)
{
	pthread_mutex_lock(&oi->lock);
	*ret = oi->c;
	pthread_mutex_unlock(&oi->lock);
}
