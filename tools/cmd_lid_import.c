/* SPDX-License-Identifier: MIT */
/* hdlamp lid import / export: measured distributions (IES, EULUMDAT, CSV) in and out. */
#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "lamp/lid.h"
#include "tools/commands.h"
#include "import/export.h"
#include "import/import.h"
#include "import/manifest.h"

static void usage_import(FILE *f)
{
	fprintf(f,
		"usage: hdlamp lid import --manifest M.ini --out LAMP.lid.exr\n"
		"\n"
		"Builds a LID file from measured distributions: each [source N] of the manifest\n"
		"names a file (IES LM-63 types A/B/C, EULUMDAT .ldt, CSV) and a name; [grid] sets\n"
		"the output grid (default type A, 0.2 deg, H -89.9..89.9, V -29.9..19.9). Every\n"
		"source is resampled in its own angles, zero outside what it covers. Prints one\n"
		"line per source: index, name, peak cd, file. See docs/import.md and hdlamp(1).\n");
}

static void usage_export(FILE *f)
{
	fprintf(f,
		"usage: hdlamp lid export LAMP.lid.exr --source N|NAME --out FILE\n"
		"                         [--format ies|csv] [--angles A|B|C] [--step DEG]\n"
		"\n"
		"Writes one source (1-based index or its name; a combined LID has source 1) as a\n"
		"goniometer table: IES LM-63-2019 (photometric type 3 = A, 2 = B, 1 = C) or CSV\n"
		"(first row H or C angles, first column V or gamma angles, cd).\n"
		"  --format  default: from the extension of --out (.ies, .csv)\n"
		"  --angles  angle system of the table; default: the LID's own (A or B)\n"
		"  --step    angle step over the source's lit region, degrees; default: the grid\n"
		"            step in the LID's own system (the values are then the grid's own),\n"
		"            a quarter of it in another system, refined where the light curves\n"
		"            (to 0.1 %%). Outside the lit region the table has a 5 degree frame of\n"
		"            zeros over the format's full range.\n");
}

