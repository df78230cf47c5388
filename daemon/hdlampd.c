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

#include "daemon/clock.h"
#include "can/socket.h"
#include "daemon/can_input.h"
#include "daemon/config.h"
#include "daemon/live.h"

static volatile sig_atomic_t stop_requested;

static void on_signal(int sig)
{
	(void)sig;
	stop_requested = 1;
}

#define MAX_OVERRIDES 128

struct options {
	struct hl_config cfg;
	const char *config_path;
	char *overrides[MAX_OVERRIDES]; /* SECTION.KEY=VALUE, in order; re-applied on reload */
	int n_overrides;
	char *lamp_names[HL_ASM_MAX_LAMPS];
	int n_lamps;
	char lamps_buf[HL_CONFIG_NAME];
	unsigned ring_slots;
	bool no_render, print_cycles, print_config;
};

static void usage(FILE *f)
{
	fprintf(f,
		"usage: hdlampd [--config FILE] [--set SECTION.KEY=VALUE ...] [options]\n"
		"\n"
		"  --config FILE      INI configuration (README lists every key; --print-config shows\n"
		"                     them with their values)\n"
		"  --set S.K=V        override one key (e.g. --set render.view=lux)\n"
		"  --can IFACE        = can.interface: a SocketCAN interface (CAN or CAN FD); waited\n"
		"                     for, and reopened when it goes down or disappears\n"
		"  --replay LOG       = can.replay: a candump -L log ('-' for stdin) with its timing\n"
		"  --fast, --loop     = can.replay_fast, can.replay_loop\n"
		"  --dbc FILE         = can.dbc (default dbc/hd84.dbc)\n"
		"  --lamps A,B        = can.lamps (default left,right)\n"
		"  --timeout-ms N     = can.timeout_ms (default 100)\n"
		"  --ring-slots N     snapshots between CAN and render thread, a power of two (256)\n"
		"  --no-render        decode only: print to stdout instead of rendering\n"
		"  --print-cycles     with --no-render: one JSON line per complete lamp cycle\n"
		"  --print-config     print the resulting configuration and exit\n"
		"\n"
		"Live mode renders every new complete cycle and serves the frames (stream, HTTP);\n"
		"SIGHUP re-reads the configuration, SIGUSR1 writes a capture, SIGINT/SIGTERM stop\n"
		"(exit 0). --no-render prints JSON lines: cycles, status changes and a summary.\n");
}

static int add_override(struct options *o, const char *section_key, const char *value)
{
	char *s;

	if (o->n_overrides == MAX_OVERRIDES || asprintf(&s, "%s=%s", section_key, value) < 0) {
		fprintf(stderr, "hdlampd: too many overrides\n");
		return -EINVAL;
	}
	o->overrides[o->n_overrides++] = s;
	return 0;
}

