/* SPDX-License-Identifier: MIT */
/*
 * hdlamp-bench-verdict: what the live verdicts cost the render thread per frame, as one JSON
 * object: every shipped regulation set (or those given) planned by daemon/core/verdicts.c exactly as
 * hdlampd plans them (the HD84 pair at its default mounted poses, right-hand traffic), then
 * evaluated on the pair's combined distributions, alternating the low and high presets as an
 * ECU would switch beams: per set, all sets together, the road KPIs, and the whole per-frame
 * check (all sets + road KPIs, what hdlampd times as verdict_ms). Median, p99, min, max in µs.
 * Target: all sets on both lamps <= 200 µs per frame.
 */
#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "daemon/core/verdicts.h"
#include "lamp/combine.h"
#include "lamp/model.h"
#include "verdict/regulation.h"
#include "tools/benchmarks/bench_stats.h"

#define TARGET_US 200.0 /* all configured sets on both lamps, per frame */

struct pct {
	struct stats s;
	double p99;
};

static struct pct summarise_us(double *t_ms, int n)
{
	struct pct r;

	for (int i = 0; i < n; i++)
		t_ms[i] *= 1000.0;
	r.s = hl_bench_summarise(t_ms, n); /* sorts */
	r.p99 = n > 0 ? t_ms[(int)((n - 1) * 0.99 + 0.5)] : -1;
	return r;
}

static void print_pct(FILE *f, const char *name, struct pct p, const char *end)
{
	fprintf(f,
		"\"%s\": {\"median_us\": %.2f, \"p99_us\": %.2f, \"min_us\": %.2f, \"max_us\": %.2f, "
		"\"n\": %d}%s",
		name, p.s.median, p.p99, p.s.min, p.s.max, p.s.n, end);
}

/* Times eval of the sets in mask (and the road KPIs with road) over runs frames. */
static struct pct time_frames(const struct hl_verdicts *v, uint32_t mask, bool road,
			      const float *const dist[2][2], struct hl_req_result *res, double *t,
			      int runs, uint32_t *ret_failed)
{
	struct hl_road_kpi k;
	uint32_t failed = 0;

	for (int r = 0; r < runs + 5; r++) {
		const float *const *d = dist[r & 1]; /* low, high, low, ... */
		const double t0 = hl_bench_now_ms();

		if (mask)
			failed |= hl_verdicts_eval(v, mask, d, res);
		if (road)
			hl_verdicts_road(v, d, &k);
		if (r >= 5) /* the first frames warm the caches */
			t[r - 5] = hl_bench_now_ms() - t0;
	}
	if (ret_failed)
		*ret_failed = failed;
	return summarise_us(t, runs);
}

/*
 * As hdlampd runs them: each frame copies the lamps' distributions into the frame and finds
 * their peaks on the way (hl_verdict_copy_peak), then evaluates with those peaks; with copy
 * false only the plain memcpy the frame needs anyway, the baseline to subtract.
 */
static struct pct time_as_daemon(const struct hl_verdicts *v, uint32_t mask, bool copy_only,
				 const float *const dist[2][2], float *const frame[2], size_t n,
				 struct hl_req_result *res, double *t, int runs)
{
	struct hl_verdict_peak peaks[2];

	for (int r = 0; r < runs + 5; r++) {
		const float *const *d = dist[r & 1];
		const double t0 = hl_bench_now_ms();

		for (int l = 0; l < 2; l++)
			if (copy_only)
				memcpy(frame[l], d[l], n * sizeof(float));
			else
				hl_verdict_copy_peak(frame[l], d[l], n, &peaks[l]);
		if (!copy_only)
			hl_verdicts_eval_peaks(v, mask, (const float *const *)frame, peaks, res);
		if (r >= 5)
			t[r - 5] = hl_bench_now_ms() - t0;
	}
	return summarise_us(t, runs);
}

static void usage(FILE *f)
{
	fprintf(f,
		"usage: hdlamp-bench-verdict [--runs N] [--regulations DIR] [--sets ID,ID,...]\n"
		"                            [--out FILE.json]\n"
		"Times the live verdicts of hdlampd (daemon/core/verdicts.c) per frame on the HD84 pair:\n"
		"each set, all sets, the road KPIs and the whole check, alternating the low and high\n"
		"beams. Default: every set of the regulations directory (the shipped ones).\n"
		"Prints one JSON object (or writes it to --out). Exit 0, 1 on a failure, 2 on a\n"
		"usage error.\n");
}

