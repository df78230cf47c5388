/* SPDX-License-Identifier: MIT */
/* Glare at the road users' eyes: see verdict/glare.h. */
#include "verdict/glare.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lamp/angles.h"
#include "world/road.h"
#include "world/world.h"

#define DEG (180.0 / M_PI)

/* A row of the limit table: one requirement of the set. */
struct row {
	enum hl_actor_role role;
	double distance_m;
	double h0_deg, h1_deg; /* the segment's H range, h0 <= h1 */
	double max_cd;
	int req;
};

struct hl_glare {
	const struct hl_scenario *sc;
	const struct hl_lid_grid *grid[2];
	int n_rows;
	struct row row[HL_GLARE_MAX_ROWS];
};

int hl_glare_row_id(const char *id, enum hl_actor_role *ret_role, double *ret_distance_m)
{
	static const struct {
		const char *word;
		enum hl_actor_role role;
	} classes[] = {
		{ "Oncoming ", HL_ROLE_ONCOMING },
		{ "Preceding ", HL_ROLE_PRECEDING },
	};

	for (size_t i = 0; i < sizeof(classes) / sizeof(classes[0]); i++) {
		const size_t n = strlen(classes[i].word);
		char *end;
		double d;

		if (strncmp(id, classes[i].word, n))
			continue;
		d = strtod(id + n, &end);
		if (end == id + n || !isfinite(d) || d <= 0.0 || strncmp(end, " m", 2) ||
		    (end[2] && end[2] != ' '))
			return -EINVAL;
		*ret_role = classes[i].role;
		*ret_distance_m = d;
		return 0;
	}
	return -EINVAL;
}

int hl_glare_new(const struct hl_scenario *sc, const struct hl_regulation *reg,
		 const struct hl_lid_grid *const grids[2], struct hl_glare **ret)
{
	struct hl_glare *g;

	if (reg->applies != HL_REG_PAIR_HALF)
		return -EINVAL;
	g = calloc(1, sizeof(*g));
	if (!g)
		return -ENOMEM;
	g->sc = sc;
	g->grid[0] = grids[0];
	g->grid[1] = grids[1];
	for (int i = 0; i < reg->n_requirements; i++) {
		const struct hl_requirement *q = &reg->req[i];
		enum hl_actor_role role;
		struct row *r;
		double d;

		if (q->kind != HL_REQ_SEGMENT || !q->max.set || q->max.of >= 0 ||
		    hl_glare_row_id(q->id, &role, &d) < 0)
			continue;
		if (g->n_rows == HL_GLARE_MAX_ROWS) {
			free(g);
			return -E2BIG;
		}
		r = &g->row[g->n_rows];
		r->role = role;
		r->distance_m = d;
		r->h0_deg = fmin(q->pts[0][0], q->pts[1][0]);
		r->h1_deg = fmax(q->pts[0][0], q->pts[1][0]);
		r->max_cd = q->max.cd;
		r->req = i;
		g->n_rows++;
	}
	if (!g->n_rows) {
		free(g);
		return -EINVAL;
	}
	*ret = g;
	return 0;
}

void hl_glare_free(struct hl_glare *g)
{
	free(g);
}

void hl_glare_limit(const struct hl_glare *g, enum hl_actor_role role, double distance_m,
		    double axis_h_deg, struct hl_glare_limit *ret)
{
	double lo = INFINITY, below = -INFINITY, d;
	int best = -1;
	bool best_holds = false;

	/* The largest tabulated distance <= distance_m; the smallest when none is. */
	for (int i = 0; i < g->n_rows; i++) {
		if (g->row[i].role != role)
			continue;
		lo = fmin(lo, g->row[i].distance_m);
		if (g->row[i].distance_m <= distance_m)
			below = fmax(below, g->row[i].distance_m);
	}
	*ret = (struct hl_glare_limit){ .max_cd = NAN, .table_distance_m = NAN, .req = -1 };
	if (isinf(lo))
		return;
	d = isinf(below) ? lo : below;
	/* The row whose segment holds the eye's H; the strictest at a tie or when none does. */
	for (int i = 0; i < g->n_rows; i++) {
		const struct row *r = &g->row[i];
		const bool holds = axis_h_deg >= r->h0_deg && axis_h_deg <= r->h1_deg;

		if (r->role != role || r->distance_m != d)
			continue;
		if (best < 0 || (holds && !best_holds) ||
		    (holds == best_holds && r->max_cd < g->row[best].max_cd)) {
			best = i;
			best_holds = holds;
		}
	}
	ret->max_cd = g->row[best].max_cd;
	ret->table_distance_m = d;
	ret->req = g->row[best].req;
}

