/* SPDX-License-Identifier: MIT */
/* The moving scene at one instant, ray cast into an ego-frame G-buffer; the road users' lamps. */
#include "render/world_scene.h"

#include <errno.h>
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "render/pixel.h"
#include "render/scenario_geom.h"
#include "render/scene_layout.h"

#define NEAR_M 1e-3 /* corners nearer the camera plane than this: the box may cover any pixel */
#define EMITTER_HIDDEN_M 0.05 /* a body this much before a lamp hides it */
#define GLOW_FLOOR 0.002 /* a disc is drawn out to where it adds this much before tone mapping */
#define GLOW_MAX_PX 48
#define RUN_PX 32 /* pixels of a row that share one choice of the road's candidate parts */

struct hl_world_scene {
	const struct hl_scenario *sc;
	struct hl_road_proj proj; /* the road's parts, for the ground's road coordinates */
	atomic_ulong objects_dropped;
	/*
	 * The lateral offsets where classify() can change its answer (edges, lines, the end of
	 * the ground), and the dashed separators' centres (where the answer depends on s).
	 */
	int n_bounds, n_dashed;
	double *bounds, *dashed;
};

/*
 * A box in the ego frame: its own frame's origin o and heading (c, s of the angle from ego +x),
 * extents lo..hi in that frame; the rows and columns of the image it may cover.
 */
struct object {
	double o[3], c, s;
	double lo[3], hi[3];
	enum hl_surface id;
	double albedo;
	int row0, row1, col0, col1; /* inclusive */
};

struct hit {
	double t;
	double n[3];
	enum hl_surface id;
	double albedo;
	bool ground;
};

/* ws->bounds and ws->dashed from the road, as classify() reads it. 0 or -ENOMEM. */
static int lateral_bounds(struct hl_world_scene *ws)
{
	const struct hl_road *road = &ws->sc->road;
	const double half = hl_road_half_width(road), ew = road->edge_line_width_m;
	const int lanes = road->lanes > 1 ? road->lanes : 1;
	double *b = malloc(sizeof(double) * (8 + 2 * lanes));
	double *dc = malloc(sizeof(double) * lanes);
	int n = 0, nd = 0;

	if (!b || !dc) {
		free(b);
		free(dc);
		return -ENOMEM;
	}
	for (int side = -1; side <= 1; side += 2) {
		b[n++] = side * HL_WORLD_GROUND_HALF_M;
		b[n++] = side * half;
		if (road->edge != HL_MARK_NONE) {
			b[n++] = side * (half - ew - ew / 2);
			b[n++] = side * (half - ew + ew / 2);
		}
	}
	for (int i = 1; road->separator != HL_MARK_NONE && i < road->lanes; i++) {
		const double c = -half + i * road->lane_width_m;

		b[n++] = c - road->separator_line_width_m / 2;
		b[n++] = c + road->separator_line_width_m / 2;
		if (road->separator == HL_MARK_DASHED)
			dc[nd++] = c;
	}
	ws->bounds = b;
	ws->n_bounds = n;
	ws->dashed = dc;
	ws->n_dashed = nd;
	return 0;
}

int hl_world_scene_new(const struct hl_scenario *sc, struct hl_world_scene **ret)
{
	struct hl_world_scene *ws = calloc(1, sizeof(*ws));

	if (!ws)
		return -ENOMEM;
	ws->sc = sc;
	hl_road_proj_init(&sc->road, &ws->proj);
	if (lateral_bounds(ws) < 0) {
		hl_world_scene_free(ws);
		return -ENOMEM;
	}
	atomic_init(&ws->objects_dropped, 0);
	*ret = ws;
	return 0;
}

void hl_world_scene_free(struct hl_world_scene *ws)
{
	if (!ws)
		return;
	free(ws->bounds);
	free(ws->dashed);
	free(ws);
}

unsigned long hl_world_scene_objects_dropped(const struct hl_world_scene *ws)
{
	return atomic_load(&((struct hl_world_scene *)ws)->objects_dropped);
}

void hl_world_to_ego(const struct hl_body_pose *ego, const double w[3], double ret[3])
{
	const double c = cos(ego->heading_rad), s = sin(ego->heading_rad);
	const double dx = w[0] - ego->pos_m[0], dy = w[1] - ego->pos_m[1];

	ret[0] = dx * c + dy * s;
	ret[1] = -dx * s + dy * c;
	ret[2] = w[2] - ego->pos_m[2];
}

void hl_ego_to_world(const struct hl_body_pose *ego, const double local[3], double ret[3])
{
	hl_body_to_world(ego, local, ret);
}

static double dot(const double a[3], const double b[3])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* The camera's projection as hl_camera_project(), with its basis computed once. */
struct view {
	double pos[3], r[3], u[3], f[3];
	double kx, ky; /* pixels per unit of tangent */
	int w, h;
};

