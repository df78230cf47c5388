/* SPDX-License-Identifier: MIT */
/*
 * hdlampd: the headlamp HIL daemon. This build runs the decode-only pipeline (the renderer
 * joins in a later issue): CAN thread -> ring -> this thread, which prints one JSON line per
 * complete lamp cycle and one per status change, and a summary of every counter at exit.
 */
#include <errno.h>
#include <getopt.h>
#include <inttypes.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "can/candump_log.h"
#include "can/socket.h"
#include "daemon/can_input.h"

#define MAX_LAMPS HL_ASM_MAX_LAMPS

static volatile sig_atomic_t stop_requested;

static void on_signal(int sig)
{
	(void)sig;
	stop_requested = 1;
}

struct options {
	const char *iface, *replay, *dbc;
	char *lamp_names[MAX_LAMPS];
	int n_lamps;
	int timeout_ms;
	unsigned ring_slots;
	bool fast, loop, no_render, print_cycles;
};

static void usage(FILE *f)
{
	fprintf(f,
		"usage: hdlampd (--can IFACE | --replay LOG [--fast] [--loop]) --no-render [options]\n"
		"\n"
		"  --can IFACE        receive from a SocketCAN interface (CAN or CAN FD); the daemon\n"
		"                     waits for it and reopens it when it goes down or disappears\n"
		"  --replay LOG       replay a candump -L log ('-' for stdin) with its timing\n"
		"  --fast             replay as fast as possible (timeouts still run on log time)\n"
		"  --loop             replay the log over and over\n"
		"  --dbc FILE         the CAN database (default dbc/hd84.dbc)\n"
		"  --lamps A,B        lamp names, as the DBC's HdlLamp attributes (default left,right)\n"
		"  --timeout-ms N     a lamp with no complete cycle for N ms is stale (default 100)\n"
		"  --ring-slots N     snapshots between CAN and output thread, a power of two (256)\n"
		"  --no-render        decode only (this build has no renderer yet)\n"
		"  --print-cycles     one JSON line per complete lamp cycle\n"
		"\n"
		"Output (stdout, JSON lines): cycles {\"lamp\",\"seq\",\"counter\",\"t_rx_ns\",\"t_done_ns\",\"i\"},\n"
		"status changes {\"event\":\"stale\"|\"recovered\"|\"bus\"|\"link\",...}, and at exit\n"
		"{\"event\":\"summary\",...} with every counter. SIGINT/SIGTERM stop it (exit 0).\n");
}

