/* SPDX-License-Identifier: MIT */
#include "daemon/core/verdicts.h"
#include "base/json_write.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

struct set {
	struct hl_regulation *reg;
	int n_parts;
	struct hl_verdicts_part part[HL_FRAME_MAX_LAMPS];
	struct hl_verdict *plan[HL_FRAME_MAX_LAMPS]; /* per part */
	bool owns[HL_FRAME_MAX_LAMPS]; /* a part may share the previous part's plan */
};

struct hl_verdicts {
	int n_lamps;
	char lamp_names[HL_FRAME_MAX_LAMPS][64];
	size_t n_samples[HL_FRAME_MAX_LAMPS]; /* each lamp's grid */
	bool traffic_left;
	int n_sets, n_results;
	struct set sets[HL_VERDICTS_MAX_SETS];
	struct hl_road_kpi_options road_opts;
	struct hl_road_kpi_plan *road;
	/* beam modes: the signal's named values and the sets of each (verdict.modes, or by the
	 * sets' beams when it is empty) */
	int mode_lamp; /* -1: no mode signal */
	const struct hl_dbc_signal *mode_signal;
	bool by_mode; /* a mode signal: the sets follow the mode */
	bool explicit_modes; /* verdict.modes given: it says which sets each mode has */
	uint32_t unnamed; /* the sets of a value without a VAL_ name */
	int n_modes;
	struct {
		int64_t raw;
		uint32_t sets;
	} modes[HL_VERDICTS_MAX_MODES];
};

static bool same_aim(const struct hl_lamp_pose *a, const struct hl_lamp_pose *b)
{
	return a->pitch_deg == b->pitch_deg && a->yaw_deg == b->yaw_deg;
}

/* The mounted aim (world/camera.h): the pose as a shift of the beam. */
static void options_of(const struct hl_verdicts *v, const struct hl_lamp_pose *pose,
		       struct hl_verdict_options *ret)
{
	*ret = (struct hl_verdict_options){
		.traffic = v->traffic_left ? HL_TRAFFIC_LEFT : HL_TRAFFIC_RIGHT,
		.aim_h_deg = -pose->yaw_deg,
		.aim_v_deg = pose->pitch_deg,
	};
}

/* Loads set i of cfg and plans its parts. */
static int add_set(struct hl_verdicts *v, const struct hl_config *cfg, int i,
		   const struct hl_lid_grid *const *grids, const struct hl_lamp_pose *poses,
		   char *err, size_t err_size)
{
	struct hl_regulation_error rerr = { 0, 0, "" };
	struct set *s = &v->sets[i];
	const char *id = cfg->verdict_sets[i];
	struct hl_verdict_options opts;
	int rc;

	rc = hl_regulation_load(cfg->regulations, id, &s->reg, &rerr);
	if (rc == -ENOENT) {
		snprintf(err, err_size,
			 "verdict.sets: no set '%s' in '%s' (no file '%s/%s.json'; "
			 "verdict.regulations names the directory)",
			 id, cfg->regulations, cfg->regulations, id);
		return rc;
	}
	if (rc < 0) {
		snprintf(err, err_size, "verdict.sets: set '%s': %s", id,
			 rerr.msg[0] ? rerr.msg : strerror(-rc));
		return rc;
	}
	if (s->reg->applies == HL_REG_PAIR_HALF) {
		if (v->n_lamps != 2) {
			snprintf(err, err_size,
				 "verdict.sets: set '%s' applies to half the sum of the pair; "
				 "can.lamps has one lamp",
				 id);
			return -EINVAL;
		}
		if (!hl_lid_grid_equal(grids[0], grids[1]) || !same_aim(&poses[0], &poses[1])) {
			snprintf(err, err_size,
				 "verdict.sets: set '%s' applies to half the sum of the pair; the "
				 "lamps '%s' and '%s' need the same LID grid and the same aim",
				 id, v->lamp_names[0], v->lamp_names[1]);
			return -EINVAL;
		}
		s->n_parts = 1;
		s->part[0] = (struct hl_verdicts_part){ HL_VERDICTS_PAIR, v->n_results };
		v->n_results += s->reg->n_requirements;
		options_of(v, &poses[0], &opts);
		rc = hl_verdict_new(s->reg, grids[0], &opts, &s->plan[0]);
		s->owns[0] = rc == 0;
	} else {
		s->n_parts = v->n_lamps;
		rc = 0;
		for (int l = 0; l < v->n_lamps && rc == 0; l++) {
			s->part[l] = (struct hl_verdicts_part){ l, v->n_results };
			v->n_results += s->reg->n_requirements;
			if (l > 0 && hl_lid_grid_equal(grids[0], grids[l]) &&
			    same_aim(&poses[0], &poses[l])) {
				s->plan[l] =
					s->plan[0]; /* the same plan: one lamp's worth of memory */
				continue;
			}
			options_of(v, &poses[l], &opts);
			rc = hl_verdict_new(s->reg, grids[l], &opts, &s->plan[l]);
			s->owns[l] = rc == 0;
		}
	}
	if (rc < 0)
		snprintf(err, err_size,
			 "verdict.sets: set '%s': cannot plan it on the lamps' grid: %s", id,
			 strerror(-rc));
	return rc;
}

