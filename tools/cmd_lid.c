/* SPDX-License-Identifier: MIT */
/* hdlamp lid: info, combine and plot LID files. */
#include <errno.h>
#include <getopt.h>
#include <libgen.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lamp/combine.h"
#include "tools/commands.h"
#include "render/plot.h"
#include "lamp/preset.h"

static void usage(FILE *f)
{
	fprintf(f,
		"usage: hdlamp lid info FILE\n"
		"       hdlamp lid combine FILE PRESET.json --lamp left|right --out L.exr\n"
		"       hdlamp lid plot FILE [PRESET.json --lamp left|right] --out D.png\n"
		"       hdlamp lid import --manifest M.ini --out LAMP.lid.exr\n"
		"       hdlamp lid export FILE --source N|NAME --out F.ies|F.csv [--angles A|B|C]\n"
		"       hdlamp lid check FILE [PRESET.json --lamp left|right] --regulation ID\n"
		"\n"
		"info     grid, angle system, sources with their non-zero boxes and peaks\n"
		"combine  L = sum_k (v_k / 63) L_k for one lamp of the preset, written as a\n"
		"         combined LID file (one channel I, cd)\n"
		"plot     H-V diagram in cd on a log colour scale; a source file needs a preset\n"
		"         (without one every source is drawn at full current)\n"
		"import   a LID file from measured IES, EULUMDAT and CSV files (manifest)\n"
		"export   one source as an IES or CSV goniometer table\n"
		"check    the verdict of a regulation set (test points, segments, zones) on the\n"
		"         lamp's distribution; exit 0 pass, 1 fail\n"
		"('hdlamp lid import|export|check --help' for their options)\n");
}

static int load(const char *path, struct hl_lid **ret)
{
	struct hl_lid_error err;
	int rc = hl_lid_read(path, ret, &err);

	if (rc < 0)
		fprintf(stderr, "hdlamp lid: %s\n", err.msg);
	return rc;
}

static int info(const char *path)
{
	struct hl_lid *lid;
	const struct hl_lid_grid *g;
	float peak = 0.0f;
	int n;

	if (load(path, &lid) < 0)
		return HL_EXIT_FAIL;
	g = hl_lid_grid(lid);
	n = hl_lid_n_sources(lid);
	printf("file:    %s\n", path);
	printf("kind:    %s\n", hl_lid_is_combined(lid) ? "combined distribution (channel I)" :
							  "light sources (src0001..)");
	printf("angles:  type %c\n", g->angles == HL_ANGLES_A ? 'A' : 'B');
	printf("grid:    %d x %d samples (H x V)\n", g->width, g->height);
	printf("H:       %.2f .. %.2f deg, step %.4f\n", g->h_first_deg, g->h_last_deg,
	       (g->h_last_deg - g->h_first_deg) / (g->width - 1));
	printf("V:       %.2f .. %.2f deg, step %.4f\n", g->v_first_deg, g->v_last_deg,
	       (g->v_last_deg - g->v_first_deg) / (g->height - 1));
	printf("sources: %d\n", n);
	for (int k = 0; k < n; k++)
		if (hl_lid_peak_cd(lid, k) > peak)
			peak = hl_lid_peak_cd(lid, k);
	printf("peak:    %.1f cd (highest single source)\n", peak);
	printf("\n%5s  %-16s %-24s %-30s %10s\n", "k", "name", "box [x0,x1)x[y0,y1)",
	       "box H..H, V..V deg", "peak cd");
	for (int k = 0; k < n; k++) {
		struct hl_lid_box b;
		char box[64], deg[64];
		const char *name = hl_lid_name(lid, k);

		hl_lid_source(lid, k, &b);
		if (b.x1 == b.x0) {
			snprintf(box, sizeof(box), "empty");
			deg[0] = '\0';
		} else {
			snprintf(box, sizeof(box), "[%d,%d)x[%d,%d)", b.x0, b.x1, b.y0, b.y1);
			snprintf(deg, sizeof(deg), "%.1f..%.1f, %.1f..%.1f",
				 hl_lid_grid_h_deg(g, b.x0), hl_lid_grid_h_deg(g, b.x1 - 1),
				 hl_lid_grid_v_deg(g, b.y1 - 1), hl_lid_grid_v_deg(g, b.y0));
		}
		printf("%5d  %-16s %-24s %-30s %10.1f\n", k + 1, name ? name : "-", box, deg,
		       hl_lid_peak_cd(lid, k));
	}
	hl_lid_free(lid);
	return HL_EXIT_OK;
}

