/* SPDX-License-Identifier: MIT */
#include "render/scene_mesh.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#define DEG (M_PI / 180.0)

/*
 * Where the paint of the built-in scenes changes comes from render/scene_layout.h (shared with
 * render/scene.c). Only the edges come from there; what lies between two edges is asked of
 * hl_scene_cast, and tests/unit/render/test_scene_mesh.c casts rays through both.
 */
#include "render/scene_layout.h"

#define CHORD_TOL_M 1e-3 /* how far a chord of a curved wall line may be from the curve */
#define MIN_COLUMN_M 1e-3 /* wall columns are not split below this */
#define SPHERE_LON 64
#define SPHERE_LAT 32
#define MAX_BREAKS 256
#define MAX_EDGES 128

struct builder {
	struct hl_scene_mesh *m;
	size_t cap;
	int rc;
};

static void vertex(struct builder *b, const double p[3], const double n[3], double albedo,
		   enum hl_surface id, const double sphere[4])
{
	struct hl_scene_mesh_vertex *v;

	if (b->rc < 0)
		return;
	if (b->m->n_vertices == b->cap) {
		const size_t cap = b->cap ? 2 * b->cap : 1024;
		struct hl_scene_mesh_vertex *nv = realloc(b->m->v, sizeof(*nv) * cap);

		if (!nv) {
			b->rc = -ENOMEM;
			return;
		}
		b->m->v = nv;
		b->cap = cap;
	}
	v = &b->m->v[b->m->n_vertices++];
	for (int i = 0; i < 3; i++) {
		v->pos[i] = (float)p[i];
		v->nrm[i] = (float)n[i];
	}
	v->albedo = (float)albedo;
	v->id = (float)id;
	for (int i = 0; i < 4; i++)
		v->sphere[i] = sphere ? (float)sphere[i] : 0.0f;
}

/* The quad a b c d (in order around it) as two triangles. */
static void quad(struct builder *b, const double a[3], const double bb[3], const double c[3],
		 const double d[3], const double n[3], double albedo, enum hl_surface id)
{
	vertex(b, a, n, albedo, id, NULL);
	vertex(b, bb, n, albedo, id, NULL);
	vertex(b, c, n, albedo, id, NULL);
	vertex(b, a, n, albedo, id, NULL);
	vertex(b, c, n, albedo, id, NULL);
	vertex(b, d, n, albedo, id, NULL);
}

/* What the caster says is at the end of the ray o + t d: albedo and id; false: nothing. */
static bool classify(const struct hl_scene *s, const double o[3], const double d[3], double *albedo,
		     enum hl_surface *id)
{
	float pos[4], nrm[4];

	*id = hl_scene_cast(s, o, d, pos, nrm);
	*albedo = pos[3];
	return *id != HL_SURF_NONE;
}

static int cmp_double(const void *a, const void *b)
{
	const double x = *(const double *)a, y = *(const double *)b;

	return (x > y) - (x < y);
}

static void add_break(double *br, int *n, double v, double lo, double hi)
{
	if (v >= lo && v <= hi && *n < MAX_BREAKS)
		br[(*n)++] = v;
}

/* Sorted, without duplicates. */
static int tidy(double *br, int n)
{
	int k = 0;

	qsort(br, n, sizeof(*br), cmp_double);
	for (int i = 0; i < n; i++)
		if (k == 0 || br[i] > br[k - 1] + 1e-9)
			br[k++] = br[i];
	return k;
}

/*
 * The ground z = 0 over the grid of breaks xb x yb: each cell classified at its centre, runs
 * of equal cells along x merged into one quad.
 */
static void ground_cells(struct builder *b, const struct hl_scene *s, const double *xb, int nx,
			 const double *yb, int ny)
{
	static const double up[3] = { 0, 0, 1 }, down[3] = { 0, 0, -1 };

	for (int j = 0; j + 1 < ny; j++) {
		const double y0 = yb[j], y1 = yb[j + 1];
		int i = 0;

		while (i + 1 < nx) {
			const double o[3] = { (xb[i] + xb[i + 1]) / 2, (y0 + y1) / 2, 1e-3 };
			double albedo, a2;
			enum hl_surface id, id2;
			int k = i + 1;

			if (!classify(s, o, down, &albedo, &id)) {
				i++;
				continue;
			}
			while (k + 1 < nx) {
				const double o2[3] = { (xb[k] + xb[k + 1]) / 2, o[1], 1e-3 };

				if (!classify(s, o2, down, &a2, &id2) || id2 != id || a2 != albedo)
					break;
				k++;
			}
			{
				const double p0[3] = { xb[i], y0, 0 }, p1[3] = { xb[k], y0, 0 };
				const double p2[3] = { xb[k], y1, 0 }, p3[3] = { xb[i], y1, 0 };

				quad(b, p0, p1, p2, p3, up, albedo, id);
			}
			i = k;
		}
	}
}

