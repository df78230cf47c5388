/* SPDX-License-Identifier: MIT */
/*
 * hdlamp-bench-suite: what measuring a suite costs per frame (verdict/suite_measure.h), as one
 * JSON object: for each shipped suite the scenario whose stimulus vehicle carries the most
 * photometers (IIHS: its first road), the variant's scenario generated as `hdlamp suite run` generates it, then
 * hl_suite_measure_frame on the HD84 pair's high beam at every 20 ms frame of it, repeated:
 * median, p99, min, max in µs per frame, and the photometers or points each frame reads.
 *
 *   hdlamp-bench-suite SUITES_DIR [--runs N] [--json FILE]
 */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lamp/combine.h"
#include "lamp/model.h"
#include "lamp/preset.h"
#include "verdict/regulation.h"
#include "verdict/suite_measure.h"
#include "verdict/suite_scenario.h"
#include "tools/benchmarks/bench_stats.h"

#define FRAME_S 0.02

struct lamps {
	struct hl_lid *lid[2];
	float *dense[2];
	const struct hl_lid_grid *grid[2];
};

static int load_lamps(struct lamps *l)
{
	struct hl_preset *p = NULL;
	float *cur = NULL;
	int rc = 0;

	for (int s = 0; s < 2 && rc == 0; s++)
		rc = hl_model_hd84((enum hl_side)s, &l->lid[s]);
	if (rc == 0)
		rc = hl_preset_new(hl_lid_n_sources(l->lid[0]), &p);
	if (rc == 0)
		rc = hl_model_hd84_preset("high", l->lid, p);
	if (rc == 0)
		cur = malloc(sizeof(float) * (size_t)p->n_sources);
	for (int s = 0; s < 2 && cur; s++) {
		l->grid[s] = hl_lid_grid(l->lid[s]);
		l->dense[s] = malloc(sizeof(float) * (size_t)l->grid[s]->width *
				     (size_t)l->grid[s]->height);
		if (!l->dense[s])
			break;
		hl_preset_intensities(p, s, cur);
		hl_combine_sparse(l->lid[s], cur, l->dense[s]);
	}
	if (rc == 0 && (!cur || !l->dense[0] || !l->dense[1]))
		rc = -ENOMEM;
	free(cur);
	hl_preset_free(p);
	return rc;
}