/* The set's bit, or 0 when verdict.sets does not name it. */
static uint32_t set_bit(const struct hl_verdicts *v, const char *id, size_t len)
{
	for (int i = 0; i < v->n_sets; i++)
		if (strlen(v->sets[i].reg->id) == len && strncmp(v->sets[i].reg->id, id, len) == 0)
			return 1u << i;
	return 0;
}

/*
 * The beam a mode's VAL_ name means (docs/live-verdicts.md, "Beam modes"), any case; NONE for
 * a name outside that vocabulary ("unset").
 */
static enum hl_reg_beam beam_of_mode(const char *name)
{
	static const struct {
		const char *name;
		enum hl_reg_beam beam;
	} words[] = {
		{ "low", HL_REG_BEAM_PASSING },	  { "passing", HL_REG_BEAM_PASSING },
		{ "high", HL_REG_BEAM_DRIVING },  { "driving", HL_REG_BEAM_DRIVING },
		{ "glarefree", HL_REG_BEAM_ADB }, { "adb", HL_REG_BEAM_ADB },
	};

	for (size_t k = 0; name && k < sizeof(words) / sizeof(words[0]); k++)
		if (strcasecmp(name, words[k].name) == 0)
			return words[k].beam;
	return HL_REG_BEAM_NONE;
}

/* Without verdict.modes: each set in the modes of its beam, a set without one in every mode. */
static void default_modes(struct hl_verdicts *v)
{
	const uint32_t all = v->n_sets ? (uint32_t)((1ull << v->n_sets) - 1) : 0;

	v->by_mode = true;
	v->unnamed = all;
	for (int m = 0; m < v->n_modes; m++) {
		const enum hl_reg_beam beam = beam_of_mode(v->mode_signal->values[m].desc);

		v->modes[m].sets = beam == HL_REG_BEAM_NONE ? all : 0;
		for (int i = 0; beam != HL_REG_BEAM_NONE && i < v->n_sets; i++)
			if (v->sets[i].reg->beam == beam ||
			    v->sets[i].reg->beam == HL_REG_BEAM_NONE)
				v->modes[m].sets |= 1u << i;
	}
}

