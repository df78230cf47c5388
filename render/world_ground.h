/* SPDX-License-Identifier: MIT */
/*
 * The ground of a moving scene (render/world_scene.h): which surface of the road a pixel's ray
 * meets, computed for a run of up to HL_GROUND_RUN_PX pixels of one image row at once
 * (docs/scenarios.md, "How a scenario is rendered").
 *
 * The rays of a run and where they meet the ground z = 0 are computed together (a fixed loop
 * the compiler vectorises). The ground points of one row lie on a line, so the road's parts
 * that can be nearest to any of them follow from the run's two ends
 * (hl_road_proj_candidates()); on a single part the run's lateral offsets lie between the
 * ends' (straight) or between the ends' and the foot of the perpendicular from the arc's
 * centre, and when no bound of the classification lies in that range the run is one surface,
 * classified once. The results equal the per-pixel classification of each point bit for bit
 * (the same expressions; the culling and the one-surface rule are exact).
 *
 * Surfaces (albedos of render/scene_layout.h): |d| <= W/2 road; edge lines with their outer
 * border one line width inside each edge; separators on the lane boundaries, dashed where
 * s mod (dash + gap) < dash; beyond the edges shoulder up to HL_WORLD_GROUND_HALF_M from the
 * centre line; farther nothing.
 *
 * Thread-safety: a struct hl_ground is read-only after hl_ground_init(); runs are the caller's.
 */
#ifndef HL_RENDER_WORLD_GROUND_H
#define HL_RENDER_WORLD_GROUND_H

#include <stdbool.h>

#include "world/scenario.h"
#include "world/road.h"
#include "render/scene.h"

#define HL_GROUND_RUN_PX 32 /* pixels of a row that share one choice of the road's parts */
#define HL_WORLD_GROUND_HALF_M 40.0 /* the ground ends this far from the road's centre line */

struct hl_ground {
	const struct hl_road *road;
	struct hl_road_proj proj; /* the road's parts, for the ground's road coordinates */
	/*
	 * The lateral offsets where the classification can change (edges, lines, the end of the
	 * ground), and the dashed separators' centres (where it depends on s).
	 */
	int n_bounds, n_dashed;
	double *bounds, *dashed;
};

/* For road (which must outlive g). 0 or -ENOMEM. */
int hl_ground_init(const struct hl_road *road, struct hl_ground *g);
void hl_ground_free(struct hl_ground *g);

/* The camera's rays: d = f + sx r + sy u, sx = (col + 0.5 - half_w) tx; its position o. */
struct hl_ground_view {
	double o[3], f[3], r[3], u[3];
	double half_w, tx;
};

/* The ego vehicle's pose in the world: position and heading's cos, sin. */
struct hl_ground_pose {
	double x, y, c, s;
};

struct hl_ground_run {
	double d[3][HL_GROUND_RUN_PX]; /* the rays (ego frame) */
	double t[HL_GROUND_RUN_PX]; /* where they meet the ground: o + t d */
	double wx[HL_GROUND_RUN_PX], wy[HL_GROUND_RUN_PX]; /* the same in the world */
	double lat[HL_GROUND_RUN_PX]; /* lateral offset on the road */
	int part[HL_GROUND_RUN_PX]; /* the road's part it is on; -1: the ray misses the ground */
	bool uniform; /* every pixel of the run is the same surface: id, albedo */
	enum hl_surface id;
	double albedo;
};

/*
 * Run of pixels col0 .. col0 + n - 1 (1 <= n <= HL_GROUND_RUN_PX) of the row whose rays have
 * vertical coordinate sy. hint: the part the previous point was on (-1 at first), updated.
 */
void hl_ground_run(const struct hl_ground *g, const struct hl_ground_view *v,
		   const struct hl_ground_pose *pose, double sy, int col0, int n, int *hint,
		   struct hl_ground_run *ret);

/*
 * Pixel c of the run: true when its ray meets a surface of the ground (*id, *albedo); false
 * when it misses the ground or the ground has ended there.
 */
bool hl_ground_hit(const struct hl_ground *g, const struct hl_ground_run *r, int c,
		   enum hl_surface *id, double *albedo);

/* Whether none of the run's first n rays meets the ground (sky). */
bool hl_ground_run_sky(const struct hl_ground_view *v, const struct hl_ground_run *r, int n);

#endif