static void view_init(const struct hl_camera *cam, struct view *v)
{
	const double t = tan(cam->fov_y_deg * M_PI / 360.0);

	hl_camera_basis(cam, v->r, v->u, v->f);
	memcpy(v->pos, cam->pos_m, sizeof(v->pos));
	v->w = cam->width;
	v->h = cam->height;
	v->kx = cam->width / (2.0 * t * ((double)cam->width / cam->height));
	v->ky = cam->height / (2.0 * t);
}

/* Camera depth of p and its image point; false when not in front of the camera. */
static bool view_project(const struct view *v, const double p[3], double *x, double *y, double *z)
{
	const double d[3] = { p[0] - v->pos[0], p[1] - v->pos[1], p[2] - v->pos[2] };

	*z = dot(d, v->f);
	if (!(*z > NEAR_M))
		return false;
	*x = v->w / 2.0 + dot(d, v->r) / *z * v->kx;
	*y = v->h / 2.0 - dot(d, v->u) / *z * v->ky;
	return true;
}

/* The object's box corner (i: bit 0 x, bit 1 y, bit 2 z) in the ego frame. */
static void corner(const struct object *ob, int i, double ret[3])
{
	const double lx = i & 1 ? ob->hi[0] : ob->lo[0], ly = i & 2 ? ob->hi[1] : ob->lo[1];

	ret[0] = ob->o[0] + lx * ob->c - ly * ob->s;
	ret[1] = ob->o[1] + lx * ob->s + ly * ob->c;
	ret[2] = ob->o[2] + (i & 4 ? ob->hi[2] : ob->lo[2]);
}

/*
 * The pixel rectangle the box can cover: all of the image when it reaches behind the camera,
 * an empty one (row1 < row0) when it lies wholly behind it.
 */
static void bound(const struct view *v, struct object *ob)
{
	double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
	int behind = 0;

	for (int i = 0; i < 8; i++) {
		double p[3], x, y, z;

		corner(ob, i, p);
		if (!view_project(v, p, &x, &y, &z)) {
			behind++;
			continue;
		}
		x0 = fmin(x0, x);
		x1 = fmax(x1, x);
		y0 = fmin(y0, y);
		y1 = fmax(y1, y);
	}
	if (behind == 8) {
		ob->row0 = ob->col0 = 0;
		ob->row1 = ob->col1 = -1;
		return;
	}
	if (behind) {
		ob->row0 = ob->col0 = 0;
		ob->row1 = v->h - 1;
		ob->col1 = v->w - 1;
		return;
	}
	/* Pixel centres inside [x0, x1] belong to columns floor(x0 - 0.5) + 1 .. floor(x1 - 0.5). */
	ob->col0 = (int)fmax(floor(x0 - 0.5), -1.0);
	ob->col1 = (int)fmin(ceil(x1), (double)v->w);
	ob->row0 = (int)fmax(floor(y0 - 0.5), -1.0);
	ob->row1 = (int)fmin(ceil(y1), (double)v->h);
}

/* Whether an object's rectangle meets rows row0 .. row1 of the image. */
static bool in_band(const struct view *v, const struct object *ob, int row0, int row1)
{
	return ob->row0 <= ob->row1 && ob->row1 >= row0 && ob->row0 <= row1 && ob->col1 >= 0 &&
	       ob->col0 < v->w;
}

static double actor_albedo(const struct hl_actor *a)
{
	return a->reflectance;
}

static enum hl_surface actor_surface(const struct hl_actor *a)
{
	switch (a->kind) {
	case HL_ACTOR_PEDESTRIAN:
		return HL_SURF_PEDESTRIAN;
	case HL_ACTOR_CYCLIST:
		return HL_SURF_CYCLIST;
	case HL_ACTOR_CAR:
		break;
	}
	return HL_SURF_VEHICLE;
}

/* A body or post given by its world pose into an object in the ego frame. */
static void place(const struct hl_body_pose *ego, const double pos_w[3], double heading_rad,
		  struct object *ob)
{
	const double rel = heading_rad - ego->heading_rad;

	hl_world_to_ego(ego, pos_w, ob->o);
	ob->c = cos(rel);
	ob->s = sin(rel);
}

static void actor_object(const struct hl_scenario *sc, const struct hl_world_state *st, int i,
			 struct object *ob)
{
	const struct hl_actor *a = &sc->actor[i];

	place(&st->ego, st->actor[i].pos_m, st->actor[i].heading_rad, ob);
	ob->lo[0] = -a->size_m[0];
	ob->hi[0] = 0.0;
	ob->lo[1] = -a->size_m[1] / 2;
	ob->hi[1] = a->size_m[1] / 2;
	ob->lo[2] = 0.0;
	ob->hi[2] = a->size_m[2];
	ob->id = actor_surface(a);
	ob->albedo = actor_albedo(a);
}

/* The ego's s on the road: from its lane path, else its projection. */
static double ego_s(const struct hl_road *road, const struct hl_body_pose *ego)
{
	double s, d;

	if (!isnan(ego->s_m))
		return ego->s_m;
	hl_road_project(road, ego->pos_m[0], ego->pos_m[1], &s, &d);
	return s;
}

