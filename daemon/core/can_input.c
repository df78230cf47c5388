/* SPDX-License-Identifier: MIT */
#include "daemon/core/can_input.h"

#include <errno.h>
#include <inttypes.h>
#include <poll.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "can/candump_log.h"
#include "can/socket.h"
#include "base/sched.h"
#include "base/clock.h"
#include "daemon/core/sched_start.h"

#define POLL_MAX_MS 100 /* longest wait, so a stop request is seen promptly */
#define MALFORMED_LOGGED 20 /* malformed log lines reported one by one; the rest counted */
#define BACKWARDS_LOGGED 20 /* the same for timestamps going backwards */
#define READ_BATCH 64

struct hl_can_input {
	struct hl_can_input_config cfg;
	struct hl_assembler *a;
	struct hl_ring *ring;
	struct hl_can_socket *sock;
	struct hl_candump_log *log;
	struct hl_snapshot *snap; /* the producer's view of every lamp, pushed on changes */
	pthread_t thread;
	bool started;
	atomic_int stop;
	pthread_mutex_t status_lock;
	struct hl_input_status status;
};

static void update_status(struct hl_can_input *in);

int hl_can_input_new(const struct hl_can_input_config *cfg, struct hl_assembler *a,
		     struct hl_ring *ring, struct hl_can_input **ret)
{
	struct hl_can_input *in = calloc(1, sizeof(*in));
	int rc;

	if (!in)
		return -ENOMEM;
	in->cfg = *cfg;
	in->a = a;
	in->ring = ring;
	atomic_init(&in->stop, 0);
	rc = hl_mutex_init_pi(&in->status_lock);
	if (rc < 0) {
		free(in);
		return rc;
	}
	rc = hl_snapshot_new(ring, &in->snap);
	if (rc == 0 && cfg->replay)
		rc = hl_candump_log_open(cfg->replay, cfg->replay_loop ? cfg->replay_passes : 1,
					 &in->log);
	if (rc == 0 && cfg->iface) {
		/* every lamp message: a filter list cut short would lose its frames unnoticed */
		uint32_t ids[HL_ASM_MAX_IDS];
		const int n = hl_assembler_ids(a, ids, HL_ASM_MAX_IDS);

		rc = n > HL_ASM_MAX_IDS ? -E2BIG : hl_can_socket_new(cfg->iface, ids, n, &in->sock);
	}
	if (rc < 0) {
		hl_can_input_free(in);
		return rc;
	}
	in->snap->status = cfg->replay ? HL_INPUT_LINK_UP : 0;
	in->snap->link_errno = cfg->replay ? 0 : ENETDOWN;
	update_status(in); /* readers see the initial state before the thread runs */
	*ret = in;
	return 0;
}

void hl_can_input_free(struct hl_can_input *in)
{
	if (!in)
		return;
	hl_can_input_stop(in);
	hl_can_socket_free(in->sock);
	hl_candump_log_free(in->log);
	hl_snapshot_free(in->snap);
	pthread_mutex_destroy(&in->status_lock);
	free(in);
}

/* CAN thread: copies what other threads may read. */
static void update_status(struct hl_can_input *in)
{
	struct hl_input_status st = { .n_lamps = hl_assembler_n_lamps(in->a) };

	for (int l = 0; l < st.n_lamps; l++) {
		st.lamps[l] = *hl_assembler_lamp_counters(in->a, l);
		st.stale[l] = hl_assembler_stale(in->a, l);
	}
	st.frames = *hl_assembler_counters(in->a);
	st.link_up = in->snap->status & HL_INPUT_LINK_UP;
	st.link_errno = in->snap->link_errno;
	st.is_socket = in->sock != NULL;
	st.done = in->snap->status & HL_INPUT_DONE;
	if (in->sock) {
		hl_can_socket_stats(in->sock, &st.socket);
		snprintf(st.bus, sizeof(st.bus), "%s", hl_can_bus_state_name(st.socket.bus));
		snprintf(st.iface, sizeof(st.iface), "%s", hl_can_socket_ifname(in->sock));
	} else {
		hl_candump_log_stats(in->log, &st.log);
		snprintf(st.bus, sizeof(st.bus), "replay");
	}
	pthread_mutex_lock(&in->status_lock);
	in->status = st;
	pthread_mutex_unlock(&in->status_lock);
}

