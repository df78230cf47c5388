/* SPDX-License-Identifier: MIT */
/* hdlamp glare: the light at the road users' eyes in a scenario and its limit (verdict/glare.h). */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lamp/combine.h"
#include "lamp/preset.h"
#include "verdict/glare.h"
#include "render/glare_plot.h"
#include "tools/commands.h"
#include "tools/world_arg.h"
#include "tools/json_out.h"
#include "tools/preset_arg.h"

#define DEFAULT_SET "unece-r149-01-adb-glare"
#define MAX_FRAMES 1000000

static void usage(FILE *f)
{
	fprintf(f,
		"usage: hdlamp glare (--scenario FILE|NAME | --world osi:file:TRACE.osi)\n"
		"                    --lid LEFT.lid.exr --lid RIGHT.lid.exr\n"
		"                    [--preset NAME|FILE] [--at T | --frames A:B:STEP] [--json]\n"
		"                    [--regulation ID|SET.json] [--regulations DIR] [--plot OUT.png]\n"
		"\n"
		"The light of the ego's lamps at each road user's eye (docs/scenarios.md, \"Glare at\n"
		"road users' eyes\"): per frame and road user the time, id, kind, role, distance\n"
		"(horizontal, from the lamps' midpoint to the eye), the intensity toward the eye from\n"
		"each lamp and half the pair's sum (cd), the illuminance at the eye E = sum I/r^2 (lux)\n"
		"and the limit of its class at the largest tabulated distance not beyond it.\n"
		"Exit 0 when no road user is over its limit, 1 when one is, 2 on a usage error.\n"
		"\n"
		"  --scenario FILE    a scenario file, or the name of a shipped one\n"
		"  --world osi:file:TRACE.osi  the scene of an ASAM OSI trace (docs/osi.md); a\n"
		"                     --scenario beside it lends the ego's lamps and a road\n"
		"  --osi-message M    the trace's messages: auto (its file name), ground-truth,\n"
		"                     sensor-view\n"
		"  --lid FILE         the left lamp, then the right lamp (sources or combined)\n"
		"  --preset NAME      low (default), high, glarefree, bend_left, bend_right (the\n"
		"                     built-in HD84 presets), or a preset .json file; not used for\n"
		"                     combined distributions\n"
		"  --at T             scenario time in seconds (default 0)\n"
		"  --frames A:B:STEP  times A, A + STEP, ... up to B\n"
		"  --json             one JSON object per road user and frame instead of the table\n"
		"  --regulation ID    the limits: a set on half the pair's sum with \"Oncoming D m\"\n"
		"                     and \"Preceding D m\" rows (default " DEFAULT_SET ")\n"
		"  --regulations DIR  where the sets are (default: the installed ones)\n"
		"  --plot OUT.png     also draw the timeline: half the pair's intensity toward each\n"
		"                     road user's eye with its limit, the lux at the eye, and where\n"
		"                     each is over its limit\n");
}

static bool ends_with(const char *s, const char *suffix)
{
	const size_t n = strlen(s), m = strlen(suffix);

	return n >= m && !strcmp(s + n - m, suffix);
}

static int load_scenario(const char *arg, struct hl_scenario **ret)
{
	struct hl_json_error err;
	char path[4096], msg[1024];
	int rc;

	if (ends_with(arg, ".json") || strchr(arg, '/')) {
		snprintf(path, sizeof(path), "%s", arg);
	} else {
		rc = hl_scenario_default_dir(path, sizeof(path));
		if (rc < 0) {
			fprintf(stderr, "hdlamp glare: cannot find the shipped scenarios: %s\n",
				strerror(-rc));
			return rc;
		}
		snprintf(path + strlen(path), sizeof(path) - strlen(path), "/%s.json", arg);
	}
	rc = hl_scenario_read(path, ret, &err);
	if (rc < 0) {
		hl_json_error_format(&err, msg, sizeof(msg));
		fprintf(stderr, "hdlamp glare: %s\n", msg);
	}
	return rc;
}

static int load_set(const char *arg, const char *dir, struct hl_regulation **ret)
{
	struct hl_regulation_error err;
	int rc;

	if (ends_with(arg, ".json"))
		rc = hl_regulation_read(arg, ret, &err);
	else
		rc = hl_regulation_load(dir, arg, ret, &err);
	if (rc < 0)
		fprintf(stderr, "hdlamp glare: %s\n", err.msg);
	return rc;
}

