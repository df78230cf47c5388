/* SPDX-License-Identifier: MIT */
/*
 * The daemon's live verdicts (daemon/core/verdicts.c) on the HD84 pair: the sets of verdict.sets
 * loaded from a directory, start-up errors naming the set and the directory, the layout of a
 * frame's results, evaluation equal to verdict/verdict.h's on the same distributions, the road
 * KPIs equal to render/road_kpi.h's, and the JSON and metrics text of a frame.
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "daemon/core/verdicts.h"
#include "lamp/combine.h"
#include "lamp/model.h"

static const char *const names[2] = { "left", "right" };

/* Counting allocations on the hot paths (libgpiod's and the render path's included). */
#include "alloc_count.h"

struct fixture {
	struct hl_lid *lamps[2];
	const struct hl_lid_grid *grids[2];
	struct hl_lamp_pose poses[2];
	float *high[2], *glarefree[2]; /* the presets' combined distributions */
	struct hl_config cfg;
};

static void combine_preset(struct fixture *fx, const char *name, float *ret[2])
{
	const struct hl_lid_grid *g = fx->grids[0];
	struct hl_preset *p;
	float i[HL_HD84_SOURCES];

	assert_int_equal(hl_preset_new(HL_HD84_SOURCES, &p), 0);
	assert_int_equal(hl_model_hd84_preset(name, fx->lamps, p), 0);
	for (int s = 0; s < 2; s++) {
		ret[s] = malloc(sizeof(float) * g->width * g->height);
		assert_non_null(ret[s]);
		hl_preset_intensities(p, s, i);
		hl_combine_sparse(fx->lamps[s], i, ret[s]);
	}
	hl_preset_free(p);
}

static int setup(void **state)
{
	struct fixture *fx = calloc(1, sizeof(*fx));
	const char *src = getenv("HL_SOURCE_DIR");

	assert_non_null(fx);
	assert_non_null(src);
	for (int s = 0; s < 2; s++) {
		assert_int_equal(hl_model_hd84(s, &fx->lamps[s]), 0);
		fx->grids[s] = hl_lid_grid(fx->lamps[s]);
		hl_lamp_pose_default(s, &fx->poses[s]);
	}
	combine_preset(fx, "high", fx->high);
	combine_preset(fx, "glarefree", fx->glarefree);
	hl_config_defaults(&fx->cfg);
	snprintf(fx->cfg.regulations, sizeof(fx->cfg.regulations), "%s/tests/data/regulations",
		 src);
	*state = fx;
	return 0;
}

static int teardown(void **state)
{
	struct fixture *fx = *state;

	for (int s = 0; s < 2; s++) {
		hl_lid_free(fx->lamps[s]);
		free(fx->high[s]);
		free(fx->glarefree[s]);
	}
	free(fx);
	return 0;
}

static void use_sets(struct hl_config *cfg, const char *a, const char *b)
{
	cfg->n_verdict_sets = 0;
	snprintf(cfg->verdict_sets[cfg->n_verdict_sets++], HL_CONFIG_SET_ID, "%s", a);
	if (b)
		snprintf(cfg->verdict_sets[cfg->n_verdict_sets++], HL_CONFIG_SET_ID, "%s", b);
}

static void verdicts_missing_set_names_the_set_and_the_directory(void **state)
{
	struct fixture *fx = *state;
	struct hl_verdicts *v = NULL;
	char err[1024], want[2048];

	use_sets(&fx->cfg, "test-adb-glare", "no-such-set");
	assert_int_equal(hl_verdicts_new(&fx->cfg, 2, names, fx->grids, fx->poses, NULL, &v, err,
					 sizeof(err)),
			 -ENOENT);
	assert_null(v);
	snprintf(want, sizeof(want),
		 "verdict.sets: no set 'no-such-set' in '%s' (no file '%s/no-such-set.json'; "
		 "verdict.regulations names the directory)",
		 fx->cfg.regulations, fx->cfg.regulations);
	assert_string_equal(err, want);
}