int main(int argc, char **argv)
{
	static const struct option opts[] = {
		{ "runs", required_argument, NULL, 'n' },
		{ "regulations", required_argument, NULL, 'r' },
		{ "sets", required_argument, NULL, 's' },
		{ "out", required_argument, NULL, 'o' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	static const char *const names[2] = { "left", "right" };
	static const char *const presets[2] = { "low", "high" };
	const char *out_path = NULL, *sets = NULL;
	struct hl_config cfg;
	struct hl_lid *lamps[2] = { NULL, NULL };
	const struct hl_lid_grid *grids[2];
	struct hl_lamp_pose poses[2];
	struct hl_preset *p = NULL;
	struct hl_verdicts *v = NULL;
	struct hl_config_error cerr;
	struct hl_req_result *res = NULL;
	float *dense[2][2] = { { NULL, NULL }, { NULL, NULL } };
	float i[HL_HD84_SOURCES];
	char **ids = NULL, err[1024], *assign = NULL;
	double *t = NULL, t_plan;
	int runs = 2000, c, n_sets, rc = 1;
	uint32_t all, failed;
	FILE *f = NULL;

	hl_config_defaults(&cfg);
	if (hl_regulation_default_dir(cfg.regulations, sizeof(cfg.regulations)) < 0)
		cfg.regulations[0] = '\0';
	while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
		switch (c) {
		case 'n':
			runs = atoi(optarg);
			if (runs < 10 || runs > 1000000) {
				fprintf(stderr, "hdlamp-bench-verdict: --runs: 10..1000000\n");
				return 2;
			}
			break;
		case 'r':
			snprintf(cfg.regulations, sizeof(cfg.regulations), "%s", optarg);
			break;
		case 's':
			sets = optarg;
			break;
		case 'o':
			out_path = optarg;
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
	/* the sets: as verdict.sets says, or every one of the directory */
	if (!sets) {
		size_t len = 1;

		if (hl_regulation_list(cfg.regulations, &ids) < 0) {
			fprintf(stderr, "hdlamp-bench-verdict: '%s': cannot list the sets\n",
				cfg.regulations);
			return 1;
		}
		for (int k = 0; ids[k]; k++)
			len += strlen(ids[k]) + 1;
		assign = calloc(1, len);
		if (!assign)
			goto out;
		for (int k = 0; ids[k]; k++) {
			if (k)
				strcat(assign, ",");
			strcat(assign, ids[k]);
		}
		sets = assign;
	}
	if (hl_config_set(&cfg, "verdict", "sets", sets, "--sets", 0, &cerr) < 0) {
		fprintf(stderr, "hdlamp-bench-verdict: %s\n", cerr.msg);
		rc = 2;
		goto out;
	}
	n_sets = cfg.n_verdict_sets;
	if (hl_model_hd84(HL_SIDE_LEFT, &lamps[0]) < 0 ||
	    hl_model_hd84(HL_SIDE_RIGHT, &lamps[1]) < 0 || hl_preset_new(HL_HD84_SOURCES, &p) < 0) {
		fprintf(stderr, "hdlamp-bench-verdict: cannot build the HD84 lamps\n");
		goto out;
	}
	for (int l = 0; l < 2; l++) {
		grids[l] = hl_lid_grid(lamps[l]);
		hl_lamp_pose_default(l, &poses[l]); /* as hdlampd places them */
	}
	for (int b = 0; b < 2; b++) {
		if (hl_model_hd84_preset(presets[b], lamps, p) < 0)
			goto out;
		for (int l = 0; l < 2; l++) {
			dense[b][l] = malloc(sizeof(float) * grids[l]->width * grids[l]->height);
			if (!dense[b][l])
				goto out;
			hl_preset_intensities(p, l, i);
			hl_combine_sparse(lamps[l], i, dense[b][l]);
		}
	}
	t_plan = hl_bench_now_ms();
	if (hl_verdicts_new(&cfg, 2, names, grids, poses, NULL, &v, err, sizeof(err)) < 0) {
		fprintf(stderr, "hdlamp-bench-verdict: %s\n", err);
		goto out;
	}
	t_plan = hl_bench_now_ms() - t_plan;
	res = calloc(hl_verdicts_n_results(v) + 1, sizeof(*res));
	t = calloc(runs, sizeof(double));
	if (!res || !t)
		goto out;
	f = hl_bench_open_json("hdlamp-bench-verdict", out_path);
	if (!f)
		goto out;
	all = n_sets ? (uint32_t)((1ull << n_sets) - 1) : 0;
	fprintf(f,
		"{\n  \"what\": \"live verdicts per frame, HD84 pair, low/high alternating\",\n");
	fprintf(f, "  \"regulations\": \"%s\",\n  \"runs\": %d,\n  \"plan_ms\": %.1f,\n",
		cfg.regulations, runs, t_plan);
	fprintf(f, "  \"target_all_sets_us\": %.0f,\n  \"sets\": [\n", TARGET_US);
	for (int s = 0; s < n_sets; s++) {
		const struct hl_regulation *reg = hl_verdicts_set(v, s);
		const struct pct one = time_frames(
			v, 1u << s, false, (const float *const(*)[2])dense, res, t, runs, &failed);

		fprintf(f,
			"    {\"id\": \"%s\", \"applies\": \"%s\", \"requirements\": %d, "
			"\"evaluations_per_frame\": %d, \"fails_low_or_high\": %s, ",
			reg->id, reg->applies == HL_REG_PAIR_HALF ? "pair_half" : "each_lamp",
			reg->n_requirements, hl_verdicts_n_parts(v, s), failed ? "true" : "false");
		print_pct(f, "per_frame", one, s + 1 < n_sets ? "},\n" : "}\n");
	}
	fprintf(f, "  ],\n  ");
	{
		const struct pct sets_all = time_frames(
			v, all, false, (const float *const(*)[2])dense, res, t, runs, NULL);
		const struct pct road = time_frames(v, 0, true, (const float *const(*)[2])dense,
						    res, t, runs, NULL);
		const struct pct frame_t = time_frames(
			v, all, true, (const float *const(*)[2])dense, res, t, runs, NULL);

		const size_t n = (size_t)grids[0]->width * grids[0]->height;
		float *frame[2] = { malloc(n * sizeof(float)), malloc(n * sizeof(float)) };
		struct pct copy, fused;
		double net;

		if (!frame[0] || !frame[1]) {
			free(frame[0]);
			free(frame[1]);
			goto out;
		}
		copy = time_as_daemon(v, all, true, (const float *const(*)[2])dense, frame, n, res,
				      t, runs);
		fused = time_as_daemon(v, all, false, (const float *const(*)[2])dense, frame, n,
				       res, t, runs);
		free(frame[0]);
		free(frame[1]);
		net = fused.s.median - copy.s.median;
		print_pct(f, "all_sets", sets_all, ",\n  ");
		print_pct(f, "road_kpis", road, ",\n  ");
		print_pct(f, "frame_all_sets_and_road", frame_t, ",\n  ");
		print_pct(f, "frame_copy_memcpy", copy, ",\n  ");
		print_pct(f, "frame_copy_peak_and_all_sets", fused, ",\n  ");
		fprintf(f, "\"all_sets_as_hdlampd_median_us\": %.2f,\n  ", net);
		fprintf(f, "\"met\": %s,\n  \"met_as_hdlampd\": %s\n}\n",
			sets_all.s.median <= TARGET_US ? "true" : "false",
			net <= TARGET_US ? "true" : "false");
	}
	rc = 0;
out:
	if (f && f != stdout && fclose(f) != 0)
		rc = 1;
	hl_verdicts_free(v);
	hl_preset_free(p);
	for (int l = 0; l < 2; l++) {
		hl_lid_free(lamps[l]);
		free(dense[0][l]);
		free(dense[1][l]);
	}
	hl_regulation_list_free(ids);
	free(assign);
	free(res);
	free(t);
	return rc;
}
