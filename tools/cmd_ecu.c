/* SPDX-License-Identifier: MIT */
/*
 * hdlamp ecu: the reference virtual headlamp ECU (docs/ecu.md) - a reference for software in
 * the loop and CI, not a product. Receives the vehicle state and the camera's objects from
 * SocketCAN (decoded by can/inputs.c from the input database), runs the lighting functions
 * (ecu/lighting.h) every 20 ms on CLOCK_MONOTONIC deadlines and sends both lamps' dimming
 * frames (encoded by the dimming database through can/assembler.c, E2E counter and CRC).
 * State changes and the final counters are JSON lines on stdout; SIGINT/SIGTERM end it cleanly.
 */
#include <errno.h>
#include <getopt.h>
#include <inttypes.h>
#include <math.h>
#include <net/if.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/signalfd.h>
#include <sys/socket.h>
#include <sys/timerfd.h>
#include <time.h>
#include <unistd.h>

#include <linux/can.h>
#include <linux/can/raw.h>

#include "can/assembler.h"
#include "can/inputs.h"
#include "can/socket.h"
#include "ecu/beams.h"
#include "ecu/lighting.h"
#include "lamp/model.h"
#include "lamp/share_dir.h"
#include "tools/commands.h"
#include "tools/json_out.h"
#include "tools/preset_arg.h"

#define PERIOD_NS 20000000LL /* the dimming cycle, 50 Hz */
#define MAX_LATE_MS 10000
#define DEFAULT_TIMEOUT_CYCLES 3 /* input cycles without a message before the fail-safe */
#define DEG (M_PI / 180.0)

struct opts {
	const char *iface;
	const char *inputs_dbc, *dbc; /* NULL: the shipped ones */
	const char *lamps_dir, *lid[2];
	int n_lid;
	const char *low, *high; /* preset files or built-in names */
	const char *windows_out;
	struct hl_ecu_config cfg;
	struct hl_ecu_mount mount[2];
	int timeout_ms; /* -1: DEFAULT_TIMEOUT_CYCLES of each input's cycle time */
	int late_ms;
	bool stuck_counter, bad_crc;
	long long cycles; /* stop after this many, 0: run until a signal */
};

/* One cycle's frames, waiting until due (the late fault) or sent at once. */
struct out_cycle {
	int64_t due_ns;
	int n[2];
	struct hl_encoded_frame frames[2][HL_ASM_MAX_PARTS];
};

struct counters {
	uint64_t cycles, frames_sent, tx_errors, skipped_deadlines, failsafe_cycles;
	uint64_t mode_cycles[4];
	uint64_t rx_frames, rx_errors, reopens, tx_reopens;
	int64_t late_max_ns; /* how far after its deadline a cycle was computed */
};