static void verdicts_pair_set_needs_two_lamps_on_one_grid_and_aim(void **state)
{
	struct fixture *fx = *state;
	struct hl_lamp_pose poses[2] = { fx->poses[0], fx->poses[1] };
	struct hl_verdicts *v = NULL;
	char err[1024];

	use_sets(&fx->cfg, "test-adb-glare", NULL);
	assert_int_equal(hl_verdicts_new(&fx->cfg, 1, names, fx->grids, fx->poses, NULL, &v, err,
					 sizeof(err)),
			 -EINVAL);
	assert_string_equal(err, "verdict.sets: set 'test-adb-glare' applies to half the sum of "
				 "the pair; can.lamps has one lamp");
	poses[1].pitch_deg += 0.5;
	assert_int_equal(hl_verdicts_new(&fx->cfg, 2, names, fx->grids, poses, NULL, &v, err,
					 sizeof(err)),
			 -EINVAL);
	assert_string_equal(err,
			    "verdict.sets: set 'test-adb-glare' applies to half the sum of "
			    "the pair; the lamps 'left' and 'right' need the same LID grid and "
			    "the same aim");
	/* an each_lamp set is fine on one lamp, or on lamps aimed apart */
	use_sets(&fx->cfg, "test-each-lamp", NULL);
	assert_int_equal(hl_verdicts_new(&fx->cfg, 1, names, fx->grids, fx->poses, NULL, &v, err,
					 sizeof(err)),
			 0);
	assert_int_equal(hl_verdicts_n_parts(v, 0), 1);
	hl_verdicts_free(v);
	assert_int_equal(hl_verdicts_new(&fx->cfg, 2, names, fx->grids, poses, NULL, &v, err,
					 sizeof(err)),
			 0);
	assert_int_equal(hl_verdicts_n_parts(v, 0), 2);
	hl_verdicts_free(v);
}

/* What verdict/verdict.h gives on its own, for comparison. */
static bool direct(const struct hl_verdicts *v, int set, const struct fixture *fx,
		   const struct hl_lamp_pose *pose, const float *a, const float *b,
		   struct hl_req_result *ret)
{
	const struct hl_verdict_options opts = { HL_TRAFFIC_RIGHT, -pose->yaw_deg,
						 pose->pitch_deg };
	struct hl_verdict *plan;
	bool pass;

	memset(ret, 0, sizeof(*ret) * hl_verdicts_set(v, set)->n_requirements); /* padding too */
	assert_int_equal(hl_verdict_new(hl_verdicts_set(v, set), fx->grids[0], &opts, &plan), 0);
	pass = hl_verdict_eval(plan, a, b, ret);
	hl_verdict_free(plan);
	return pass;
}

static void verdicts_layout_and_results_are_the_evaluators(void **state)
{
	struct fixture *fx = *state;
	struct hl_verdicts *v;
	struct hl_req_result *res, want[8];
	char err[1024];
	uint32_t failed;
	int n;

	use_sets(&fx->cfg, "test-adb-glare", "test-each-lamp");
	assert_int_equal(hl_verdicts_new(&fx->cfg, 2, names, fx->grids, fx->poses, NULL, &v, err,
					 sizeof(err)),
			 0);
	assert_int_equal(hl_verdicts_n_sets(v), 2);
	assert_string_equal(hl_verdicts_set(v, 0)->id, "test-adb-glare");
	assert_string_equal(hl_verdicts_set(v, 1)->id, "test-each-lamp");
	/* set 0: the pair's 2 requirements; set 1: 2 on each lamp */
	n = hl_verdicts_n_results(v);
	assert_int_equal(n, 6);
	assert_int_equal(hl_verdicts_n_parts(v, 0), 1);
	assert_int_equal(hl_verdicts_part(v, 0, 0)->lamp, HL_VERDICTS_PAIR);
	assert_int_equal(hl_verdicts_part(v, 0, 0)->first, 0);
	assert_string_equal(hl_verdicts_part_name(v, 0, 0), "pair");
	assert_int_equal(hl_verdicts_n_parts(v, 1), 2);
	assert_int_equal(hl_verdicts_part(v, 1, 0)->lamp, 0);
	assert_int_equal(hl_verdicts_part(v, 1, 0)->first, 2);
	assert_int_equal(hl_verdicts_part(v, 1, 1)->lamp, 1);
	assert_int_equal(hl_verdicts_part(v, 1, 1)->first, 4);
	assert_string_equal(hl_verdicts_part_name(v, 1, 1), "right");
	res = calloc(n, sizeof(*res));
	assert_non_null(res);

	/* the high beam glares into the oncoming window; the glare-free beam does not */
	failed = hl_verdicts_eval(v, 0x3, (const float *const *)fx->high, res);
	assert_int_equal(failed, 0x1);
	assert_false(res[0].pass);
	assert_true(res[0].margin < 0.0);
	assert_false(direct(v, 0, fx, &fx->poses[0], fx->high[0], fx->high[1], want));
	assert_memory_equal(res, want, 2 * sizeof(*res));
	for (int l = 0; l < 2; l++) {
		assert_true(direct(v, 1, fx, &fx->poses[l], fx->high[l], NULL, want));
		assert_memory_equal(res + 2 + 2 * l, want, 2 * sizeof(*res));
	}
	failed = hl_verdicts_eval(v, 0x3, (const float *const *)fx->glarefree, res);
	assert_int_equal(failed, 0x0);
	assert_true(res[0].pass);
	assert_true(res[0].margin > 0.0);
	assert_true(direct(v, 0, fx, &fx->poses[0], fx->glarefree[0], fx->glarefree[1], want));
	assert_memory_equal(res, want, 2 * sizeof(*res));

	/* a set that is not active keeps what its entries held */
	memset(res, 0xa5, sizeof(*res) * n);
	failed = hl_verdicts_eval(v, 0x2, (const float *const *)fx->high, res);
	assert_int_equal(failed, 0x0);
	for (size_t b = 0; b < 2 * sizeof(*res); b++)
		assert_int_equal(((const uint8_t *)res)[b], 0xa5);
	assert_true(res[2].pass && res[5].pass);
	free(res);
	hl_verdicts_free(v);
}

