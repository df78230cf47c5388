/* SPDX-License-Identifier: MIT */
/*
 * hdlamp dbc: show a CAN database, decode candump logs with it, encode frames. This file holds
 * the usage, the options and the dispatch, and what the subcommands share (loading a .dbc with
 * its warnings, formatting doubles); each subcommand is a file of its own (cmd_dbc_info.c,
 * cmd_dbc_decode.c, cmd_dbc_encode.c) so that none grows past a readable size.
 */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>

#include "can/candump.h"
#include "dbc/database.h"
#include "tools/cmd_dbc.h"
#include "tools/commands.h"

static void usage(FILE *f)
{
	fprintf(f,
		"usage: hdlamp dbc info [--strict] FILE\n"
		"       hdlamp dbc decode [--strict] --dbc FILE [LOG|-]\n"
		"       hdlamp dbc encode [--strict] --dbc FILE --message NAME [--e2e] [--counter N]\n"
		"                         [--time SEC.USEC] [--iface NAME] [SIGNAL=VALUE ...]\n"
		"\n"
		"The .dbc is loaded leniently: what real files get wrong but can be read (comments\n"
		"or values for signals that do not exist, signals past their message, exponents\n"
		"in integers, ...) is read and printed as a warning with file:line:column on\n"
		"stderr. --strict refuses such files instead (the daemon: dbc.strict = true).\n"
		"See docs/dbc-compat.md.\n"
		"\n"
		"info    messages, signals, multiplexing, value tables, comments and every\n"
		"        attribute (set or default) of a .dbc file\n"
		"decode  reads candump -L lines (classic and CAN FD) from LOG or stdin and writes\n"
		"        one JSON object per frame: t, iface, id, name, signals (physical values),\n"
		"        e2e: ok | crc | repeated | lost (with \"lost\": n) | counter | none\n"
		"        (unknown IDs: \"name\": null; short frames: \"error\"; error frames:\n"
		"        \"error_frame\": true, counted apart). A float value that is NaN or\n"
		"        infinite is written as the string \"NaN\", \"Infinity\" or \"-Infinity\"\n"
		"encode  prints one candump -L line of message NAME; unset signals are 0, a VALUE\n"
		"        is a physical value or a VAL_ description; --e2e computes the CRC of the\n"
		"        message's HdlE2E profile and writes --counter N (default: the counter the\n"
		"        payload already has)\n");
}

int load(const char *path, unsigned flags, struct hl_dbc **ret)
{
	struct hl_dbc_error err;
	int rc = hl_dbc_parse_file_flags(path, flags, ret, &err);

	if (rc < 0) {
		if (err.line)
			fprintf(stderr, "hdlamp dbc: '%s':%d:%d: %s\n", path, err.line, err.column,
				err.msg);
		else
			fprintf(stderr, "hdlamp dbc: '%s': %s\n", path, err.msg);
		return rc;
	}
	for (int i = 0; i < hl_dbc_n_warnings(*ret); i++) {
		int line, col;
		const char *w = hl_dbc_warning(*ret, i, &line, &col);

		fprintf(stderr, "hdlamp dbc: '%s':%d:%d: warning: %s\n", path, line, col, w);
	}
	return 0;
}

/* The shortest %g that reads back as the same double, into buf (32 bytes). */
void format_double(char *buf, double v)
{
	if (!isfinite(v)) {
		strcpy(buf, "null");
		return;
	}
	for (int prec = 15; prec <= 17; prec++) {
		snprintf(buf, 32, "%.*g", prec, v);
		if (strtod(buf, NULL) == v)
			break;
	}
}

