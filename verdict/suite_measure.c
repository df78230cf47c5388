/* SPDX-License-Identifier: MIT */
/* Measuring a suite's scenario variant frame by frame: see verdict/suite_measure.h. */
#include "verdict/suite_measure.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "verdict/glare.h"
#include "verdict/photometer.h"
#include "verdict/suite_judge.h"

struct hl_suite_measure {
	const struct hl_suite *s;
	const struct hl_suite_scenario *d;
	const struct hl_regulation *reg;
	struct hl_suite_variant *v;
	struct hl_glare *glare; /* r149: planned at the first frame (it needs the grids) */
	struct hl_glare_result gr[HL_SCN_MAX_ACTORS];
	int series_of[HL_SUITE_MAX_PHOTOMETERS]; /* photometer -> series, -1 none */
	int err;
	bool last_valid[HL_SUITE_MAX_SERIES];
	double last_range_m[HL_SUITE_MAX_SERIES], last_lx[HL_SUITE_MAX_SERIES];
	/* iihs: the last frame's figures */
	bool iihs_valid;
	double vis_m[2], glare_max_lx, glare_at_m, iihs_t_s;
};

static int add_series(struct hl_suite_variant *v, const char *label, enum hl_actor_role role)
{
	struct hl_suite_series *se;

	if (v->n_series == HL_SUITE_MAX_SERIES)
		return -1;
	se = &v->series[v->n_series];
	memset(se, 0, sizeof(*se));
	snprintf(se->label, sizeof(se->label), "%s", label);
	se->role = role;
	return v->n_series++;
}

int hl_suite_measure_new(const struct hl_suite *s, const struct hl_suite_scenario *d,
			 const struct hl_regulation *reg, struct hl_suite_variant *v,
			 struct hl_suite_measure **ret)
{
	struct hl_suite_measure *m;
	int rc = 0;

	if (s->procedure == HL_SUITE_R149_ADB && !reg)
		return -EINVAL;
	m = calloc(1, sizeof(*m));
	if (!m)
		return -ENOMEM;
	m->s = s;
	m->d = d;
	m->reg = reg;
	m->v = v;
	for (int p = 0; p < HL_SUITE_MAX_PHOTOMETERS; p++)
		m->series_of[p] = -1;
	switch (s->procedure) {
	case HL_SUITE_FMVSS108_ADB:
		if (!d->has_role)
			break;
		rc = hl_suite_fmvss_cases(s, d->role, v);
		for (int p = 0; p < s->n_photometers; p++)
			if (s->photometer[p].role == d->role)
				m->series_of[p] = add_series(v, s->photometer[p].id, d->role);
		break;
	case HL_SUITE_R149_ADB:
		if (!d->has_role)
			break;
		rc = hl_suite_r149_cases(reg, d->role, v);
		add_series(v, "E at the driver's eye", d->role);
		break;
	case HL_SUITE_IIHS:
		v->has_birdseye = true;
		add_series(v, "left edge", HL_ROLE_ROADSIDE);
		add_series(v, "right edge", HL_ROLE_ROADSIDE);
		add_series(v, "glare over lane 2", HL_ROLE_ONCOMING);
		break;
	}
	if (rc < 0) {
		free(m);
		return rc;
	}
	*ret = m;
	return 0;
}

/* The newest reading of a series (IIHS: its highest of the frame). */
static void newest(struct hl_suite_measure *m, int series, double x, double lx, bool highest)
{
	if (series < 0 || series >= HL_SUITE_MAX_SERIES)
		return;
	if (!highest || !m->last_valid[series] || lx > m->last_lx[series]) {
		m->last_range_m[series] = x;
		m->last_lx[series] = lx;
	}
	m->last_valid[series] = true;
}

static void keep(struct hl_suite_measure *m, int series, double x, double lx, double t)
{
	if (series >= 0 && hl_suite_series_add(&m->v->series[series], x, lx, t) < 0)
		m->err = -ENOMEM;
}

bool hl_suite_measure_last(const struct hl_suite_measure *m, int series, double *ret_range_m,
			   double *ret_lx)
{
	if (series < 0 || series >= HL_SUITE_MAX_SERIES || !m->last_valid[series])
		return false;
	*ret_range_m = m->last_range_m[series];
	*ret_lx = m->last_lx[series];
	return true;
}