static void verdicts_road_kpis_are_the_planners(void **state)
{
	struct fixture *fx = *state;
	struct hl_headlight_lamp lamps[2];
	struct hl_road_kpi_options o;
	struct hl_road_kpi_plan *plan;
	struct hl_road_kpi got, want;
	struct hl_frame_header h = { 0 };
	struct hl_verdicts *v;
	struct hl_config cfg = fx->cfg;
	char err[1024];

	cfg.n_verdict_sets = 0; /* the road KPIs come without sets */
	cfg.road_levels_lx[0] = 2.0;
	cfg.road_width_at_m[1] = 40.0;
	assert_int_equal(hl_verdicts_new(&cfg, 2, names, fx->grids, fx->poses, NULL, &v, err,
					 sizeof(err)),
			 0);
	assert_int_equal(hl_verdicts_n_results(v), 0);
	hl_verdicts_road(v, (const float *const *)fx->high, &got);
	hl_road_kpi_defaults(&o);
	o.levels_lx[0] = 2.0;
	o.width_at_m[1] = 40.0;
	for (int l = 0; l < 2; l++)
		lamps[l] = (struct hl_headlight_lamp){ fx->poses[l], *fx->grids[l] };
	assert_int_equal(hl_road_kpi_new(2, lamps, &o, &plan), 0);
	hl_road_kpi_run(plan, (const float *const *)fx->high, &want);
	hl_road_kpi_free(plan);
	assert_memory_equal(&got, &want, sizeof(got));
	/* horizontal illuminance on the road: 2 lx some 28 m ahead, farther than 3 lx */
	assert_true(got.centre_range_m[0] > 20.0 && got.centre_range_m[0] > got.centre_range_m[1]);
	hl_verdicts_road_to_header(&got, &h);
	for (int k = 0; k < 2; k++) {
		assert_true(h.centre_range_m[k] == (float)got.centre_range_m[k]);
		assert_true(h.edge_range_m[k] == (float)got.edge_range_m[k]);
		assert_true(h.width_m[k] == (float)got.width_m[k]);
	}
	assert_true(hl_verdicts_road_options(v)->levels_lx[0] == 2.0);
	hl_verdicts_free(v);
}

