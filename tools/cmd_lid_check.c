/* SPDX-License-Identifier: MIT */
/* hdlamp lid check: a regulation set's verdict on a lamp's distribution (docs/verdicts.md). */
#include <errno.h>
#include <getopt.h>
#include <libgen.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lamp/preset.h"
#include "verdict/verdict.h"
#include "render/verdict_plot.h"
#include "tools/commands.h"
#include "tools/json_out.h"

static void usage(FILE *f)
{
	fprintf(f,
		"usage: hdlamp lid check FILE [PRESET.json --lamp left|right] --regulation ID|SET.json\n"
		"                        [--other FILE] [--traffic right|left]\n"
		"                        [--aim mounted|regulation] [--json] [--plot OUT.png]\n"
		"                        [--regulations DIR]\n"
		"       hdlamp lid check --regulation list [--regulations DIR]\n"
		"\n"
		"Checks a lamp's distribution against a regulation set (regulations/, docs/verdicts.md):\n"
		"prints every requirement (id, position, value, limit, margin, pass) and the verdict.\n"
		"Exit 0 when every requirement passes, 1 when one fails, 2 on a usage error.\n"
		"\n"
		"  FILE               a LID file: a combined distribution, or light sources with a\n"
		"                     preset (without one every source is at full current)\n"
		"  --regulation ID    a set of the regulations directory, or a set file (*.json);\n"
		"                     'list' lists the sets\n"
		"  --other FILE       the other lamp of the pair, for sets on half the pair's sum\n"
		"                     (with a preset: its other side)\n"
		"  --traffic          right (default) or left: left-hand traffic mirrors H\n"
		"  --aim              mounted (default): the distribution as the file has it;\n"
		"                     regulation: aimed as the set says (R149: the cut-off's\n"
		"                     inflection point at 2.5L on line B, 0.57D), with the cut-off's\n"
		"                     sharpness G and linearity reported\n"
		"  --json             the verdict as one JSON object on stdout instead of the table\n"
		"  --plot OUT.png     the H-V isocandela diagram with every requirement marked\n"
		"  --regulations DIR  where the sets are (default: the installed ones)\n");
}

static int list(const char *dir)
{
	char **ids;
	int rc = hl_regulation_list(dir, &ids);

	if (rc < 0) {
		fprintf(stderr, "hdlamp lid check: '%s': %s\n", dir, strerror(-rc));
		return HL_EXIT_FAIL;
	}
	for (char **id = ids; *id; id++) {
		struct hl_regulation *reg;
		struct hl_regulation_error err;

		if (hl_regulation_load(dir, *id, &reg, &err) < 0) {
			printf("%-32s  (invalid: %s)\n", *id, err.msg);
			continue;
		}
		printf("%-32s  %3d requirements  %s\n", *id, reg->n_requirements, reg->title);
		hl_regulation_free(reg);
	}
	hl_regulation_list_free(ids);
	return HL_EXIT_OK;
}

static void angle(double deg, char pos, char neg, char zero, char *buf, size_t size)
{
	if (fabs(deg) < 5e-4)
		snprintf(buf, size, "%c", zero);
	else
		snprintf(buf, size, "%.2f%c", fabs(deg), deg > 0 ? pos : neg);
}

static void where(const struct hl_req_result *r, char *buf, size_t size)
{
	char h[16], v[16];

	if (isnan(r->at_h_deg)) {
		snprintf(buf, size, "outside grid");
		return;
	}
	angle(r->at_h_deg, 'R', 'L', 'V', h, sizeof(h));
	angle(r->at_v_deg, 'U', 'D', 'H', v, sizeof(v));
	snprintf(buf, size, "%s %s", h, v);
}

static void limit(const struct hl_req_result *r, char *buf, size_t size)
{
	const bool lo = !isnan(r->min_cd), hi = !isnan(r->max_cd);

	if (lo && hi)
		snprintf(buf, size, "%.0f..%.0f", r->min_cd, r->max_cd);
	else if (lo)
		snprintf(buf, size, ">= %.0f", r->min_cd);
	else
		snprintf(buf, size, "<= %.0f", r->max_cd);
}

