/* SPDX-License-Identifier: MIT */
/* hdlampd --suite: see daemon/live_suite.h. */
#include "daemon/live_suite.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/make_dirs.h"
#include "daemon/core/suite_live.h"
#include "daemon/live_log.h"
#include "verdict/regulation.h"
#include "verdict/suite_plan.h"

/* NAME (shipped) or a .json path. 0 or -errno (logged). */
static int load(const char *arg, struct hl_suite **ret)
{
	const size_t n = strlen(arg);
	const bool file = strchr(arg, '/') || (n > 5 && !strcmp(arg + n - 5, ".json"));
	char path[4096], buf[1024];
	struct hl_json_error err;
	int rc;

	if (file) {
		snprintf(path, sizeof(path), "%s", arg);
	} else if (hl_suite_default_dir(path, sizeof(path) - 64) < 0) {
		hl_live_log(
			"--suite: cannot find the shipped suites beside the binary; give a file");
		return -ENOENT;
	} else {
		snprintf(path + strlen(path), 64, "/%.48s.json", arg);
	}
	rc = hl_suite_read(path, ret, &err);
	if (rc == -ENOENT && !file)
		hl_live_log("--suite: no suite named '%s' (hdlamp suite list shows them)", arg);
	else if (rc < 0)
		hl_live_log("--suite: %s", hl_json_error_format(&err, buf, sizeof(buf)));
	return rc;
}

static int load_glare_set(const struct hl_config *cfg, const struct hl_suite *s,
			  struct hl_regulation **ret)
{
	struct hl_regulation_error err;
	char dir[4096];
	int rc;

	if (s->procedure != HL_SUITE_R149_ADB)
		return 0;
	if (cfg->regulations[0])
		snprintf(dir, sizeof(dir), "%s", cfg->regulations);
	else if (hl_regulation_default_dir(dir, sizeof(dir)) < 0) {
		hl_live_log("--suite: cannot find the shipped regulation sets");
		return -ENOENT;
	}
	rc = hl_regulation_load(dir, s->glare_set, ret, &err);
	if (rc < 0)
		hl_live_log("--suite: %s", err.msg);
	return rc;
}

/* One variant: a run of the daemon on its scenario. The run's code; *ret_stop after a signal. */
static int run_variant(const struct hl_config *base, const struct hl_live_args *args,
		       struct hl_suite_live *sl, struct hl_suite_result *r, int i, const char *out,
		       bool *ret_stop)
{
	struct hl_suite_variant *v = &r->v[i];
	const struct hl_suite_scenario *d = &r->suite->scenario[v->scenario_index];
	struct hl_config *cfg = malloc(sizeof(*cfg));
	struct hl_live_args a = *args;
	const char *end = "setup_error";
	char path[4096], msg[1024], trace[4096];
	int rc, code;

	if (!cfg)
		return 1;
	*cfg = *base;
	rc = hl_suite_plan_scenario(r->suite, v, out, path, sizeof(path), msg, sizeof(msg));
	if (rc == 0 && (strlen(path) >= sizeof(cfg->scenario) ||
			snprintf(cfg->loop_report, sizeof(cfg->loop_report), "%s/runs/%s.json", out,
				 v->id) >= (int)sizeof(cfg->loop_report))) {
		snprintf(msg, sizeof(msg), "'%.900s': the path is too long", out);
		rc = -ENAMETOOLONG;
	}
	if (rc < 0) {
		hl_live_log("--suite: %s: %s", v->id, msg);
		free(cfg);
		return rc == -EINVAL || rc == -ENAMETOOLONG ? 2 : 1;
	}
	memcpy(cfg->scenario, path, strlen(path) + 1);
	cfg->loop_exit_at_end = true;
	rc = hl_suite_live_begin(sl, d, i);
	if (rc < 0) {
		free(cfg);
		return 1;
	}
	hl_live_log("suite %s: variant %d of %d: %s", r->suite->name, i + 1, r->n_variants, v->id);
	a.suite = sl;
	a.ret_end = &end;
	if (cfg->ecu_model[0]) { /* the virtual bus is ours to trace; a CAN interface is not */
		snprintf(v->trace_file, sizeof(v->trace_file), "traces/%s.log", v->id);
		snprintf(trace, sizeof(trace), "%.3900s/%s", out, v->trace_file);
		a.trace = trace;
	}
	code = hl_live_run(cfg, &a);
	rc = hl_suite_live_end(sl);
	v->exit_code = code == 3 ? 0 : code; /* 3: the loop's own verdict, not the suite's */
	if (strcmp(end, "scenario_end") != 0) {
		snprintf(v->error, sizeof(v->error), "the run ended before the scenario's end: %s",
			 end);
		*ret_stop = !strcmp(end, "signal");
	}
	if (rc < 0 && !v->error[0])
		snprintf(v->error, sizeof(v->error), "out of memory for the frames' readings");
	if (hl_suite_plan_plot(r, v, out) < 0)
		hl_live_log("--suite: '%s/%s': cannot write the plot", out, v->plot_file);
	free(cfg);
	return code == 2 ? 2 : 0;
}