/* The text of f's verdicts (JSON members and metrics) into the buffers. */
static void texts(const struct hl_verdicts *v, const struct hl_frame *f, char *json, size_t jn,
		  char *prom, size_t pn)
{
	const uint64_t frames[2] = { 7, 7 }, failed[2] = { 3, 0 };
	static struct hl_record_cellinfo cells[2][8];
	struct hl_verdicts_so_far sf[2];
	FILE *m = fmemopen(json, jn, "w");
	struct hl_prom p;

	/* the records so far: set 0 failed 3 of 7 frames (requirement 0 of the pair), then passed;
	 * set 1 passed all 7 */
	for (int i = 0; i < 2; i++) {
		struct hl_record *r;

		assert_int_equal(hl_record_new(8, &r), 0);
		for (int k = 0; k < 7; k++) {
			const bool fail = i == 0 && k < 3;
			const struct hl_record_frame fr = { .t_s = 0.02 * k,
							    .cell = fail ? HL_RECORD_FAIL :
									   HL_RECORD_PASS,
							    .req = 0,
							    .part = 0,
							    .margin = fail ? -0.5 : 0.25,
							    .mode = -1 };

			hl_record_add(r, &fr);
		}
		hl_record_summary(r, &sf[i].sum);
		sf[i].n_strip = hl_record_strip(r, cells[i], 8);
		sf[i].strip = cells[i];
		hl_record_free(r);
	}
	assert_non_null(m);
	hl_verdicts_json(v, f, sf, m);
	fputc('\0', m);
	fclose(m);
	hl_prom_init(&p, prom, pn);
	hl_verdicts_metrics(v, f, frames, failed, &p);
	assert_true(hl_prom_end(&p) > 0);
}