/*
 * The bodies and posts whose pixel rectangles meet rows row0 .. row1 into obs (at most max);
 * the rest are counted as dropped. Returns how many.
 */
static int gather(struct hl_world_scene *ws, const struct hl_world_state *st, const struct view *v,
		  int row0, int row1, struct object *obs, int max)
{
	const struct hl_scenario *sc = ws->sc;
	const struct hl_road *road = &sc->road;
	const int n_posts = hl_road_post_count(road);
	unsigned long dropped = 0;
	int n = 0;

	for (int i = 0; i < st->n_actors && i < sc->n_actors; i++) {
		struct object ob;

		actor_object(sc, st, i, &ob);
		bound(v, &ob);
		if (!in_band(v, &ob, row0, row1))
			continue;
		if (n == max) {
			dropped++;
			continue;
		}
		obs[n++] = ob;
	}
	if (n_posts > 0) {
		const double s = ego_s(road, &st->ego), step = road->post_spacing_m;
		const int k0 = (int)fmax(floor((s - HL_WORLD_POST_RANGE_M) / step) - 1, 0.0);
		const int k1 = (int)fmin(ceil((s + HL_WORLD_POST_RANGE_M) / step), n_posts - 1.0);

		for (int k = k0; k <= k1; k++)
			for (int side = -1; side <= 1; side += 2) {
				struct hl_pose2 c;
				double foot[3];
				struct object ob = {
					.lo = { -HL_WORLD_POST_SIDE_M / 2,
						-HL_WORLD_POST_SIDE_M / 2, 0.0 },
					.hi = { HL_WORLD_POST_SIDE_M / 2, HL_WORLD_POST_SIDE_M / 2,
						road->post_height_m },
					.id = HL_SURF_POST,
					.albedo = HL_ALBEDO_POST,
				};

				hl_road_post(road, k, side, foot);
				hl_road_centre(road, (k + 1) * step, &c);
				place(&st->ego, foot, c.heading_rad, &ob);
				bound(v, &ob);
				if (!in_band(v, &ob, row0, row1))
					continue;
				if (n == max) {
					dropped++;
					continue;
				}
				obs[n++] = ob;
			}
	}
	if (dropped)
		atomic_fetch_add(&ws->objects_dropped, dropped);
	return n;
}

/* Ray o + t d against the oriented box: keeps the entry point if nearer than best. */
static void box_hit(const struct object *ob, const double o[3], const double d[3], struct hit *best)
{
	/* Into the box's frame: translate, then rotate by -heading. */
	const double ox = o[0] - ob->o[0], oy = o[1] - ob->o[1];
	const double lo_[3] = { ox * ob->c + oy * ob->s, -ox * ob->s + oy * ob->c,
				o[2] - ob->o[2] };
	const double ld[3] = { d[0] * ob->c + d[1] * ob->s, -d[0] * ob->s + d[1] * ob->c, d[2] };
	double t0 = -INFINITY, t1 = INFINITY, n[3] = { 0, 0, 0 };
	int axis = -1;

	for (int i = 0; i < 3; i++) {
		double a, b;

		if (ld[i] == 0.0) {
			if (lo_[i] < ob->lo[i] || lo_[i] > ob->hi[i])
				return;
			continue;
		}
		a = (ob->lo[i] - lo_[i]) / ld[i];
		b = (ob->hi[i] - lo_[i]) / ld[i];
		if (a > b) {
			const double tmp = a;

			a = b;
			b = tmp;
		}
		if (a > t0) {
			t0 = a;
			axis = i;
		}
		if (b < t1)
			t1 = b;
	}
	if (axis < 0 || t0 > t1 || !(t0 > 1e-6) || t0 >= best->t)
		return;
	n[axis] = ld[axis] > 0.0 ? -1.0 : 1.0;
	best->t = t0;
	/* The normal back into the ego frame. */
	best->n[0] = n[0] * ob->c - n[1] * ob->s;
	best->n[1] = n[0] * ob->s + n[1] * ob->c;
	best->n[2] = n[2];
	best->id = ob->id;
	best->albedo = ob->albedo;
	best->ground = false;
}

static bool near_line(double d, double centre, double width)
{
	return fabs(d - centre) <= width / 2;
}

/*
 * What the ground is at (x, y) (world) with lateral offset d on part k of the road: s is
 * computed only where a dashed line needs it.
 */