/* verdict.modes against the mode signal's VAL_ names and the sets. */
static int plan_modes(struct hl_verdicts *v, const char *text, char *err, size_t err_size)
{
	const struct hl_dbc_signal *sg = v->mode_signal;
	const char *entry = text;

	if (sg && sg->n_values > HL_VERDICTS_MAX_MODES) {
		snprintf(err, err_size, "signal %s: HdlBeamMode with more than %d named values",
			 sg->name, HL_VERDICTS_MAX_MODES);
		return -EINVAL;
	}
	for (int k = 0; sg && k < sg->n_values; k++)
		v->modes[v->n_modes++].raw = sg->values[k].value;
	if (!*text) {
		if (sg)
			default_modes(v);
		return 0;
	}
	if (!sg) {
		snprintf(
			err, err_size,
			"verdict.modes: the DBC has no signal with the attribute HdlBeamMode in the "
			"lamps' messages");
		return -EINVAL;
	}
	v->by_mode = true;
	v->explicit_modes = true;
	v->unnamed = 0;
	while (*entry) {
		const char *colon = strchr(entry, ':'), *end = strchr(entry, ',');
		size_t name_len;
		int m = 0;

		if (!end)
			end = entry + strlen(entry);
		if (!colon || colon > end) {
			snprintf(err, err_size, "verdict.modes: '%.*s': expected MODE:ID+ID",
				 (int)(end - entry), entry);
			return -EINVAL;
		}
		name_len = (size_t)(colon - entry);
		while (m < sg->n_values && (strlen(sg->values[m].desc) != name_len ||
					    strncmp(sg->values[m].desc, entry, name_len) != 0))
			m++;
		if (m == sg->n_values) {
			char names[256] = "";
			size_t at = 0;

			for (int k = 0; k < sg->n_values && at < sizeof(names); k++)
				at += (size_t)snprintf(names + at, sizeof(names) - at, "%s%s",
						       k ? ", " : "", sg->values[k].desc);
			snprintf(
				err, err_size,
				"verdict.modes: '%.*s' is not a mode of signal %s (its VAL_ names: %s)",
				(int)name_len, entry, sg->name, names);
			return -EINVAL;
		}
		for (const char *id = colon + 1; id < end;) {
			const char *plus = memchr(id, '+', (size_t)(end - id));
			const char *id_end = plus ? plus : end;
			const uint32_t bit = set_bit(v, id, (size_t)(id_end - id));

			if (!bit) {
				snprintf(
					err, err_size,
					"verdict.modes: mode '%.*s': '%.*s' is not one of verdict.sets",
					(int)name_len, entry, (int)(id_end - id), id);
				return -EINVAL;
			}
			v->modes[m].sets |= bit;
			id = plus ? plus + 1 : end;
		}
		entry = *end ? end + 1 : end;
	}
	return 0;
}

int hl_verdicts_new(const struct hl_config *cfg, int n_lamps, const char *const *lamp_names,
		    const struct hl_lid_grid *const *grids, const struct hl_lamp_pose *poses,
		    const struct hl_verdicts_mode_source *mode, struct hl_verdicts **ret, char *err,
		    size_t err_size)
{
	struct hl_headlight_lamp lamps[HL_FRAME_MAX_LAMPS];
	struct hl_verdicts *v;
	int rc = 0;

	if (n_lamps < 1 || n_lamps > HL_FRAME_MAX_LAMPS ||
	    cfg->n_verdict_sets > HL_VERDICTS_MAX_SETS) {
		snprintf(err, err_size, "verdicts: %d lamps, %d sets", n_lamps,
			 cfg->n_verdict_sets);
		return -EINVAL;
	}
	v = calloc(1, sizeof(*v));
	if (!v) {
		snprintf(err, err_size, "out of memory");
		return -ENOMEM;
	}
	v->n_lamps = n_lamps;
	for (int l = 0; l < n_lamps; l++)
		v->n_samples[l] = (size_t)grids[l]->width * grids[l]->height;
	v->traffic_left = cfg->traffic_left;
	v->mode_lamp = mode && mode->signal && mode->lamp >= 0 ? mode->lamp : -1;
	v->mode_signal = v->mode_lamp >= 0 ? mode->signal : NULL;
	for (int l = 0; l < n_lamps; l++)
		snprintf(v->lamp_names[l], sizeof(v->lamp_names[l]), "%s", lamp_names[l]);
	for (int i = 0; i < cfg->n_verdict_sets && rc == 0; i++) {
		rc = add_set(v, cfg, i, grids, poses, err, err_size);
		v->n_sets = i + 1; /* freed with the rest on failure */
	}
	if (rc == 0)
		rc = plan_modes(v, cfg->verdict_modes, err, err_size);
	if (rc < 0)
		goto err;
	_Static_assert(HL_ROAD_KPI_LEVELS == HL_CONFIG_ROAD_LEVELS &&
			       HL_ROAD_KPI_WIDTHS == HL_CONFIG_ROAD_WIDTHS,
		       "road.levels and road.width_at hold what the road KPIs take");
	_Static_assert(HL_ROAD_KPI_LEVELS == 2 && HL_ROAD_KPI_WIDTHS == 2,
		       "the frame header carries two of each");
	hl_road_kpi_defaults(&v->road_opts);
	for (int k = 0; k < HL_ROAD_KPI_LEVELS; k++)
		v->road_opts.levels_lx[k] = cfg->road_levels_lx[k];
	for (int k = 0; k < HL_ROAD_KPI_WIDTHS; k++)
		v->road_opts.width_at_m[k] = cfg->road_width_at_m[k];
	for (int l = 0; l < n_lamps; l++)
		lamps[l] = (struct hl_headlight_lamp){ .pose = poses[l], .grid = *grids[l] };
	rc = hl_road_kpi_new(n_lamps, lamps, &v->road_opts, &v->road);
	if (rc < 0) {
		snprintf(err, err_size,
			 "road: cannot plan the road KPIs (road.levels, road.width_at): %s",
			 strerror(-rc));
		goto err;
	}
	*ret = v;
	return 0;
err:
	hl_verdicts_free(v);
	return rc;
}