void hl_can_input_status(struct hl_can_input *in, struct hl_input_status *ret)
{
	pthread_mutex_lock(&in->status_lock);
	*ret = in->status;
	pthread_mutex_unlock(&in->status_lock);
}

int hl_can_input_filters(const struct hl_can_input *in, const struct can_filter **ret)
{
	*ret = NULL;
	return in->sock ? hl_can_socket_filters(in->sock, ret) : 0;
}

int hl_can_input_wake_fd(const struct hl_can_input *in)
{
	return hl_ring_wake_fd(in->ring);
}

static void push(struct hl_can_input *in, int64_t t_event_ns)
{
	/*
	 * A fast replay waits for the consumer instead of overrunning the ring: a log can wait,
	 * a bus cannot (a live input never gets here blocked).
	 */
	while (in->log && in->cfg.replay_fast && !atomic_load(&in->stop) &&
	       hl_ring_pending(in->ring) + 1 >= hl_ring_slots(in->ring))
		hl_clock_sleep_until_ns(hl_clock_monotonic_ns() + 100000, NULL);

	in->snap->t_push_ns = hl_clock_monotonic_ns();
	in->snap->t_event_ns = t_event_ns;
	hl_ring_push(in->ring, in->snap); /* and the ring wakes the consumer */
	update_status(in);
}

static void mark_stale(struct hl_can_input *in, uint32_t mask, int64_t t_ns)
{
	if (!mask)
		return;
	for (int l = 0; l < hl_assembler_n_lamps(in->a); l++)
		if (mask & (1u << l))
			in->snap->lamps[l].status |= HL_LAMP_STALE;
	push(in, t_ns);
}

static void take_cycle(struct hl_can_input *in, const struct hl_cycle *c,
		       const struct hl_asm_events *ev, int64_t t_event_ns)
{
	struct hl_lamp_snapshot *ls = &in->snap->lamps[c->lamp];

	memcpy(in->snap->i + (size_t)c->lamp * in->snap->n_sources, c->i,
	       sizeof(float) * c->n_sources);
	ls->cycle_seq = c->seq;
	ls->counter = (uint8_t)c->counter;
	ls->mode = c->mode;
	ls->t_rx_first_ns = c->t_rx_first_ns;
	ls->t_complete_ns = t_event_ns;
	ls->t_complete_mono_ns = hl_clock_monotonic_ns();
	ls->status = HL_LAMP_VALID;
	(void)ev; /* a recovery shows as the STALE bit going away */
	push(in, t_event_ns);
}

static void feed(struct hl_can_input *in, const struct canfd_frame *f, int64_t t_rx_ns,
		 int64_t now_ns)
{
	struct hl_asm_events ev;
	struct hl_cycle c;
	const int done = hl_assembler_feed(in->a, f, t_rx_ns, now_ns, &c, &ev);

	mark_stale(in, ev.stale, now_ns);
	if (done == 1)
		take_cycle(in, &c, &ev, now_ns);
}

/* A malformed line (rc -EBADMSG) or a timestamp going backwards (rc 2): the first ones logged. */
static void report_line(struct hl_can_input *in, int rc, const struct hl_candump_log_error *err)
{
	struct hl_candump_log_stats st;
	const bool bad = rc == -EBADMSG;
	uint64_t n;

	hl_candump_log_stats(in->log, &st);
	n = bad ? st.malformed : st.backwards;
	if (n <= (bad ? MALFORMED_LOGGED : BACKWARDS_LOGGED))
		fprintf(in->cfg.log, "hdlampd: '%s':%ld:%d: %s%s%s\n", in->cfg.replay, err->line,
			err->column, bad ? "malformed candump line: " : "", err->msg,
			n == (bad ? MALFORMED_LOGGED : BACKWARDS_LOGGED) ?
				" (further ones only counted)" :
				"");
}

