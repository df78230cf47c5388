/* SPDX-License-Identifier: MIT */
/* The moving scene at one instant, ray cast into an ego-frame G-buffer; the road users' lamps. */
#include "render/world_scene.h"

#include <errno.h>
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "render/pixel.h"
#include "world/road.h"
#include "render/world_ground.h"
#include "render/scene_layout.h"

#define NEAR_M 1e-3 /* corners nearer the camera plane than this: the box may cover any pixel */
#define EMITTER_HIDDEN_M 0.05 /* a body this much before a lamp hides it */
#define GLOW_FLOOR 0.002 /* a disc is drawn out to where it adds this much before tone mapping */
#define GLOW_MAX_PX 48

struct hl_world_scene {
	const struct hl_scenario *sc;
	struct hl_ground ground; /* the road's surfaces */
	atomic_ulong objects_dropped;
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

int hl_world_scene_new(const struct hl_scenario *sc, struct hl_world_scene **ret)
{
	struct hl_world_scene *ws = calloc(1, sizeof(*ws));

	if (!ws)
		return -ENOMEM;
	ws->sc = sc;
	if (hl_ground_init(&sc->road, &ws->ground) < 0) {
		free(ws);
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
	hl_ground_free(&ws->ground);
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
	case HL_ACTOR_TRUCK:
	case HL_ACTOR_MOTORBIKE:
	case HL_ACTOR_KINDS:
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

		if (!hl_world_present(st, i))
			continue;
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

/* A raster's record of a pixel (struct hl_world_raster): not known yet, or the surface id. */
#define MIRROR_UNKNOWN 0xff
#define MIRROR_GROUND 0x80 /* or'ed into the id: the ground (its position and normal are fixed) */

/*
 * Whether a raster's run of len pixels (from column col, its record at mirror) is what it was
 * and needs nothing written: no body or post reaches into its columns, and it is all sky as
 * before, or all one surface of the ground (r->uniform) as before.
 */
static bool run_settled(const struct hl_ground_view *gv, const struct hl_ground_run *r, int len,
			const uint8_t *mirror, const struct object *obs, const int *cur, int m,
			int col)
{
	uint8_t want;

	for (int k = 0; k < m; k++)
		if (obs[cur[k]].col0 < col + len && obs[cur[k]].col1 >= col)
			return false;
	if (hl_ground_run_sky(gv, r, len))
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
	const struct hl_ground_pose pose = { st->ego.pos_m[0], st->ego.pos_m[1],
					     cos(st->ego.heading_rad), sin(st->ego.heading_rad) };
	const size_t w = gb->width, end = first + count;
	const int row0 = (int)(first / w), row1 = (int)((end - 1) / w);
	struct hl_ground_view gv;
	struct hl_ground_run run;
	double tx, ty;
	int hint = -1, run0 = 0;

	view_init(cam, &v);
	/* The ray through (x, y) is f + sx r + sy u, as hl_camera_ray(). */
	ty = 1.0 / v.ky;
	tx = 1.0 / v.kx;
	memcpy(gv.o, cam->pos_m, sizeof(gv.o));
	memcpy(gv.f, v.f, sizeof(gv.f));
	memcpy(gv.r, v.r, sizeof(gv.r));
	memcpy(gv.u, v.u, sizeof(gv.u));
	gv.half_w = v.w / 2.0;
	gv.tx = tx;
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
			if (col == c0 || col % HL_GROUND_RUN_PX == 0) {
				const int run_end = (col / HL_GROUND_RUN_PX + 1) * HL_GROUND_RUN_PX;
				const int len = (run_end < c1 ? run_end : c1) - col;

				run0 = col;
				hl_ground_run(&ws->ground, &gv, &pose, sy, col, len, &hint, &run);
				if (mirror &&
				    run_settled(&gv, &run, len, mirror + i, obs, cur, m, col)) {
					if (changed)
						memset(changed + i, 0, len);
					col += len - 1;
					continue;
				}
			}
			const double d[3] = { run.d[0][col - run0], run.d[1][col - run0],
					      run.d[2][col - run0] };

			enum hl_surface gid;
			double galb;

			if (hl_ground_hit(&ws->ground, &run, col - run0, &gid, &galb))
				best = (struct hit){
					run.t[col - run0], { 0, 0, 1 }, gid, galb, true
				};
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
		const bool lit = hl_world_present(st, i) && (st->lamps_on >> i) & 1u;
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

				if (!hl_world_present(st, k))
					continue;
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