static void road_ground(struct builder *b, const struct hl_scene *s)
{
	double xb[MAX_BREAKS], yb[MAX_BREAKS];
	int nx = 0, ny = 0;
	const bool bird = s->kind == HL_SCENE_BIRD;

	add_break(xb, &nx, ROAD_START_M, ROAD_START_M, HL_ROAD_LENGTH_M);
	add_break(xb, &nx, HL_ROAD_LENGTH_M, ROAD_START_M, HL_ROAD_LENGTH_M);
	for (double x = DASH_PERIOD_M * floor(ROAD_START_M / DASH_PERIOD_M); x < HL_ROAD_LENGTH_M;
	     x += DASH_PERIOD_M) {
		add_break(xb, &nx, x, ROAD_START_M, HL_ROAD_LENGTH_M);
		add_break(xb, &nx, x + DASH_M, ROAD_START_M, HL_ROAD_LENGTH_M);
	}
	for (int sgn = -1; sgn <= 1; sgn += 2) {
		add_break(yb, &ny, sgn * GRASS_HALF_WIDTH_M, -GRASS_HALF_WIDTH_M,
			  GRASS_HALF_WIDTH_M);
		add_break(yb, &ny, sgn * HL_LANE_WIDTH_M, -GRASS_HALF_WIDTH_M, GRASS_HALF_WIDTH_M);
		add_break(yb, &ny, sgn * (MARK_EDGE_Y_M - MARK_EDGE_W_M / 2), -GRASS_HALF_WIDTH_M,
			  GRASS_HALF_WIDTH_M);
		add_break(yb, &ny, sgn * (MARK_EDGE_Y_M + MARK_EDGE_W_M / 2), -GRASS_HALF_WIDTH_M,
			  GRASS_HALF_WIDTH_M);
		add_break(yb, &ny, sgn * MARK_CENTRE_W_M / 2, -GRASS_HALF_WIDTH_M,
			  GRASS_HALF_WIDTH_M);
	}
	if (bird) {
		add_break(xb, &nx, 0.0, ROAD_START_M, HL_ROAD_LENGTH_M);
		for (double g = 0.0; g <= HL_ROAD_LENGTH_M + GRID_STEP_M; g += GRID_STEP_M) {
			add_break(xb, &nx, g - GRID_LINE_M / 2, 0.0, HL_ROAD_LENGTH_M);
			add_break(xb, &nx, g + GRID_LINE_M / 2, 0.0, HL_ROAD_LENGTH_M);
		}
		for (double g = -GRASS_HALF_WIDTH_M; g <= GRASS_HALF_WIDTH_M; g += GRID_STEP_M) {
			add_break(yb, &ny, g - GRID_LINE_M / 2, -GRASS_HALF_WIDTH_M,
				  GRASS_HALF_WIDTH_M);
			add_break(yb, &ny, g + GRID_LINE_M / 2, -GRASS_HALF_WIDTH_M,
				  GRASS_HALF_WIDTH_M);
		}
	}
	nx = tidy(xb, nx);
	ny = tidy(yb, ny);
	ground_cells(b, s, xb, nx, yb, ny);
}

/* The axis-aligned box [lo, hi] without its bottom, normals out. */
static void box(struct builder *b, const struct hl_scene *s, const double lo[3], const double hi[3])
{
	for (int axis = 0; axis < 3; axis++)
		for (int side = 0; side < 2; side++) {
			const int u = (axis + 1) % 3, v = (axis + 2) % 3;
			double n[3] = { 0, 0, 0 }, c[4][3], o[3], d[3] = { 0, 0, 0 }, albedo;
			enum hl_surface id;

			if (axis == 2 && side == 0)
				continue; /* the bottom stands on the ground */
			n[axis] = side ? 1.0 : -1.0;
			for (int k = 0; k < 4; k++) {
				c[k][axis] = side ? hi[axis] : lo[axis];
				c[k][u] = (k == 1 || k == 2) ? hi[u] : lo[u];
				c[k][v] = (k >= 2) ? hi[v] : lo[v];
			}
			/* Asked from just outside the face's centre. */
			for (int k = 0; k < 3; k++)
				o[k] = (lo[k] + hi[k]) / 2;
			o[axis] = (side ? hi[axis] : lo[axis]) + 0.5 * n[axis];
			d[axis] = -n[axis];
			if (classify(s, o, d, &albedo, &id))
				quad(b, c[0], c[1], c[2], c[3], n, albedo, id);
		}
}