static void run_replay(struct hl_can_input *in)
{
	const int64_t base_ns = hl_clock_monotonic_ns();
	uint64_t n_frames = 0, pass = 1;

	while (!atomic_load(&in->stop)) {
		struct hl_candump_log_error err;
		struct hl_candump_log_stats st;
		struct hl_candump_frame f;
		int64_t due_ns, d;
		int rc = hl_candump_log_next(in->log, &f, &due_ns, &err);

		if (rc == -EBADMSG || rc == 2)
			report_line(in, rc, &err);
		if (rc == -EBADMSG)
			continue;
		if (rc <= 0) {
			if (rc < 0)
				fprintf(in->cfg.log, "hdlampd: '%s': %s\n", in->cfg.replay,
					strerror(-rc));
			break;
		}
		hl_candump_log_stats(in->log, &st);
		if (st.passes != pass) {
			/* the log starts again, and so do its alive counters: no fault */
			pass = st.passes;
			hl_assembler_restart(in->a);
			in->snap->t_pass_ns = due_ns; /* the scenario clock starts again */
		}
		/* lamps whose timeout falls before this frame go stale at their deadline */
		while ((d = hl_assembler_next_deadline(in->a)) <= due_ns) {
			if (!in->cfg.replay_fast)
				hl_clock_sleep_until_ns(base_ns + d, NULL);
			mark_stale(in, hl_assembler_expire(in->a, d), d);
		}
		if (!in->cfg.replay_fast)
			hl_clock_sleep_until_ns(base_ns + due_ns, NULL);
		feed(in, &f.frame, f.t_us * 1000, due_ns);
		if (++n_frames % 64 == 0)
			update_status(in); /* at least every 64 frames, for the status readers */
	}
	in->snap->status |= HL_INPUT_DONE;
	push(in, hl_clock_monotonic_ns());
}

static void link_change(struct hl_can_input *in, int err)
{
	const bool up = err == 0;

	if (up == ((in->snap->status & HL_INPUT_LINK_UP) != 0) && in->snap->link_errno == err)
		return;
	in->snap->status = up ? (in->snap->status | HL_INPUT_LINK_UP) :
				(in->snap->status & ~HL_INPUT_LINK_UP);
	in->snap->link_errno = err;
	push(in, hl_clock_monotonic_ns());
}

/* Waits up to ms for the stop flag, expiring lamps on the way. */
static void idle(struct hl_can_input *in, int ms)
{
	const int64_t until = hl_clock_monotonic_ns() + (int64_t)ms * 1000000;

	while (!atomic_load(&in->stop)) {
		const int64_t now = hl_clock_monotonic_ns();
		int64_t wake = hl_assembler_next_deadline(in->a);

		mark_stale(in, hl_assembler_expire(in->a, now), now);
		update_status(in);
		if (now >= until)
			return;
		if (wake > until)
			wake = until;
		if (wake > now + (int64_t)POLL_MAX_MS * 1000000)
			wake = now + (int64_t)POLL_MAX_MS * 1000000;
		hl_clock_sleep_until_ns(wake, NULL);
	}
}

