/* SPDX-License-Identifier: MIT */
/*
 * hdlamp ecu on the bus (docs/ecu.md): the receive and send sockets, the 20 ms deadlines on
 * CLOCK_MONOTONIC (a timerfd armed at absolute times), SIGINT/SIGTERM through a signalfd, the
 * late fault's queue of computed cycles, and the JSON lines start, mode and summary.
 */
#include "tools/ecu_bus.h"

#include <errno.h>
#include <inttypes.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/signalfd.h>
#include <sys/timerfd.h>
#include <time.h>
#include <unistd.h>

#include <linux/can.h>

#include "can/socket.h"
#include "tools/json_out.h"
#include "base/clock.h"

#define PERIOD_NS 20000000LL /* the dimming cycle, 50 Hz */

/* One cycle's frames, waiting until due (the late fault) or sent at once. */
struct out_cycle {
	int64_t due_ns;
	int n[2];
	struct hl_encoded_frame frames[2][HL_ASM_MAX_PARTS];
};

struct counters {
	uint64_t cycles, frames_sent, tx_errors, skipped_deadlines, failsafe_cycles;
	/* objects over the cycles that looked at them (one object in 50 cycles counts 50) */
	uint64_t objects_relevant, objects_ignored, objects_invalid, sources_masked;
	uint64_t mode_cycles[4];
	uint64_t rx_frames, socket_losses; /* the socket closed by a failed read or send */
	int64_t late_max_ns; /* how far after its deadline a cycle was computed */
};

static int64_t real_ns(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_REALTIME, &ts);
	return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

static const char *const failsafe_names[] = { "vehicle_missing", "objects_missing", "vehicle_e2e",
					      "objects_e2e" };

static void print_failsafe(unsigned fs)
{
	bool first = true;

	printf("[");
	for (int b = 0; b < 4; b++) {
		if (!(fs & (1u << b)))
			continue;
		printf("%s\"%s\"", first ? "" : ",", failsafe_names[b]);
		first = false;
	}
	printf("]");
}

static void print_mode(int64_t t_ns, uint64_t cycle, const struct hl_ecu_status *st)
{
	printf("{\"event\":\"mode\",\"t_ns\":%" PRId64 ",\"cycle\":%" PRIu64 ",\"mode\":\"%s\","
	       "\"failsafe\":",
	       t_ns, cycle, hl_ecu_mode_name(st->mode));
	print_failsafe(st->failsafe);
	printf(",\"objects\":%d,\"swivel_deg\":", st->objects);
	hl_tool_json_num(stdout, st->swivel_deg);
	printf("}\n");
	fflush(stdout);
}

static void print_summary(const struct counters *c, const struct hl_inputs_counters *in,
			  const struct hl_can_socket_stats *ss)
{
	printf("{\"event\":\"summary\",\"cycles\":%" PRIu64 ",\"frames_sent\":%" PRIu64
	       ",\"tx_errors\":%" PRIu64 ",\"skipped_deadlines\":%" PRIu64
	       ",\"late_max_ms\":%.3f,\"failsafe_cycles\":%" PRIu64 ",\"modes\":{",
	       c->cycles, c->frames_sent, c->tx_errors, c->skipped_deadlines, c->late_max_ns / 1e6,
	       c->failsafe_cycles);
	for (int m = 0; m < 4; m++)
		printf("%s\"%s\":%" PRIu64, m ? "," : "", hl_ecu_mode_name(m), c->mode_cycles[m]);
	printf("},\"object_cycles\":{\"relevant\":%" PRIu64 ",\"ignored\":%" PRIu64
	       ",\"invalid\":%" PRIu64 "},\"sources_masked\":%" PRIu64,
	       c->objects_relevant, c->objects_ignored, c->objects_invalid, c->sources_masked);
	printf(",\"inputs\":{\"frames\":%" PRIu64 ",\"unknown_id\":%" PRIu64
	       ",\"short_frames\":%" PRIu64 ",\"crc_errors\":%" PRIu64
	       ",\"counter_repeated\":%" PRIu64 ",\"counter_lost\":%" PRIu64
	       ",\"bad_values\":%" PRIu64 ",\"duplicates\":%" PRIu64 ",\"vehicle_states\":%" PRIu64
	       ",\"object_frames\":%" PRIu64 ",\"cycles_complete\":%" PRIu64
	       ",\"cycles_incomplete\":%" PRIu64 "}",
	       in->frames, in->unknown_id, in->short_frames, in->crc_errors, in->counter_repeated,
	       in->counter_lost, in->bad_values, in->duplicates, in->vehicle_states,
	       in->object_frames, in->cycles_complete, in->cycles_incomplete);
	printf(",\"socket\":{\"frames\":%" PRIu64 ",\"kernel_drops\":%" PRIu64
	       ",\"error_frames\":%" PRIu64 ",\"losses\":%" PRIu64 ",\"opens\":%" PRIu64
	       ",\"closes\":%" PRIu64 "}}\n",
	       ss->frames, ss->kernel_drops, ss->error_frames, c->socket_losses, ss->opens,
	       ss->closes);
	fflush(stdout);
}