static enum hl_surface classify(const struct hl_road *road, const struct hl_road_proj *proj, int k,
				double x, double y, double d, double *albedo)
{
	const double half = hl_road_half_width(road), ad = fabs(d);

	if (ad > half) {
		if (ad > HL_WORLD_GROUND_HALF_M)
			return HL_SURF_NONE;
		*albedo = HL_ALBEDO_SHOULDER;
		return HL_SURF_SHOULDER;
	}
	*albedo = HL_ALBEDO_MARKING;
	/* Edge lines: their outer border one line width inside the edge, as the road scene's. */
	if (road->edge != HL_MARK_NONE &&
	    near_line(ad, half - road->edge_line_width_m, road->edge_line_width_m))
		return HL_SURF_MARKING;
	if (road->separator != HL_MARK_NONE) {
		for (int i = 1; i < road->lanes; i++) {
			const double c = -half + i * road->lane_width_m;
			const double period = road->dash_m + road->gap_m;
			double s;

			if (!near_line(d, c, road->separator_line_width_m))
				continue;
			if (road->separator == HL_MARK_SOLID)
				return HL_SURF_MARKING;
			s = hl_road_proj_s(proj, k, x, y);
			if (s - period * floor(s / period) < road->dash_m)
				return HL_SURF_MARKING;
		}
	}
	*albedo = HL_ALBEDO_ROAD;
	return HL_SURF_ROAD;
}

/* The ego pose's rotation, once per band. */
struct ego_xf {
	double x, y, c, s;
};

/* The road's parts that can hold the ground points of a run of pixels (road coordinates). */
struct parts {
	int n, i[HL_SCN_MAX_SEGMENTS + 2];
};

/*
 * One run of up to RUN_PX pixels of a row, first its rays and ground points all together (a
 * fixed trip count and no branches: the compiler does them two or four at a time), then the
 * road coordinates. The lateral offsets are those of hl_road_part_dist2(), bit for bit: the
 * same expressions in the same order.
 */
struct run {
	double d[3][RUN_PX]; /* the rays */
	double t[RUN_PX], wx[RUN_PX], wy[RUN_PX]; /* where they meet the ground */
	double lat[RUN_PX]; /* lateral offset on the road */
	int part[RUN_PX]; /* the road's part it is measured on; -1: the ray misses the ground */
	bool uniform; /* every pixel of the run is the same ground: id, albedo */
	enum hl_surface id;
	double albedo;
};

static void run_rays(const struct view *v, const struct ego_xf *xf, const double o[3], double sy,
		     double tx, int col0, struct run *r)
{
	for (int c = 0; c < RUN_PX; c++) {
		const double sx = (col0 + c + 0.5 - v->w / 2.0) * tx;
		const double d0 = v->f[0] + sx * v->r[0] + sy * v->u[0];
		const double d1 = v->f[1] + sx * v->r[1] + sy * v->u[1];
		const double d2 = v->f[2] + sx * v->r[2] + sy * v->u[2];
		const double t = -o[2] / d2, px = o[0] + t * d0, py = o[1] + t * d1;

		r->d[0][c] = d0;
		r->d[1][c] = d1;
		r->d[2][c] = d2;
		r->t[c] = t;
		r->wx[c] = xf->x + px * xf->c - py * xf->s;
		r->wy[c] = xf->y + px * xf->s + py * xf->c;
	}
}

/* The lateral offset of (x, y) on part pp: hl_road_part_dist2()'s, the same expressions. */
static inline double part_lat(const struct hl_road_proj_part *pp, double x, double y)
{
	if (!pp->arc) {
		const double dx = x - pp->x0_m, dy = y - pp->y0_m;

		return -dx * pp->s + dy * pp->c;
	}
	const double vx = x - pp->cx_m, vy = y - pp->cy_m;

	return pp->turn * (pp->r0_m - sqrt(vx * vx + vy * vy));
}

/* Lateral offsets of the run's pixels on the one part pp (no other can be nearer). */
static void run_lateral_one(const struct hl_road_proj_part *pp, struct run *r)
{
	if (!pp->arc) {
		for (int c = 0; c < RUN_PX; c++)
			r->lat[c] = part_lat(pp, r->wx[c], r->wy[c]);
	} else {
		for (int c = 0; c < RUN_PX; c++)
			r->lat[c] = part_lat(pp, r->wx[c], r->wy[c]);
	}
}

/*
 * The least and greatest lateral offset on part pp of the run's first n ground points, from
 * its ends alone: the points lie on the segment between the ends' (up to rounding, far below
 * UNIFORM_SLACK_M). On a straight part the offset is affine along it; on an arc it is the
 * distance from the centre, greatest at an end and least at an end or the foot of the
 * perpendicular from the centre.
 */
static void lat_range(const struct hl_road_proj_part *pp, const struct run *r, int n, double *lo,
		      double *hi)
{
	const double ax = r->wx[0], ay = r->wy[0], bx = r->wx[n - 1], by = r->wy[n - 1];

	if (!pp->arc) {
		const double la = part_lat(pp, ax, ay), lb = part_lat(pp, bx, by);

		*lo = la < lb ? la : lb;
		*hi = la < lb ? lb : la;
		return;
	}
	const double vax = ax - pp->cx_m, vay = ay - pp->cy_m, ex = bx - ax, ey = by - ay;
	const double vbx = bx - pp->cx_m, vby = by - pp->cy_m;
	const double da = sqrt(vax * vax + vay * vay), db = sqrt(vbx * vbx + vby * vby);
	const double len2 = ex * ex + ey * ey;
	double u = len2 > 0.0 ? -(vax * ex + vay * ey) / len2 : 0.0, dmin, dmax;

	u = u < 0.0 ? 0.0 : u > 1.0 ? 1.0 : u;
	const double fx = vax + u * ex, fy = vay + u * ey;

	dmin = sqrt(fx * fx + fy * fy);
	dmin = fmin(dmin, fmin(da, db));
	dmax = fmax(da, db);
	*lo = pp->turn > 0 ? pp->r0_m - dmax : dmin - pp->r0_m;
	*hi = pp->turn > 0 ? pp->r0_m - dmin : dmax - pp->r0_m;
}