static void run_socket(struct hl_can_input *in)
{
	struct hl_can_socket_stats st;

	while (!atomic_load(&in->stop)) {
		struct pollfd pfd;
		int64_t now, deadline;
		int timeout_ms, rc;

		if (hl_can_socket_fd(in->sock) < 0) {
			rc = hl_can_socket_open(in->sock);
			link_change(in, -rc);
			if (rc < 0) {
				idle(in, hl_can_socket_retry_ms(in->sock));
				continue;
			}
		}
		now = hl_clock_monotonic_ns();
		deadline = hl_assembler_next_deadline(in->a);
		timeout_ms = POLL_MAX_MS;
		if (deadline != INT64_MAX && (deadline - now) / 1000000 + 1 < timeout_ms)
			timeout_ms = deadline <= now ? 0 : (int)((deadline - now) / 1000000 + 1);
		pfd = (struct pollfd){ .fd = hl_can_socket_fd(in->sock), .events = POLLIN };
		if (poll(&pfd, 1, timeout_ms) == 0)
			update_status(in);
		now = hl_clock_monotonic_ns();
		mark_stale(in, hl_assembler_expire(in->a, now), now);
		for (int n = 0; n < READ_BATCH; n++) {
			struct hl_can_rx rx;

			rc = hl_can_socket_read(in->sock, &rx);
			if (rc <= 0)
				break;
			now = hl_clock_monotonic_ns();
			feed(in, &rx.frame, rx.t_rx_ns, now);
			if (rx.error) {
				hl_can_socket_stats(in->sock, &st);
				if (st.bus != in->snap->bus) {
					in->snap->bus = st.bus;
					push(in, now);
				}
			}
		}
		if (rc < 0)
			link_change(in, -rc); /* closed: reopened on the next turn */
	}
}

static void *thread_main(void *arg)
{
	struct hl_can_input *in = arg;

	pthread_setname_np(pthread_self(), "hl-can");
	hl_sched_start_thread("CAN", in->cfg.rt_priority, in->cfg.log);
	update_status(in);
	if (in->log)
		run_replay(in);
	else
		run_socket(in);
	update_status(in); /* the final counts, for the summary after stop */
	return NULL;
}

int hl_can_input_start(struct hl_can_input *in)
{
	int rc = pthread_create(&in->thread, NULL, thread_main, in);

	if (rc)
		return -rc;
	in->started = true;
	return 0;
}

void hl_can_input_stop(struct hl_can_input *in)
{
	if (!in->started)
		return;
	atomic_store(&in->stop, 1);
	pthread_join(in->thread, NULL);
	in->started = false;
}

void hl_can_input_report(struct hl_can_input *in, FILE *f)
{
	struct hl_input_status st;
	const struct hl_asm_counters *c = &st.frames;

	hl_can_input_status(in, &st);
	fprintf(f,
		"\"frames\":{\"decoded\":%" PRIu64 ",\"unknown_id\":%" PRIu64 ",\"short\":%" PRIu64
		",\"other\":%" PRIu64 ",\"error_frames\":%" PRIu64 "}",
		c->dbc.decoded, c->dbc.unknown_id, c->dbc.short_frame, c->other_frames,
		c->error_frames);
	if (!st.is_socket)
		fprintf(f,
			",\"log\":{\"lines\":%" PRIu64 ",\"frames\":%" PRIu64
			",\"malformed\":%" PRIu64 ",\"backwards\":%" PRIu64 ",\"passes\":%" PRIu64
			"}",
			st.log.lines, st.log.frames, st.log.malformed, st.log.backwards,
			st.log.passes);
	else
		fprintf(f,
			",\"socket\":{\"iface\":\"%s\",\"fd\":%s,\"bus\":\"%s\",\"frames\":%" PRIu64
			",\"fd_frames\":%" PRIu64 ",\"error_frames\":%" PRIu64
			",\"kernel_drops\":%" PRIu64 ",\"bus_off\":%" PRIu64
			",\"restarts\":%" PRIu64 ",\"opens\":%" PRIu64 ",\"closes\":%" PRIu64 "}",
			st.iface, st.socket.fd_enabled ? "true" : "false", st.bus, st.socket.frames,
			st.socket.fd_frames, st.socket.error_frames, st.socket.kernel_drops,
			st.socket.bus_off, st.socket.restarts, st.socket.opens, st.socket.closes);
}