static void usage(FILE *f)
{
	fprintf(f,
		"usage: hdlamp ecu --can IFACE [--inputs-dbc FILE] [--dbc FILE]\n"
		"                  [--lamps DIR | --lid LEFT --lid RIGHT] [--low PRESET] [--high PRESET]\n"
		"                  [--camera X,Y,Z[,YAW,PITCH]] [--lamp-left X,Y,Z[,YAW,PITCH]]\n"
		"                  [--lamp-right X,Y,Z[,YAW,PITCH]] [--timeout-ms MS] [--margin-deg D]\n"
		"                  [--window-fraction F] [--auto-kmh V] [--min-confidence C] [--no-bend]\n"
		"                  [--fault NAME]... [--cycles N] [--windows FILE]\n"
		"\n"
		"The reference virtual headlamp ECU (docs/ecu.md; a reference, not a product): reads\n"
		"the vehicle state and the camera's objects from IFACE (the messages of --inputs-dbc,\n"
		"default the shipped hd84_inputs.dbc), runs low/high beam, auto and glare-free high\n"
		"beam, bend light and the fail-safe, and sends the lamps 'left' and 'right' of --dbc\n"
		"(default the shipped hd84.dbc) every 20 ms with E2E. Lamps: the built-in HD84 pair,\n"
		"DIR/hd84_left.lid.exr and _right, or two LID files; beams: the HD84 presets or\n"
		"--low/--high (preset files or built-in names).\n"
		"\n"
		"Positions in the vehicle frame (m; x forward, y left, z up; yaw left, pitch up, deg):\n"
		"camera default -1.5,0,1.3; lamps 0,0.7,0.65 and 0,-0.7,0.65 pitched -0.573.\n"
		"--timeout-ms: each input's timeout (default 3 of its GenMsgCycleTime); --margin-deg\n"
		"(0.5) around each object; --window-fraction (0.05) of the high beam that makes a\n"
		"source's window; --auto-kmh (40) auto high beam speed; --min-confidence (0.5).\n"
		"\n"
		"--fault NAME: ignore-objects (sees no objects), no-failsafe (keeps the last inputs),\n"
		"late=MS (sends every cycle MS late), stuck-counter (the alive counter stops),\n"
		"bad-crc (every frame's CRC is wrong).\n"
		"--cycles N stops after N cycles; --windows FILE writes every source's window (JSON).\n"
		"Prints JSON lines: start, mode (each change), summary. SIGINT/SIGTERM end it.\n");
}

static int bad(const char *opt, const char *arg, const char *expected)
{
	fprintf(stderr, "hdlamp ecu: %s '%s': expected %s\n", opt, arg, expected);
	return HL_EXIT_USAGE;
}

static int parse_num(const char *s, double lo, double hi, double *ret)
{
	char *end;
	double v;

	errno = 0;
	v = strtod(s, &end);
	if (errno || end == s || *end || !isfinite(v) || v < lo || v > hi)
		return -EINVAL;
	*ret = v;
	return 0;
}

/* X,Y,Z or X,Y,Z,YAW,PITCH */
static int parse_mount(const char *s, struct hl_ecu_mount *m)
{
	double v[5] = { 0 };
	int n = 0;
	const char *p = s;

	for (;;) {
		char *end;

		if (n == 5)
			return -EINVAL;
		errno = 0;
		v[n] = strtod(p, &end);
		if (errno || end == p || !isfinite(v[n]))
			return -EINVAL;
		n++;
		if (*end == '\0')
			break;
		if (*end != ',')
			return -EINVAL;
		p = end + 1;
	}
	if ((n != 3 && n != 5) || fabs(v[0]) > 30 || fabs(v[1]) > 5 || v[2] < 0 || v[2] > 5 ||
	    fabs(v[3]) > 90 || fabs(v[4]) > 30)
		return -EINVAL;
	*m = (struct hl_ecu_mount){ .pos_m = { v[0], v[1], v[2] },
				    .yaw_deg = v[3],
				    .pitch_deg = v[4] };
	return 0;
}

static int parse_fault(const char *s, struct opts *o)
{
	char *end;
	long ms;

	if (strcmp(s, "ignore-objects") == 0)
		o->cfg.faults |= HL_ECU_FAULT_IGNORE_OBJECTS;
	else if (strcmp(s, "no-failsafe") == 0)
		o->cfg.faults |= HL_ECU_FAULT_NO_FAILSAFE;
	else if (strcmp(s, "stuck-counter") == 0)
		o->stuck_counter = true;
	else if (strcmp(s, "bad-crc") == 0)
		o->bad_crc = true;
	else if (strncmp(s, "late=", 5) == 0) {
		errno = 0;
		ms = strtol(s + 5, &end, 10);
		if (errno || end == s + 5 || *end || ms < 1 || ms > MAX_LATE_MS)
			return -EINVAL;
		o->late_ms = (int)ms;
	} else
		return -EINVAL;
	return 0;
}