int hl_cmd_lid_import(int argc, char **argv)
{
	static const struct option opts[] = {
		{ "manifest", required_argument, NULL, 'm' },
		{ "out", required_argument, NULL, 'o' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	const char *manifest = NULL, *out = NULL;
	struct hl_import_error err;
	struct hl_manifest *m = NULL;
	struct hl_lid *lid = NULL;
	struct hl_lid_error lerr;
	int c, rc = HL_EXIT_FAIL;

	optind = 1;
	while ((c = getopt_long(argc, argv, "m:o:h", opts, NULL)) != -1) {
		switch (c) {
		case 'm':
			manifest = optarg;
			break;
		case 'o':
			out = optarg;
			break;
		case 'h':
			usage_import(stdout);
			return HL_EXIT_OK;
		default:
			usage_import(stderr);
			return HL_EXIT_USAGE;
		}
	}
	if (!manifest || !out || optind != argc) {
		usage_import(stderr);
		return HL_EXIT_USAGE;
	}
	if (hl_manifest_read(manifest, &m, &err) < 0) {
		fprintf(stderr, "hdlamp lid import: %s\n", err.msg);
		return HL_EXIT_FAIL;
	}
	if (hl_import_lid(m, &lid, &err) < 0) {
		fprintf(stderr, "hdlamp lid import: %s\n", err.msg);
		goto out;
	}
	if (hl_lid_write(lid, out, &lerr) < 0) {
		fprintf(stderr, "hdlamp lid import: %s\n", lerr.msg);
		goto out;
	}
	for (int k = 0; k < hl_lid_n_sources(lid); k++)
		printf("%d\t%s\t%.3f\t%s\n", k + 1, hl_lid_name(lid, k), hl_lid_peak_cd(lid, k),
		       hl_manifest_file(m, k));
	rc = HL_EXIT_OK;
out:
	hl_lid_free(lid);
	hl_manifest_free(m);
	return rc;
}

/* A 1-based index or a source name to a 0-based index; -1 if neither. */
static int find_source(const struct hl_lid *lid, const char *s)
{
	char *end;
	long k = strtol(s, &end, 10);

	if (*s && !*end)
		return (k >= 1 && k <= hl_lid_n_sources(lid)) ? (int)k - 1 : -1;
	for (int i = 0; i < hl_lid_n_sources(lid); i++)
		if (hl_lid_name(lid, i) && strcmp(hl_lid_name(lid, i), s) == 0)
			return i;
	return -1;
}

int hl_cmd_lid_export(int argc, char **argv)
{
	static const struct option opts[] = {
		{ "source", required_argument, NULL, 's' },
		{ "out", required_argument, NULL, 'o' },
		{ "format", required_argument, NULL, 'f' },
		{ "angles", required_argument, NULL, 'a' },
		{ "step", required_argument, NULL, 't' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	const char *source = NULL, *out = NULL, *in;
	int format = -1, system = -1, c, k, rc = HL_EXIT_FAIL;
	double step = 0.0;
	struct hl_lid *lid = NULL;
	struct hl_gonio *g = NULL;
	struct hl_lid_error lerr;
	char origin[512], date[32];
	struct hl_export_meta meta;
	time_t now = time(NULL);
	struct tm tm;
	FILE *f;

	optind = 1;
	while ((c = getopt_long(argc, argv, "s:o:f:a:t:h", opts, NULL)) != -1) {
		switch (c) {
		case 's':
			source = optarg;
			break;
		case 'o':
			out = optarg;
			break;
		case 'f':
			format = hl_import_format_from_name(optarg);
			if (format != HL_IMPORT_IES && format != HL_IMPORT_CSV) {
				fprintf(stderr,
					"hdlamp lid export: --format '%s': expected ies or "
					"csv\n",
					optarg);
				return HL_EXIT_USAGE;
			}
			break;
		case 'a':
			if (strcmp(optarg, "A") == 0)
				system = HL_GONIO_A;
			else if (strcmp(optarg, "B") == 0)
				system = HL_GONIO_B;
			else if (strcmp(optarg, "C") == 0)
				system = HL_GONIO_C;
			else {
				fprintf(stderr,
					"hdlamp lid export: --angles '%s': expected A, B or "
					"C\n",
					optarg);
				return HL_EXIT_USAGE;
			}
			break;
		case 't': {
			char *end;

			step = strtod(optarg, &end);
			if (*end || !(step >= 0.001 && step <= 10.0)) {
				fprintf(stderr,
					"hdlamp lid export: --step '%s': expected degrees, "
					"0.001 to 10\n",
					optarg);
				return HL_EXIT_USAGE;
			}
			break;
		}
		case 'h':
			usage_export(stdout);
			return HL_EXIT_OK;
		default:
			usage_export(stderr);
			return HL_EXIT_USAGE;
		}
	}
	if (!out || optind + 1 != argc) {
		usage_export(stderr);
		return HL_EXIT_USAGE;
	}
	in = argv[optind];
	if (format < 0) {
		format = hl_import_format_from_path(out);
		if (format != HL_IMPORT_IES && format != HL_IMPORT_CSV) {
			fprintf(stderr,
				"hdlamp lid export: cannot tell the format from '%s': "
				"give --format ies|csv\n",
				out);
			return HL_EXIT_USAGE;
		}
	}
	if (hl_lid_read(in, &lid, &lerr) < 0) {
		fprintf(stderr, "hdlamp lid export: %s\n", lerr.msg);
		return HL_EXIT_FAIL;
	}
	if (!source && hl_lid_n_sources(lid) != 1) {
		fprintf(stderr, "hdlamp lid export: '%s' has %d sources: give --source\n", in,
			hl_lid_n_sources(lid));
		rc = HL_EXIT_USAGE;
		goto out;
	}
	k = source ? find_source(lid, source) : 0;
	if (k < 0) {
		fprintf(stderr, "hdlamp lid export: '%s' has no source '%s' (1..%d or a name)\n",
			in, source, hl_lid_n_sources(lid));
		goto out;
	}
	if (system < 0)
		system = hl_lid_grid(lid)->angles == HL_ANGLES_A ? HL_GONIO_A : HL_GONIO_B;
	c = hl_export_sample(lid, k, system, step, &g);
	if (c == -EFBIG) {
		fprintf(stderr,
			"hdlamp lid export: source %d at a step of %g deg needs more than %d angles "
			"or %ld values: give a coarser --step\n",
			k + 1, step, HL_EXPORT_MAX_ANGLES, HL_EXPORT_MAX_VALUES);
		goto out;
	}
	if (c < 0) {
		fprintf(stderr, "hdlamp lid export: cannot sample source %d: %s\n", k + 1,
			strerror(-c));
		goto out;
	}
	snprintf(origin, sizeof(origin), "source %d of %s", k + 1, in);
	gmtime_r(&now, &tm);
	strftime(date, sizeof(date), "%Y-%m-%d", &tm);
	meta = (struct hl_export_meta){
		.name = hl_lid_name(lid, k) ? hl_lid_name(lid, k) : "I",
		.origin = origin,
		.issue_date = date,
	};
	f = fopen(out, "we");
	if (!f) {
		fprintf(stderr, "hdlamp lid export: '%s': %s\n", out, strerror(errno));
		goto out;
	}
	c = format == HL_IMPORT_IES ? hl_export_ies(g, &meta, f) : hl_export_csv(g, &meta, f);
	if (fclose(f) != 0 && c == 0)
		c = -errno;
	if (c < 0) {
		fprintf(stderr, "hdlamp lid export: '%s': %s\n", out, strerror(-c));
		goto out;
	}
	printf("%s\ttype %c\t%d x %d angles\tpeak %.3f cd\n", out, hl_gonio_system_letter(system),
	       hl_gonio_n_planes(g), hl_gonio_n_in(g), hl_gonio_peak_cd(g));
	rc = HL_EXIT_OK;
out:
	hl_gonio_free(g);
	hl_lid_free(lid);
	return rc;
}