/* Slack for rounding (m) when a run's offsets are judged to lie between two bounds. */
#define UNIFORM_SLACK_M 1e-6

/*
 * Whether the run's pixels (all on the ground, on part k, lateral offsets within lo .. hi)
 * are one surface: the offsets lie between two neighbouring bounds of classify() and not on a
 * dashed line (where s decides). Then classify()'s answer for the first (offset lat0) is every
 * pixel's.
 */
static bool run_uniform(const struct hl_world_scene *ws, int k, double lo, double hi, double lat0,
			struct run *r)
{
	for (int b = 0; b < ws->n_bounds; b++)
		if (ws->bounds[b] >= lo - UNIFORM_SLACK_M && ws->bounds[b] <= hi + UNIFORM_SLACK_M)
			return false;
	for (int b = 0; b < ws->n_dashed; b++)
		if (fabs(lat0 - ws->dashed[b]) <=
		    ws->sc->road.separator_line_width_m / 2 + UNIFORM_SLACK_M)
			return false;
	r->albedo = 0.0;
	r->id = classify(&ws->sc->road, &ws->proj, k, r->wx[0], r->wy[0], lat0, &r->albedo);
	r->uniform = true;
	return true;
}

/*
 * Rays, ground points and road coordinates of cols col0 .. col0 + n - 1. The ground points of
 * a row's pixels lie on one line (the plane of their rays meets the ground in a line), between
 * those of the run's ends when both ends' rays meet the ground (the rays between them then do
 * too): the road's parts that can be nearest come from those two points.
 */
static void run_ground(const struct hl_world_scene *ws, const struct view *v,
		       const struct ego_xf *xf, const double o[3], double sy, double tx, int col0,
		       int n, int *hint, struct run *r)
{
	struct parts parts;
	bool ends;

	r->uniform = false;
	run_rays(v, xf, o, sy, tx, col0, r);
	ends = o[2] > 0.0 && r->d[2][0] < 0.0 && r->d[2][n - 1] < 0.0;
	if (ends) {
		parts.n = hl_road_proj_candidates(&ws->proj, r->wx[0], r->wy[0], r->wx[n - 1],
						  r->wy[n - 1], parts.i);
		if (parts.n == 1) {
			const int k = parts.i[0];
			const struct hl_road_proj_part *pp = &ws->proj.part[k];
			double lo, hi;

			*hint = k;
			for (int c = 0; c < n; c++)
				r->part[c] = k;
			lat_range(pp, r, n, &lo, &hi);
			if (!run_uniform(ws, k, lo, hi, part_lat(pp, r->wx[0], r->wy[0]), r))
				run_lateral_one(pp, r);
			return;
		}
	} else {
		parts.n = ws->proj.n;
		for (int i = 0; i < parts.n; i++)
			parts.i[i] = i;
	}
	for (int c = 0; c < n; c++) {
		r->part[c] = -1;
		if (!(r->d[2][c] < 0.0) || o[2] <= 0.0)
			continue;
		r->part[c] = hl_road_proj_lateral_among(&ws->proj, parts.i, parts.n, r->wx[c],
							r->wy[c], *hint, &r->lat[c]);
		*hint = r->part[c];
	}
}

/* The ground at pixel c of the run into best (nothing where the ground ends). */
static void ground(const struct hl_world_scene *ws, const struct run *r, int c, struct hit *best)
{
	double albedo = 0.0;
	enum hl_surface id;

	if (r->part[c] < 0 || !(r->d[2][c] < 0.0))
		return;
	if (r->uniform) {
		if (r->id != HL_SURF_NONE)
			*best = (struct hit){ r->t[c], { 0, 0, 1 }, r->id, r->albedo, true };
		return;
	}
	id = classify(&ws->sc->road, &ws->proj, r->part[c], r->wx[c], r->wy[c], r->lat[c], &albedo);
	if (id == HL_SURF_NONE)
		return;
	*best = (struct hit){ r->t[c], { 0, 0, 1 }, id, albedo, true };
}

/* A raster's record of a pixel (struct hl_world_raster): not known yet, or the surface id. */
#define MIRROR_UNKNOWN 0xff
#define MIRROR_GROUND 0x80 /* or'ed into the id: the ground (its position and normal are fixed) */

/*
 * Whether a raster's run of len pixels (from column col, its record at mirror) is what it was
 * and needs nothing written: no body or post reaches into its columns, and it is all sky as
 * before, or all one surface of the ground (r->uniform) as before.
 */