static void verdicts_json_and_metrics_of_a_frame(void **state)
{
	struct fixture *fx = *state;
	struct hl_frame f = { 0 };
	struct hl_verdicts *v;
	struct hl_road_kpi road;
	char err[1024], json[16384], prom[16384], line[512];

	use_sets(&fx->cfg, "test-adb-glare", "test-each-lamp");
	assert_int_equal(hl_verdicts_new(&fx->cfg, 2, names, fx->grids, fx->poses, NULL, &v, err,
					 sizeof(err)),
			 0);
	f.n_results = hl_verdicts_n_results(v);
	f.results = calloc(f.n_results, sizeof(*f.results));
	assert_non_null(f.results);
	f.hdr.seq = 42;
	f.hdr.n_sets = 2;
	f.hdr.sets_evaluated = 0x1; /* the pair set only, as a beam mode would */
	f.hdr.sets_failed = hl_verdicts_eval(v, 0x1, (const float *const *)fx->high, f.results);
	hl_verdicts_road(v, (const float *const *)fx->high, &road);
	hl_verdicts_road_to_header(&road, &f.hdr);
	texts(v, &f, json, sizeof(json), prom, sizeof(prom));

	assert_non_null(strstr(
		json, "\"verdicts\":{\"traffic\":\"right\",\"frame\":42,\"mode\":null,"
		      "\"mode_aware\":false,\"modes_configured\":false,\"sets\":"
		      "[{\"id\":\"test-adb-glare\",\"title\":\"Test set: an "
		      "oncoming vehicle's window at 50 m, half the pair's sum\","
		      "\"applies\":\"pair_half\",\"beam\":\"adb\",\"evaluated\":true,"
		      "\"frames\":7,\"failed_frames\":3,\"now\":{\"result\":\"pass\","
		      "\"t_s\":0.1200,\"requirement\":\"Oncoming 50 m\",\"part\":\"pair\"},"
		      "\"so_far\":{\"result\":\"FAIL\",\"frames\":7,\"evaluated\":7,"
		      "\"failed\":3,\"not_applicable\":0,\"longest_failing_s\":0.0600,"
		      "\"longest_failing_from_s\":0.0000,\"worst\":{\"margin\":-0.5,"
		      "\"requirement\":\"Oncoming 50 m\",\"part\":\"pair\",\"t_s\":0.0000},"
		      "\"frames_unstripped\":0},\"strip\":{\"cells\":\"fffpppp\",\"failing\":"
		      "[[0,3,\"Oncoming 50 m\",\"pair\"]],\"modes\":[[0,7,null]]},"
		      "\"results\":[{\"lamp\":"
		      "\"pair\",\"pass\":false,\"requirements\":[{\"id\":\"Oncoming "
		      "50 m\",\"kind\":\"segment\",\"value_cd\":"));
	snprintf(line, sizeof(line), "\"max_cd\":625,\"margin\":%.9g,\"pass\":false,",
		 f.results[0].margin);
	assert_non_null(strstr(json, line));
	/* the other set was not evaluated on this frame: no results; so far it passed */
	assert_non_null(strstr(json, "{\"id\":\"test-each-lamp\",\"title\":\"Test set: two "
				     "requirements on each lamp\",\"applies\":\"each_lamp\","
				     "\"beam\":null,\"evaluated\":false,\"frames\":7,"
				     "\"failed_frames\":0,\"now\":{\"result\":\"pass\","));
	assert_non_null(strstr(json, "\"so_far\":{\"result\":\"pass\",\"frames\":7,"
				     "\"evaluated\":7,\"failed\":0,"));
	assert_non_null(strstr(json, "\"cells\":\"ppppppp\",\"failing\":[],\"modes\":"
				     "[[0,7,null]]},\"results\":[]}]}"));
	snprintf(line, sizeof(line),
		 ",\"road\":{\"levels_lx\":[1,3],\"width_at_m\":[25,50],\"centre_range_m\":"
		 "[%.9g,%.9g],",
		 f.hdr.centre_range_m[0], f.hdr.centre_range_m[1]);
	assert_non_null(strstr(json, line));

	assert_non_null(strstr(prom,
			       "hdlamp_verdict_failed_frames_total{set=\"test-adb-glare\"} 3\n"
			       "hdlamp_verdict_failed_frames_total{set=\"test-each-lamp\"} 0\n"));
	assert_non_null(
		strstr(prom, "hdlamp_verdict_pass{set=\"test-adb-glare\",lamp=\"pair\"} 0\n"));
	assert_null(strstr(prom, "hdlamp_verdict_pass{set=\"test-each-lamp\""));
	snprintf(line, sizeof(line),
		 "hdlamp_requirement_margin{set=\"test-adb-glare\",id=\"Oncoming 50 m\","
		 "lamp=\"pair\"} ");
	assert_non_null(strstr(prom, line));
	assert_true(strtod(strstr(prom, line) + strlen(line), NULL) == f.results[0].margin);
	assert_non_null(strstr(prom, "hdlamp_road_range_meters{line=\"centre\",level_lx=\"1\"} "));
	assert_non_null(strstr(prom, "hdlamp_road_range_meters{line=\"edge\",level_lx=\"3\"} "));
	assert_non_null(strstr(prom, "hdlamp_road_width_meters{at_m=\"50\"} "));

	/* both sets: ids with quotes escaped in JSON and in label values */
	f.hdr.sets_evaluated = 0x3;
	f.hdr.sets_failed = hl_verdicts_eval(v, 0x3, (const float *const *)fx->high, f.results);
	texts(v, &f, json, sizeof(json), prom, sizeof(prom));
	assert_non_null(strstr(json, "{\"lamp\":\"left\",\"pass\":true,\"requirements\":[{\"id\":"
				     "\"H-V \\\"centre\\\"\",\"kind\":\"point\","));
	assert_non_null(strstr(prom, "hdlamp_requirement_margin{set=\"test-each-lamp\",id=\"H-V "
				     "\\\"centre\\\"\",lamp=\"right\"} "));
	assert_non_null(
		strstr(prom, "hdlamp_verdict_pass{set=\"test-each-lamp\",lamp=\"left\"} 1\n"));

	/* no frame yet: counters only, no gauges; road values null */
	texts(v, NULL, json, sizeof(json), prom, sizeof(prom));
	assert_non_null(strstr(json, "\"frame\":null"));
	assert_non_null(
		strstr(json, "\"centre_range_m\":null,\"edge_range_m\":null,\"width_m\":null}"));
	assert_null(strstr(prom, "hdlamp_verdict_pass"));
	assert_null(strstr(prom, "hdlamp_road_range_meters"));
	assert_non_null(strstr(prom, "hdlamp_verdict_frames_total{set=\"test-adb-glare\"} 7\n"));
	free(f.results);
	hl_verdicts_free(v);
}