/* The lamp's distribution for the preset (or all sources at 1 when preset_path is NULL). */
int hl_cli_lid_distribution(const struct hl_lid *lid, const char *preset_path, int side,
			    float **ret)
{
	const struct hl_lid_grid *g = hl_lid_grid(lid);
	const int n = hl_lid_n_sources(lid);
	float *i = malloc(sizeof(float) * n);
	float *out = malloc(sizeof(float) * (size_t)g->width * g->height);
	struct hl_preset *p = NULL;
	int rc = 0;

	if (!i || !out) {
		rc = -ENOMEM;
		goto out;
	}
	if (hl_lid_is_combined(lid)) {
		if (preset_path) {
			fprintf(stderr, "hdlamp lid: a combined distribution takes no preset\n");
			rc = -EINVAL;
			goto out;
		}
		hl_lid_source_dense(lid, 0, out);
		goto out;
	}
	if (preset_path) {
		struct hl_preset_error err;

		rc = hl_preset_read(preset_path, &p, &err);
		if (rc < 0) {
			if (err.line)
				fprintf(stderr, "hdlamp lid: '%s':%d:%d: %s\n", preset_path,
					err.line, err.column, err.msg);
			else
				fprintf(stderr, "hdlamp lid: '%s': %s\n", preset_path, err.msg);
			goto out;
		}
		if (p->n_sources != n) {
			fprintf(stderr,
				"hdlamp lid: '%s' has %d values per lamp; the lamp has %d sources\n",
				preset_path, p->n_sources, n);
			rc = -EINVAL;
			goto out;
		}
		hl_preset_intensities(p, side, i);
	} else {
		for (int k = 0; k < n; k++)
			i[k] = 1.0f;
	}
	hl_combine_sparse(lid, i, out);
out:
	hl_preset_free(p);
	free(i);
	if (rc < 0) {
		free(out);
		return rc;
	}
	*ret = out;
	return 0;
}

int hl_cmd_lid(int argc, char **argv)
{
	static const struct option opts[] = {
		{ "lamp", required_argument, NULL, 'l' },
		{ "out", required_argument, NULL, 'o' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	const char *out_path = NULL, *verb, *file, *preset = NULL;
	int side = -1, c, rc = HL_EXIT_FAIL;
	struct hl_lid *lid = NULL;
	float *dense = NULL;

	if (argc < 2) {
		usage(stderr);
		return HL_EXIT_USAGE;
	}
	verb = argv[1];
	if (strcmp(verb, "--help") == 0 || strcmp(verb, "-h") == 0) {
		usage(stdout);
		return HL_EXIT_OK;
	}
	if (strcmp(verb, "import") == 0)
		return hl_cmd_lid_import(argc - 1, argv + 1);
	if (strcmp(verb, "export") == 0)
		return hl_cmd_lid_export(argc - 1, argv + 1);
	if (strcmp(verb, "check") == 0)
		return hl_cmd_lid_check(argc - 1, argv + 1);
	optind = 2;
	while ((c = getopt_long(argc, argv, "l:o:h", opts, NULL)) != -1) {
		switch (c) {
		case 'l':
			side = hl_side_from_name(optarg);
			if (side < 0) {
				fprintf(stderr, "hdlamp lid: --lamp '%s': expected left or right\n",
					optarg);
				return HL_EXIT_USAGE;
			}
			break;
		case 'o':
			out_path = optarg;
			break;
		case 'h':
			usage(stdout);
			return HL_EXIT_OK;
		default:
			usage(stderr);
			return HL_EXIT_USAGE;
		}
	}
	if (optind >= argc) {
		usage(stderr);
		return HL_EXIT_USAGE;
	}
	file = argv[optind++];
	if (optind < argc)
		preset = argv[optind++];
	if (optind != argc) {
		usage(stderr);
		return HL_EXIT_USAGE;
	}

	if (strcmp(verb, "info") == 0) {
		if (preset || out_path || side >= 0) {
			usage(stderr);
			return HL_EXIT_USAGE;
		}
		return info(file);
	}
	if (strcmp(verb, "combine") != 0 && strcmp(verb, "plot") != 0) {
		fprintf(stderr, "hdlamp lid: unknown verb '%s'\n", verb);
		usage(stderr);
		return HL_EXIT_USAGE;
	}
	if (!out_path || (preset && side < 0) || (!preset && side >= 0) ||
	    (strcmp(verb, "combine") == 0 && !preset)) {
		usage(stderr);
		return HL_EXIT_USAGE;
	}
	if (load(file, &lid) < 0)
		return HL_EXIT_FAIL;
	if (hl_cli_lid_distribution(lid, preset, side, &dense) < 0)
		goto out;
	if (strcmp(verb, "combine") == 0) {
		struct hl_lid_error err;

		if (hl_lid_write_combined(hl_lid_grid(lid), dense, out_path, &err) < 0) {
			fprintf(stderr, "hdlamp lid: %s\n", err.msg);
			goto out;
		}
	} else {
		char title[512], *tmp = strdup(file), *tmp2 = preset ? strdup(preset) : NULL;

		snprintf(title, sizeof(title), "%s%s%s%s%s", tmp ? basename(tmp) : file,
			 preset ? "  " : "", tmp2 ? basename(tmp2) : "", preset ? "  " : "",
			 preset ? hl_side_name(side) : "");
		free(tmp);
		free(tmp2);
		c = hl_plot_lid_png(hl_lid_grid(lid), dense, title, out_path);
		if (c < 0) {
			fprintf(stderr, "hdlamp lid: '%s': %s\n", out_path, strerror(-c));
			goto out;
		}
	}
	rc = HL_EXIT_OK;
out:
	free(dense);
	hl_lid_free(lid);
	return rc;
}