struct ecu_run {
	const struct hl_ecu_bus_opts *o;
	const struct hl_ecu_config *cfg;
	struct hl_assembler *a;
	const struct hl_inputs_map *map;
	struct hl_inputs_decoder *dec;
	struct hl_ecu *e;
	struct hl_can_socket *s; /* receives the inputs (kernel filter) and sends the frames */
	int tfd, sfd;
	struct out_cycle *q; /* ring of pending cycles */
	int q_size, q_head, q_len;
	unsigned counter[2];
	struct counters c;
	struct hl_ecu_status last;
	bool have_last;
	int64_t retry_ns; /* when to reopen the closed socket, 0: open */
};

/* A read or send found the interface down or gone and closed the socket: reopen later. */
static void socket_lost(struct ecu_run *r, int rc, const char *what)
{
	r->c.socket_losses++;
	fprintf(stderr, "hdlamp ecu: can: '%s': %s: %s, reopening\n", r->o->iface, what,
		strerror(-rc));
	r->retry_ns = hl_clock_monotonic_ns() + (int64_t)hl_can_socket_retry_ms(r->s) * 1000000;
}

/* Sends one cycle's frames; a frame that cannot go is counted, never retried. */
static void send_cycle(struct ecu_run *r, const struct out_cycle *oc)
{
	for (int l = 0; l < 2; l++) {
		for (int i = 0; i < oc->n[l]; i++) {
			const struct hl_encoded_frame *e = &oc->frames[l][i];
			int rc;

			if (r->retry_ns) {
				r->c.tx_errors++;
				continue;
			}
			rc = hl_can_socket_send(r->s, e->frame.can_id, e->frame.data, e->frame.len,
						e->fd);
			if (rc == 0) {
				r->c.frames_sent++;
				continue;
			}
			r->c.tx_errors++;
			if (hl_can_socket_fd(r->s) < 0)
				socket_lost(r, rc, "send");
		}
	}
}

/* Drains the receive socket into the ECU. */
static void receive(struct ecu_run *r)
{
	struct hl_can_rx f;
	const int64_t mono_minus_real = hl_clock_monotonic_ns() - real_ns();
	int rc;

	while ((rc = hl_can_socket_read(r->s, &f)) == 1) {
		struct hl_vehicle_state vs;
		struct hl_camera_objects ob;
		/* the kernel's receive time, on the monotonic clock the deadlines run on */
		const int64_t t = f.t_rx_ns + mono_minus_real;
		/* the database's key: HL_DBC_EFF_FLAG marks an extended ID, as CAN_EFF_FLAG does */
		const uint32_t id = f.frame.can_id & CAN_EFF_FLAG ?
					    (f.frame.can_id & CAN_EFF_MASK) | HL_DBC_EFF_FLAG :
					    f.frame.can_id & CAN_SFF_MASK;
		int d;

		if (f.error)
			continue;
		r->c.rx_frames++;
		d = hl_inputs_decode(r->dec, id, f.frame.data, f.frame.len, &vs, &ob);
		if (d == HL_INPUTS_VEHICLE) {
			hl_ecu_vehicle(r->e, &vs, t);
		} else if (d == HL_INPUTS_OBJECTS) {
			hl_ecu_objects(r->e, &ob, t);
		} else if (d == -EBADMSG) {
			for (int i = 0; i < hl_inputs_map_n_messages(r->map); i++) {
				const struct hl_inputs_message *m =
					hl_inputs_map_message(r->map, i);

				if (m->msg->can_id == id)
					hl_ecu_input_error(r->e, m->kind == HL_INPUTS_VEHICLE ?
									 HL_ECU_INPUT_VEHICLE :
									 HL_ECU_INPUT_OBJECTS);
			}
		}
	}
	if (rc < 0)
		socket_lost(r, rc, "receive");
}