static int parse_args(int argc, char **argv, struct opts *o)
{
	static const struct option long_opts[] = {
		{ "can", required_argument, NULL, 'c' },
		{ "inputs-dbc", required_argument, NULL, 'I' },
		{ "dbc", required_argument, NULL, 'd' },
		{ "lamps", required_argument, NULL, 'L' },
		{ "lid", required_argument, NULL, 'l' },
		{ "low", required_argument, NULL, 'w' },
		{ "high", required_argument, NULL, 'H' },
		{ "camera", required_argument, NULL, 'C' },
		{ "lamp-left", required_argument, NULL, '0' },
		{ "lamp-right", required_argument, NULL, '1' },
		{ "timeout-ms", required_argument, NULL, 't' },
		{ "margin-deg", required_argument, NULL, 'm' },
		{ "window-fraction", required_argument, NULL, 'f' },
		{ "auto-kmh", required_argument, NULL, 'a' },
		{ "min-confidence", required_argument, NULL, 'k' },
		{ "no-bend", no_argument, NULL, 'B' },
		{ "fault", required_argument, NULL, 'F' },
		{ "cycles", required_argument, NULL, 'n' },
		{ "windows", required_argument, NULL, 'W' },
		{ "help", no_argument, NULL, 'h' },
		{ 0 },
	};
	int c;
	double v;

	hl_ecu_config_default(&o->cfg);
	for (int s = 0; s < 2; s++)
		o->mount[s] = (struct hl_ecu_mount){ .pos_m = { 0.0, s == 0 ? 0.7 : -0.7, 0.65 },
						     .pitch_deg = atan(-0.01) / DEG };
	o->timeout_ms = -1;
	while ((c = getopt_long(argc, argv, "h", long_opts, NULL)) != -1) {
		switch (c) {
		case 'c':
			if (!*optarg || strlen(optarg) >= IFNAMSIZ)
				return bad("--can", optarg, "an interface name");
			o->iface = optarg;
			break;
		case 'I':
			o->inputs_dbc = optarg;
			break;
		case 'd':
			o->dbc = optarg;
			break;
		case 'L':
			o->lamps_dir = optarg;
			break;
		case 'l':
			if (o->n_lid == 2)
				return bad("--lid", optarg, "two files: --lid LEFT --lid RIGHT");
			o->lid[o->n_lid++] = optarg;
			break;
		case 'w':
			o->low = optarg;
			break;
		case 'H':
			o->high = optarg;
			break;
		case 'C':
			if (parse_mount(optarg, &o->cfg.camera) < 0)
				return bad("--camera", optarg,
					   "X,Y,Z[,YAW,PITCH]: |X| <= 30, |Y| <= 5, Z in [0, 5] m, "
					   "|YAW| <= 90, |PITCH| <= 30 degrees");
			break;
		case '0':
		case '1':
			if (parse_mount(optarg, &o->mount[c - '0']) < 0)
				return bad(c == '0' ? "--lamp-left" : "--lamp-right", optarg,
					   "X,Y,Z[,YAW,PITCH]: |X| <= 30, |Y| <= 5, Z in [0, 5] m, "
					   "|YAW| <= 90, |PITCH| <= 30 degrees");
			break;
		case 't':
			if (parse_num(optarg, 1, 60000, &v) < 0 || v != floor(v))
				return bad("--timeout-ms", optarg, "an integer in [1, 60000]");
			o->timeout_ms = (int)v;
			break;
		case 'm':
			if (parse_num(optarg, 0, 45, &o->cfg.margin_deg) < 0)
				return bad("--margin-deg", optarg, "degrees in [0, 45]");
			break;
		case 'f':
			if (parse_num(optarg, 0, 1, &v) < 0 || v == 0 || v == 1)
				return bad("--window-fraction", optarg, "a number in (0, 1)");
			o->cfg.window_fraction = v;
			break;
		case 'a':
			if (parse_num(optarg, 0, 360, &v) < 0)
				return bad("--auto-kmh", optarg, "km/h in [0, 360]");
			o->cfg.auto_high_mps = v / 3.6;
			break;
		case 'k':
			if (parse_num(optarg, 0, 1, &o->cfg.min_confidence) < 0)
				return bad("--min-confidence", optarg, "a number in [0, 1]");
			break;
		case 'B':
			o->cfg.bend = false;
			break;
		case 'F':
			if (parse_fault(optarg, o) < 0)
				return bad("--fault", optarg,
					   "ignore-objects, no-failsafe, late=MS (1..10000), "
					   "stuck-counter or bad-crc");
			break;
		case 'n':
			if (parse_num(optarg, 1, 1e12, &v) < 0 || v != floor(v))
				return bad("--cycles", optarg, "a positive integer");
			o->cycles = (long long)v;
			break;
		case 'W':
			o->windows_out = optarg;
			break;
		case 'h':
			usage(stdout);
			return -1;
		default:
			usage(stderr);
			return HL_EXIT_USAGE;
		}
	}
	if (optind < argc)
		return bad("argument", argv[optind], "options only");
	if (!o->iface) {
		fprintf(stderr, "hdlamp ecu: --can IFACE is required\n");
		return HL_EXIT_USAGE;
	}
	if (o->lamps_dir && o->n_lid) {
		fprintf(stderr, "hdlamp ecu: --lamps and --lid exclude each other\n");
		return HL_EXIT_USAGE;
	}
	if (o->n_lid == 1) {
		fprintf(stderr, "hdlamp ecu: --lid needs two files: --lid LEFT --lid RIGHT\n");
		return HL_EXIT_USAGE;
	}
	return 0;
}