/* The beam mode: verdict.modes against tests/data/dbc/hd84_fd_beam_mode.dbc's HL_Mode_L. */
static void verdicts_beam_mode_selects_the_sets(void **state)
{
	struct fixture *fx = *state;
	struct hl_config cfg = fx->cfg;
	struct hl_dbc *db;
	struct hl_dbc_error derr;
	struct hl_verdicts *v;
	struct hl_verdicts_mode_source mode = { 0, NULL };
	char path[600], err[1024];

	snprintf(path, sizeof(path), "%s/tests/data/dbc/hd84_fd_beam_mode.dbc",
		 getenv("HL_SOURCE_DIR"));
	assert_int_equal(hl_dbc_parse_file(path, &db, &derr), 0);
	mode.signal = hl_dbc_find_signal(hl_dbc_find_message(db, "HL_DimB_L"), "HL_Mode_L");
	assert_non_null(mode.signal);
	use_sets(&cfg, "test-adb-glare", "test-each-lamp");

	/* a mode signal but no verdict.modes: the sets by their beams, test-adb-glare ("adb") in
	 * glarefree only, test-each-lamp (no beam) in every mode */
	assert_int_equal(hl_verdicts_new(&cfg, 2, names, fx->grids, fx->poses, &mode, &v, err,
					 sizeof(err)),
			 0);
	assert_int_equal(hl_verdicts_mode_lamp(v), 0);
	assert_true(hl_verdicts_mode_aware(v));
	assert_string_equal(hl_verdicts_set_beam(v, 0), "adb");
	assert_null(hl_verdicts_set_beam(v, 1));
	assert_int_equal(hl_verdicts_active(v, 0), 0x2); /* low */
	assert_int_equal(hl_verdicts_active(v, 1), 0x2); /* high */
	assert_int_equal(hl_verdicts_active(v, 2), 0x3); /* glarefree */
	assert_int_equal(hl_verdicts_active(v, 7), 0x3); /* a value without a name */
	assert_int_equal(hl_verdicts_active(v, -1), 0x3);
	assert_string_equal(hl_verdicts_mode_name(v, 2), "glarefree");
	assert_null(hl_verdicts_mode_name(v, 7));
	hl_verdicts_free(v);

	snprintf(cfg.verdict_modes, sizeof(cfg.verdict_modes),
		 "high:test-each-lamp,glarefree:test-adb-glare+test-each-lamp");
	assert_int_equal(hl_verdicts_new(&cfg, 2, names, fx->grids, fx->poses, &mode, &v, err,
					 sizeof(err)),
			 0);
	assert_int_equal(hl_verdicts_active(v, 0), 0x0); /* low: not named, nothing */
	assert_int_equal(hl_verdicts_active(v, 1), 0x2);
	assert_int_equal(hl_verdicts_active(v, 2), 0x3);
	assert_int_equal(hl_verdicts_active(v, 9), 0x0); /* a value without a name */
	assert_int_equal(hl_verdicts_active(v, -1), 0x3); /* no cycle yet: every set */
	hl_verdicts_free(v);

	/* errors: a mode the signal does not name, a set not configured, no signal */
	snprintf(cfg.verdict_modes, sizeof(cfg.verdict_modes), "hi:test-each-lamp");
	assert_int_equal(hl_verdicts_new(&cfg, 2, names, fx->grids, fx->poses, &mode, &v, err,
					 sizeof(err)),
			 -EINVAL);
	assert_string_equal(err, "verdict.modes: 'hi' is not a mode of signal HL_Mode_L (its "
				 "VAL_ names: low, high, glarefree)");
	snprintf(cfg.verdict_modes, sizeof(cfg.verdict_modes), "high:test-each-lamp+nope");
	assert_int_equal(hl_verdicts_new(&cfg, 2, names, fx->grids, fx->poses, &mode, &v, err,
					 sizeof(err)),
			 -EINVAL);
	assert_string_equal(err, "verdict.modes: mode 'high': 'nope' is not one of verdict.sets");
	snprintf(cfg.verdict_modes, sizeof(cfg.verdict_modes), "high:test-each-lamp");
	assert_int_equal(hl_verdicts_new(&cfg, 2, names, fx->grids, fx->poses, NULL, &v, err,
					 sizeof(err)),
			 -EINVAL);
	assert_string_equal(err, "verdict.modes: the DBC has no signal with the attribute "
				 "HdlBeamMode in the lamps' messages");
	hl_dbc_free(db);
}

/* A mode signal of hd84.dbc (its own database, the VAL_ names the daemon maps to beams). */
static const struct hl_dbc_signal *shipped_mode_signal(const char *file, struct hl_dbc **ret_db)
{
	char path[600];
	struct hl_dbc_error derr;
	const struct hl_dbc_signal *sg;

	snprintf(path, sizeof(path), "%s/dbc/%s", getenv("HL_SOURCE_DIR"), file);
	assert_int_equal(hl_dbc_parse_file(path, ret_db, &derr), 0);
	sg = hl_dbc_find_signal(hl_dbc_find_message(*ret_db, "HL_Dim_L"), "HL_Mode_L");
	assert_non_null(sg);
	return sg;
}