static void fmvss_frame(struct hl_suite_measure *m, const struct hl_scenario *sc,
			const struct hl_world_state *w, const struct hl_lamp_pose lamps[2],
			const struct hl_lid_grid *const grids[2], const float *const dist[2])
{
	const struct hl_suite *s = m->s;

	if (sc->n_actors < 1 || w->n_actors < 1)
		return;
	for (int p = 0; p < s->n_photometers; p++) {
		struct hl_photometer_reading rd;
		double pt[3], n[3];

		if (m->series_of[p] < 0)
			continue;
		hl_photometer_place(&w->actor[0], s->photometer[p].pos_m, s->photometer[p].normal,
				    pt, n);
		hl_photometer_read(lamps, grids, dist, pt, n, &rd);
		newest(m, m->series_of[p], rd.range_m, rd.illuminance_lx, false);
		if (rd.range_m >= m->v->range_m[0] - 1e-9 && rd.range_m <= m->v->range_m[1] + 1e-9)
			keep(m, m->series_of[p], rd.range_m, rd.illuminance_lx, w->t_s);
		hl_suite_fmvss_sample(s, m->v, p, rd.range_m, rd.illuminance_lx, w->t_s);
	}
}

static void r149_frame(struct hl_suite_measure *m, const struct hl_scenario *sc,
		       const struct hl_world_state *w, const struct hl_lid_grid *const grids[2],
		       const float *const dist[2])
{
	if (!m->glare && !m->err) {
		const int rc = hl_glare_new(sc, m->reg, grids, &m->glare);

		if (rc < 0)
			m->err = rc;
	}
	if (!m->glare || sc->n_actors < 1 || w->n_actors < 1)
		return;
	hl_glare_eval_world(m->glare, w, dist, m->gr);
	newest(m, 0, m->gr[0].distance_m, m->gr[0].illuminance_lx, false);
	if (m->gr[0].distance_m >= m->v->range_m[0] - 1e-9 &&
	    m->gr[0].distance_m <= m->v->range_m[1] + 1e-9)
		keep(m, 0, m->gr[0].distance_m, m->gr[0].illuminance_lx, w->t_s);
	hl_suite_r149_sample(m->v, &m->gr[0]);
}

/* E at p on a plane facing the lamps' midpoint. */
static double facing(const struct hl_lamp_pose lamps[2], const struct hl_lid_grid *const grids[2],
		     const float *const dist[2], const double p[3])
{
	struct hl_photometer_reading rd;
	double n[3], len = 0.0;

	for (int k = 0; k < 3; k++) {
		n[k] = 0.5 * (lamps[0].pos_m[k] + lamps[1].pos_m[k]) - p[k];
		len += n[k] * n[k];
	}
	len = sqrt(len);
	for (int k = 0; k < 3; k++)
		n[k] = len > 0.0 ? n[k] / len : 0.0;
	return hl_photometer_read(lamps, grids, dist, p, n, &rd);
}