static bool run_settled(const struct run *r, const double o[3], int len, const uint8_t *mirror,
			const struct object *obs, const int *cur, int m, int col)
{
	uint8_t want;
	bool sky = true;

	for (int k = 0; k < m; k++)
		if (obs[cur[k]].col0 < col + len && obs[cur[k]].col1 >= col)
			return false;
	for (int c = 0; c < len; c++)
		sky &= !(r->d[2][c] < 0.0) || o[2] <= 0.0;
	if (sky)
		want = HL_SURF_NONE;
	else if (r->uniform)
		want = r->id == HL_SURF_NONE ? HL_SURF_NONE : MIRROR_GROUND | (uint8_t)r->id;
	else
		return false;
	for (int c = 0; c < len; c++)
		if (mirror[c] != want)
			return false;
	return true;
}

/*
 * Pixels first .. + count - 1 into gb. With changed: whether each pixel's geometry changed
 * (render/gbuffer_diff.h's rule). With mirror (a raster's: gb holds what the raster drew, and
 * the camera is the raster's): a pixel of the ground that was the ground before with the same
 * surface is left as it is, neither read nor written (its position and normal depend on the
 * camera only, its albedo on the surface), and so is one that hit nothing before and now.
 */
static int render_range(struct hl_world_scene *ws, const struct hl_world_state *st,
			const struct hl_camera *cam, struct hl_gbuffer *gb, size_t first,
			size_t count, uint8_t *changed, uint8_t *mirror)
{
	struct object obs[HL_WORLD_MAX_OBJECTS];
	int cur[HL_WORLD_MAX_OBJECTS];
	struct view v;
	int n;

	if (cam->width != gb->width || cam->height != gb->height ||
	    first > (size_t)gb->width * gb->height ||
	    count > (size_t)gb->width * gb->height - first)
		return -EINVAL;
	if (count == 0)
		return 0;
	const struct ego_xf xf = { st->ego.pos_m[0], st->ego.pos_m[1], cos(st->ego.heading_rad),
				   sin(st->ego.heading_rad) };
	const size_t w = gb->width, end = first + count;
	const int row0 = (int)(first / w), row1 = (int)((end - 1) / w);
	struct run run;
	double tx, ty;
	int hint = -1, run0 = 0;

	view_init(cam, &v);
	/* The ray through (x, y) is f + sx r + sy u, as hl_camera_ray(). */
	ty = 1.0 / v.ky;
	tx = 1.0 / v.kx;
	n = gather(ws, st, &v, row0, row1, obs, HL_WORLD_MAX_OBJECTS);
	for (int row = row0; row <= row1; row++) {
		const double sy = (v.h / 2.0 - (row + 0.5)) * ty;
		const size_t row_first = (size_t)row * w;
		const int c0 = row == row0 ? (int)(first - row_first) : 0;
		const int c1 = row == row1 ? (int)(end - row_first) : (int)w;
		int m = 0;

		for (int k = 0; k < n; k++)
			if (obs[k].row0 <= row && row <= obs[k].row1)
				cur[m++] = k;
		for (int col = c0; col < c1; col++) {
			const size_t i = row_first + col;
			float *pos = gb->pos + 4 * i, *nrm = gb->nrm + 4 * i;
			struct hit best = { INFINITY, { 0, 0, 0 }, HL_SURF_NONE, 0.0, false };
			if (col == c0 || col % RUN_PX == 0) {
				const int run_end = (col / RUN_PX + 1) * RUN_PX;
				const int len = (run_end < c1 ? run_end : c1) - col;

				run0 = col;
				run_ground(ws, &v, &xf, cam->pos_m, sy, tx, col, len, &hint, &run);
				if (mirror && run_settled(&run, cam->pos_m, len, mirror + i, obs,
							  cur, m, col)) {
					if (changed)
						memset(changed + i, 0, len);
					col += len - 1;
					continue;
				}
			}
			const double d[3] = { run.d[0][col - run0], run.d[1][col - run0],
					      run.d[2][col - run0] };

			ground(ws, &run, col - run0, &best);
			for (int k = 0; k < m; k++) {
				const struct object *ob = &obs[cur[k]];

				if (ob->col0 <= col && col <= ob->col1)
					box_hit(ob, cam->pos_m, d, &best);
			}
			if (mirror && best.ground && mirror[i] != MIRROR_UNKNOWN &&
			    (mirror[i] & MIRROR_GROUND)) {
				const uint8_t now = MIRROR_GROUND | (uint8_t)best.id;

				if (changed)
					changed[i] = 0;
				if (mirror[i] == now)
					continue;
				pos[3] = (float)best.albedo;
				nrm[3] = (float)best.id;
				gb->albedo[i] = pos[3];
				mirror[i] = now;
				continue;
			}
			if (mirror && best.id == HL_SURF_NONE && mirror[i] == HL_SURF_NONE) {
				if (changed) /* nothing before and now: all zero, as it is */
					changed[i] = 0;
				continue;
			}
			if (mirror)
				mirror[i] = (best.ground ? MIRROR_GROUND : 0) | (uint8_t)best.id;
			const bool had = nrm[3] != (float)HL_SURF_NONE;

			if (best.id == HL_SURF_NONE) {
				memset(pos, 0, sizeof(float) * 4);
				memset(nrm, 0, sizeof(float) * 4);
				gb->albedo[i] = 0.0f;
				if (changed)
					changed[i] = had;
				continue;
			}
			float np[3], nn[3];

			for (int j = 0; j < 3; j++) {
				np[j] = (float)(cam->pos_m[j] + best.t * d[j]);
				nn[j] = (float)best.n[j];
			}
			/* The ground is exactly z = 0 (no rounding of t): its lamp terms stay put. */
			if (best.ground)
				np[2] = 0.0f;
			/* as render/gbuffer_diff.h: bit for bit, a hit now and not before, or moved */
			if (changed)
				changed[i] = !had || memcmp(np, pos, sizeof(np)) != 0 ||
					     memcmp(nn, nrm, sizeof(nn)) != 0;
			memcpy(pos, np, sizeof(np));
			memcpy(nrm, nn, sizeof(nn));
			pos[3] = (float)best.albedo;
			nrm[3] = (float)best.id;
			gb->albedo[i] = pos[3];
		}
	}
	return 0;
}