static int64_t mono_ns(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

static int64_t real_ns(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_REALTIME, &ts);
	return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

static int load_dbc(const char *arg, const char *shipped, struct hl_dbc **ret)
{
	char path[4096];
	struct hl_dbc_error err;
	int rc;

	if (arg) {
		snprintf(path, sizeof(path), "%s", arg);
	} else {
		rc = hl_share_dir("dbc", path, sizeof(path));
		if (rc < 0) {
			fprintf(stderr, "hdlamp ecu: cannot find the shipped databases: %s\n",
				strerror(-rc));
			return rc;
		}
		strncat(path, "/", sizeof(path) - strlen(path) - 1);
		strncat(path, shipped, sizeof(path) - strlen(path) - 1);
	}
	rc = hl_dbc_parse_file(path, ret, &err);
	if (rc < 0) {
		if (err.line > 0)
			fprintf(stderr, "hdlamp ecu: '%s':%d:%d: %s\n", path, err.line, err.column,
				err.msg);
		else
			fprintf(stderr, "hdlamp ecu: '%s': %s\n", path, err.msg);
	}
	return rc;
}

static int load_lamps(const struct opts *o, struct hl_lid *lids[2])
{
	for (int s = 0; s < 2; s++) {
		char path[4096];
		struct hl_lid_error err;
		int rc;

		if (!o->lamps_dir && !o->n_lid) {
			rc = hl_model_hd84(s, &lids[s]);
			if (rc < 0) {
				fprintf(stderr, "hdlamp ecu: the HD84 model: %s\n", strerror(-rc));
				return rc;
			}
			continue;
		}
		if (o->lamps_dir)
			snprintf(path, sizeof(path), "%s/hd84_%s.lid.exr", o->lamps_dir,
				 hl_side_name(s));
		else
			snprintf(path, sizeof(path), "%s", o->lid[s]);
		rc = hl_lid_read(path, &lids[s], &err);
		if (rc < 0) {
			fprintf(stderr, "hdlamp ecu: %s\n", err.msg);
			return rc;
		}
		if (hl_lid_is_combined(lids[s])) {
			fprintf(stderr,
				"hdlamp ecu: '%s': a combined distribution; expected a LID file of "
				"sources\n",
				path);
			return -EINVAL;
		}
	}
	return 0;
}

/* The beams: --low/--high (preset files or built-in names), else ecu/beams.h's defaults. */
static int load_beams(const struct opts *o, struct hl_lid *lids[2], float *low[2], float *high[2])
{
	for (int s = 0; s < 2; s++) {
		int rc = hl_ecu_beams_default(lids[s], s, o->cfg.window_fraction, low[s], high[s]);

		if (rc < 0) {
			fprintf(stderr, "hdlamp ecu: the beams of the %s lamp: %s\n",
				hl_side_name(s), strerror(-rc));
			return rc;
		}
	}
	for (int b = 0; b < 2; b++) {
		const char *arg = b == 0 ? o->low : o->high;
		struct hl_preset *p;
		int rc;

		if (!arg)
			continue;
		rc = hl_tool_preset_load("ecu", arg, lids, 2, &p);
		if (rc < 0)
			return rc;
		for (int s = 0; s < 2; s++)
			hl_preset_intensities(p, s, b == 0 ? low[s] : high[s]);
		hl_preset_free(p);
	}
	return 0;
}

static int write_windows(const char *path, const struct hl_ecu *e, struct hl_lid *lids[2])
{
	FILE *f = fopen(path, "we");

	if (!f) {
		fprintf(stderr, "hdlamp ecu: '%s': %s\n", path, strerror(errno));
		return -errno;
	}
	fprintf(f, "{");
	for (int s = 0; s < 2; s++) {
		const struct hl_ecu_window *w = hl_ecu_windows_of(e, s);

		fprintf(f, "%s\"%s\":[", s ? "," : "", hl_side_name(s));
		for (int k = 0; k < hl_lid_n_sources(lids[s]); k++) {
			fprintf(f, "%s", k ? "," : "");
			if (w[k].empty) {
				fprintf(f, "null");
				continue;
			}
			fprintf(f, "[");
			hl_tool_json_num(f, w[k].h0_deg);
			fprintf(f, ",");
			hl_tool_json_num(f, w[k].h1_deg);
			fprintf(f, ",");
			hl_tool_json_num(f, w[k].v0_deg);
			fprintf(f, ",");
			hl_tool_json_num(f, w[k].v1_deg);
			fprintf(f, "]");
		}
		fprintf(f, "]");
	}
	fprintf(f, "}\n");
	if (fclose(f) != 0) {
		fprintf(stderr, "hdlamp ecu: '%s': %s\n", path, strerror(errno));
		return -EIO;
	}
	return 0;
}

/* The sending socket: raw CAN on iface, CAN FD frames allowed when fd. */
static int tx_open(const char *iface, bool fd)
{
	struct sockaddr_can addr = { .can_family = AF_CAN };
	const int on = 1;
	const struct can_filter none = { .can_id = 0, .can_mask = CAN_EFF_FLAG | CAN_RTR_FLAG };
	int s;

	addr.can_ifindex = (int)if_nametoindex(iface);
	if (addr.can_ifindex == 0)
		return -ENODEV;
	s = socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC | SOCK_NONBLOCK, CAN_RAW);
	if (s < 0)
		return -errno;
	/* it only sends: a filter no frame passes (an 11-bit ID 0 that must be extended) */
	if (setsockopt(s, SOL_CAN_RAW, CAN_RAW_FILTER, &none, sizeof(none)) < 0 ||
	    (fd && setsockopt(s, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &on, sizeof(on)) < 0) ||
	    bind(s, (struct sockaddr *)&addr, sizeof(addr)) < 0) {
		const int rc = -errno;

		close(s);
		return rc;
	}
	return s;
}

