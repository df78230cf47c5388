/* SPDX-License-Identifier: MIT */
/*
 * hl-bench-dbc: how fast frames decode with a database (default dbc/hd84.dbc).
 *
 * Generates N random valid frames (all messages in turn, multiplexor values within range,
 * E2E CRC and counters per HdlE2E), writes them as a candump -L log (generated here, deleted
 * afterwards unless --keep), and measures single-threaded:
 *   decode       hl_dbc_decode_frame() over the frames in memory (lookup by ID + all present
 *                signals to physical values): the decode step, no I/O, no text
 *   decode_e2e   the same plus the E2E CRC check of every frame
 *   parse_decode hl_candump_parse() of the log lines in memory, then decode
 *   cli          `hdlamp dbc decode --dbc FILE LOG > /dev/null`, end to end (wall clock)
 * and prints one JSON object. The in-process passes are timed in thread CPU time (best of
 * repeated passes over at least --min-seconds), the tool in its CPU time (user + system) and
 * in wall-clock time, so that a busy shared machine disturbs the numbers as little as possible.
 */
#include <errno.h>
#include <getopt.h>
#include <libgen.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "can/candump.h"
#include "can/e2e.h"
#include "dbc/database.h"

struct frame {
	uint32_t can_id;
	uint8_t len;
	uint8_t data[HL_DBC_MAX_PAYLOAD];
};