int hl_world_scene_render_pixels(struct hl_world_scene *ws, const struct hl_world_state *st,
				 const struct hl_camera *cam, struct hl_gbuffer *gb, size_t first,
				 size_t count)
{
	return render_range(ws, st, cam, gb, first, count, NULL, NULL);
}

struct hl_world_raster {
	struct hl_world_scene *ws;
	struct hl_camera cam;
	struct hl_gbuffer *gb;
	uint8_t *mirror; /* per pixel: what the raster last drew there (MIRROR_*) */
};

int hl_world_raster_new(struct hl_world_scene *ws, const struct hl_camera *cam,
			struct hl_gbuffer *gb, struct hl_world_raster **ret)
{
	struct hl_world_raster *r;

	if (cam->width != gb->width || cam->height != gb->height)
		return -EINVAL;
	r = calloc(1, sizeof(*r));
	if (!r)
		return -ENOMEM;
	r->mirror = malloc((size_t)gb->width * gb->height);
	if (!r->mirror) {
		free(r);
		return -ENOMEM;
	}
	memset(r->mirror, MIRROR_UNKNOWN, (size_t)gb->width * gb->height);
	r->ws = ws;
	r->cam = *cam;
	r->gb = gb;
	*ret = r;
	return 0;
}

void hl_world_raster_free(struct hl_world_raster *r)
{
	if (!r)
		return;
	free(r->mirror);
	free(r);
}

struct hl_gbuffer *hl_world_raster_gbuffer(const struct hl_world_raster *r)
{
	return r->gb;
}

int hl_world_raster_pixels(struct hl_world_raster *r, const struct hl_world_state *st, size_t first,
			   size_t count, uint8_t *changed)
{
	return render_range(r->ws, st, &r->cam, r->gb, first, count, changed, r->mirror);
}

int hl_world_scene_render_rows(struct hl_world_scene *ws, const struct hl_world_state *st,
			       const struct hl_camera *cam, struct hl_gbuffer *gb, int row0,
			       int nrows)
{
	if (row0 < 0 || nrows < 0 || row0 + nrows > gb->height)
		return -EINVAL;
	return render_range(ws, st, cam, gb, (size_t)row0 * gb->width, (size_t)nrows * gb->width,
			    NULL, NULL);
}

int hl_world_scene_render(struct hl_world_scene *ws, const struct hl_world_state *st,
			  const struct hl_camera *cam, struct hl_gbuffer *gb)
{
	return hl_world_scene_render_rows(ws, st, cam, gb, 0, gb->height);
}