/* The shipped sets with the shipped hd84.dbc (0 unset, 1 low, 2 high, 3 glarefree). */
static void use_shipped_sets(struct hl_config *cfg)
{
	snprintf(cfg->regulations, sizeof(cfg->regulations), "%s/regulations",
		 getenv("HL_SOURCE_DIR"));
	cfg->n_verdict_sets = 0;
	snprintf(cfg->verdict_sets[cfg->n_verdict_sets++], HL_CONFIG_SET_ID, "%s",
		 "unece-r149-01-passing-c");
	snprintf(cfg->verdict_sets[cfg->n_verdict_sets++], HL_CONFIG_SET_ID, "%s",
		 "unece-r149-01-driving-b");
	snprintf(cfg->verdict_sets[cfg->n_verdict_sets++], HL_CONFIG_SET_ID, "%s",
		 "unece-r149-01-adb-glare");
	snprintf(cfg->verdict_sets[cfg->n_verdict_sets++], HL_CONFIG_SET_ID, "%s",
		 "fmvss108-upper-ub1");
}

/* Without verdict.modes each set is active in the modes of its beam; unset and unknown: all. */
static void verdicts_default_modes_follow_the_sets_beams(void **state)
{
	struct fixture *fx = *state;
	struct hl_config cfg = fx->cfg;
	struct hl_dbc *db;
	struct hl_verdicts *v;
	struct hl_verdicts_mode_source mode = { 0, NULL };
	char err[1024];

	mode.signal = shipped_mode_signal("hd84.dbc", &db);
	use_shipped_sets(&cfg);
	assert_int_equal(hl_verdicts_new(&cfg, 2, names, fx->grids, fx->poses, &mode, &v, err,
					 sizeof(err)),
			 0);
	assert_true(hl_verdicts_mode_aware(v));
	assert_string_equal(hl_verdicts_set_beam(v, 0), "passing");
	assert_string_equal(hl_verdicts_set_beam(v, 1), "driving");
	assert_string_equal(hl_verdicts_set_beam(v, 2), "adb");
	assert_string_equal(hl_verdicts_set_beam(v, 3), "driving");
	assert_string_equal(hl_verdicts_mode_name(v, 0), "unset");
	assert_int_equal(hl_verdicts_active(v, 0), 0xf); /* unset: not said, every set */
	assert_int_equal(hl_verdicts_active(v, 1), 0x1); /* low: the passing set */
	assert_int_equal(hl_verdicts_active(v, 2), 0xa); /* high: both driving sets */
	assert_int_equal(hl_verdicts_active(v, 3), 0x4); /* glarefree: the ADB set */
	assert_int_equal(hl_verdicts_active(v, 5), 0xf); /* a value without a name */
	assert_int_equal(hl_verdicts_active(v, -1), 0xf); /* no cycle yet */
	hl_verdicts_free(v);

	/* verdict.modes given wins entirely: what it does not name has no set */
	snprintf(cfg.verdict_modes, sizeof(cfg.verdict_modes),
		 "high:unece-r149-01-passing-c+unece-r149-01-adb-glare");
	assert_int_equal(hl_verdicts_new(&cfg, 2, names, fx->grids, fx->poses, &mode, &v, err,
					 sizeof(err)),
			 0);
	assert_true(hl_verdicts_mode_aware(v));
	assert_int_equal(hl_verdicts_active(v, 0), 0x0);
	assert_int_equal(hl_verdicts_active(v, 1), 0x0);
	assert_int_equal(hl_verdicts_active(v, 2), 0x5);
	assert_int_equal(hl_verdicts_active(v, 3), 0x0);
	assert_int_equal(hl_verdicts_active(v, 5), 0x0);
	assert_int_equal(hl_verdicts_active(v, -1), 0xf);
	hl_verdicts_free(v);

	/* no mode signal: every set on every frame */
	cfg.verdict_modes[0] = '\0';
	assert_int_equal(hl_verdicts_new(&cfg, 2, names, fx->grids, fx->poses, NULL, &v, err,
					 sizeof(err)),
			 0);
	assert_false(hl_verdicts_mode_aware(v));
	assert_int_equal(hl_verdicts_mode_lamp(v), -1);
	for (int64_t m = -1; m <= 4; m++)
		assert_int_equal(hl_verdicts_active(v, m), 0xf);
	hl_verdicts_free(v);
	hl_dbc_free(db);
}