/* Sends one cycle's frames; returns the last failed write's -errno, 0 when all went out. */
static int send_cycle(int tx, const struct out_cycle *oc, struct counters *cnt)
{
	int rc = 0;

	for (int l = 0; l < 2; l++) {
		for (int i = 0; i < oc->n[l]; i++) {
			const struct hl_encoded_frame *e = &oc->frames[l][i];
			struct canfd_frame f = e->frame;
			const size_t size = e->fd ? CANFD_MTU : CAN_MTU;

			if (e->fd)
				f.flags |= CANFD_BRS;
			if (tx >= 0 && write(tx, &f, size) == (ssize_t)size) {
				cnt->frames_sent++;
				continue;
			}
			cnt->tx_errors++;
			rc = tx < 0 ? -ENODEV : -errno;
		}
	}
	return rc;
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
	printf("},\"inputs\":{\"frames\":%" PRIu64 ",\"unknown_id\":%" PRIu64
	       ",\"short_frames\":%" PRIu64 ",\"crc_errors\":%" PRIu64
	       ",\"counter_repeated\":%" PRIu64 ",\"counter_lost\":%" PRIu64
	       ",\"bad_values\":%" PRIu64 ",\"duplicates\":%" PRIu64 ",\"vehicle_states\":%" PRIu64
	       ",\"object_frames\":%" PRIu64 ",\"cycles_complete\":%" PRIu64
	       ",\"cycles_incomplete\":%" PRIu64 "}",
	       in->frames, in->unknown_id, in->short_frames, in->crc_errors, in->counter_repeated,
	       in->counter_lost, in->bad_values, in->duplicates, in->vehicle_states,
	       in->object_frames, in->cycles_complete, in->cycles_incomplete);
	printf(",\"socket\":{\"frames\":%" PRIu64 ",\"kernel_drops\":%" PRIu64
	       ",\"error_frames\":%" PRIu64 ",\"read_errors\":%" PRIu64 ",\"reopens\":%" PRIu64
	       ",\"tx_reopens\":%" PRIu64 "}}\n",
	       ss->frames, ss->kernel_drops, ss->error_frames, c->rx_errors, c->reopens,
	       c->tx_reopens);
	fflush(stdout);
}