static void road_posts(struct builder *b, const struct hl_scene *s)
{
	for (double x = POST_STEP_M; x <= HL_ROAD_LENGTH_M + 1e-9; x += POST_STEP_M)
		for (int side = -1; side <= 1; side += 2) {
			const double lo[3] = { x - POST_SIDE_M / 2,
					       side * POST_Y_M - POST_SIDE_M / 2, 0.0 };
			const double hi[3] = { x + POST_SIDE_M / 2,
					       side * POST_Y_M + POST_SIDE_M / 2, POST_HEIGHT_M };

			box(b, s, lo, hi);
		}
}

/* The wall scene's screen x = D and what is painted on it. */
struct wall {
	const struct hl_scene *s;
	double dist, cy, cz;
	double lamp_z[2];
	int n_lamp_z;
};

struct edge {
	double zl, zr; /* height at the column's left and right end */
};

static int cmp_edge(const void *a, const void *b)
{
	const struct edge *x = a, *y = b;

	return (x->zl > y->zl) - (x->zl < y->zl);
}

static double v_line_z(const struct wall *w, double tan_v, double y)
{
	return w->cz + tan_v * hypot(w->dist, w->cy - y);
}

/* Edges of the paint across the column [y0, y1]: lines of constant height and V-line chords. */
static int column_edges(const struct wall *w, double y0, double y1, struct edge *e)
{
	const double half = tan(WALL_LINE_DEG / 2 * DEG) * w->dist;
	int n = 0;

	e[n++] = (struct edge){ 0.0, 0.0 };
	e[n++] = (struct edge){ WALL_HEIGHT_M, WALL_HEIGHT_M };
	for (int k = 0; k < w->n_lamp_z; k++) {
		e[n++] = (struct edge){ w->lamp_z[k] - half, w->lamp_z[k] - half };
		e[n++] = (struct edge){ w->lamp_z[k] + half, w->lamp_z[k] + half };
	}
	for (int k = -17; k <= 17 && n + 2 <= MAX_EDGES; k++)
		for (int sgn = -1; sgn <= 1; sgn += 2) {
			const double t = tan((k * WALL_STEP_DEG + sgn * WALL_LINE_DEG / 2) * DEG);
			const struct edge ed = { v_line_z(w, t, y0), v_line_z(w, t, y1) };

			if (fmax(ed.zl, ed.zr) < 0.0 || fmin(ed.zl, ed.zr) > WALL_HEIGHT_M)
				continue;
			e[n++] = ed;
		}
	qsort(e, n, sizeof(*e), cmp_edge);
	return n;
}

/* Whether the edges keep their order across the column and stay on one side of the borders. */
static bool column_simple(const struct edge *e, int n)
{
	for (int i = 0; i < n; i++) {
		if ((e[i].zl < 0.0) != (e[i].zr < 0.0) ||
		    (e[i].zl > WALL_HEIGHT_M) != (e[i].zr > WALL_HEIGHT_M))
			return false;
		if (i + 1 < n && e[i].zr > e[i + 1].zr + 1e-9)
			return false;
	}
	return true;
}

static void wall_column(struct builder *b, const struct wall *w, double y0, double y1)
{
	static const double n[3] = { -1, 0, 0 }, fwd[3] = { 1, 0, 0 };
	struct edge e[MAX_EDGES];
	const int ne = column_edges(w, y0, y1, e);

	if (!column_simple(e, ne) && y1 - y0 > MIN_COLUMN_M) {
		wall_column(b, w, y0, (y0 + y1) / 2);
		wall_column(b, w, (y0 + y1) / 2, y1);
		return;
	}
	for (int i = 0; i + 1 < ne; i++) {
		const double zl0 = fmin(fmax(e[i].zl, 0.0), WALL_HEIGHT_M);
		const double zr0 = fmin(fmax(e[i].zr, 0.0), WALL_HEIGHT_M);
		const double zl1 = fmin(fmax(e[i + 1].zl, 0.0), WALL_HEIGHT_M);
		const double zr1 = fmin(fmax(e[i + 1].zr, 0.0), WALL_HEIGHT_M);
		const double o[3] = { w->dist - 0.5, (y0 + y1) / 2, (zl0 + zr0 + zl1 + zr1) / 4 };
		double albedo;
		enum hl_surface id;

		if (zl1 - zl0 < 1e-9 && zr1 - zr0 < 1e-9)
			continue;
		if (!classify(w->s, o, fwd, &albedo, &id))
			continue;
		{
			/* Seen from the vehicle (normal -x): y0 is on the right. */
			const double a[3] = { w->dist, y0, zl0 }, bb[3] = { w->dist, y1, zr0 };
			const double c[3] = { w->dist, y1, zr1 }, d[3] = { w->dist, y0, zl1 };

			quad(b, a, bb, c, d, n, albedo, id);
		}
	}
}