/* Computes the cycle of deadline t_deadline and queues (or sends) its frames. */
static int compute_cycle(struct ecu_run *r, int64_t t_deadline)
{
	struct hl_ecu_status st;
	struct out_cycle *oc;
	const int64_t now = hl_clock_monotonic_ns();

	hl_ecu_step(r->e, now, &st);
	if (now - t_deadline > r->c.late_max_ns)
		r->c.late_max_ns = now - t_deadline;
	r->c.cycles++;
	r->c.mode_cycles[st.mode]++;
	if (st.failsafe)
		r->c.failsafe_cycles++;
	r->c.objects_relevant += (uint64_t)st.objects;
	r->c.objects_ignored += (uint64_t)st.ignored;
	r->c.objects_invalid += (uint64_t)st.invalid;
	r->c.sources_masked += (uint64_t)(st.masked[0] + st.masked[1]);
	if (!r->have_last || st.mode != r->last.mode || st.failsafe != r->last.failsafe)
		print_mode(now, r->c.cycles, &st);
	r->last = st;
	r->have_last = true;
	if (r->q_len == r->q_size) /* cannot happen: the ring holds the late fault's cycles */
		return -ENOSPC;
	oc = &r->q[(r->q_head + r->q_len) % r->q_size];
	oc->due_ns = t_deadline + (int64_t)r->o->late_ms * 1000000;
	for (int l = 0; l < 2; l++) {
		const unsigned max = hl_assembler_counter_max(r->a, l);

		oc->n[l] = hl_assembler_encode(r->a, l, hl_ecu_output(r->e, l), r->counter[l],
					       oc->frames[l], HL_ASM_MAX_PARTS);
		if (oc->n[l] < 0)
			return oc->n[l];
		if (r->o->bad_crc)
			for (int i = 0; i < oc->n[l]; i++)
				oc->frames[l][i].frame.data[0] ^= 0x01;
		if (!r->o->stuck_counter)
			r->counter[l] = max ? (r->counter[l] + 1) % (max + 1) : 0;
	}
	r->q_len++;
	return 0;
}

static void send_due(struct ecu_run *r, int64_t now)
{
	while (r->q_len > 0 && r->q[r->q_head].due_ns <= now) {
		send_cycle(r, &r->q[r->q_head]);
		r->q_head = (r->q_head + 1) % r->q_size;
		r->q_len--;
	}
}

static int arm(int tfd, int64_t t_ns)
{
	struct itimerspec its = { .it_value = { .tv_sec = t_ns / 1000000000,
						.tv_nsec = t_ns % 1000000000 } };

	return timerfd_settime(tfd, TFD_TIMER_ABSTIME, &its, NULL) < 0 ? -errno : 0;
}

/* Cycles at first, first + 20 ms, ... (a deadline woken past is skipped, never shifted). */
static int run_loop(struct ecu_run *r, int64_t first)
{
	int64_t next = first;

	for (;;) {
		struct pollfd p[3] = {
			{ .fd = r->tfd, .events = POLLIN },
			{ .fd = r->sfd, .events = POLLIN },
			{ .fd = r->retry_ns ? -1 : hl_can_socket_fd(r->s), .events = POLLIN },
		};
		int64_t wake = next, now;
		int rc;

		if (r->q_len > 0 && r->q[r->q_head].due_ns < wake)
			wake = r->q[r->q_head].due_ns;
		if (r->retry_ns && r->retry_ns < wake)
			wake = r->retry_ns;
		rc = arm(r->tfd, wake);
		if (rc < 0)
			return rc;
		if (poll(p, 3, -1) < 0) {
			if (errno == EINTR)
				continue;
			return -errno;
		}
		if (p[1].revents & POLLIN) {
			struct signalfd_siginfo si;

			if (read(r->sfd, &si, sizeof(si)) == sizeof(si))
				return 0;
		}
		if (p[2].revents & POLLIN)
			receive(r);
		if (p[0].revents & POLLIN) {
			uint64_t exp;

			if (read(r->tfd, &exp, sizeof(exp)) < 0 && errno != EAGAIN)
				return -errno;
		}
		now = hl_clock_monotonic_ns();
		if (r->retry_ns && now >= r->retry_ns) {
			r->retry_ns = 0;
			if (hl_can_socket_open(r->s) < 0)
				r->retry_ns = now + (int64_t)hl_can_socket_retry_ms(r->s) * 1000000;
		}
		if (now >= next && (!r->o->cycles || r->c.cycles < (uint64_t)r->o->cycles)) {
			/* take what arrived up to the deadline first */
			if (!r->retry_ns)
				receive(r);
			rc = compute_cycle(r, next);
			if (rc < 0)
				return rc;
			next += PERIOD_NS;
			/* a wake-up later than whole periods: those deadlines are skipped, counted */
			while (next <= now) {
				next += PERIOD_NS;
				r->c.skipped_deadlines++;
			}
		}
		send_due(r, hl_clock_monotonic_ns());
		if (r->o->cycles && r->c.cycles >= (uint64_t)r->o->cycles && r->q_len == 0)
			return 0;
	}
}