/* Times one suite's first scenario; prints its object (no trailing comma). 0 or -errno. */
static int bench(FILE *out, const char *dir, const char *name, const struct lamps *l, int runs,
		 const char *sep)
{
	char path[4096], msg[1024], *text = NULL;
	struct hl_suite *s = NULL;
	struct hl_scenario *sc = NULL;
	struct hl_regulation *reg = NULL;
	struct hl_json_error err;
	struct hl_regulation_error rerr;
	const struct hl_suite_scenario *d;
	double *t = NULL, speed, radius;
	char id[96];
	int rc, n_frames, reads = 0;

	snprintf(path, sizeof(path), "%s/%s.json", dir, name);
	rc = hl_suite_read(path, &s, &err);
	if (rc < 0) {
		fprintf(stderr, "hdlamp-bench-suite: %s\n", hl_json_error_format(&err, msg, 1024));
		return rc;
	}
	/* the scenario whose stimulus vehicle carries the most photometers */
	d = &s->scenario[0];
	for (int i = 0, best = -1; i < s->n_scenarios; i++) {
		int n = 0;

		for (int p = 0; p < s->n_photometers; p++)
			n += s->scenario[i].has_role &&
			     s->photometer[p].role == s->scenario[i].role;
		if (n > best) {
			best = n;
			d = &s->scenario[i];
		}
	}
	hl_suite_variant_params(d, 2, 0, &speed, &radius, id, sizeof(id));
	rc = hl_suite_variant_scenario(s, d, speed, radius, &text, msg, sizeof(msg));
	if (rc == 0)
		rc = hl_scenario_parse(text, id, &sc, &err);
	if (rc == 0 && s->procedure == HL_SUITE_R149_ADB) {
		char rdir[4096];

		rc = hl_regulation_default_dir(rdir, sizeof(rdir));
		if (rc == 0)
			rc = hl_regulation_load(rdir, s->glare_set, &reg, &rerr);
	}
	if (rc < 0) {
		fprintf(stderr, "hdlamp-bench-suite: %s: cannot set up: %s\n", name, strerror(-rc));
		goto out;
	}
	n_frames = s->procedure == HL_SUITE_IIHS ? 1 : (int)floor(sc->duration_s / FRAME_S) + 1;
	t = calloc((size_t)runs, sizeof(*t));
	if (!t) {
		rc = -ENOMEM;
		goto out;
	}
	for (int r = 0; r < runs; r++) {
		struct hl_suite_variant v = { .range_m = { d->range_m[0], d->range_m[1] } };
		struct hl_suite_measure *m;
		double t0;

		rc = hl_suite_measure_new(s, d, reg, &v, &m);
		if (rc < 0)
			goto out;
		t0 = hl_bench_now_ms();
		for (int k = 0; k < n_frames; k++) {
			struct hl_world_state w;

			hl_world_at(sc, k * FRAME_S, &w);
			hl_suite_measure_frame(m, sc, &w, l->grid, (const float *const *)l->dense);
		}
		t[r] = (hl_bench_now_ms() - t0) * 1000.0 / n_frames;
		if (r == 0)
			for (int i = 0; i < v.n_series; i++)
				reads += v.series[i].n;
		hl_suite_measure_finish(m);
		hl_suite_measure_free(m);
		free(v.cases);
		for (int i = 0; i < v.n_series; i++) {
			free(v.series[i].range_m);
			free(v.series[i].lx);
			free(v.series[i].t_s);
		}
		free(v.birdseye.left);
		free(v.birdseye.right);
	}
	{
		const int n = runs;
		struct stats st = hl_bench_summarise(t, n);

		fprintf(out,
			"%s\"%s\": {\"scenario\": \"%s\", \"frames\": %d, \"readings_per_frame\": %.1f, "
			"\"median_us\": %.3f, \"p99_us\": %.3f, \"min_us\": %.3f, \"max_us\": %.3f, "
			"\"runs\": %d}",
			sep, name, id, n_frames, (double)reads / n_frames, st.median,
			t[(int)((n - 1) * 0.99 + 0.5)], st.min, st.max, n);
	}
out:
	free(t);
	free(text);
	hl_regulation_free(reg);
	hl_scenario_free(sc);
	hl_suite_free(s);
	return rc;
}

int main(int argc, char **argv)
{
	static const struct option opts[] = { { "runs", required_argument, NULL, 'r' },
					      { "json", required_argument, NULL, 'j' },
					      { NULL, 0, NULL, 0 } };
	const char *json = NULL;
	struct lamps l = { 0 };
	int runs = 50, c, rc;
	FILE *out;

	while ((c = getopt_long(argc, argv, "", opts, NULL)) != -1) {
		if (c == 'r')
			runs = atoi(optarg);
		else if (c == 'j')
			json = optarg;
		else
			return 2;
	}
	if (optind != argc - 1 || runs < 1) {
		fprintf(stderr, "usage: hdlamp-bench-suite SUITES_DIR [--runs N] [--json FILE]\n");
		return 2;
	}
	if (load_lamps(&l) < 0) {
		fprintf(stderr, "hdlamp-bench-suite: cannot build the HD84 pair\n");
		return 1;
	}
	out = hl_bench_open_json("hdlamp-bench-suite", json);
	if (!out)
		return 1;
	fprintf(out, "{");
	rc = bench(out, argv[optind], "fmvss108-adb", &l, runs, "");
	if (rc == 0)
		rc = bench(out, argv[optind], "r149-adb", &l, runs, ", ");
	if (rc == 0)
		rc = bench(out, argv[optind], "iihs", &l, runs, ", ");
	fprintf(out, "}\n");
	if (out != stdout)
		fclose(out);
	for (int s = 0; s < 2; s++) {
		free(l.dense[s]);
		hl_lid_free(l.lid[s]);
	}
	return rc < 0 ? 1 : 0;
}