static void iihs_frame(struct hl_suite_measure *m, const struct hl_scenario *sc,
		       const struct hl_world_state *w, const struct hl_lamp_pose lamps[2],
		       const struct hl_lid_grid *const grids[2], const float *const dist[2])
{
	const struct hl_suite *s = m->s;
	struct hl_suite_variant *v = m->v;
	struct hl_suite_birdseye *b = &v->birdseye;
	const double hw = hl_road_half_width(&sc->road);
	const double s0 = w->ego.s_m;
	const int n = (int)floor(v->range_m[1] / HL_SUITE_IIHS_STEP_M + 1e-9) + 1;

	if (!isfinite(s0))
		return;
	if (!b->left) {
		b->left = calloc((size_t)n, sizeof(*b->left));
		b->right = calloc((size_t)n, sizeof(*b->right));
		if (!b->left || !b->right) {
			m->err = -ENOMEM;
			return;
		}
	}
	/* the last frame is the one reported: the series start over */
	for (int k = 0; k < 3; k++) {
		v->series[k].n = 0;
		m->last_valid[k] = false;
	}
	b->n = n;
	b->ego[0] = w->ego.pos_m[0];
	b->ego[1] = w->ego.pos_m[1];
	b->ego_heading_rad = w->ego.heading_rad;
	for (int side = 0; side < 2; side++) {
		double(*edge)[2] = side ? b->right : b->left;
		double along = 0.0, prev[2] = { 0 };

		m->vis_m[side] = NAN;
		for (int i = 0; i < n; i++) {
			double p[3], lx;

			hl_road_point(&sc->road, s0 + i * HL_SUITE_IIHS_STEP_M, side ? -hw : hw, p);
			p[2] = s->visibility_height_m;
			edge[i][0] = p[0];
			edge[i][1] = p[1];
			if (i)
				along += hypot(p[0] - prev[0], p[1] - prev[1]);
			prev[0] = p[0];
			prev[1] = p[1];
			lx = facing(lamps, grids, dist, p);
			keep(m, side, along, lx, w->t_s);
			newest(m, side, along, lx, true);
			if (lx >= s->visibility_lx) {
				m->vis_m[side] = along;
				b->vis_at[side][0] = p[0];
				b->vis_at[side][1] = p[1];
			}
		}
		b->vis_m[side] = m->vis_m[side];
	}
	m->glare_max_lx = -INFINITY;
	m->glare_at_m = NAN;
	for (int i = (int)ceil(v->range_m[0] / HL_SUITE_IIHS_STEP_M - 1e-9); i < n; i++) {
		const double x = i * HL_SUITE_IIHS_STEP_M;
		double p[3], lx;

		hl_road_point(&sc->road, s0 + x, hl_road_lane_offset(&sc->road, 2), p);
		p[2] = s->glare_height_m;
		lx = facing(lamps, grids, dist, p);
		keep(m, 2, x, lx, w->t_s);
		newest(m, 2, x, lx, true);
		if (lx > m->glare_max_lx) {
			m->glare_max_lx = lx;
			m->glare_at_m = x;
		}
	}
	m->iihs_valid = true;
	m->iihs_t_s = w->t_s;
}

void hl_suite_measure_frame(struct hl_suite_measure *m, const struct hl_scenario *sc,
			    const struct hl_world_state *w,
			    const struct hl_lid_grid *const grids[2], const float *const dist[2])
{
	struct hl_lamp_pose lamps[2];

	m->v->n_frames++;
	hl_world_ego_lamps(sc, &w->ego, lamps);
	switch (m->s->procedure) {
	case HL_SUITE_FMVSS108_ADB:
		fmvss_frame(m, sc, w, lamps, grids, dist);
		break;
	case HL_SUITE_R149_ADB:
		r149_frame(m, sc, w, grids, dist);
		break;
	case HL_SUITE_IIHS:
		iihs_frame(m, sc, w, lamps, grids, dist);
		break;
	}
}

static struct hl_suite_case *reported(struct hl_suite_variant *v, const char *name,
				      const char *unit, double value, double at_m, double t_s,
				      const char *source)
{
	struct hl_suite_case *c = hl_suite_case_add(v);

	if (!c)
		return NULL;
	snprintf(c->name, sizeof(c->name), "%s", name);
	c->unit = unit;
	c->n_samples = 1;
	c->max_raw = value;
	c->at_range_m = at_m;
	c->at_t_s = t_s;
	snprintf(c->source, sizeof(c->source), "%s", source);
	return c;
}

int hl_suite_measure_finish(struct hl_suite_measure *m)
{
	const struct hl_suite *s = m->s;

	if (s->procedure == HL_SUITE_IIHS && m->iihs_valid) {
		char name[128];

		for (int side = 0; side < 2; side++) {
			snprintf(name, sizeof(name), "visibility along the %s edge (%g lx at %g m)",
				 side ? "right" : "left", s->visibility_lx, s->visibility_height_m);
			if (!reported(m->v, name, "m", m->vis_m[side], m->vis_m[side], m->iihs_t_s,
				      s->iihs_source))
				return -ENOMEM;
		}
		snprintf(name, sizeof(name), "highest illuminance %g m over lane 2 (%g-%g m)",
			 s->glare_height_m, m->v->range_m[0], m->v->range_m[1]);
		if (!reported(m->v, name, "lx", m->glare_max_lx, m->glare_at_m, m->iihs_t_s,
			      s->iihs_source))
			return -ENOMEM;
	}
	hl_suite_judge_finish(s, m->v);
	return m->err;
}

void hl_suite_measure_free(struct hl_suite_measure *m)
{
	if (!m)
		return;
	hl_glare_free(m->glare);
	free(m);
}