void hl_verdicts_free(struct hl_verdicts *v)
{
	if (!v)
		return;
	for (int i = 0; i < v->n_sets; i++) {
		for (int j = 0; j < HL_FRAME_MAX_LAMPS; j++)
			if (v->sets[i].owns[j])
				hl_verdict_free(v->sets[i].plan[j]);
		hl_regulation_free(v->sets[i].reg);
	}
	hl_road_kpi_free(v->road);
	free(v);
}

int hl_verdicts_n_sets(const struct hl_verdicts *v)
{
	return v->n_sets;
}

int hl_verdicts_n_results(const struct hl_verdicts *v)
{
	return v->n_results;
}

const struct hl_regulation *hl_verdicts_set(const struct hl_verdicts *v, int set)
{
	return v->sets[set].reg;
}

int hl_verdicts_n_parts(const struct hl_verdicts *v, int set)
{
	return v->sets[set].n_parts;
}

const struct hl_verdicts_part *hl_verdicts_part(const struct hl_verdicts *v, int set, int part)
{
	return &v->sets[set].part[part];
}

const char *hl_verdicts_part_name(const struct hl_verdicts *v, int set, int part)
{
	const int l = v->sets[set].part[part].lamp;

	return l == HL_VERDICTS_PAIR ? "pair" : v->lamp_names[l];
}

int hl_verdicts_mode_lamp(const struct hl_verdicts *v)
{
	return v->mode_lamp;
}

uint32_t hl_verdicts_active(const struct hl_verdicts *v, int64_t mode)
{
	const uint32_t all = v->n_sets ? (uint32_t)((1ull << v->n_sets) - 1) : 0;

	if (!v->by_mode || mode < 0)
		return all;
	for (int m = 0; m < v->n_modes; m++)
		if (v->modes[m].raw == mode)
			return v->modes[m].sets;
	return v->unnamed;
}

bool hl_verdicts_mode_aware(const struct hl_verdicts *v)
{
	return v->by_mode;
}

const char *hl_verdicts_set_beam(const struct hl_verdicts *v, int set)
{
	return hl_reg_beam_name(v->sets[set].reg->beam);
}

const char *hl_verdicts_mode_name(const struct hl_verdicts *v, int64_t mode)
{
	if (!v->mode_signal || mode < 0)
		return NULL;
	for (int k = 0; k < v->mode_signal->n_values; k++)
		if (v->mode_signal->values[k].value == mode)
			return v->mode_signal->values[k].desc;
	return NULL;
}

const struct hl_road_kpi_options *hl_verdicts_road_options(const struct hl_verdicts *v)
{
	return &v->road_opts;
}

uint32_t hl_verdicts_eval(const struct hl_verdicts *v, uint32_t active, const float *const *dist,
			  struct hl_req_result *results)
{
	return hl_verdicts_eval_peaks(v, active, dist, NULL, results);
}

uint32_t hl_verdicts_eval_peaks(const struct hl_verdicts *v, uint32_t active,
				const float *const *dist, const struct hl_verdict_peak *lamp_peaks,
				struct hl_req_result *results)
{
	/* each distribution's peak once per frame, for every set with an Imax row:
	 * [0], [1] the lamps, [2] half the pair's sum */
	struct hl_verdict_peak peak[3];
	bool have[3] = { false, false, false };
	uint32_t failed = 0;

