/* SPDX-License-Identifier: MIT */
/*
 * Glare at the road users' eyes (docs/scenarios.md, "Glare at road users' eyes"; docs/design.md
 * §8): per road user of a scenario at time t, the direction from each ego lamp to its driver's
 * eye in that lamp's angle system, the intensity toward it (a point lookup of the lamp's
 * distribution, bilinear as hl_lid_grid_lookup()), half the pair's sum, the illuminance at the
 * eye on a plane facing each lamp E = sum_l I_l / r_l^2, its distance from the ego, and the
 * limit of a regulation set that applies to half the pair's sum (default
 * unece-r149-01-adb-glare).
 *
 * The limit: the set's rows are named "<Class> <D> m" or "<Class> <D> m <anything>" with Class
 * "Oncoming" or "Preceding" (the road user's role) and D the distance in metres. A road user at
 * distance d takes the rows of the largest tabulated D <= d; closer than the smallest D, the
 * smallest D's rows; beyond the largest, the largest's. Among the rows at that D, the segment
 * whose H range holds the eye's H seen from the lamps' midpoint (the vehicle's axis, system A,
 * positive right); at a shared end, or when none holds it, the strictest of them. Crossing and
 * roadside users have no row in the table: no limit.
 *
 * Distance: horizontal straight line from the midpoint of the two lamps to the eye (metres), the
 * distance at which R123 Table 7 places the observer.
 *
 * Plan once with hl_glare_new() (which reads the regulation's rows), evaluate per frame with
 * hl_glare_eval(), which allocates nothing. Thread-safety: a plan is read-only after
 * hl_glare_new(); hl_glare_eval() may run on any thread.
 */
#ifndef HL_VERDICT_GLARE_H
#define HL_VERDICT_GLARE_H

#include <stdbool.h>

#include "lamp/lid.h"
#include "verdict/regulation.h"
#include "world/scenario.h"
#include "world/world.h"

#define HL_GLARE_MAX_ROWS 32 /* limit rows read from one set */

/* The limit that applies to a road user. */
struct hl_glare_limit {
	double max_cd; /* on half the pair's sum; NAN: no limit for this class */
	double table_distance_m; /* the tabulated distance used; NAN without a limit */
	int req; /* the requirement's index in the set, -1 without a limit */
};

/* One road user at one time. */
struct hl_glare_result {
	int actor; /* index in the scenario */
	double t_s;
	double eye_m[3]; /* world */
	double h_deg[2], v_deg[2]; /* the eye in each lamp's angle system (left, right) */
	double r_m[2]; /* from each lamp to the eye */
	double intensity_cd[2]; /* toward the eye, each lamp */
	double pair_half_cd; /* (I_left + I_right) / 2 */
	double illuminance_lx; /* I_left / r_left^2 + I_right / r_right^2 */
	double distance_m; /* horizontal, the lamps' midpoint to the eye */
	double axis_h_deg; /* the eye's H from the lamps' midpoint about the vehicle's axis */
	struct hl_glare_limit limit;
	bool pass; /* pair_half_cd <= limit.max_cd; true without a limit */
	bool present; /* the road user is in the world; if not: NAN values, no limit, pass */
};

struct hl_glare;

/* A row's id, "Oncoming 50 m" or "Preceding 100 m beyond": its role and distance. 0, -EINVAL. */
int hl_glare_row_id(const char *id, enum hl_actor_role *ret_role, double *ret_distance_m);

/*
 * Plans the glare of sc's road users under reg for two lamps on grids[0] (left), grids[1]
 * (right); sc, reg and the grids must outlive the plan. 0, -EINVAL (reg does not apply to half
 * the pair's sum, or has no "Oncoming"/"Preceding" rows), -E2BIG (more than
 * HL_GLARE_MAX_ROWS rows), -ENOMEM.
 */
int hl_glare_new(const struct hl_scenario *sc, const struct hl_regulation *reg,
		 const struct hl_lid_grid *const grids[2], struct hl_glare **ret);
void hl_glare_free(struct hl_glare *g);

/*
 * The limit for a road user of this role at distance_m whose eye is at axis_h_deg (see the top).
 * Allocates nothing.
 */
void hl_glare_limit(const struct hl_glare *g, enum hl_actor_role role, double distance_m,
		    double axis_h_deg, struct hl_glare_limit *ret);

/*
 * Every road user at t_s under the lamps' distributions dense[0] (left), dense[1] (right), each
 * on its grid (cd): fills ret[0 .. n_actors - 1]. Returns how many fail. Allocates nothing.
 */
int hl_glare_eval(const struct hl_glare *g, double t_s, const float *const dense[2],
		  struct hl_glare_result *ret);
/*
 * The same for a given world state (world/world.h: from the scenario clock, or poses from a
 * driving simulator): the ego's lamps and the road users' eyes where w puts them; fills
 * ret[0 .. min(n_actors, w->n_actors) - 1]. hl_glare_eval(g, t, ...) is this with
 * hl_world_at(t). Returns how many fail. Allocates nothing.
 */
int hl_glare_eval_world(const struct hl_glare *g, const struct hl_world_state *w,
			const float *const dense[2], struct hl_glare_result *ret);

#endif