static void wall_scene(struct builder *b, const struct hl_scene *s)
{
	const double dist = s->wall_distance_m;
	const double half = tan(WALL_LINE_DEG / 2 * DEG) * dist;
	struct wall w = { .s = s, .dist = dist };
	double yb[MAX_BREAKS], kappa = 0.0, col;
	int ny = 0;

	w.cy = (s->lamps[0].pos_m[1] + s->lamps[1].pos_m[1]) / 2;
	w.cz = (s->lamps[0].pos_m[2] + s->lamps[1].pos_m[2]) / 2;
	/* The ground before the screen, as one quad: the caster paints it plain. */
	{
		static const double up[3] = { 0, 0, 1 }, down[3] = { 0, 0, -1 };
		const double o[3] = { dist / 2, 0.0, 1e-3 };
		const double p0[3] = { HL_SCENE_MESH_BACK_M, -2 * WALL_HALF_WIDTH_M, 0 };
		const double p1[3] = { dist, -2 * WALL_HALF_WIDTH_M, 0 };
		const double p2[3] = { dist, 2 * WALL_HALF_WIDTH_M, 0 };
		const double p3[3] = { HL_SCENE_MESH_BACK_M, 2 * WALL_HALF_WIDTH_M, 0 };
		double albedo;
		enum hl_surface id;

		if (classify(s, o, down, &albedo, &id))
			quad(b, p0, p1, p2, p3, up, albedo, id);
	}
	add_break(yb, &ny, -WALL_HALF_WIDTH_M, -WALL_HALF_WIDTH_M, WALL_HALF_WIDTH_M);
	add_break(yb, &ny, WALL_HALF_WIDTH_M, -WALL_HALF_WIDTH_M, WALL_HALF_WIDTH_M);
	/* Lines of constant H are straight: y = cy - D tan(H). */
	for (int k = -17; k <= 17; k++)
		for (int sgn = -1; sgn <= 1; sgn += 2)
			add_break(yb, &ny,
				  w.cy - dist * tan((k * WALL_STEP_DEG + sgn * WALL_LINE_DEG / 2) *
						    DEG),
				  -WALL_HALF_WIDTH_M, WALL_HALF_WIDTH_M);
	/* The lamps' centre lines: where each optical axis meets the screen. */
	for (int k = 0; k < 2; k++) {
		double ax[3], ay[3], az[3], t;

		hl_lamp_basis(&s->lamps[k], ax, ay, az);
		if (!(az[0] > 0.0))
			continue;
		t = (dist - s->lamps[k].pos_m[0]) / az[0];
		add_break(yb, &ny, s->lamps[k].pos_m[1] + t * az[1] - half, -WALL_HALF_WIDTH_M,
			  WALL_HALF_WIDTH_M);
		add_break(yb, &ny, s->lamps[k].pos_m[1] + t * az[1] + half, -WALL_HALF_WIDTH_M,
			  WALL_HALF_WIDTH_M);
		w.lamp_z[w.n_lamp_z++] = s->lamps[k].pos_m[2] + t * az[2];
	}
	ny = tidy(yb, ny);
	/*
	 * Column width: a chord of z = cz + tan(V) hypot(D, cy - y) over width c is within
	 * z'' c^2 / 8 of the curve, z'' <= |tan V| / D; the steepest V line on the screen decides.
	 */
	for (int k = -17; k <= 17; k++) {
		const double t =
			tan((k * WALL_STEP_DEG + (k < 0 ? -1 : 1) * WALL_LINE_DEG / 2) * DEG);
		/* The line's height nearest to the centre height, at y = cy. */
		const double z_near = w.cz + t * dist;

		if ((t >= 0.0 && z_near <= WALL_HEIGHT_M) || (t < 0.0 && z_near >= 0.0))
			kappa = fmax(kappa, fabs(t) / dist);
	}
	col = kappa > 0.0 ? sqrt(8.0 * CHORD_TOL_M / kappa) : 2 * WALL_HALF_WIDTH_M;
	for (int j = 0; j + 1 < ny; j++) {
		const int parts = (int)ceil((yb[j + 1] - yb[j]) / col);

		for (int p = 0; p < parts; p++)
			wall_column(b, &w, yb[j] + (yb[j + 1] - yb[j]) * p / parts,
				    yb[j] + (yb[j + 1] - yb[j]) * (p + 1) / parts);
	}
}