/* Each lamp's distribution under the preset (combined files as they are). 0 or -errno. */
static int distributions(const char *const paths[2], const char *preset_name,
			 struct hl_lid *lids[2], float *dense[2])
{
	struct hl_preset *p = NULL;
	float *cur = NULL;
	int rc = 0;

	for (int k = 0; k < 2; k++) {
		struct hl_lid_error err;

		rc = hl_lid_read(paths[k], &lids[k], &err);
		if (rc < 0) {
			fprintf(stderr, "hdlamp glare: %s\n", err.msg);
			return rc;
		}
	}
	if (!hl_lid_is_combined(lids[0]) || !hl_lid_is_combined(lids[1])) {
		rc = hl_tool_preset_load("glare", preset_name, lids, 2, &p);
		if (rc < 0)
			return rc;
		cur = malloc(sizeof(float) * p->n_sources);
		if (!cur) {
			rc = -ENOMEM;
			goto out;
		}
	}
	for (int k = 0; k < 2; k++) {
		const struct hl_lid_grid *g = hl_lid_grid(lids[k]);

		dense[k] = malloc(sizeof(float) * (size_t)g->width * g->height);
		if (!dense[k]) {
			rc = -ENOMEM;
			goto out;
		}
		if (hl_lid_is_combined(lids[k])) {
			hl_lid_source_dense(lids[k], 0, dense[k]);
		} else {
			hl_preset_intensities(p, k, cur);
			hl_combine_sparse(lids[k], cur, dense[k]);
		}
	}
out:
	if (rc == -ENOMEM)
		fprintf(stderr, "hdlamp glare: out of memory\n");
	free(cur);
	hl_preset_free(p);
	return rc;
}

static void print_json(const struct hl_scenario *sc, const struct hl_regulation *reg,
		       const struct hl_glare_result *r)
{
	const struct hl_actor *a = &sc->actor[r->actor];

	printf("{\"t_s\": ");
	hl_tool_json_num(stdout, r->t_s);
	printf(", \"id\": ");
	hl_tool_json_str(stdout, a->id);
	printf(", \"kind\": \"%s\", \"role\": \"%s\", \"distance_m\": ",
	       hl_actor_kind_name(a->kind), hl_actor_role_name(a->role));
	hl_tool_json_num(stdout, r->distance_m);
	printf(", \"axis_h_deg\": ");
	hl_tool_json_num(stdout, r->axis_h_deg);
	printf(", \"eye_m\": [");
	for (int k = 0; k < 3; k++) {
		printf("%s", k ? ", " : "");
		hl_tool_json_num(stdout, r->eye_m[k]);
	}
	printf("], \"lamps\": [");
	for (int l = 0; l < 2; l++) {
		printf("%s{\"side\": \"%s\", \"h_deg\": ", l ? ", " : "", hl_side_name(l));
		hl_tool_json_num(stdout, r->h_deg[l]);
		printf(", \"v_deg\": ");
		hl_tool_json_num(stdout, r->v_deg[l]);
		printf(", \"r_m\": ");
		hl_tool_json_num(stdout, r->r_m[l]);
		printf(", \"intensity_cd\": ");
		hl_tool_json_num(stdout, r->intensity_cd[l]);
		printf("}");
	}
	printf("], \"pair_half_cd\": ");
	hl_tool_json_num(stdout, r->pair_half_cd);
	printf(", \"illuminance_lx\": ");
	hl_tool_json_num(stdout, r->illuminance_lx);
	printf(", \"regulation\": ");
	hl_tool_json_str(stdout, reg->id);
	printf(", \"limit_id\": ");
	if (r->limit.req >= 0)
		hl_tool_json_str(stdout, reg->req[r->limit.req].id);
	else
		printf("null");
	printf(", \"limit_distance_m\": ");
	hl_tool_json_num(stdout, r->limit.table_distance_m);
	printf(", \"limit_cd\": ");
	hl_tool_json_num(stdout, r->limit.max_cd);
	printf(", \"pass\": %s}\n", r->pass ? "true" : "false");
}