static void table(const struct hl_regulation *reg, const struct hl_verdict_options *o,
		  const struct hl_req_result *res, bool pass)
{
	printf("%s: %s\n%s\n", reg->id, reg->title, reg->source);
	/* the beam the set is for: hdlampd applies it to that beam's frames (docs/verdicts.md) */
	if (hl_reg_beam_name(reg->beam))
		printf("a set for the %s beam\n", hl_reg_beam_name(reg->beam));
	printf("traffic %s, aim H %+.2f V %+.2f deg, receiver %s %.3f deg\n\n",
	       o->traffic == HL_TRAFFIC_LEFT ? "left" : "right", o->aim_h_deg, o->aim_v_deg,
	       reg->receiver == HL_RECEIVER_SQUARE ? "square" : "circle", reg->receiver_deg);
	printf("%-24s %-8s %-16s %12s %16s %9s  %s\n", "id", "kind", "at", "value cd", "limit cd",
	       "margin", "pass");
	for (int i = 0; i < reg->n_requirements; i++) {
		char at[48], lim[48];

		where(&res[i], at, sizeof(at));
		limit(&res[i], lim, sizeof(lim));
		printf("%-24s %-8s %-16s %12.1f %16s %+8.1f%%  %s", reg->req[i].id,
		       hl_req_kind_name(reg->req[i].kind), at, res[i].value_cd, lim,
		       100.0 * res[i].margin, res[i].pass ? "pass" : "FAIL");
		if (res[i].n_outside)
			printf("  (%d positions beyond the measured grid)", res[i].n_outside);
		printf("\n");
	}
	/* the words of the live verdicts: "pass", "FAIL" (one distribution: no "so far") */
	printf("\nverdict: %s\n", pass ? "pass" : "FAIL");
}

static void json_pt(const struct hl_verdict_options *o, const double p[2])
{
	printf("[");
	if (fabs(p[0]) > 1e8)
		printf("%s", (p[0] < 0) != (o->traffic == HL_TRAFFIC_LEFT) ? "\"L\"" : "\"R\"");
	else
		hl_tool_json_num(stdout, o->traffic == HL_TRAFFIC_LEFT ? -p[0] : p[0]);
	printf(", ");
	if (fabs(p[1]) > 1e8)
		printf("%s", p[1] < 0 ? "\"D\"" : "\"U\"");
	else
		hl_tool_json_num(stdout, p[1]);
	printf("]");
}