/* The vocabulary: passing/driving/adb as well as low/high/glarefree, in any case. */
static void verdicts_default_modes_match_names_in_any_case(void **state)
{
	static const struct hl_dbc_value_desc values[] = {
		{ 0, "PASSING" },   { 1, "High" }, { 2, "Driving" }, { 4, "ADB" },
		{ 5, "GlareFree" }, { 6, "Low" },  { 7, "fog" },
	};
	struct fixture *fx = *state;
	struct hl_config cfg = fx->cfg;
	struct hl_dbc_signal sg = { .name = "Mode", .length = 4, .n_values = 7, .values = values };
	struct hl_verdicts_mode_source mode = { 1, &sg };
	struct hl_verdicts *v;
	char err[1024];

	use_shipped_sets(&cfg);
	assert_int_equal(hl_verdicts_new(&cfg, 2, names, fx->grids, fx->poses, &mode, &v, err,
					 sizeof(err)),
			 0);
	assert_int_equal(hl_verdicts_mode_lamp(v), 1);
	assert_int_equal(hl_verdicts_active(v, 0), 0x1);
	assert_int_equal(hl_verdicts_active(v, 1), 0xa);
	assert_int_equal(hl_verdicts_active(v, 2), 0xa);
	assert_int_equal(hl_verdicts_active(v, 3), 0xf); /* no name */
	assert_int_equal(hl_verdicts_active(v, 4), 0x4);
	assert_int_equal(hl_verdicts_active(v, 5), 0x4);
	assert_int_equal(hl_verdicts_active(v, 6), 0x1);
	assert_int_equal(hl_verdicts_active(v, 7), 0xf); /* not a beam: every set */
	hl_verdicts_free(v);
}

/* A frame's verdicts and road KPIs allocate nothing (the render thread's part). */
static void verdicts_eval_and_road_allocate_nothing(void **state)
{
	struct fixture *fx = *state;
	struct hl_config cfg = fx->cfg;
	struct hl_verdicts *v;
	struct hl_req_result *res;
	struct hl_road_kpi road;
	char err[1024];
	long counted;

	if (!HL_COUNT_ALLOCS)
		skip();
	use_sets(&cfg, "test-adb-glare", "test-each-lamp");
	assert_int_equal(hl_verdicts_new(&cfg, 2, names, fx->grids, fx->poses, NULL, &v, err,
					 sizeof(err)),
			 0);
	res = calloc(hl_verdicts_n_results(v), sizeof(*res));
	assert_non_null(res);
	allocs = 0;
	for (int k = 0; k < 20; k++) {
		hl_verdicts_eval(v, 0x3, (const float *const *)(k & 1 ? fx->high : fx->glarefree),
				 res);
		hl_verdicts_road(v, (const float *const *)fx->high, &road);
	}
	counted = allocs;
	allocs = -1;
	assert_int_equal(counted, 0);
	/* the counter works: planning allocates */
	allocs = 0;
	hl_verdicts_free(v);
	assert_int_equal(hl_verdicts_new(&cfg, 2, names, fx->grids, fx->poses, NULL, &v, err,
					 sizeof(err)),
			 0);
	counted = allocs;
	allocs = -1;
	assert_true(counted > 0);
	free(res);
	hl_verdicts_free(v);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(verdicts_missing_set_names_the_set_and_the_directory),
		cmocka_unit_test(verdicts_pair_set_needs_two_lamps_on_one_grid_and_aim),
		cmocka_unit_test(verdicts_layout_and_results_are_the_evaluators),
		cmocka_unit_test(verdicts_road_kpis_are_the_planners),
		cmocka_unit_test(verdicts_json_and_metrics_of_a_frame),
		cmocka_unit_test(verdicts_beam_mode_selects_the_sets),
		cmocka_unit_test(verdicts_default_modes_follow_the_sets_beams),
		cmocka_unit_test(verdicts_default_modes_match_names_in_any_case),
		cmocka_unit_test(verdicts_eval_and_road_allocate_nothing),
	};

	return cmocka_run_group_tests(tests, setup, teardown);
}