int hl_glare_eval(const struct hl_glare *g, double t_s, const float *const dense[2],
		  struct hl_glare_result *ret)
{
	struct hl_world_state w;

	hl_world_at(g->sc, t_s, &w);
	return hl_glare_eval_world(g, &w, dense, ret);
}

/* A road user not in the world: nothing measured, nothing to judge. */
static void absent(struct hl_glare_result *r)
{
	for (int k = 0; k < 3; k++)
		r->eye_m[k] = NAN;
	for (int l = 0; l < 2; l++)
		r->h_deg[l] = r->v_deg[l] = r->r_m[l] = r->intensity_cd[l] = NAN;
	r->pair_half_cd = r->illuminance_lx = r->distance_m = r->axis_h_deg = NAN;
	r->limit = (struct hl_glare_limit){ .max_cd = NAN, .table_distance_m = NAN, .req = -1 };
	r->pass = true;
}

int hl_glare_eval_world(const struct hl_glare *g, const struct hl_world_state *w,
			const float *const dense[2], struct hl_glare_result *ret)
{
	const struct hl_scenario *sc = g->sc;
	struct hl_lamp_pose lamp[2];
	double mid[3], fwd[2];
	int n_fail = 0;

	hl_world_ego_lamps(sc, &w->ego, lamp);
	for (int k = 0; k < 3; k++)
		mid[k] = 0.5 * (lamp[0].pos_m[k] + lamp[1].pos_m[k]);
	fwd[0] = cos(w->ego.heading_rad);
	fwd[1] = sin(w->ego.heading_rad);
	for (int i = 0; i < sc->n_actors && i < w->n_actors; i++) {
		struct hl_glare_result *r = &ret[i];
		double dx, dy, along, right;

		memset(r, 0, sizeof(*r));
		r->actor = i;
		r->t_s = w->t_s;
		if (!hl_world_present(w, i)) {
			absent(r);
			continue;
		}
		r->present = true;
		hl_world_actor_eye(sc, i, &w->actor[i], r->eye_m);
		for (int l = 0; l < 2; l++) {
			double p[3], h, v;

			hl_lamp_to_lamp_space(&lamp[l], r->eye_m, p);
			r->r_m[l] = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
			hl_angles_from_dir(g->grid[l]->angles, p, &h, &v);
			r->h_deg[l] = h * DEG;
			r->v_deg[l] = v * DEG;
			r->intensity_cd[l] = hl_lid_grid_lookup(
				g->grid[l], dense[l], (float)r->h_deg[l], (float)r->v_deg[l]);
			r->illuminance_lx += r->intensity_cd[l] / (r->r_m[l] * r->r_m[l]);
		}
		r->pair_half_cd = 0.5 * (r->intensity_cd[0] + r->intensity_cd[1]);
		dx = r->eye_m[0] - mid[0];
		dy = r->eye_m[1] - mid[1];
		r->distance_m = hypot(dx, dy);
		along = dx * fwd[0] + dy * fwd[1];
		right = dx * fwd[1] - dy * fwd[0]; /* the vehicle's -y */
		r->axis_h_deg = atan2(right, along) * DEG;
		hl_glare_limit(g, sc->actor[i].role, r->distance_m, r->axis_h_deg, &r->limit);
		r->pass = isnan(r->limit.max_cd) || r->pair_half_cd <= r->limit.max_cd;
		if (!r->pass)
			n_fail++;
	}
	return n_fail;
}