	for (int l = 0; lamp_peaks && l < v->n_lamps; l++) {
		peak[l] = lamp_peaks[l];
		have[l] = true;
	}

	for (int i = 0; i < v->n_sets; i++) {
		const struct set *s = &v->sets[i];

		if (!(active & (1u << i)))
			continue;
		for (int j = 0; j < s->n_parts; j++) {
			const int l = s->part[j].lamp;
			const int pk = l == HL_VERDICTS_PAIR ? 2 : l;
			const float *a = l == HL_VERDICTS_PAIR ? dist[0] : dist[l];
			const float *b = l == HL_VERDICTS_PAIR ? dist[1] : NULL;
			bool pass;

			if (!have[pk] && hl_verdict_needs_peak(s->plan[j])) {
				/* a pair set exists only on one grid (checked at start) */
				hl_verdict_peak(v->n_samples[l == HL_VERDICTS_PAIR ? 0 : l], a, b,
						&peak[pk]);
				have[pk] = true;
			}
			pass = hl_verdict_eval_peak(s->plan[j], a, b, have[pk] ? &peak[pk] : NULL,
						    results + s->part[j].first);

			if (!pass)
				failed |= 1u << i;
		}
	}
	return failed;
}

void hl_verdicts_road(const struct hl_verdicts *v, const float *const *dist,
		      struct hl_road_kpi *ret)
{
	hl_road_kpi_run(v->road, dist, ret);
}

void hl_verdicts_road_to_header(const struct hl_road_kpi *k, struct hl_frame_header *h)
{
	for (int i = 0; i < 2; i++) {
		h->centre_range_m[i] = (float)k->centre_range_m[i];
		h->edge_range_m[i] = (float)k->edge_range_m[i];
		h->width_m[i] = (float)k->width_m[i];
	}
}

/* ---------------------------------------------------------------- readers */

static bool part_pass(const struct hl_regulation *reg, const struct hl_req_result *r)
{
	for (int k = 0; k < reg->n_requirements; k++)
		if (!r[k].pass)
			return false;
	return true;
}

static void json_part(const struct hl_verdicts *v, int i, int j, const struct hl_frame *f,
		      FILE *out)
{
	const struct set *s = &v->sets[i];
	const struct hl_req_result *r = f->results + s->part[j].first;

	fputs("{\"lamp\":", out);
	hl_json_write_str(out, hl_verdicts_part_name(v, i, j));
	fprintf(out, ",\"pass\":%s,\"requirements\":[", part_pass(s->reg, r) ? "true" : "false");
	for (int k = 0; k < s->reg->n_requirements; k++) {
		fputs(k ? ",{\"id\":" : "{\"id\":", out);
		hl_json_write_str(out, s->reg->req[k].id);
		fprintf(out,
			",\"kind\":\"%s\",\"value_cd\":", hl_req_kind_name(s->reg->req[k].kind));
		hl_json_write_num(out, r[k].value_cd, "%.9g");
		fputs(",\"min_cd\":", out);
		hl_json_write_num(out, r[k].min_cd, "%.9g");
		fputs(",\"max_cd\":", out);
		hl_json_write_num(out, r[k].max_cd, "%.9g");
		fputs(",\"margin\":", out);
		hl_json_write_num(out, r[k].margin, "%.9g");
		fprintf(out, ",\"pass\":%s,\"at_h_deg\":", r[k].pass ? "true" : "false");
		hl_json_write_num(out, r[k].at_h_deg, "%.9g");
		fputs(",\"at_v_deg\":", out);
		hl_json_write_num(out, r[k].at_v_deg, "%.9g");
		fprintf(out, ",\"n_outside\":%d}", r[k].n_outside);
	}
	fputs("]}", out);
}

void hl_verdicts_names(const struct hl_verdicts *v, int set, const char **ret_req_ids,
		       const char **ret_part_names)
{
	const struct hl_regulation *reg = v->sets[set].reg;

	for (int k = 0; k < reg->n_requirements; k++)
		ret_req_ids[k] = reg->req[k].id;
	for (int j = 0; j < v->sets[set].n_parts; j++)
		ret_part_names[j] = hl_verdicts_part_name(v, set, j);
}