int hl_world_scene_emitters(const struct hl_world_scene *ws, const struct hl_world_state *st,
			    const struct hl_camera *cam, struct hl_world_emitter *ret, int max)
{
	const struct hl_scenario *sc = ws->sc;
	struct view v;
	int n = 0;

	view_init(cam, &v);
	for (int i = 0; i < st->n_actors && i < sc->n_actors; i++) {
		const struct hl_actor *a = &sc->actor[i];
		const bool lit = i < 32 && (st->lamps_on >> i) & 1u;
		const double rel = st->actor[i].heading_rad - st->ego.heading_rad;
		const double fwd[3] = { cos(rel), sin(rel), 0.0 };

		for (int l = 0; l < a->n_lamps && n < max; l++) {
			const struct hl_emitter *em = &a->lamp[l];
			struct hl_world_emitter *e = &ret[n++];
			double w[3], p[3], d[3], z, facing;
			struct hit best = { INFINITY, { 0, 0, 0 }, HL_SURF_NONE, 0.0, false };

			hl_body_to_world(&st->actor[i], em->pos_m, w);
			hl_world_to_ego(&st->ego, w, p);
			for (int j = 0; j < 3; j++)
				d[j] = p[j] - cam->pos_m[j];
			*e = (struct hl_world_emitter){ .actor = i, .lamp = l };
			memcpy(e->rgb, em->rgb, sizeof(e->rgb));
			e->distance_m = sqrt(dot(d, d));
			e->visible = view_project(&v, p, &e->x_px, &e->y_px, &z) && lit &&
				     e->x_px >= 0.0 && e->x_px < v.w && e->y_px >= 0.0 &&
				     e->y_px < v.h;
			/* From the lamp toward the camera is -d: forward for a headlamp. */
			facing = -dot(d, fwd);
			if (em->kind == HL_EMITTER_TAIL)
				facing = -facing;
			e->visible = e->visible && facing > 0.0;
			/* Any body on the way (t in units of d: 1 at the lamp). */
			for (int k = 0; e->visible && k < st->n_actors && k < sc->n_actors; k++) {
				struct object ob;

				actor_object(sc, st, k, &ob);
				box_hit(&ob, cam->pos_m, d, &best);
			}
			if (best.t < 1.0 - EMITTER_HIDDEN_M / e->distance_m)
				e->visible = false;
			if (e->visible)
				e->illuminance_lx =
					em->intensity_cd / (e->distance_m * e->distance_m);
		}
	}
	return n;
}

/* sRGB8 back to linear, then through the inverse of x / (1 + x). */
static double untone(uint8_t v)
{
	const double c = v / 255.0;
	const double y = c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);

	return y >= 0.999 ? 999.0 : y / (1.0 - y);
}

static uint8_t tone(double x)
{
	return hl_pixel_srgb8((float)(x / (1.0 + x)));
}

/* The glow's radius, a lens's blur, in pixels. */
static double glow_sigma(const struct hl_camera *cam)
{
	return fmax(0.6, cam->width / 1280.0);
}

/*
 * Emitter e's glow: its peak luminance (as the display view's tone map takes it) and the pixel
 * box it can reach (x0, y0, x1, y1, inclusive, clipped to the image). False: nothing drawn.
 */
static bool glow_box(const struct hl_camera *cam, const struct hl_world_emitter *e,
		     double exposure_ev, double *ret_peak, int box[4])
{
	const int w = cam->width, h = cam->height;
	/* Solid angle of a pixel at the image centre. */
	const double pix_rad = 2.0 * tan(cam->fov_y_deg * M_PI / 360.0) / h;
	const double omega = pix_rad * pix_rad, sigma = glow_sigma(cam);
	/* Luminance at the disc's centre: the illuminance spread as a Gaussian. */
	const double peak = e->illuminance_lx / omega / (M_PI * sigma * sigma) * exp2(exposure_ev);
	double reach;

	if (!e->visible || !(peak > GLOW_FLOOR))
		return false;
	reach = fmin(sigma * sqrt(log(peak / GLOW_FLOOR)), GLOW_MAX_PX);
	box[0] = (int)fmax(floor(e->x_px - reach), 0.0);
	box[1] = (int)fmax(floor(e->y_px - reach), 0.0);
	box[2] = (int)fmin(ceil(e->x_px + reach), w - 1.0);
	box[3] = (int)fmin(ceil(e->y_px + reach), h - 1.0);
	*ret_peak = peak;
	return box[0] <= box[2] && box[1] <= box[3];
}

int hl_world_emitters_boxes(const struct hl_camera *cam, const struct hl_world_emitter *e, int n,
			    double exposure_ev, int (*ret)[4], int max)
{
	int m = 0;

	for (int k = 0; k < n && m < max; k++) {
		double peak;

		if (glow_box(cam, &e[k], exposure_ev, &peak, ret[m]))
			m++;
	}
	return m;
}

void hl_world_emitters_draw(const struct hl_camera *cam, const struct hl_world_emitter *e, int n,
			    double exposure_ev, uint8_t *rgb)
{
	const int w = cam->width;
	const double sigma = glow_sigma(cam);

	for (int k = 0; k < n; k++) {
		double peak;
		int box[4], x0, x1, y0, y1;

		if (!glow_box(cam, &e[k], exposure_ev, &peak, box))
			continue;
		x0 = box[0];
		y0 = box[1];
		x1 = box[2];
		y1 = box[3];
		for (int y = y0; y <= y1; y++)
			for (int x = x0; x <= x1; x++) {
				const double dx = x + 0.5 - e[k].x_px, dy = y + 0.5 - e[k].y_px;
				const double a = peak * exp(-(dx * dx + dy * dy) / (sigma * sigma));
				uint8_t *px = rgb + 3 * ((size_t)y * w + x);

				if (a < GLOW_FLOOR)
					continue;
				for (int c = 0; c < 3; c++)
					px[c] = tone(untone(px[c]) + a * e[k].rgb[c]);
			}
	}
}