static void bounce_scene(struct builder *b, const struct hl_scene *s)
{
	static const double up[3] = { 0, 0, 1 }, down[3] = { 0, 0, -1 }, fx[3] = { 1, 0, 0 },
			    back[3] = { -1, 0, 0 };
	double albedo;
	enum hl_surface id;
	const double of[3] = { 10.0, 0.0, 1.0 }, ow[3] = { 0.0, 0.0, 1.0 };

	if (classify(s, of, down, &albedo, &id)) {
		const double p0[3] = { HL_BOUNCE_WALL_X_M, -HL_BOUNCE_FLOOR_HALF_M, 0 };
		const double p1[3] = { HL_BOUNCE_FLOOR_END_M, -HL_BOUNCE_FLOOR_HALF_M, 0 };
		const double p2[3] = { HL_BOUNCE_FLOOR_END_M, HL_BOUNCE_FLOOR_HALF_M, 0 };
		const double p3[3] = { HL_BOUNCE_WALL_X_M, HL_BOUNCE_FLOOR_HALF_M, 0 };

		quad(b, p0, p1, p2, p3, up, albedo, id);
	}
	if (classify(s, ow, back, &albedo, &id)) {
		const double p0[3] = { HL_BOUNCE_WALL_X_M, -HL_BOUNCE_WALL_HALF_M, 0 };
		const double p1[3] = { HL_BOUNCE_WALL_X_M, HL_BOUNCE_WALL_HALF_M, 0 };
		const double p2[3] = { HL_BOUNCE_WALL_X_M, HL_BOUNCE_WALL_HALF_M,
				       HL_BOUNCE_WALL_HEIGHT_M };
		const double p3[3] = { HL_BOUNCE_WALL_X_M, -HL_BOUNCE_WALL_HALF_M,
				       HL_BOUNCE_WALL_HEIGHT_M };

		quad(b, p0, p1, p2, p3, fx, albedo, id);
	}
}

/* The sphere seen from inside: vertices on the surface, normals towards the centre. */
static void sphere_scene(struct builder *b, const struct hl_scene *s)
{
	const double *c = s->lamps[0].pos_m;
	const double r = s->sphere_radius_m;
	/*
	 * Vertices a little outside, so that every chord plane is at least r from the centre: the
	 * true sphere (and a sensor on it) stays inside the mesh. half_diag bounds the angle from
	 * a triangle's vertices to any point of it.
	 */
	const double half_diag = hypot(M_PI / SPHERE_LAT, 2 * M_PI / SPHERE_LON) / 2;
	const double rv = r / cos(half_diag);
	const double sph[4] = { c[0], c[1], c[2], -r };
	const double o[3] = { c[0], c[1], c[2] }, d[3] = { 0, 0, 1 };
	double albedo;
	enum hl_surface id;

	if (!classify(s, o, d, &albedo, &id))
		return;
	for (int j = 0; j < SPHERE_LAT; j++)
		for (int i = 0; i < SPHERE_LON; i++) {
			double p[4][3], n[4][3];

			for (int k = 0; k < 4; k++) {
				const double th = M_PI * (j + (k >= 2)) / SPHERE_LAT;
				const double ph = 2 * M_PI * (i + (k == 1 || k == 2)) / SPHERE_LON;
				const double u[3] = { sin(th) * cos(ph), sin(th) * sin(ph),
						      cos(th) };

				for (int a = 0; a < 3; a++) {
					p[k][a] = c[a] + rv * u[a];
					n[k][a] = -u[a];
				}
			}
			for (int t = 0; t < 2; t++) {
				const int idx[2][3] = { { 0, 1, 2 }, { 0, 2, 3 } };

				for (int k = 0; k < 3; k++)
					vertex(b, p[idx[t][k]], n[idx[t][k]], albedo, id, sph);
			}
		}
}