struct ecu_run {
	struct opts *o;
	struct hl_assembler *a;
	struct hl_inputs_map *map;
	struct hl_inputs_decoder *dec;
	struct hl_ecu *e;
	struct hl_can_socket *rx;
	int tx, tfd, sfd;
	bool tx_fd; /* the dimming frames include CAN FD ones */
	struct out_cycle *q; /* ring of pending cycles */
	int q_size, q_head, q_len;
	unsigned counter[2];
	struct counters c;
	struct hl_ecu_status last;
	bool have_last;
	int64_t rx_retry_ns; /* when to reopen a closed receive socket, 0: open */
};

/* Drains the receive socket into the ECU. */
static void receive(struct ecu_run *r)
{
	struct hl_can_rx f;
	const int64_t mono_minus_real = mono_ns() - real_ns();
	int rc;

	while ((rc = hl_can_socket_read(r->rx, &f)) == 1) {
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
	if (rc < 0) {
		r->c.rx_errors++;
		fprintf(stderr, "hdlamp ecu: can: '%s': %s, reopening\n", r->o->iface,
			strerror(-rc));
		r->rx_retry_ns = mono_ns() + (int64_t)hl_can_socket_retry_ms(r->rx) * 1000000;
	}
}

/* Computes the cycle of deadline t_deadline and queues (or sends) its frames. */
static int compute_cycle(struct ecu_run *r, int64_t t_deadline)
{
	struct hl_ecu_status st;
	struct out_cycle *oc;
	const int64_t now = mono_ns();

	hl_ecu_step(r->e, now, &st);
	if (now - t_deadline > r->c.late_max_ns)
		r->c.late_max_ns = now - t_deadline;
	r->c.cycles++;
	r->c.mode_cycles[st.mode]++;
	if (st.failsafe)
		r->c.failsafe_cycles++;
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
		int rc;

		/* an interface deleted and added again: the old socket is bound to nothing */
		if (r->tx < 0) {
			r->tx = tx_open(r->o->iface, r->tx_fd);
			if (r->tx >= 0)
				r->c.tx_reopens++;
		}
		rc = send_cycle(r->tx, &r->q[r->q_head], &r->c);

		/* raw CAN's send: -ENXIO when its interface is gone, -ENETDOWN while it is down */
		if ((rc == -ENXIO || rc == -ENODEV) && r->tx >= 0) {
			close(r->tx);
			r->tx = -1;
		}
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

static int run_loop(struct ecu_run *r)
{
	int64_t next = mono_ns() + PERIOD_NS;

	for (;;) {
		struct pollfd p[3] = {
			{ .fd = r->tfd, .events = POLLIN },
			{ .fd = r->sfd, .events = POLLIN },
			{ .fd = r->rx_retry_ns ? -1 : hl_can_socket_fd(r->rx), .events = POLLIN },
		};
		int64_t wake = next, now;
		int rc;

		if (r->q_len > 0 && r->q[r->q_head].due_ns < wake)
			wake = r->q[r->q_head].due_ns;
		if (r->rx_retry_ns && r->rx_retry_ns < wake)
			wake = r->rx_retry_ns;
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
		now = mono_ns();
		if (r->rx_retry_ns && now >= r->rx_retry_ns) {
			r->rx_retry_ns = 0;
			if (hl_can_socket_open(r->rx) < 0)
				r->rx_retry_ns =
					now + (int64_t)hl_can_socket_retry_ms(r->rx) * 1000000;
			else
				r->c.reopens++;
		}
		if (now >= next && (!r->o->cycles || r->c.cycles < (uint64_t)r->o->cycles)) {
			/* take what arrived up to the deadline first */
			if (!r->rx_retry_ns)
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
		send_due(r, mono_ns());
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
	rc = hl_can_socket_new(r->o->iface, ids, n_ids, &r->rx);
	if (rc == 0)
		rc = hl_can_socket_open(r->rx);
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
	r->tx_fd = fd;
	r->tx = tx_open(r->o->iface, fd);
	if (r->tx < 0) {
		fprintf(stderr, "hdlamp ecu: can: '%s': cannot send: %s\n", r->o->iface,
			strerror(-r->tx));
		return r->tx;
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

/* Each input's timeout: --timeout-ms, else DEFAULT_TIMEOUT_CYCLES of its message's cycle. */
static void set_timeouts(struct opts *o, const struct hl_inputs_map *map)
{
	for (int i = 0; i < hl_inputs_map_n_messages(map); i++) {
		const struct hl_inputs_message *m = hl_inputs_map_message(map, i);
		const int64_t cycle_ns = (int64_t)(m->cycle_ms ? m->cycle_ms : 20) * 1000000;
		const int64_t t = o->timeout_ms > 0 ? (int64_t)o->timeout_ms * 1000000 :
						      DEFAULT_TIMEOUT_CYCLES * cycle_ns;

		if (m->kind == HL_INPUTS_VEHICLE)
			o->cfg.vehicle_timeout_ns = t;
		else
			o->cfg.objects_timeout_ns = t;
	}
}

static int prepare(struct ecu_run *r, struct hl_dbc *dim_db, struct hl_dbc *in_db,
		   struct hl_lid *lids[2], float *beams)
{
	static const char *const names[2] = { "left", "right" };
	struct hl_asm_error aerr = { { 0 } };
	char msg[512] = "";
	float *low[2], *high[2];
	struct hl_ecu_lamp lamps[2];
	const char *what = NULL;
	int rc;

	rc = hl_assembler_new(dim_db, names, 2, 1000, mono_ns(), &r->a, &aerr);
	if (rc < 0) {
		fprintf(stderr, "hdlamp ecu: the dimming database: %s\n", aerr.msg);
		return rc;
	}
	rc = hl_inputs_map_new(in_db, &r->map, msg, sizeof(msg));
	if (rc < 0) {
		fprintf(stderr, "hdlamp ecu: the input database: %s\n", msg);
		return rc;
	}
	rc = hl_inputs_decoder_new(r->map, &r->dec);
	if (rc < 0)
		return rc;
	set_timeouts(r->o, r->map);
	for (int s = 0; s < 2; s++) {
		if (hl_assembler_n_sources(r->a, s) != hl_lid_n_sources(lids[s])) {
			fprintf(stderr,
				"hdlamp ecu: the %s lamp has %d sources, the dimming database "
				"carries %d\n",
				names[s], hl_lid_n_sources(lids[s]),
				hl_assembler_n_sources(r->a, s));
			return -EINVAL;
		}
		low[s] = beams + (size_t)2 * s * HL_LID_MAX_SOURCES;
		high[s] = low[s] + HL_LID_MAX_SOURCES;
	}
	rc = load_beams(r->o, lids, low, high);
	if (rc < 0)
		return rc;
	for (int s = 0; s < 2; s++)
		lamps[s] = (struct hl_ecu_lamp){
			.lid = lids[s], .mount = r->o->mount[s], .low = low[s], .high = high[s]
		};
	rc = hl_ecu_new(&r->o->cfg, lamps, 2, &r->e, &what);
	if (rc < 0)
		fprintf(stderr, "hdlamp ecu: %s\n", what ? what : strerror(-rc));
	return rc;
}

int hl_cmd_ecu(int argc, char **argv)
{
	struct opts o = { 0 };
	struct ecu_run r = { .o = &o, .tx = -1, .tfd = -1, .sfd = -1 };
	struct hl_dbc *dim_db = NULL, *in_db = NULL;
	struct hl_lid *lids[2] = { NULL, NULL };
	float *beams = NULL;
	int rc = parse_args(argc, argv, &o), ret = HL_EXIT_FAIL;

	if (rc != 0)
		return rc < 0 ? HL_EXIT_OK : rc;
	beams = malloc(sizeof(float) * 4 * HL_LID_MAX_SOURCES);
	if (!beams || load_dbc(o.dbc, "hd84.dbc", &dim_db) < 0 ||
	    load_dbc(o.inputs_dbc, "hd84_inputs.dbc", &in_db) < 0 || load_lamps(&o, lids) < 0 ||
	    prepare(&r, dim_db, in_db, lids, beams) < 0)
		goto out;
	if (o.windows_out && write_windows(o.windows_out, r.e, lids) < 0)
		goto out;
	if (setup_io(&r) < 0)
		goto out;
	printf("{\"event\":\"start\",\"t_ns\":%" PRId64 ",\"iface\":\"%s\",\"sources\":[%d,%d],"
	       "\"vehicle_timeout_ms\":%.3f,\"objects_timeout_ms\":%.3f,\"late_ms\":%d}\n",
	       mono_ns(), o.iface, hl_lid_n_sources(lids[0]), hl_lid_n_sources(lids[1]),
	       o.cfg.vehicle_timeout_ns / 1e6, o.cfg.objects_timeout_ns / 1e6, o.late_ms);
	fflush(stdout);
	rc = run_loop(&r);
	if (rc < 0) {
		fprintf(stderr, "hdlamp ecu: %s\n", strerror(-rc));
	} else {
		struct hl_can_socket_stats ss;

		hl_can_socket_stats(r.rx, &ss);
		print_summary(&r.c, hl_inputs_decoder_counters(r.dec), &ss);
		ret = HL_EXIT_OK;
	}
out:
	if (r.tx >= 0)
		close(r.tx);
	if (r.tfd >= 0)
		close(r.tfd);
	if (r.sfd >= 0)
		close(r.sfd);
	free(r.q);
	hl_can_socket_free(r.rx);
	hl_ecu_free(r.e);
	hl_inputs_decoder_free(r.dec);
	hl_inputs_map_free(r.map);
	hl_assembler_free(r.a);
	hl_lid_free(lids[0]);
	hl_lid_free(lids[1]);
	hl_dbc_free(dim_db);
	hl_dbc_free(in_db);
	free(beams);
	return ret;
}