static int setup_io(struct ecu_run *r)
{
	uint32_t ids[HL_INPUTS_MAX_OBJ_MESSAGES + 1];
	const int n_ids = hl_inputs_map_n_messages(r->map);
	bool fd = false;
	sigset_t mask;
	int rc;

	for (int i = 0; i < n_ids && i < (int)(sizeof(ids) / sizeof(ids[0])); i++) {
		const struct hl_dbc_message *m = hl_inputs_map_message(r->map, i)->msg;

		ids[i] = m->id | (m->extended ? CAN_EFF_FLAG : 0);
	}
	rc = hl_can_socket_new(r->o->iface, ids, n_ids, &r->s);
	if (rc == 0)
		rc = hl_can_socket_open(r->s);
	if (rc < 0) {
		fprintf(stderr, "hdlamp ecu: can: '%s': %s\n", r->o->iface, strerror(-rc));
		return rc;
	}
	for (int p = 0; p < 2; p++) {
		struct hl_encoded_frame f[HL_ASM_MAX_PARTS];
		float zero[HL_LID_MAX_SOURCES] = { 0 };
		const int n = hl_assembler_encode(r->a, p, zero, 0, f, HL_ASM_MAX_PARTS);

		for (int i = 0; i < n; i++)
			fd |= f[i].fd;
	}
	{
		struct hl_can_socket_stats ss;

		hl_can_socket_stats(r->s, &ss);
		if (fd && !ss.fd_enabled) {
			fprintf(stderr,
				"hdlamp ecu: can: '%s': the dimming database has CAN FD frames, the "
				"interface is classic CAN only (MTU 16)\n",
				r->o->iface);
			return -EPROTONOSUPPORT;
		}
	}
	r->tfd = timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC | TFD_NONBLOCK);
	sigemptyset(&mask);
	sigaddset(&mask, SIGINT);
	sigaddset(&mask, SIGTERM);
	if (r->tfd < 0 || sigprocmask(SIG_BLOCK, &mask, NULL) < 0 ||
	    (r->sfd = signalfd(-1, &mask, SFD_CLOEXEC | SFD_NONBLOCK)) < 0) {
		rc = -errno;
		fprintf(stderr, "hdlamp ecu: the timer and signals: %s\n", strerror(-rc));
		return rc;
	}
	r->q_size = r->o->late_ms / 20 + 3;
	r->q = calloc((size_t)r->q_size, sizeof(*r->q));
	if (!r->q) {
		fprintf(stderr, "hdlamp ecu: out of memory\n");
		return -ENOMEM;
	}
	return 0;
}

int hl_ecu_bus_run(const struct hl_ecu_bus_opts *o, const struct hl_ecu_config *cfg,
		   struct hl_assembler *a, const struct hl_inputs_map *map,
		   struct hl_inputs_decoder *dec, struct hl_ecu *e)
{
	struct ecu_run r = {
		.o = o,
		.cfg = cfg,
		.a = a,
		.map = map,
		.dec = dec,
		.e = e,
		.tfd = -1,
		.sfd = -1,
	};
	int rc = setup_io(&r);
	int64_t now, first;

	if (rc < 0)
		goto out;
	now = hl_clock_monotonic_ns();
	first = now + PERIOD_NS;
	printf("{\"event\":\"start\",\"t_ns\":%" PRId64 ",\"first_deadline_ns\":%" PRId64
	       ",\"iface\":\"%s\",\"sources\":[%d,%d],"
	       "\"vehicle_timeout_ms\":%.3f,\"objects_timeout_ms\":%.3f,\"late_ms\":%d}\n",
	       now, first, o->iface, hl_assembler_n_sources(a, 0), hl_assembler_n_sources(a, 1),
	       cfg->vehicle_timeout_ns / 1e6, cfg->objects_timeout_ns / 1e6, o->late_ms);
	fflush(stdout);
	rc = run_loop(&r, first);
	if (rc < 0) {
		fprintf(stderr, "hdlamp ecu: %s\n", strerror(-rc));
	} else {
		struct hl_can_socket_stats ss;

		hl_can_socket_stats(r.s, &ss);
		print_summary(&r.c, hl_inputs_decoder_counters(r.dec), &ss);
	}
out:
	if (r.tfd >= 0)
		close(r.tfd);
	if (r.sfd >= 0)
		close(r.sfd);
	free(r.q);
	hl_can_socket_free(r.s);
	return rc;
}
