/* SPDX-License-Identifier: MIT */
/* hdlamp model: writes the HD84 lamp pair and its presets, or a pixel lamp for scaling work. */
#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "tools/commands.h"
#include "lamp/model.h"

static void usage(FILE *f)
{
	fprintf(f,
		"usage: hdlamp model --out DIR [--sources N]\n"
		"\n"
		"Without --sources: writes DIR/hd84_left.lid.exr, DIR/hd84_right.lid.exr (95 sources,\n"
		"900 x 250 samples at 0.2°, type A) and the presets low, high, glarefree, bend_left,\n"
		"bend_right as DIR/NAME.json (raw 6-bit dimming values per lamp).\n"
		"With --sources N (1..4096): a pixel lamp, DIR/pixelN_left.lid.exr and _right, and\n"
		"DIR/pixelN_all.json with every source at 63.\n");
}

static int write_lamp(struct hl_lid *lid, const char *dir, const char *stem, const char *side)
{
	struct hl_lid_error err;
	char path[4096];
	int rc;

	snprintf(path, sizeof(path), "%s/%s_%s.lid.exr", dir, stem, side);
	rc = hl_lid_write(lid, path, &err);
	if (rc < 0) {
		fprintf(stderr, "hdlamp model: %s\n", err.msg);
		return rc;
	}
	printf("%s\n", path);
	return 0;
}

static int write_preset(const struct hl_preset *p, const char *dir, const char *name)
{
	char path[4096];
	int rc;

	snprintf(path, sizeof(path), "%s/%s.json", dir, name);
	rc = hl_preset_write(p, path);
	if (rc < 0) {
		fprintf(stderr, "hdlamp model: '%s': %s\n", path, strerror(-rc));
		return rc;
	}
	printf("%s\n", path);
	return 0;
}

static int model_hd84(const char *dir)
{
	struct hl_lid *lamps[2] = { NULL, NULL };
	struct hl_preset *p = NULL;
	int rc;

	for (int s = 0; s < 2; s++) {
		rc = hl_model_hd84(s, &lamps[s]);
		if (rc < 0) {
			fprintf(stderr, "hdlamp model: cannot build the HD84 lamp: %s\n",
				strerror(-rc));
			goto out;
		}
		rc = write_lamp(lamps[s], dir, "hd84", hl_side_name(s));
		if (rc < 0)
			goto out;
	}
	rc = hl_preset_new(HL_HD84_SOURCES, &p);
	for (int i = 0; rc == 0 && hl_model_preset_names[i]; i++) {
		rc = hl_model_hd84_preset(hl_model_preset_names[i], lamps, p);
		if (rc == 0)
			rc = write_preset(p, dir, hl_model_preset_names[i]);
	}
out:
	hl_preset_free(p);
	hl_lid_free(lamps[0]);
	hl_lid_free(lamps[1]);
	return rc;
}

static int model_pixel(const char *dir, int n)
{
	struct hl_lid *lid = NULL;
	struct hl_preset *p = NULL;
	char stem[32], name[40];
	int rc;

	rc = hl_model_pixel(n, &lid);
	if (rc < 0) {
		fprintf(stderr, "hdlamp model: cannot build a pixel lamp of %d sources: %s\n", n,
			strerror(-rc));
		return rc;
	}
	snprintf(stem, sizeof(stem), "pixel%d", n);
	/* A pixel lamp's field is symmetric: both sides are the same lamp. */
	rc = write_lamp(lid, dir, stem, "left");
	if (rc == 0)
		rc = write_lamp(lid, dir, stem, "right");
	if (rc == 0)
		rc = hl_preset_new(n, &p);
	if (rc == 0) {
		memset(p->dim[0], HL_DIM_MAX, n);
		memset(p->dim[1], HL_DIM_MAX, n);
		snprintf(name, sizeof(name), "%s_all", stem);
		rc = write_preset(p, dir, name);
	}
	hl_preset_free(p);
	hl_lid_free(lid);
	return rc;
}

int hl_cmd_model(int argc, char **argv)
{
	static const struct option opts[] = {
		{ "out", required_argument, NULL, 'o' },
		{ "sources", required_argument, NULL, 'n' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	const char *dir = NULL;
	long n = 0;
	char *end;
	int c;

	optind = 1;
	while ((c = getopt_long(argc, argv, "o:n:h", opts, NULL)) != -1) {
		switch (c) {
		case 'o':
			dir = optarg;
			break;
		case 'n':
			errno = 0;
			n = strtol(optarg, &end, 10);
			if (errno || *end || n < 1 || n > HL_LID_MAX_SOURCES) {
				fprintf(stderr, "hdlamp model: --sources '%s': expected 1..%d\n",
					optarg, HL_LID_MAX_SOURCES);
				return HL_EXIT_USAGE;
			}
			break;
		case 'h':
			usage(stdout);
			return HL_EXIT_OK;
		default:
			usage(stderr);
			return HL_EXIT_USAGE;
		}
	}
	if (!dir || optind != argc) {
		usage(stderr);
		return HL_EXIT_USAGE;
	}
	if (mkdir(dir, 0777) < 0 && errno != EEXIST) {
		fprintf(stderr, "hdlamp model: cannot create '%s': %s\n", dir, strerror(errno));
		return HL_EXIT_FAIL;
	}
	if ((n ? model_pixel(dir, (int)n) : model_hd84(dir)) < 0)
		return HL_EXIT_FAIL;
	return HL_EXIT_OK;
}