static void json(const struct hl_regulation *reg, const struct hl_verdict_options *o,
		 const struct hl_cutoff *cut, const struct hl_req_result *res, bool pass)
{
	printf("{\"regulation\": ");
	hl_tool_json_str(stdout, reg->id);
	printf(", \"beam\": ");
	if (hl_reg_beam_name(reg->beam))
		hl_tool_json_str(stdout, hl_reg_beam_name(reg->beam));
	else
		printf("null");
	printf(", \"traffic\": \"%s\", \"aim\": {\"h_deg\": ",
	       o->traffic == HL_TRAFFIC_LEFT ? "left" : "right");
	hl_tool_json_num(stdout, o->aim_h_deg);
	printf(", \"v_deg\": ");
	hl_tool_json_num(stdout, o->aim_v_deg);
	printf("}");
	if (cut) {
		printf(", \"cutoff\": {\"v_deg\": ");
		hl_tool_json_num(stdout, cut->v_deg);
		printf(", \"g\": ");
		hl_tool_json_num(stdout, cut->g);
		printf(", \"linearity_deg\": ");
		hl_tool_json_num(stdout, cut->linearity_deg);
		printf(", \"sharp_ok\": %s, \"linear_ok\": %s}", cut->sharp_ok ? "true" : "false",
		       cut->linear_ok ? "true" : "false");
	}
	printf(", \"pass\": %s, \"result\": \"%s\", \"requirements\": [", pass ? "true" : "false",
	       pass ? "pass" : "FAIL");
	for (int i = 0; i < reg->n_requirements; i++) {
		const struct hl_requirement *q = &reg->req[i];
		const struct hl_req_result *r = &res[i];

		printf("%s\n  {\"id\": ", i ? "," : "");
		hl_tool_json_str(stdout, q->id);
		printf(", \"kind\": \"%s\"", hl_req_kind_name(q->kind));
		if (q->kind == HL_REQ_POINT) {
			printf(", \"h_deg\": ");
			hl_tool_json_num(stdout, o->traffic == HL_TRAFFIC_LEFT ? -q->pts[0][0] :
										 q->pts[0][0]);
			printf(", \"v_deg\": ");
			hl_tool_json_num(stdout, q->pts[0][1]);
		} else if (q->kind != HL_REQ_IMAX) {
			printf(", \"%s\": [", q->kind == HL_REQ_SEGMENT ? "line_deg" :
					      q->kind == HL_REQ_ZONE	? "polygon_deg" :
									  "points_deg");
			for (int k = 0; k < q->n_pts; k++) {
				printf("%s", k ? ", " : "");
				json_pt(o, q->pts[k]);
			}
			printf("]");
		}
		if (q->kind == HL_REQ_SEGMENT || q->kind == HL_REQ_ZONE || q->kind == HL_REQ_IMAX) {
			printf(", \"at_h_deg\": ");
			hl_tool_json_num(stdout, r->at_h_deg);
			printf(", \"at_v_deg\": ");
			hl_tool_json_num(stdout, r->at_v_deg);
		}
		printf(", \"value_cd\": ");
		hl_tool_json_num(stdout, r->value_cd);
		printf(", \"min_cd\": ");
		hl_tool_json_num(stdout, r->min_cd);
		printf(", \"max_cd\": ");
		hl_tool_json_num(stdout, r->max_cd);
		printf(", \"margin\": ");
		hl_tool_json_num(stdout, r->margin);
		if (r->n_outside)
			printf(", \"positions_outside\": %d", r->n_outside);
		printf(", \"pass\": %s}", r->pass ? "true" : "false");
	}
	printf("\n]}\n");
}

static int load_set(const char *arg, const char *dir, struct hl_regulation **ret)
{
	struct hl_regulation_error err;
	const size_t n = strlen(arg);
	int rc;

	if (n > 5 && !strcmp(arg + n - 5, ".json"))
		rc = hl_regulation_read(arg, ret, &err);
	else
		rc = hl_regulation_load(dir, arg, ret, &err);
	if (rc < 0)
		fprintf(stderr, "hdlamp lid check: %s\n", err.msg);
	return rc;
}

static int load_lamp(const char *path, const char *preset, int side, struct hl_lid **ret_lid,
		     float **ret_dense)
{
	struct hl_lid_error err;

	if (hl_lid_read(path, ret_lid, &err) < 0) {
		fprintf(stderr, "hdlamp lid check: %s\n", err.msg);
		return -EINVAL;
	}
	return hl_cli_lid_distribution(*ret_lid, preset, side, ret_dense);
}