static void print_row(const struct hl_scenario *sc, const struct hl_glare_result *r)
{
	const struct hl_actor *a = &sc->actor[r->actor];
	char lim[32];

	if (isnan(r->limit.max_cd))
		snprintf(lim, sizeof(lim), "none");
	else
		snprintf(lim, sizeof(lim), "%.0f@%.0fm", r->limit.max_cd,
			 r->limit.table_distance_m);
	printf("%8.3f %-20s %-10s %-9s %9.2f %11.1f %11.1f %11.1f %10.4f %12s  %s\n", r->t_s, a->id,
	       hl_actor_kind_name(a->kind), hl_actor_role_name(a->role), r->distance_m,
	       r->intensity_cd[0], r->intensity_cd[1], r->pair_half_cd, r->illuminance_lx, lim,
	       isnan(r->limit.max_cd) ? "-" :
	       r->pass		      ? "pass" :
					"FAIL");
}

/* "A:B:STEP": 0 or -EINVAL. */
static int parse_frames(const char *s, double *a, double *b, double *step)
{
	char tail;

	if (sscanf(s, "%lf:%lf:%lf%c", a, b, step, &tail) != 3 || !isfinite(*a) || !isfinite(*b) ||
	    !isfinite(*step) || *step <= 0.0 || *b < *a || (*b - *a) / *step > MAX_FRAMES)
		return -EINVAL;
	return 0;
}

