/* SPDX-License-Identifier: MIT */
/* hdlamp suite run: see tools/suite_run.h. */
#include "tools/suite_run.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/make_dirs.h"
#include "lamp/combine.h"
#include "lamp/lid.h"
#include "lamp/model.h"
#include "tools/preset_arg.h"
#include "verdict/regulation.h"
#include "verdict/suite_measure.h"
#include "verdict/suite_plan.h"
#include "verdict/suite_report.h"
#include "verdict/suite_scenario.h"
#include "world/world.h"

#define FRAME_S 0.02 /* a held preset is measured at the ECU's 50 Hz */

struct run {
	const struct hl_suite_run_options *o;
	struct hl_regulation *reg; /* r149-adb's glare set */
	struct hl_lid *lids[2]; /* a held preset's lamps */
	float *dense[2];
	struct hl_suite_result res;
};

static void say(const struct run *r, const char *fmt, const char *a, const char *b)
{
	fprintf(r->o->log, "hdlamp suite: ");
	fprintf(r->o->log, fmt, a, b);
	fputc('\n', r->o->log);
}

/* The lamps, once for every run (building the HD84 model takes longer than a run). 0 or -errno
 * (logged). */
static int load_lamps(struct run *r)
{
	const struct hl_config *cfg = r->o->cfg;
	const char *paths[2] = { cfg->lid_left, cfg->lid_right };
	int rc;

	for (int l = 0; l < 2; l++) {
		struct hl_lid_error err;

		if (!paths[l][0]) {
			rc = hl_model_hd84((enum hl_side)l, &r->lids[l]);
		} else {
			rc = hl_lid_read(paths[l], &r->lids[l], &err);
			if (rc < 0)
				say(r, "%s%s", err.msg, "");
		}
		if (rc < 0)
			return rc;
	}
	return 0;
}

/* The lamps' distributions under the held preset, once. 0 or -errno (logged). */
static int load_preset(struct run *r)
{
	struct hl_preset *p = NULL;
	float *cur = NULL;
	int rc;

	rc = hl_tool_preset_load("suite", r->o->preset, r->lids, 2, &p);
	if (rc < 0)
		return rc;
	cur = malloc(sizeof(float) * (size_t)p->n_sources);
	for (int l = 0; l < 2 && cur; l++) {
		const struct hl_lid_grid *g = hl_lid_grid(r->lids[l]);

		r->dense[l] = malloc(sizeof(float) * (size_t)g->width * (size_t)g->height);
		if (!r->dense[l])
			break;
		hl_preset_intensities(p, l, cur);
		hl_combine_sparse(r->lids[l], cur, r->dense[l]);
	}
	rc = cur && r->dense[0] && r->dense[1] ? 0 : -ENOMEM;
	free(cur);
	hl_preset_free(p);
	return rc;
}

static void on_frame(void *ctx, const struct hl_scenario *sc, const struct hl_world_state *w,
		     const struct hl_lid_grid *const grids[2], const float *const dist[2])
{
	hl_suite_measure_frame(ctx, sc, w, grids, dist);
}

/* The held preset through the scenario at 50 Hz (IIHS: its first instant). */
static void run_preset(struct run *r, const struct hl_scenario *sc, struct hl_suite_measure *m)
{
	const struct hl_lid_grid *grids[2] = { hl_lid_grid(r->lids[0]), hl_lid_grid(r->lids[1]) };
	const float *dist[2] = { r->dense[0], r->dense[1] };
	const long n = r->o->suite->procedure == HL_SUITE_IIHS ?
			       1 :
			       (long)floor(sc->duration_s / FRAME_S + 1e-9) + 1;

	for (long k = 0; k < n; k++) {
		struct hl_world_state w;

		hl_world_at(sc, (double)k * FRAME_S, &w);
		hl_suite_measure_frame(m, sc, &w, grids, dist);
	}
}