static double now_s(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* CPU time of this thread: what a pass costs, whatever else the shared machine runs. */
static double now_cpu(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
	return ts.tv_sec + ts.tv_nsec * 1e-9;
}

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;

static uint64_t rnd(void)
{
	/* xorshift64*: reproducible, no libc state */
	rng_state ^= rng_state >> 12;
	rng_state ^= rng_state << 25;
	rng_state ^= rng_state >> 27;
	return rng_state * 0x2545f4914f6cdd1dull;
}

static uint64_t random_raw(const struct hl_dbc_signal *s)
{
	uint64_t top = s->length == 64 ? UINT64_MAX : ((uint64_t)1 << s->length) - 1;

	if (s->min < s->max && s->type == HL_DBC_INTEGER && !s->is_signed && s->offset == 0 &&
	    s->max / s->factor < (double)top)
		top = (uint64_t)(s->max / s->factor + 1e-9);
	return top == UINT64_MAX ? rnd() : rnd() % (top + 1);
}

static void usage(FILE *f)
{
	fprintf(f, "usage: hl-bench-dbc [--dbc FILE] [--frames N] [--log PATH] [--keep]\n"
		   "                    [--hdlamp PATH] [--min-seconds S]\n"
		   "Decode benchmark; prints JSON (frames/s) on stdout.\n");
}

/* One pass of the decode step over all frames; returns a checksum so nothing is elided. */
static double decode_pass(const struct hl_dbc *db, const struct frame *fr, long n,
			  struct hl_dbc_value *vals, struct hl_dbc_counters *c)
{
	double sum = 0;

	for (long i = 0; i < n; i++) {
		const struct hl_dbc_message *m;
		int k = hl_dbc_decode_frame(db, fr[i].can_id, fr[i].data, fr[i].len, c, &m, vals);

		if (k > 0)
			sum += vals[k - 1].phys;
	}
	return sum;
}

static double decode_e2e_pass(const struct hl_dbc *db, const struct frame *fr, long n,
			      struct hl_dbc_value *vals, const struct hl_e2e_config *cfg,
			      long *ret_bad)
{
	double sum = 0;

	for (long i = 0; i < n; i++) {
		const struct hl_dbc_message *m;
		int k = hl_dbc_decode_frame(db, fr[i].can_id, fr[i].data, fr[i].len, NULL, &m,
					    vals);

		if (k > 0) {
			sum += vals[k - 1].phys;
			if (cfg[m - hl_dbc_message(db, 0)].profile != HL_E2E_NONE &&
			    hl_e2e_check(&cfg[m - hl_dbc_message(db, 0)], fr[i].data, fr[i].len) <
				    0)
				(*ret_bad)++;
		}
	}
	return sum;
}

int main(int argc, char **argv)
{
	static const struct option opts[] = {
		{ "dbc", required_argument, NULL, 'd' },
		{ "frames", required_argument, NULL, 'n' },
		{ "log", required_argument, NULL, 'l' },
		{ "keep", no_argument, NULL, 'k' },
		{ "hdlamp", required_argument, NULL, 'x' },
		{ "min-seconds", required_argument, NULL, 's' },
		{ "help", no_argument, NULL, 'h' },
		{ 0 },
	};
	const char *dbc_path = HL_DBC_DIR "/hd84.dbc";
	char log_default[64], hdlamp_default[PATH_MAX], self[PATH_MAX];
	const char *log_path = NULL, *hdlamp = NULL;
	long n_frames = 1000000, bad = 0;
	double min_s = 1.0;
	bool keep = false;
	struct hl_dbc *db;
	struct hl_dbc_error err;
	struct hl_e2e_config *cfg;
	struct hl_dbc_value *vals;
	struct frame *fr;
	char *text;
	size_t text_len = 0;
	unsigned *counters;
	long total_signals = 0;
	int c, n_msgs;
	FILE *log;

	while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
		switch (c) {
		case 'd':
			dbc_path = optarg;
			break;
		case 'n':
			n_frames = strtol(optarg, NULL, 10);
			if (n_frames < 1 || n_frames > 100000000) {
				fprintf(stderr, "hl-bench-dbc: --frames: expected 1..1e8\n");
				return 2;
			}
			break;
		case 'l':
			log_path = optarg;
			break;
		case 'k':
			keep = true;
			break;
		case 'x':
			hdlamp = optarg;
			break;
		case 's':
			min_s = strtod(optarg, NULL);
			break;
		case 'h':
			usage(stdout);
			return 0;
		default:
			usage(stderr);
			return 2;
		}
	}
	if (optind != argc) {
		usage(stderr);
		return 2;
	}
	if (!hdlamp) {
		ssize_t k = readlink("/proc/self/exe", self, sizeof(self) - 1);

		if (k < 0) {
			fprintf(stderr, "hl-bench-dbc: /proc/self/exe: %s\n", strerror(errno));
			return 1;
		}
		self[k] = '\0';
		snprintf(hdlamp_default, sizeof(hdlamp_default), "%s/hdlamp", dirname(self));
		hdlamp = hdlamp_default;
	}
	if (!log_path) {
		snprintf(log_default, sizeof(log_default), "/tmp/hl-bench-dbc-%d.log",
			 (int)getpid());
		log_path = log_default;
	}
	if (hl_dbc_parse_file(dbc_path, &db, &err) < 0) {
		fprintf(stderr, "hl-bench-dbc: '%s':%d:%d: %s\n", dbc_path, err.line, err.column,
			err.msg);
		return 1;
	}
	n_msgs = hl_dbc_n_messages(db);
	cfg = calloc(n_msgs, sizeof(*cfg));
	counters = calloc(n_msgs, sizeof(*counters));
	vals = malloc(sizeof(*vals) * (hl_dbc_max_signals(db) + 1));
	fr = malloc(sizeof(*fr) * n_frames);
	text = malloc((size_t)n_frames * 200);
	if (!cfg || !counters || !vals || !fr || !text) {
		fprintf(stderr, "hl-bench-dbc: out of memory\n");
		return 1;
	}
	for (int i = 0; i < n_msgs; i++) {
		struct hl_dbc_attr_value v;

		if (hl_dbc_message_attr(db, hl_dbc_message(db, i), "HdlE2E", &v) >= 0 &&
		    v.type == HL_DBC_ATTR_STRING)
			hl_e2e_config_parse(v.s, &cfg[i]);
	}

	/* the frames, and the log with the same frames */
	log = fopen(log_path, "we");
	if (!log) {
		fprintf(stderr, "hl-bench-dbc: '%s': %s\n", log_path, strerror(errno));
		return 1;
	}
	for (long i = 0; i < n_frames; i++) {
		int mi = (int)(i % n_msgs);
		const struct hl_dbc_message *m = hl_dbc_message(db, mi);
		struct hl_candump_frame f = { 0 };
		int len;

		memset(&fr[i], 0, sizeof(fr[i]));
		fr[i].can_id = m->can_id;
		fr[i].len = (uint8_t)m->size;
		for (int k = 0; k < m->n_signals; k++)
			if (m->signals[k].mux_parent < 0)
				hl_dbc_signal_set_raw(&m->signals[k], random_raw(&m->signals[k]),
						      fr[i].data, m->size);
		for (int k = 0; k < m->n_signals; k++)
			if (m->signals[k].mux_parent >= 0 &&
			    hl_dbc_signal_present(m, &m->signals[k], fr[i].data, m->size))
				hl_dbc_signal_set_raw(&m->signals[k], random_raw(&m->signals[k]),
						      fr[i].data, m->size);
		if (cfg[mi].profile != HL_E2E_NONE) {
			hl_e2e_protect(&cfg[mi], fr[i].data, m->size, counters[mi]);
			counters[mi] =
				(counters[mi] + 1) % (hl_e2e_counter_max(cfg[mi].profile) + 1);
		}
		f.t_us = 1436509052000000LL + i * 20000 / 24;
		strcpy(f.iface, "can0");
		f.fd = m->size > 8;
		f.frame.can_id = m->id | (m->extended ? CAN_EFF_FLAG : 0);
		f.frame.len = (uint8_t)m->size;
		memcpy(f.frame.data, fr[i].data, m->size);
		len = hl_candump_format(&f, text + text_len, HL_CANDUMP_MAX_LINE);
		if (len < 0) {
			fprintf(stderr, "hl-bench-dbc: cannot format frame %ld\n", i);
			return 1;
		}
		text[text_len + len] = '\n';
		text_len += len + 1;
	}
	if (fwrite(text, 1, text_len, log) != text_len || fclose(log) != 0) {
		fprintf(stderr, "hl-bench-dbc: '%s': write error\n", log_path);
		return 1;
	}

	/* decode step: repeat passes for at least min_s, keep the best */
	double best = 1e30, best_e2e = 1e30, best_parse = 1e30, sum = 0, t0;
	struct hl_dbc_counters cnt = { 0 };

	decode_pass(db, fr, n_frames, vals, &cnt);
	for (long i = 0; i < n_frames; i++) {
		const struct hl_dbc_message *m;

		total_signals += hl_dbc_decode_frame(db, fr[i].can_id, fr[i].data, fr[i].len, NULL,
						     &m, vals);
	}
	t0 = now_s();
	do {
		double a = now_cpu(), b;

		sum += decode_pass(db, fr, n_frames, vals, &cnt);
		b = now_cpu();
		if (b - a < best)
			best = b - a;
	} while (now_s() - t0 < min_s);
	t0 = now_s();
	do {
		double a = now_cpu(), b;

		bad = 0;
		sum += decode_e2e_pass(db, fr, n_frames, vals, cfg, &bad);
		b = now_cpu();
		if (b - a < best_e2e)
			best_e2e = b - a;
	} while (now_s() - t0 < min_s);
	t0 = now_s();
	do {
		double a = now_cpu(), b;
		const char *p = text, *end = text + text_len;

		while (p < end) {
			const char *nl = memchr(p, '\n', end - p);
			struct hl_candump_frame f;
			const struct hl_dbc_message *m;
			int k;

			if (hl_candump_parse(p, nl - p, &f, NULL) == 0) {
				k = hl_dbc_decode_frame(
					db, f.frame.can_id & (CAN_EFF_FLAG | CAN_EFF_MASK),
					f.frame.data, f.frame.len, NULL, &m, vals);
				if (k > 0)
					sum += vals[k - 1].phys;
			}
			p = nl + 1;
		}
		b = now_cpu();
		if (b - a < best_parse)
			best_parse = b - a;
	} while (now_s() - t0 < min_s);

	/* end to end: the tool, output to /dev/null */
	double cli_s = -1, cli_cpu_s = -1;
	{
		double a = now_s();
		pid_t pid = fork();
		struct rusage ru;
		int status;

		if (pid == 0) {
			if (!freopen("/dev/null", "w", stdout))
				_exit(127);
			execl(hdlamp, hdlamp, "dbc", "decode", "--dbc", dbc_path, log_path,
			      (char *)NULL);
			_exit(127);
		}
		if (pid > 0 && wait4(pid, &status, 0, &ru) == pid && WIFEXITED(status) &&
		    WEXITSTATUS(status) == 0) {
			cli_s = now_s() - a;
			cli_cpu_s = ru.ru_utime.tv_sec + ru.ru_utime.tv_usec * 1e-6 +
				    ru.ru_stime.tv_sec + ru.ru_stime.tv_usec * 1e-6;
		} else {
			fprintf(stderr, "hl-bench-dbc: '%s dbc decode' failed\n", hdlamp);
		}
	}
	if (!keep)
		unlink(log_path);

	printf("{\"dbc\":\"%s\",\"frames\":%ld,\"log_bytes\":%zu,\"signals_per_frame\":%.2f,"
	       "\"decode_fps\":%.0f,\"decode_ns_per_frame\":%.1f,"
	       "\"decode_e2e_fps\":%.0f,\"e2e_failures\":%ld,"
	       "\"parse_decode_fps\":%.0f,"
	       "\"cli_decode_fps\":%.0f,\"cli_cpu_seconds\":%.3f,"
	       "\"cli_decode_fps_wall\":%.0f,\"cli_wall_seconds\":%.3f,\"checksum\":%.6g}\n",
	       dbc_path, n_frames, text_len, (double)total_signals / n_frames, n_frames / best,
	       best / n_frames * 1e9, n_frames / best_e2e, bad, n_frames / best_parse,
	       cli_cpu_s > 0 ? n_frames / cli_cpu_s : 0.0, cli_cpu_s,
	       cli_s > 0 ? n_frames / cli_s : 0.0, cli_s, sum);
	free(text);
	free(fr);
	free(vals);
	free(counters);
	free(cfg);
	hl_dbc_free(db);
	return bad || cli_s < 0 ? 1 : 0;
}