int hl_live_suite_run(const struct hl_config *cfg, const struct hl_live_args *args,
		      const struct hl_live_suite_options *so)
{
	struct hl_suite *s = NULL;
	struct hl_regulation *reg = NULL;
	struct hl_suite_live *sl = NULL;
	struct hl_suite_result r = { 0 };
	struct hl_suite_totals t;
	char out[4096], msg[1024], runs[4200];
	bool stop = false;
	int rc, code = 0;

	rc = load(so->suite, &s);
	if (rc == 0)
		rc = load_glare_set(cfg, s, &reg);
	if (rc < 0)
		goto out;
	snprintf(out, sizeof(out), "%s", so->out ? so->out : "");
	if (!so->out)
		snprintf(out, sizeof(out), "suite-%s", s->name);
	rc = hl_suite_plan(s, so->only, 2, &r, msg, sizeof(msg));
	if (rc < 0) {
		/* msg says "--only 'ID': ..."; the daemon's option is --suite-only */
		hl_live_log("--suite-%s", msg + 2);
		goto out;
	}
	snprintf(r.ecu, sizeof(r.ecu), "%s%.240s", cfg->ecu_model[0] ? "" : "can:",
		 cfg->ecu_model[0] ? cfg->ecu_model : cfg->interface);
	snprintf(r.fault, sizeof(r.fault), "%s", cfg->ecu_faults);
	snprintf(runs, sizeof(runs), "%s/runs", out);
	rc = hl_suite_plan_dirs(out, cfg->ecu_model[0] != '\0', msg, sizeof(msg));
	if (rc == 0) {
		rc = hl_make_dirs(runs);
		if (rc < 0)
			snprintf(msg, sizeof(msg), "'%.900s': cannot make the directory: %s", runs,
				 strerror(-rc));
	}
	if (rc < 0) {
		hl_live_log("--suite-out %s", msg);
		goto out;
	}
	rc = hl_suite_live_new(&r, reg, &sl);
	if (rc < 0)
		goto out;
	hl_live_log("suite %s: %d variants in real time, results in %s", s->name, r.n_variants,
		    out);
	for (int i = 0; i < r.n_variants && code == 0; i++) {
		if (stop) {
			snprintf(r.v[i].error, sizeof(r.v[i].error),
				 "not run: the suite was stopped by a signal");
			continue;
		}
		code = run_variant(cfg, args, sl, &r, i, out, &stop);
	}
	if (code == 0) {
		if (hl_suite_plan_write(&r, out, msg, sizeof(msg)) < 0) {
			hl_live_log("--suite: %s", msg);
			code = 1;
		} else {
			code = hl_suite_result_passed(&r) ? 0 : 3;
		}
		hl_suite_result_totals(&r, &t);
		hl_live_log("suite %s: %d variants, %d cases judged, %d failed, %d bins not "
			    "reached, %d runs not finished: %s; results in %s",
			    s->name, r.n_variants, t.judged, t.failed, t.no_samples, t.errors,
			    code == 0 ? "PASSED" : "FAILED", out);
	}
out:
	if (rc < 0)
		code = rc == -ENOMEM ? 1 : 2;
	hl_suite_live_free(sl);
	hl_suite_result_free(&r);
	hl_regulation_free(reg);
	hl_suite_free(s);
	return code;
}