int hl_cmd_lid_check(int argc, char **argv)
{
	enum { OPT_REG = 256, OPT_REGS, OPT_OTHER, OPT_TRAFFIC, OPT_AIM, OPT_JSON, OPT_PLOT };
	static const struct option opts[] = {
		{ "lamp", required_argument, NULL, 'l' },
		{ "regulation", required_argument, NULL, OPT_REG },
		{ "regulations", required_argument, NULL, OPT_REGS },
		{ "other", required_argument, NULL, OPT_OTHER },
		{ "traffic", required_argument, NULL, OPT_TRAFFIC },
		{ "aim", required_argument, NULL, OPT_AIM },
		{ "json", no_argument, NULL, OPT_JSON },
		{ "plot", required_argument, NULL, OPT_PLOT },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	const char *set = NULL, *other = NULL, *plot = NULL, *file, *preset = NULL;
	char dir[4096] = "";
	bool as_json = false, aim_reg = false;
	struct hl_verdict_options o = { .traffic = HL_TRAFFIC_RIGHT };
	struct hl_regulation *reg = NULL;
	struct hl_lid *lid = NULL, *lid2 = NULL;
	float *dense = NULL, *dense2 = NULL;
	struct hl_verdict *v = NULL;
	struct hl_req_result *res = NULL;
	struct hl_cutoff cut;
	int side = -1, c, rc = HL_EXIT_FAIL;
	bool pass;

	optind = 1;
	while ((c = getopt_long(argc, argv, "l:h", opts, NULL)) != -1) {
		switch (c) {
		case 'l':
			side = hl_side_from_name(optarg);
			if (side < 0) {
				fprintf(stderr,
					"hdlamp lid check: --lamp '%s': expected left or right\n",
					optarg);
				return HL_EXIT_USAGE;
			}
			break;
		case OPT_REG:
			set = optarg;
			break;
		case OPT_REGS:
			snprintf(dir, sizeof(dir), "%s", optarg);
			break;
		case OPT_OTHER:
			other = optarg;
			break;
		case OPT_TRAFFIC:
			if (strcmp(optarg, "right") && strcmp(optarg, "left")) {
				fprintf(stderr,
					"hdlamp lid check: --traffic '%s': expected right or left\n",
					optarg);
				return HL_EXIT_USAGE;
			}
			o.traffic = strcmp(optarg, "left") ? HL_TRAFFIC_RIGHT : HL_TRAFFIC_LEFT;
			break;
		case OPT_AIM:
			if (strcmp(optarg, "mounted") && strcmp(optarg, "regulation")) {
				fprintf(stderr,
					"hdlamp lid check: --aim '%s': expected mounted or regulation\n",
					optarg);
				return HL_EXIT_USAGE;
			}
			aim_reg = !strcmp(optarg, "regulation");
			break;
		case OPT_JSON:
			as_json = true;
			break;
		case OPT_PLOT:
			plot = optarg;
			break;
		case 'h':
			usage(stdout);
			return HL_EXIT_OK;
		default:
			usage(stderr);
			return HL_EXIT_USAGE;
		}
	}
	if (!set) {
		fprintf(stderr, "hdlamp lid check: --regulation is required\n");
		usage(stderr);
		return HL_EXIT_USAGE;
	}
	if (!dir[0] && hl_regulation_default_dir(dir, sizeof(dir)) < 0) {
		fprintf(stderr, "hdlamp lid check: cannot find the regulations directory; "
				"give --regulations DIR\n");
		return HL_EXIT_FAIL;
	}
	if (!strcmp(set, "list")) {
		if (optind != argc) {
			usage(stderr);
			return HL_EXIT_USAGE;
		}
		return list(dir);
	}
	if (optind >= argc) {
		fprintf(stderr, "hdlamp lid check: expected a LID FILE\n");
		usage(stderr);
		return HL_EXIT_USAGE;
	}
	file = argv[optind++];
	if (optind < argc)
		preset = argv[optind++];
	if (optind != argc || (preset && side < 0) || (!preset && side >= 0)) {
		fprintf(stderr, "hdlamp lid check: a preset needs --lamp and --lamp a preset\n");
		usage(stderr);
		return HL_EXIT_USAGE;
	}
	if (load_set(set, dir, &reg) < 0)
		goto out;
	if (reg->applies == HL_REG_PAIR_HALF && !other) {
		fprintf(stderr,
			"hdlamp lid check: '%s' applies to half the sum of the pair: give the other "
			"lamp with --other FILE\n",
			reg->id);
		rc = HL_EXIT_USAGE;
		goto out;
	}
	if (aim_reg && reg->aim != HL_REG_AIM_CUTOFF)
		fprintf(stderr, "hdlamp lid check: '%s' aims nothing (measured as mounted)\n",
			reg->id);
	if (load_lamp(file, preset, side, &lid, &dense) < 0)
		goto out;
	if (reg->applies == HL_REG_PAIR_HALF) {
		if (load_lamp(other, preset, side < 0 ? -1 : !side, &lid2, &dense2) < 0)
			goto out;
		if (!hl_lid_grid_equal(hl_lid_grid(lid), hl_lid_grid(lid2))) {
			fprintf(stderr, "hdlamp lid check: '%s' and '%s' are on different grids\n",
				file, other);
			goto out;
		}
	} else if (other) {
		fprintf(stderr,
			"hdlamp lid check: '%s' applies to each lamp: --other is not used\n",
			reg->id);
	}
	if (aim_reg && reg->aim == HL_REG_AIM_CUTOFF) {
		c = hl_verdict_find_cutoff(reg, hl_lid_grid(lid), dense, o.traffic, &cut);
		if (c < 0) {
			fprintf(stderr,
				"hdlamp lid check: '%s': no cut-off on the vertical scan at %.2f%c; "
				"cannot aim as %s says\n",
				file, fabs(reg->aim_scan_h_deg),
				reg->aim_scan_h_deg < 0 ? 'L' : 'R', reg->id);
			goto out;
		}
		o.aim_v_deg = reg->aim_cutoff_v_deg - cut.v_deg;
	}
	if (hl_verdict_new(reg, hl_lid_grid(lid), &o, &v) < 0) {
		fprintf(stderr, "hdlamp lid check: cannot plan '%s' on '%s'\n", reg->id, file);
		goto out;
	}
	res = calloc(reg->n_requirements, sizeof(*res));
	if (!res)
		goto out;
	pass = hl_verdict_eval(v, dense, dense2, res);
	if (as_json) {
		json(reg, &o, aim_reg && reg->aim == HL_REG_AIM_CUTOFF ? &cut : NULL, res, pass);
	} else {
		if (aim_reg && reg->aim == HL_REG_AIM_CUTOFF)
			printf("cut-off: inflection point at %.3f deg on the scan at %.2f%c, moved "
			       "%+.3f deg to %.2fD; sharpness G %.3f (%.2f..%.2f: %s); linearity "
			       "%.3f deg (<= %.2f: %s)\n\n",
			       cut.v_deg, fabs(reg->aim_scan_h_deg),
			       reg->aim_scan_h_deg < 0 ? 'L' : 'R', o.aim_v_deg,
			       -reg->aim_cutoff_v_deg, cut.g, reg->aim_g_min, reg->aim_g_max,
			       cut.sharp_ok ? "ok" : "out of range", cut.linearity_deg,
			       reg->aim_linearity_max_deg, cut.linear_ok ? "ok" : "not linear");
		table(reg, &o, res, pass);
	}
	if (plot) {
		char title[256], *tmp = strdup(file);

		snprintf(title, sizeof(title), "%s%s%s", tmp ? basename(tmp) : file,
			 side >= 0 ? " " : "", side >= 0 ? hl_side_name(side) : "");
		free(tmp);
		if (dense2) /* the plot shows what was evaluated: half the pair's sum */
			for (size_t i = 0;
			     i < (size_t)hl_lid_grid(lid)->width * hl_lid_grid(lid)->height; i++)
				dense[i] = 0.5f * (dense[i] + dense2[i]);
		c = hl_plot_verdict_png(hl_lid_grid(lid), dense, reg, &o, res, title, plot);
		if (c < 0) {
			fprintf(stderr, "hdlamp lid check: '%s': %s\n", plot, strerror(-c));
			goto out;
		}
	}
	rc = pass ? HL_EXIT_OK : HL_EXIT_FAIL;
out:
	free(res);
	hl_verdict_free(v);
	free(dense);
	free(dense2);
	hl_lid_free(lid);
	hl_lid_free(lid2);
	hl_regulation_free(reg);
	return rc;
}