static int parse_time(const char *s, int64_t *ret)
{
	char *end;
	long long sec;
	long usec = 0;
	int digits = 0;

	errno = 0;
	sec = strtoll(s, &end, 10);
	if (errno || end == s || sec < 0 || sec > 999999999999LL)
		return -EINVAL;
	if (*end == '.') {
		for (end++; *end >= '0' && *end <= '9' && digits < 6; end++, digits++)
			usec = usec * 10 + (*end - '0');
		if (digits == 0)
			return -EINVAL;
		for (; digits < 6; digits++)
			usec *= 10;
	}
	if (*end)
		return -EINVAL;
	*ret = sec * 1000000 + usec;
	return 0;
}

int hl_cmd_dbc(int argc, char **argv)
{
	static const struct option opts[] = {
		{ "dbc", required_argument, NULL, 'd' },
		{ "message", required_argument, NULL, 'm' },
		{ "e2e", no_argument, NULL, 'e' },
		{ "counter", required_argument, NULL, 'c' },
		{ "time", required_argument, NULL, 't' },
		{ "iface", required_argument, NULL, 'i' },
		{ "strict", no_argument, NULL, 's' },
		{ "help", no_argument, NULL, 'h' },
		{ 0 },
	};
	unsigned flags = 0;
	const char *dbc = NULL, *msg = NULL, *iface = "can0", *sub;
	bool e2e = false;
	long counter = -1;
	int64_t t_us = -1;
	int c;

	if (argc < 2) {
		usage(stderr);
		return HL_EXIT_USAGE;
	}
	sub = argv[1];
	if (strcmp(sub, "--help") == 0 || strcmp(sub, "-h") == 0) {
		usage(stdout);
		return HL_EXIT_OK;
	}
	argc--;
	argv++;
	optind = 1;
	while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
		char *end;

		switch (c) {
		case 'd':
			dbc = optarg;
			break;
		case 'm':
			msg = optarg;
			break;
		case 'e':
			e2e = true;
			break;
		case 'c':
			errno = 0;
			counter = strtol(optarg, &end, 0);
			if (errno || *end || end == optarg || counter < 0 || counter > 255) {
				fprintf(stderr, "hdlamp dbc: --counter: expected 0..255\n");
				return HL_EXIT_USAGE;
			}
			break;
		case 't':
			if (parse_time(optarg, &t_us) < 0) {
				fprintf(stderr, "hdlamp dbc: --time: expected SECONDS[.MICROS]\n");
				return HL_EXIT_USAGE;
			}
			break;
		case 'i':
			if (!optarg[0] || strlen(optarg) >= IFNAMSIZ || strpbrk(optarg, " \t\n")) {
				fprintf(stderr,
					"hdlamp dbc: --iface: expected a name of 1..%d chars\n",
					IFNAMSIZ - 1);
				return HL_EXIT_USAGE;
			}
			iface = optarg;
			break;
		case 's':
			flags |= HL_DBC_STRICT;
			break;
		case 'h':
			usage(stdout);
			return HL_EXIT_OK;
		default:
			usage(stderr);
			return HL_EXIT_USAGE;
		}
	}
	if (strcmp(sub, "info") == 0) {
		if (optind != argc - 1 || dbc || msg) {
			usage(stderr);
			return HL_EXIT_USAGE;
		}
		return info(argv[optind], flags);
	}
	if (strcmp(sub, "decode") == 0) {
		if (!dbc || msg || optind < argc - 1) {
			usage(stderr);
			return HL_EXIT_USAGE;
		}
		return decode(dbc, flags, optind < argc ? argv[optind] : "-");
	}
	if (strcmp(sub, "encode") == 0) {
		if (!dbc || !msg) {
			usage(stderr);
			return HL_EXIT_USAGE;
		}
		if (t_us < 0) {
			struct timeval tv;

			gettimeofday(&tv, NULL);
			t_us = (int64_t)tv.tv_sec * 1000000 + tv.tv_usec;
		}
		return encode(dbc, flags, msg, e2e, counter, t_us, iface, argc - optind,
			      argv + optind);
	}
	fprintf(stderr, "hdlamp dbc: unknown subcommand '%s'\n", sub);
	usage(stderr);
	return HL_EXIT_USAGE;
}