int hl_scene_mesh_new_empty(struct hl_scene_mesh **ret)
{
	struct hl_scene_mesh *m = calloc(1, sizeof(*m));

	if (!m)
		return -ENOMEM;
	*ret = m;
	return 0;
}

int hl_scene_mesh_new(const struct hl_scene *s, struct hl_scene_mesh **ret)
{
	struct builder b = { 0 };
	int rc = hl_scene_mesh_new_empty(&b.m);

	if (rc < 0)
		return rc;
	switch (s->kind) {
	case HL_SCENE_SPHERE:
		sphere_scene(&b, s);
		break;
	case HL_SCENE_WALL:
		wall_scene(&b, s);
		break;
	case HL_SCENE_ROAD:
	case HL_SCENE_BIRD:
		road_ground(&b, s);
		road_posts(&b, s);
		break;
	case HL_SCENE_BOUNCE:
		bounce_scene(&b, s);
		break;
	}
	if (b.rc < 0) {
		hl_scene_mesh_free(b.m);
		return b.rc;
	}
	*ret = b.m;
	return 0;
}

void hl_scene_mesh_free(struct hl_scene_mesh *m)
{
	if (!m)
		return;
	free(m->v);
	free(m);
}

static void sub(const float a[3], const double b[3], double r[3])
{
	for (int i = 0; i < 3; i++)
		r[i] = a[i] - b[i];
}

static void crossd(const double a[3], const double b[3], double r[3])
{
	r[0] = a[1] * b[2] - a[2] * b[1];
	r[1] = a[2] * b[0] - a[0] * b[2];
	r[2] = a[0] * b[1] - a[1] * b[0];
}

static double dotd(const double a[3], const double b[3])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

enum hl_surface hl_scene_mesh_cast(const struct hl_scene_mesh *m, const double o[3],
				   const double d[3], float pos[4], float nrm[4])
{
	const struct hl_scene_mesh_vertex *best = NULL;
	double best_t = INFINITY;

	for (size_t i = 0; i + 2 < m->n_vertices; i += 3) {
		const struct hl_scene_mesh_vertex *v = &m->v[i];
		const double nv[3] = { v->nrm[0], v->nrm[1], v->nrm[2] };
		double e1[3], e2[3], s[3], pv[3], qv[3], det, u, w, t;

		if (v->sphere[3] == 0.0f && dotd(nv, d) >= 0.0)
			continue; /* one-sided flat triangles, seen from behind (as the GLES pass) */
		/* Möller-Trumbore. */
		for (int k = 0; k < 3; k++) {
			e1[k] = (double)v[1].pos[k] - v[0].pos[k];
			e2[k] = (double)v[2].pos[k] - v[0].pos[k];
		}
		crossd(d, e2, pv);
		det = dotd(e1, pv);
		if (fabs(det) < 1e-15)
			continue;
		sub(v[0].pos, o, s);
		for (int k = 0; k < 3; k++)
			s[k] = -s[k];
		u = dotd(s, pv) / det;
		if (u < 0.0 || u > 1.0)
			continue;
		crossd(s, e1, qv);
		w = dotd(d, qv) / det;
		if (w < 0.0 || u + w > 1.0)
			continue;
		t = dotd(e2, qv) / det;
		if (t > 1e-6 && t < best_t) {
			best_t = t;
			best = v;
		}
	}
	if (!best) {
		memset(pos, 0, sizeof(float) * 4);
		memset(nrm, 0, sizeof(float) * 4);
		return HL_SURF_NONE;
	}
	{
		double p[3], n[3];

		for (int k = 0; k < 3; k++) {
			p[k] = o[k] + best_t * d[k];
			n[k] = best->nrm[k];
		}
		if (best->sphere[3] != 0.0f) {
			const double r = fabs(best->sphere[3]), sg = best->sphere[3] < 0 ? -1 : 1;
			double len = 0.0;

			for (int k = 0; k < 3; k++) {
				n[k] = p[k] - best->sphere[k];
				len += n[k] * n[k];
			}
			len = sqrt(len);
			for (int k = 0; k < 3; k++) {
				n[k] /= len;
				p[k] = best->sphere[k] + r * n[k];
				n[k] *= sg;
			}
		}
		for (int k = 0; k < 3; k++) {
			pos[k] = (float)p[k];
			nrm[k] = (float)n[k];
		}
		pos[3] = best->albedo;
		nrm[3] = best->id;
		return (enum hl_surface)(int)best->id;
	}
}