static int parse_options(int argc, char **argv, struct options *o)
{
	static const struct option opts[] = {
		{ "config", required_argument, NULL, 'C' },
		{ "set", required_argument, NULL, 'S' },
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
		{ "print-config", no_argument, NULL, 'P' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	struct hl_config_error err;
	char *end;
	long v;
	int c, rc = 0;

	*o = (struct options){ .ring_slots = 256 };
	hl_config_defaults(&o->cfg);
	while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1 && rc == 0) {
		switch (c) {
		case 'C':
			o->config_path = optarg;
			break;
		case 'S':
			if (o->n_overrides == MAX_OVERRIDES)
				return -EINVAL;
			o->overrides[o->n_overrides++] = strdup(optarg);
			break;
		case 'c':
			rc = add_override(o, "can.interface", optarg);
			break;
		case 'r':
			rc = add_override(o, "can.replay", optarg);
			break;
		case 'f':
			rc = add_override(o, "can.replay_fast", "true");
			break;
		case 'l':
			rc = add_override(o, "can.replay_loop", "true");
			break;
		case 'd':
			rc = add_override(o, "can.dbc", optarg);
			break;
		case 'L':
			rc = add_override(o, "can.lamps", optarg);
			break;
		case 't':
			rc = add_override(o, "can.timeout_ms", optarg);
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
		case 'P':
			o->print_config = true;
			break;
		case 'h':
			usage(stdout);
			exit(0);
		default:
			usage(stderr);
			return -EINVAL;
		}
	}
	if (rc < 0)
		return rc;
	if (optind != argc) {
		fprintf(stderr, "hdlampd: unexpected argument '%s'\n", argv[optind]);
		return -EINVAL;
	}
	/* defaults, then the file, then the command line, whatever their order there */
	if (o->config_path) {
		rc = hl_config_load(&o->cfg, o->config_path, &err);
		if (rc < 0) {
			fprintf(stderr, "hdlampd: %s\n", err.msg);
			return rc == -EINVAL ? -EINVAL : -ENOENT;
		}
	}
	for (int i = 0; i < o->n_overrides; i++) {
		if (!o->overrides[i] ||
		    hl_config_set_arg(&o->cfg, o->overrides[i], "command line", &err) < 0) {
			fprintf(stderr, "hdlampd: %s\n", err.msg);
			return -EINVAL;
		}
	}
	if (o->print_config)
		return 0;
	if (hl_config_check(&o->cfg, &err) < 0) {
		fprintf(stderr, "hdlampd: %s (--can IFACE or --replay LOG)\n", err.msg);
		return -EINVAL;
	}
	snprintf(o->lamps_buf, sizeof(o->lamps_buf), "%s", o->cfg.lamps);
	for (char *save = NULL, *tok = strtok_r(o->lamps_buf, ",", &save); tok;
	     tok = strtok_r(NULL, ",", &save)) {
		if (o->n_lamps == HL_ASM_MAX_LAMPS) {
			fprintf(stderr, "hdlampd: can.lamps: at most %d lamps\n", HL_ASM_MAX_LAMPS);
			return -EINVAL;
		}
		o->lamp_names[o->n_lamps++] = tok;
	}
	if (o->n_lamps == 0) {
		fprintf(stderr, "hdlampd: can.lamps: expected names such as left,right\n");
		return -EINVAL;
	}
	return 0;
}

/* What the output thread last saw, to report changes. */
struct seen {
	uint64_t cycle_seq[HL_ASM_MAX_LAMPS];
	uint32_t lamp_status[HL_ASM_MAX_LAMPS];
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
	const char *iface = o->cfg.interface[0] ? o->cfg.interface : o->cfg.replay;

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

static int run_decode_only(struct options *op)
{
	struct options o = *op;
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

	rc = hl_dbc_parse_file(o.cfg.dbc, &db, &derr);
	if (rc < 0) {
		if (derr.line)
			fprintf(stderr, "hdlampd: '%s':%d:%d: %s\n", o.cfg.dbc, derr.line,
				derr.column, derr.msg);
		else
			fprintf(stderr, "hdlampd: '%s': %s\n", o.cfg.dbc, derr.msg);
		return 1;
	}
	rc = hl_assembler_new(db, (const char *const *)o.lamp_names, o.n_lamps, o.cfg.timeout_ms, 0,
			      &a, &aerr);
	if (rc < 0) {
		fprintf(stderr, "hdlampd: '%s': %s\n", o.cfg.dbc, aerr.msg);
		goto out;
	}
	for (int l = 0; l < o.n_lamps; l++)
		if (hl_assembler_n_sources(a, l) > n_src)
			n_src = hl_assembler_n_sources(a, l);
	/* replays run on the log's timeline (0 = first frame); a live bus on CLOCK_MONOTONIC */
	if (o.cfg.interface[0]) {
		hl_assembler_free(a);
		rc = hl_assembler_new(db, (const char *const *)o.lamp_names, o.n_lamps,
				      o.cfg.timeout_ms, hl_clock_monotonic_ns(), &a, &aerr);
		if (rc < 0)
			goto out;
	}
	rc = hl_ring_new(o.ring_slots, o.n_lamps, n_src, &ring);
	if (rc == 0)
		rc = hl_snapshot_new(ring, &snap);
	if (rc == 0) {
		struct hl_can_input_config cfg = {
			.iface = o.cfg.interface[0] ? o.cfg.interface : NULL,
			.replay = o.cfg.replay[0] ? o.cfg.replay : NULL,
			.replay_fast = o.cfg.replay_fast,
			.replay_loop = o.cfg.replay_loop,
			.log = stderr,
		};

		rc = hl_can_input_new(&cfg, a, ring, &in);
		if (rc < 0)
			fprintf(stderr, "hdlampd: '%s': %s\n", cfg.iface ? cfg.iface : cfg.replay,
				strerror(-rc));
	}
	if (rc < 0)
		goto out;
	seen.status = o.cfg.replay[0] ? HL_INPUT_LINK_UP : 0;
	seen.link_errno = o.cfg.replay[0] ? 0 : ENETDOWN;
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

int main(int argc, char **argv)
{
	struct options o;
	int rc;

	setvbuf(stdout, NULL, _IOLBF, 0);
	rc = parse_options(argc, argv, &o);
	if (rc < 0)
		return rc == -ENOENT ? 1 : 2;
	if (o.print_config) {
		hl_config_print(&o.cfg, stdout);
		rc = 0;
	} else if (o.no_render) {
		rc = run_decode_only(&o);
	} else {
		struct hl_live_args args = {
			.config_path = o.config_path,
			.overrides = o.overrides,
			.n_overrides = o.n_overrides,
			.ring_slots = o.ring_slots,
		};

		if (o.print_cycles) {
			fprintf(stderr, "hdlampd: --print-cycles goes with --no-render\n");
			return 2;
		}
		rc = hl_live_run(&o.cfg, &args);
	}
	for (int i = 0; i < o.n_overrides; i++)
		free(o.overrides[i]);
	return rc;
}