static int parse_options(int argc, char **argv, struct options *o)
{
	static const struct option opts[] = {
		{ "can", required_argument, NULL, 'c' },
		{ "replay", required_argument, NULL, 'r' },
		{ "fast", no_argument, NULL, 'f' },
		{ "loop", no_argument, NULL, 'l' },
		{ "dbc", required_argument, NULL, 'd' },
		{ "lamps", required_argument, NULL, 'L' },
		{ "timeout-ms", required_argument, NULL, 't' },
		{ "ring-slots", required_argument, NULL, 's' },
		{ "no-render", no_argument, NULL, 'n' },
		{ "print-cycles", no_argument, NULL, 'p' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	static char default_lamps[] = "left,right";
	char *lamps = default_lamps, *end;
	long v;
	int c;

	*o = (struct options){ .dbc = "dbc/hd84.dbc", .timeout_ms = 100, .ring_slots = 256 };
	while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
		switch (c) {
		case 'c':
			o->iface = optarg;
			break;
		case 'r':
			o->replay = optarg;
			break;
		case 'f':
			o->fast = true;
			break;
		case 'l':
			o->loop = true;
			break;
		case 'd':
			o->dbc = optarg;
			break;
		case 'L':
			lamps = optarg;
			break;
		case 't':
			v = strtol(optarg, &end, 10);
			if (*end || v < 1 || v > 60000) {
				fprintf(stderr, "hdlampd: --timeout-ms '%s': expected 1..60000\n",
					optarg);
				return -EINVAL;
			}
			o->timeout_ms = (int)v;
			break;
		case 's':
			v = strtol(optarg, &end, 10);
			if (*end || v < 2 || v > 65536 || (v & (v - 1))) {
				fprintf(stderr,
					"hdlampd: --ring-slots '%s': expected a power of two 2..65536\n",
					optarg);
				return -EINVAL;
			}
			o->ring_slots = (unsigned)v;
			break;
		case 'n':
			o->no_render = true;
			break;
		case 'p':
			o->print_cycles = true;
			break;
		case 'h':
			usage(stdout);
			exit(0);
		default:
			usage(stderr);
			return -EINVAL;
		}
	}
	if (optind != argc || !o->iface == !o->replay || ((o->fast || o->loop) && !o->replay)) {
		fprintf(stderr,
			"hdlampd: give exactly one of --can IFACE and --replay LOG (--fast and --loop go with --replay)\n");
		return -EINVAL;
	}
	if (!o->no_render) {
		fprintf(stderr, "hdlampd: this build has no renderer yet; run with --no-render\n");
		return -EINVAL;
	}
	for (char *save = NULL, *tok = strtok_r(lamps, ",", &save); tok;
	     tok = strtok_r(NULL, ",", &save)) {
		if (o->n_lamps == MAX_LAMPS) {
			fprintf(stderr, "hdlampd: --lamps: at most %d lamps\n", MAX_LAMPS);
			return -EINVAL;
		}
		o->lamp_names[o->n_lamps++] = tok;
	}
	if (o->n_lamps == 0) {
		fprintf(stderr, "hdlampd: --lamps: expected names such as left,right\n");
		return -EINVAL;
	}
	return 0;
}

/* What the output thread last saw, to report changes. */
struct seen {
	uint64_t cycle_seq[MAX_LAMPS];
	uint32_t lamp_status[MAX_LAMPS];
	uint32_t status, bus;
	int32_t link_errno;
};

static void print_cycle(const struct hl_assembler *a, const struct hl_snapshot *s, int l)
{
	const int n = hl_assembler_n_sources(a, l);
	const float *i = s->i + (size_t)l * s->n_sources;

	printf("{\"lamp\":\"%s\",\"seq\":%" PRIu64 ",\"counter\":%u,\"t_rx_ns\":%" PRId64
	       ",\"t_done_ns\":%" PRId64 ",\"i\":[",
	       hl_assembler_lamp_name(a, l), s->lamps[l].cycle_seq, s->lamps[l].counter,
	       s->lamps[l].t_rx_first_ns, s->lamps[l].t_complete_ns);
	for (int k = 0; k < n; k++)
		printf("%s%.9g", k ? "," : "", i[k]);
	printf("]}\n");
}

static bool report(const struct options *o, const struct hl_assembler *a,
		   const struct hl_snapshot *s, struct seen *seen)
{
	const char *iface = o->iface ? o->iface : o->replay;

	if ((s->status & HL_INPUT_LINK_UP) != (seen->status & HL_INPUT_LINK_UP) ||
	    s->link_errno != seen->link_errno)
		printf("{\"event\":\"link\",\"iface\":\"%s\",\"state\":\"%s\",\"error\":\"%s\",\"t_ns\":%" PRId64
		       "}\n",
		       iface, (s->status & HL_INPUT_LINK_UP) ? "up" : "down",
		       s->link_errno ? strerror(s->link_errno) : "", s->t_event_ns);
	if (s->bus != seen->bus)
		printf("{\"event\":\"bus\",\"iface\":\"%s\",\"state\":\"%s\",\"t_ns\":%" PRId64
		       "}\n",
		       iface, hl_can_bus_state_name(s->bus), s->t_event_ns);
	for (int l = 0; l < hl_assembler_n_lamps(a); l++) {
		const bool was_stale = seen->lamp_status[l] & HL_LAMP_STALE;
		const bool stale = s->lamps[l].status & HL_LAMP_STALE;

		if (s->lamps[l].cycle_seq != seen->cycle_seq[l] && o->print_cycles)
			print_cycle(a, s, l);
		if (stale != was_stale)
			printf("{\"event\":\"%s\",\"lamp\":\"%s\",\"t_ns\":%" PRId64 "}\n",
			       stale ? "stale" : "recovered", hl_assembler_lamp_name(a, l),
			       s->t_event_ns);
		seen->cycle_seq[l] = s->lamps[l].cycle_seq;
		seen->lamp_status[l] = s->lamps[l].status;
	}
	seen->status = s->status;
	seen->bus = s->bus;
	seen->link_errno = s->link_errno;
	return s->status & HL_INPUT_DONE;
}

static void summary(const struct hl_assembler *a, const struct hl_ring *ring,
		    const struct hl_can_input *in)
{
	struct hl_ring_counts rc;

	hl_ring_counts(ring, &rc);
	printf("{\"event\":\"summary\",\"lamps\":{");
	for (int l = 0; l < hl_assembler_n_lamps(a); l++) {
		const struct hl_lamp_counters *c = hl_assembler_lamp_counters(a, l);

		printf("%s\"%s\":{\"frames\":%" PRIu64 ",\"cycles\":%" PRIu64
		       ",\"crc_errors\":%" PRIu64 ",\"incomplete\":%" PRIu64
		       ",\"lost_cycles\":%" PRIu64 ",\"repeated_frames\":%" PRIu64
		       ",\"out_of_range\":%" PRIu64 ",\"stale_events\":%" PRIu64
		       ",\"recoveries\":%" PRIu64 ",\"stale\":%s}",
		       l ? "," : "", hl_assembler_lamp_name(a, l), c->frames, c->cycles,
		       c->crc_errors, c->incomplete, c->lost_cycles, c->repeated_frames,
		       c->out_of_range, c->stale_events, c->recoveries,
		       hl_assembler_stale(a, l) ? "true" : "false");
	}
	printf("},");
	hl_can_input_report(in, stdout);
	printf(",\"ring\":{\"pushed\":%" PRIu64 ",\"consumed\":%" PRIu64 ",\"superseded\":%" PRIu64
	       ",\"dropped\":%" PRIu64 "}}\n",
	       rc.pushed, rc.consumed, rc.superseded, rc.dropped);
}

int main(int argc, char **argv)
{
	struct options o;
	struct hl_dbc *db = NULL;
	struct hl_dbc_error derr;
	struct hl_assembler *a = NULL;
	struct hl_asm_error aerr;
	struct hl_ring *ring = NULL;
	struct hl_snapshot *snap = NULL;
	struct hl_can_input *in = NULL;
	struct seen seen = { .status = 0 };
	struct sigaction sa = { .sa_handler = on_signal };
	int rc, n_src = 1, exit_code = 1;
	bool done = false;

	setvbuf(stdout, NULL, _IOLBF, 0);
	if (parse_options(argc, argv, &o) < 0)
		return 2;
	rc = hl_dbc_parse_file(o.dbc, &db, &derr);
	if (rc < 0) {
		if (derr.line)
			fprintf(stderr, "hdlampd: '%s':%d:%d: %s\n", o.dbc, derr.line, derr.column,
				derr.msg);
		else
			fprintf(stderr, "hdlampd: '%s': %s\n", o.dbc, derr.msg);
		return 1;
	}
	rc = hl_assembler_new(db, (const char *const *)o.lamp_names, o.n_lamps, o.timeout_ms, 0, &a,
			      &aerr);
	if (rc < 0) {
		fprintf(stderr, "hdlampd: '%s': %s\n", o.dbc, aerr.msg);
		goto out;
	}
	for (int l = 0; l < o.n_lamps; l++)
		if (hl_assembler_n_sources(a, l) > n_src)
			n_src = hl_assembler_n_sources(a, l);
	/* replays run on the log's timeline (0 = first frame); a live bus on CLOCK_MONOTONIC */
	if (o.iface) {
		hl_assembler_free(a);
		rc = hl_assembler_new(db, (const char *const *)o.lamp_names, o.n_lamps,
				      o.timeout_ms, hl_monotonic_ns(), &a, &aerr);
		if (rc < 0)
			goto out;
	}
	rc = hl_ring_new(o.ring_slots, o.n_lamps, n_src, &ring);
	if (rc == 0)
		rc = hl_snapshot_new(ring, &snap);
	if (rc == 0) {
		struct hl_can_input_config cfg = {
			.iface = o.iface,
			.replay = o.replay,
			.replay_fast = o.fast,
			.replay_loop = o.loop,
			.log = stderr,
		};

		rc = hl_can_input_new(&cfg, a, ring, &in);
		if (rc < 0)
			fprintf(stderr, "hdlampd: '%s': %s\n", o.iface ? o.iface : o.replay,
				strerror(-rc));
	}
	if (rc < 0)
		goto out;
	seen.status = o.replay ? HL_INPUT_LINK_UP : 0;
	seen.link_errno = o.replay ? 0 : ENETDOWN;
	sigaction(SIGINT, &sa, NULL);
	sigaction(SIGTERM, &sa, NULL);
	rc = hl_can_input_start(in);
	if (rc < 0) {
		fprintf(stderr, "hdlampd: cannot start the CAN thread: %s\n", strerror(-rc));
		goto out;
	}
	while (!done) {
		struct pollfd pfd = { .fd = hl_can_input_wake_fd(in), .events = POLLIN };
		uint64_t wakes;

		if (stop_requested)
			hl_can_input_stop(in); /* joined: everything it pushed is in the ring */
		while (!done && hl_ring_pop(ring, snap))
			done = report(&o, a, snap, &seen);
		if (stop_requested)
			break;
		if (!done && poll(&pfd, 1, 100) > 0 && read(pfd.fd, &wakes, sizeof(wakes)) < 0) {
			/* reset failed: the next poll returns at once, nothing is lost */
		}
	}
	hl_can_input_stop(in);
	summary(a, ring, in);
	exit_code = 0;
out:
	hl_can_input_free(in);
	hl_snapshot_free(snap);
	hl_ring_free(ring);
	hl_assembler_free(a);
	hl_dbc_free(db);
	return exit_code;
}