/* One variant: its scenario written, run, measured, judged, plotted. 0, or -errno to stop. */
static int run_variant(struct run *r, struct hl_suite_variant *v)
{
	const struct hl_suite_run_options *o = r->o;
	const struct hl_suite_scenario *d = &o->suite->scenario[v->scenario_index];
	struct hl_suite_measure *m = NULL;
	char path[4096], msg[1024] = "";
	struct hl_scenario *sc = NULL;
	struct hl_json_error jerr;
	int rc;

	rc = hl_suite_plan_scenario(o->suite, v, o->out, path, sizeof(path), msg, sizeof(msg));
	if (rc < 0) {
		say(r, "%s: %s", v->id, msg);
		return rc == -ENOMEM ? rc : rc == -EINVAL ? -EINVAL : -EIO;
	}
	rc = hl_scenario_read(path, &sc, &jerr);
	if (rc < 0) {
		say(r, "%s%s", hl_json_error_format(&jerr, msg, sizeof(msg)), "");
		return rc;
	}
	rc = hl_suite_measure_new(o->suite, d, r->reg, v, &m);
	if (rc < 0) {
		hl_scenario_free(sc);
		return rc;
	}
	if (o->preset) {
		run_preset(r, sc, m);
	} else {
		struct hl_config *cfg = malloc(sizeof(*cfg));
		struct hl_sil_options so = o->sil;
		char trace[4096];

		if (!cfg) {
			rc = -ENOMEM;
			goto out;
		}
		*cfg = *o->cfg;
		if (strlen(path) >= sizeof(cfg->scenario)) {
			say(r, "--out '%s': the path is too long%s", o->out, "");
			free(cfg);
			rc = -EINVAL;
			goto out;
		}
		memcpy(cfg->scenario, path, strlen(path) + 1);
		cfg->n_verdict_sets = 0; /* the suite judges; the sets' verdicts are not asked */
		snprintf(v->trace_file, sizeof(v->trace_file), "traces/%s.log", v->id);
		snprintf(trace, sizeof(trace), "%s/%s", o->out, v->trace_file);
		so.cfg = cfg;
		so.trace = trace;
		so.report = so.junit = so.frames = NULL;
		so.lids = r->lids;
		so.on_frame = on_frame;
		so.on_frame_ctx = m;
		so.quiet = true;
		so.log = o->log;
		v->exit_code = hl_sil_run(&so);
		free(cfg);
		if (v->exit_code == 2) {
			rc = -EINVAL;
			goto out;
		}
		if (v->exit_code == 1)
			snprintf(v->error, sizeof(v->error),
				 "the run could not go on (the ECU failed, or a file could not "
				 "be written): see the log");
		else
			v->exit_code = 0; /* the loop's own verdict is not the suite's */
	}
	rc = hl_suite_measure_finish(m);
	if (rc < 0)
		goto out;
	if (hl_suite_plan_plot(&r->res, v, o->out) < 0) {
		say(r, "'%s/%s': cannot write the plot", o->out, v->plot_file);
		rc = -EIO;
	}
out:
	hl_suite_measure_free(m);
	hl_scenario_free(sc);
	return rc;
}

static int prepare(struct run *r)
{
	const struct hl_suite_run_options *o = r->o;
	char msg[1024];
	int rc;

	rc = hl_suite_plan_dirs(o->out, !o->preset, msg, sizeof(msg));
	if (rc < 0) {
		say(r, "--out %s%s", msg, "");
		return rc;
	}
	if (o->suite->procedure == HL_SUITE_R149_ADB) {
		struct hl_regulation_error err;
		const char *dir = o->cfg->regulations;
		char def[4096];

		if (!dir[0]) {
			if (hl_regulation_default_dir(def, sizeof(def)) < 0) {
				say(r, "cannot find the shipped regulation sets%s%s", "", "");
				return -ENOENT;
			}
			dir = def;
		}
		rc = hl_regulation_load(dir, o->suite->glare_set, &r->reg, &err);
		if (rc < 0) {
			say(r, "%s%s", err.msg, "");
			return rc;
		}
	}
	rc = load_lamps(r);
	if (rc == 0 && o->preset)
		rc = load_preset(r);
	return rc;
}

int hl_suite_run(const struct hl_suite_run_options *o)
{
	const struct hl_suite *s = o->suite;
	struct run r = { .o = o };
	char msg[1024];
	int rc = 0, code;

	r.res.suite = s;
	if (o->preset) {
		snprintf(r.res.preset, sizeof(r.res.preset), "%s", o->preset);
	} else {
		snprintf(r.res.ecu, sizeof(r.res.ecu), "%s", o->sil.ecu);
		snprintf(r.res.fault, sizeof(r.res.fault), "%s",
			 o->fault_text ? o->fault_text : "");
	}
	rc = hl_suite_plan(s, o->only, o->samples, &r.res, msg, sizeof(msg));
	if (rc < 0)
		say(&r, "%s%s", msg, "");
	else
		rc = prepare(&r);
	for (int i = 0; rc == 0 && i < r.res.n_variants; i++) {
		struct hl_suite_variant *v = &r.res.v[i];

		rc = run_variant(&r, v);
		if (rc == 0) {
			struct hl_suite_totals t;

			hl_suite_variant_totals(v, &t);
			fprintf(o->log,
				"hdlamp suite: %s: %d frames, %d cases judged, %d failed%s%s\n",
				v->id, v->n_frames, t.judged, t.failed,
				t.no_samples ? ", bins not reached" : "",
				v->error[0] ? ", the run did not finish" : "");
		}
	}
	code = rc == -ENOMEM || rc == -EIO    ? 1 :
	       rc < 0			      ? 2 :
	       hl_suite_result_passed(&r.res) ? 0 :
						3;
	if (rc == 0) {
		if (hl_suite_plan_write(&r.res, o->out, msg, sizeof(msg)) < 0) {
			say(&r, "%s%s", msg, "");
			code = 1;
		}
		{
			struct hl_suite_totals t;

			hl_suite_result_totals(&r.res, &t);
			fprintf(o->log,
				"hdlamp suite: %s, %s: %d variants, %d cases judged, %d failed, %d "
				"bins not reached, %d runs not finished: %s; results in %s\n",
				s->name, o->preset ? o->preset : o->sil.ecu, r.res.n_variants,
				t.judged, t.failed, t.no_samples, t.errors,
				code == 0 ? "PASSED" : "FAILED", o->out);
		}
	}
	hl_suite_result_free(&r.res);
	for (int l = 0; l < 2; l++) {
		free(r.dense[l]);
		hl_lid_free(r.lids[l]);
	}
	hl_regulation_free(r.reg);
	return code;
}