static const char *mode_name(const void *ud, int mode)
{
	return hl_verdicts_mode_name(ud, mode);
}

/* A set's record (docs/verdicts.md, "Now and so far"): "now", "so_far" and "strip". */
static void record_json(const struct hl_verdicts *v, int set, const struct hl_verdicts_so_far *sf,
			FILE *out)
{
	const char *req_ids[HL_REG_MAX_REQUIREMENTS], *part_names[HL_FRAME_MAX_LAMPS];

	hl_verdicts_names(v, set, req_ids, part_names);
	hl_record_json_summary(&sf->sum, req_ids, part_names, out);
	if (sf->strip) {
		fputs(",\"strip\":{", out);
		hl_record_json_strip(sf->strip, sf->n_strip, req_ids, part_names, mode_name, v,
				     out);
		fputc('}', out);
	}
}

void hl_verdicts_json(const struct hl_verdicts *v, const struct hl_frame *f,
		      const struct hl_verdicts_so_far *so_far, FILE *out)
{
	const struct hl_road_kpi_options *o = &v->road_opts;

	fprintf(out,
		"\"verdicts\":{\"traffic\":\"%s\",\"frame\":", v->traffic_left ? "left" : "right");
	if (f)
		fprintf(out, "%" PRIu64, f->hdr.seq);
	else
		fputs("null", out);
	fputs(",\"mode\":", out); /* the VAL_ name, the raw value without one, or null */
	if (!f || v->mode_lamp < 0 || f->beam_mode < 0)
		fputs("null", out);
	else if (hl_verdicts_mode_name(v, f->beam_mode))
		hl_json_write_str(out, hl_verdicts_mode_name(v, f->beam_mode));
	else
		fprintf(out, "%" PRId64, f->beam_mode);
	/* how the sets are applied: each in its beam's modes (a mode signal), or every set on
	 * every frame (none); modes_configured: verdict.modes says which sets each mode has */
	fprintf(out, ",\"mode_aware\":%s,\"modes_configured\":%s,\"sets\":[",
		v->by_mode ? "true" : "false", v->explicit_modes ? "true" : "false");
	for (int i = 0; i < v->n_sets; i++) {
		const struct set *s = &v->sets[i];
		const bool evaluated = f && (f->hdr.sets_evaluated & (1u << i));

		fputs(i ? ",{\"id\":" : "{\"id\":", out);
		hl_json_write_str(out, s->reg->id);
		fputs(",\"title\":", out);
		hl_json_write_str(out, s->reg->title);
		fprintf(out, ",\"applies\":\"%s\",\"beam\":",
			s->reg->applies == HL_REG_PAIR_HALF ? "pair_half" : "each_lamp");
		if (hl_reg_beam_name(s->reg->beam))
			fprintf(out, "\"%s\"", hl_reg_beam_name(s->reg->beam));
		else
			fputs("null", out);
		/* "evaluated": the newest frame; its result is "now", apart from "so_far" */
		fprintf(out, ",\"evaluated\":%s", evaluated ? "true" : "false");
		if (so_far) {
			fprintf(out, ",\"frames\":%" PRIu64 ",\"failed_frames\":%" PRIu64 ",",
				so_far[i].sum.evaluated, so_far[i].sum.failed);
			record_json(v, i, &so_far[i], out);
		}
		fputs(",\"results\":[", out);
		for (int j = 0; evaluated && j < s->n_parts; j++) {
			if (j)
				fputc(',', out);
			json_part(v, i, j, f, out);
		}
		fputs("]}", out);
	}
	fprintf(out, "]},\"road\":{\"levels_lx\":[%g,%g],\"width_at_m\":[%g,%g]", o->levels_lx[0],
		o->levels_lx[1], o->width_at_m[0], o->width_at_m[1]);
	if (f) {
		const struct hl_frame_header *h = &f->hdr;

		fprintf(out,
			",\"centre_range_m\":[%.9g,%.9g],\"edge_range_m\":[%.9g,%.9g],"
			"\"width_m\":[%.9g,%.9g]}",
			h->centre_range_m[0], h->centre_range_m[1], h->edge_range_m[0],
			h->edge_range_m[1], h->width_m[0], h->width_m[1]);
	} else {
		fputs(",\"centre_range_m\":null,\"edge_range_m\":null,\"width_m\":null}", out);
	}
}