int hl_cmd_glare(int argc, char **argv)
{
	enum {
		OPT_SCN = 256,
		OPT_LID,
		OPT_PRESET,
		OPT_AT,
		OPT_FRAMES,
		OPT_JSON,
		OPT_REG,
		OPT_REGS,
		OPT_PLOT,
		OPT_WORLD,
		OPT_OSI_MESSAGE
	};
	static const struct option opts[] = {
		{ "scenario", required_argument, NULL, OPT_SCN },
		{ "lid", required_argument, NULL, OPT_LID },
		{ "preset", required_argument, NULL, OPT_PRESET },
		{ "at", required_argument, NULL, OPT_AT },
		{ "frames", required_argument, NULL, OPT_FRAMES },
		{ "json", no_argument, NULL, OPT_JSON },
		{ "regulation", required_argument, NULL, OPT_REG },
		{ "regulations", required_argument, NULL, OPT_REGS },
		{ "plot", required_argument, NULL, OPT_PLOT },
		{ "world", required_argument, NULL, OPT_WORLD },
		{ "osi-message", required_argument, NULL, OPT_OSI_MESSAGE },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	const char *scn = NULL, *lid_path[2] = { NULL, NULL }, *preset = "low", *set = DEFAULT_SET;
	const char *plot = NULL, *world = NULL, *osi_message = NULL;
	char dir[4096] = "", *end;
	bool as_json = false, have_at = false, have_frames = false;
	double a = 0.0, b = 0.0, step = 1.0;
	int n_lid = 0, c, rc = HL_EXIT_FAIL, n_fail = 0, n_frames;
	struct hl_scenario *sc = NULL;
	struct hl_regulation *reg = NULL;
	struct hl_lid *lids[2] = { NULL, NULL };
	float *dense[2] = { NULL, NULL };
	struct hl_glare *g = NULL;
	struct hl_glare_result res[HL_SCN_MAX_ACTORS], *all = NULL;

	optind = 1;
	while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
		switch (c) {
		case OPT_SCN:
			scn = optarg;
			break;
		case OPT_LID:
			if (n_lid == 2) {
				fprintf(stderr,
					"hdlamp glare: --lid: two lamps, left then right\n");
				return HL_EXIT_USAGE;
			}
			lid_path[n_lid++] = optarg;
			break;
		case OPT_PRESET:
			preset = optarg;
			break;
		case OPT_AT:
			a = b = strtod(optarg, &end);
			if (end == optarg || *end || !isfinite(a)) {
				fprintf(stderr, "hdlamp glare: --at '%s': expected seconds\n",
					optarg);
				return HL_EXIT_USAGE;
			}
			have_at = true;
			break;
		case OPT_FRAMES:
			if (parse_frames(optarg, &a, &b, &step) < 0) {
				fprintf(stderr,
					"hdlamp glare: --frames '%s': expected A:B:STEP (seconds, "
					"A <= B, STEP > 0, at most %d frames)\n",
					optarg, MAX_FRAMES);
				return HL_EXIT_USAGE;
			}
			have_frames = true;
			break;
		case OPT_JSON:
			as_json = true;
			break;
		case OPT_REG:
			set = optarg;
			break;
		case OPT_REGS:
			snprintf(dir, sizeof(dir), "%s", optarg);
			break;
		case OPT_PLOT:
			plot = optarg;
			break;
		case OPT_WORLD:
			world = optarg;
			break;
		case OPT_OSI_MESSAGE:
			osi_message = optarg;
			break;
		case 'h':
			usage(stdout);
			return HL_EXIT_OK;
		default:
			usage(stderr);
			return HL_EXIT_USAGE;
		}
	}
	if (optind != argc || (!scn && !world) || n_lid != 2 || (have_at && have_frames)) {
		fprintf(stderr, "hdlamp glare: %s\n",
			optind != argc ? "unexpected arguments" :
			!scn && !world ? "--scenario or --world is required" :
			n_lid != 2     ? "give two lamps: --lid LEFT --lid RIGHT" :
					 "--at or --frames, not both");
		usage(stderr);
		return HL_EXIT_USAGE;
	}
	if (!dir[0] && hl_regulation_default_dir(dir, sizeof(dir)) < 0) {
		fprintf(stderr, "hdlamp glare: cannot find the regulations directory; "
				"give --regulations DIR\n");
		return HL_EXIT_FAIL;
	}
	if ((scn && load_scenario(scn, &sc) < 0) ||
	    (world && hl_tool_world_load("hdlamp glare", world, osi_message, sc, &sc) < 0) ||
	    load_set(set, dir, &reg) < 0 || distributions(lid_path, preset, lids, dense) < 0)
		goto out;
	{
		const struct hl_lid_grid *const grids[2] = { hl_lid_grid(lids[0]),
							     hl_lid_grid(lids[1]) };

		c = hl_glare_new(sc, reg, grids, &g);
	}
	if (c < 0) {
		fprintf(stderr, "hdlamp glare: '%s' gives no glare limits: %s\n", reg->id,
			c == -EINVAL ? "it must apply to half the pair's sum and have \"Oncoming D "
				       "m\" or \"Preceding D m\" segment rows" :
				       strerror(-c));
		goto out;
	}
	if (!as_json)
		printf("%8s %-20s %-10s %-9s %9s %11s %11s %11s %10s %12s  %s\n", "t_s", "id",
		       "kind", "role", "dist_m", "I_left_cd", "I_right_cd", "I_half_cd", "E_lx",
		       "limit_cd", "pass");
	n_frames = (int)floor((b - a) / step + 1e-9) + 1;
	if (plot) {
		all = calloc((size_t)n_frames * sc->n_actors, sizeof(*all));
		if (!all && sc->n_actors) {
			fprintf(stderr, "hdlamp glare: out of memory for %d frames of the plot\n",
				n_frames);
			goto out;
		}
	}
	for (int f = 0; f < n_frames; f++) {
		const double t = a + f * step;

		n_fail += hl_glare_eval(g, t, (const float *const *)dense, res);
		for (int i = 0; i < sc->n_actors; i++) {
			if (as_json)
				print_json(sc, reg, &res[i]);
			else
				print_row(sc, &res[i]);
		}
		if (all)
			memcpy(all + (size_t)f * sc->n_actors, res, sizeof(*res) * sc->n_actors);
	}
	if (plot) {
		char title[HL_SCN_TEXT_MAX + 128];

		snprintf(title, sizeof(title), "%s  %s", sc->title, reg->id);
		c = sc->n_actors ? hl_glare_plot_png(sc, all, n_frames, title, plot) : -EINVAL;
		if (c < 0) {
			fprintf(stderr, "hdlamp glare: --plot '%s': %s\n", plot,
				c == -EINVAL ? "the scenario has no road users to plot" :
					       strerror(-c));
			goto out;
		}
	}
	if (!as_json)
		printf("\n%s: %d road users, %d frames, %d over the limit: %s\n", reg->id,
		       sc->n_actors, n_frames, n_fail, n_fail ? "FAIL" : "PASS");
	rc = n_fail ? HL_EXIT_FAIL : HL_EXIT_OK;
out:
	free(all);
	hl_glare_free(g);
	for (int k = 0; k < 2; k++) {
		free(dense[k]);
		hl_lid_free(lids[k]);
	}
	hl_regulation_free(reg);
	hl_scenario_free(sc);
	return rc;
}