void hl_verdicts_metrics(const struct hl_verdicts *v, const struct hl_frame *f,
			 const uint64_t *frames, const uint64_t *failed_frames, struct hl_prom *p)
{
	const uint32_t evaluated = f ? f->hdr.sets_evaluated : 0;
	char level[2][32], at[2][32];

	if (v->n_sets > 0) {
		hl_prom_family(p, "hdlamp_verdict_frames_total", HL_PROM_COUNTER,
			       "Frames the regulation set was evaluated on.");
		for (int i = 0; i < v->n_sets; i++)
			hl_prom_counter(p, "hdlamp_verdict_frames_total",
					(const char *const[]){ "set", v->sets[i].reg->id, NULL },
					frames[i]);
		hl_prom_family(p, "hdlamp_verdict_failed_frames_total", HL_PROM_COUNTER,
			       "Frames on which some requirement of the set failed.");
		for (int i = 0; i < v->n_sets; i++)
			hl_prom_counter(p, "hdlamp_verdict_failed_frames_total",
					(const char *const[]){ "set", v->sets[i].reg->id, NULL },
					failed_frames[i]);
	}
	if (evaluated) {
		hl_prom_family(p, "hdlamp_verdict_pass", HL_PROM_GAUGE,
			       "Whether every requirement of the set passed on the newest frame.");
		for (int i = 0; i < v->n_sets; i++) {
			const struct set *s = &v->sets[i];

			if (!(evaluated & (1u << i)))
				continue;
			for (int j = 0; j < s->n_parts; j++)
				hl_prom_gauge(p, "hdlamp_verdict_pass",
					      (const char *const[]){ "set", s->reg->id, "lamp",
								     hl_verdicts_part_name(v, i, j),
								     NULL },
					      part_pass(s->reg, f->results + s->part[j].first));
		}
		hl_prom_family(p, "hdlamp_requirement_margin", HL_PROM_GAUGE,
			       "The requirement's margin on the newest frame: (value - min) / min "
			       "or (max - value) / max, the smaller; below 0 fails.");
		for (int i = 0; i < v->n_sets; i++) {
			const struct set *s = &v->sets[i];

			if (!(evaluated & (1u << i)))
				continue;
			for (int j = 0; j < s->n_parts; j++)
				for (int k = 0; k < s->reg->n_requirements; k++)
					hl_prom_gauge(p, "hdlamp_requirement_margin",
						      (const char *const[]){
							      "set", s->reg->id, "id",
							      s->reg->req[k].id, "lamp",
							      hl_verdicts_part_name(v, i, j),
							      NULL },
						      f->results[s->part[j].first + k].margin);
		}
	}
	if (!f)
		return;
	for (int k = 0; k < 2; k++) {
		snprintf(level[k], sizeof(level[k]), "%g", v->road_opts.levels_lx[k]);
		snprintf(at[k], sizeof(at[k]), "%g", v->road_opts.width_at_m[k]);
	}
	hl_prom_family(p, "hdlamp_road_range_meters", HL_PROM_GAUGE,
		       "The farthest distance along the line where the road's illuminance reaches "
		       "the level (0: never), newest frame.");
	for (int k = 0; k < 2; k++)
		hl_prom_gauge(p, "hdlamp_road_range_meters",
			      (const char *const[]){ "line", "centre", "level_lx", level[k], NULL },
			      f->hdr.centre_range_m[k]);
	for (int k = 0; k < 2; k++)
		hl_prom_gauge(p, "hdlamp_road_range_meters",
			      (const char *const[]){ "line", "edge", "level_lx", level[k], NULL },
			      f->hdr.edge_range_m[k]);
	hl_prom_family(p, "hdlamp_road_width_meters", HL_PROM_GAUGE,
		       "The width of the road area at the first level, across the road at the "
		       "distance, newest frame.");
	for (int k = 0; k < 2; k++)
		hl_prom_gauge(p, "hdlamp_road_width_meters",
			      (const char *const[]){ "at_m", at[k], NULL }, f->hdr.width_m[k]);
}
