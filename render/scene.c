/* SPDX-License-Identifier: MIT */
#include "render/scene.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "render/scene_layout.h"

#define DEG (M_PI / 180.0)

/* Reflectances (albedo) of the surfaces. */
#define ALBEDO_ROAD HL_ALBEDO_ROAD
#define ALBEDO_MARKING HL_ALBEDO_MARKING
#define ALBEDO_SHOULDER HL_ALBEDO_SHOULDER
#define ALBEDO_POST HL_ALBEDO_POST
#define ALBEDO_WALL 0.8
#define ALBEDO_WALL_LINE 0.25
#define ALBEDO_SPHERE 0.5
#define ALBEDO_GRID 0.45

static const char *const names[] = { "sphere", "wall", "road", "bird", "bounce" };

int hl_scene_from_name(const char *name)
{
	for (size_t i = 0; i < sizeof(names) / sizeof(names[0]); i++)
		if (strcmp(name, names[i]) == 0)
			return (int)i;
	return -EINVAL;
}

const char *hl_scene_name(enum hl_scene_kind kind)
{
	return (unsigned)kind < sizeof(names) / sizeof(names[0]) ? names[kind] : NULL;
}

void hl_scene_init(struct hl_scene *s, enum hl_scene_kind kind, const struct hl_lamp_pose lamps[2])
{
	*s = (struct hl_scene){
		.kind = kind,
		.lamps = { lamps[0], lamps[1] },
		.wall_distance_m = HL_WALL_DISTANCE_M,
		.sphere_radius_m = HL_SPHERE_RADIUS_M,
	};
}

void hl_scene_default_camera(const struct hl_scene *s, int width, int height, struct hl_camera *ret)
{
	*ret = (struct hl_camera){ .width = width, .height = height };
	switch (s->kind) {
	case HL_SCENE_SPHERE: {
		double x[3], y[3], z[3];

		hl_lamp_basis(&s->lamps[0], x, y, z);
		memcpy(ret->pos_m, s->lamps[0].pos_m, sizeof(ret->pos_m));
		memcpy(ret->dir, z, sizeof(ret->dir));
		memcpy(ret->up, y, sizeof(ret->up));
		ret->fov_y_deg = 60.0;
		break;
	}
	case HL_SCENE_BIRD: {
		/* Straight down, the road running left to right, the vehicle at the left. */
		const double aspect = (double)width / height;
		const double half_span_m = (HL_ROAD_LENGTH_M - ROAD_START_M) / 2 + 2.0;

		ret->fov_y_deg = 30.0;
		ret->pos_m[0] = ROAD_START_M + half_span_m - 2.0;
		ret->pos_m[2] = half_span_m / (tan(ret->fov_y_deg * DEG / 2) * aspect);
		ret->dir[2] = -1.0;
		ret->up[1] = 1.0;
		break;
	}
	case HL_SCENE_BOUNCE:
		/* 8 m ahead of the lamps, looking back at the wall over the lit floor. */
		ret->pos_m[0] = 8.0;
		ret->pos_m[2] = 2.0;
		ret->dir[0] = -1.0;
		ret->dir[2] = -0.12;
		ret->up[2] = 1.0;
		ret->fov_y_deg = 50.0;
		break;
	case HL_SCENE_WALL:
	case HL_SCENE_ROAD:
		/* Driver's eye: left-hand drive, 1.8 m behind the bumper, 1.2 m up. */
		ret->pos_m[0] = -1.8;
		ret->pos_m[1] = 0.37;
		ret->pos_m[2] = 1.2;
		ret->dir[0] = 1.0;
		ret->dir[2] = -0.03;
		ret->up[2] = 1.0;
		ret->fov_y_deg = 36.0;
		break;
	}
}

int hl_gbuffer_new(int width, int height, struct hl_gbuffer **ret)
{
	struct hl_gbuffer *gb;

	if (width < 1 || height < 1 || width > 16384 || height > 16384)
		return -EINVAL;
	gb = calloc(1, sizeof(*gb));
	if (!gb)
		return -ENOMEM;
	gb->width = width;
	gb->height = height;
	gb->pos = calloc((size_t)width * height * 4, sizeof(float));
	gb->nrm = calloc((size_t)width * height * 4, sizeof(float));
	gb->albedo = calloc((size_t)width * height, sizeof(float));
	if (!gb->pos || !gb->nrm || !gb->albedo) {
		hl_gbuffer_free(gb);
		return -ENOMEM;
	}
	*ret = gb;
	return 0;
}

void hl_gbuffer_free(struct hl_gbuffer *gb)
{
	if (!gb)
		return;
	free(gb->pos);
	free(gb->nrm);
	free(gb->albedo);
	free(gb);
}

struct hit {
	double t;
	double n[3];
	enum hl_surface id;
	double albedo;
};

/* Keeps the nearer hit. */
static void take(struct hit *best, double t, double nx, double ny, double nz, enum hl_surface id,
		 double albedo)
{
	if (!(t > 1e-6 && t < best->t))
		return;
	*best = (struct hit){ t, { nx, ny, nz }, id, albedo };
}

static bool near_multiple(double v, double step, double half_width)
{
	const double r = v - step * floor(v / step + 0.5);

	return fabs(r) <= half_width;
}

/* The ground z = 0 with the road's paint (and the bird's grid). */
static void ground(const struct hl_scene *s, const double o[3], const double d[3], struct hit *best)
{
	double t, x, y, ay;

	if (!(d[2] < 0.0) || o[2] <= 0.0)
		return;
	t = -o[2] / d[2];
	x = o[0] + t * d[0];
	y = o[1] + t * d[1];
	if (s->kind == HL_SCENE_WALL) {
		if (x < s->wall_distance_m && fabs(y) < WALL_HALF_WIDTH_M * 2)
			take(best, t, 0, 0, 1, HL_SURF_ROAD, ALBEDO_ROAD);
		return;
	}
	if (x < ROAD_START_M || x > HL_ROAD_LENGTH_M)
		return;
	ay = fabs(y);
	if (s->kind == HL_SCENE_BIRD && x >= 0.0 && ay < GRASS_HALF_WIDTH_M &&
	    (near_multiple(x, GRID_STEP_M, GRID_LINE_M / 2) ||
	     (ay > HL_LANE_WIDTH_M && near_multiple(y, GRID_STEP_M, GRID_LINE_M / 2)))) {
		take(best, t, 0, 0, 1, HL_SURF_GRID, ALBEDO_GRID);
		return;
	}
	if (ay > HL_LANE_WIDTH_M) {
		if (ay < GRASS_HALF_WIDTH_M)
			take(best, t, 0, 0, 1, HL_SURF_SHOULDER, ALBEDO_SHOULDER);
		return;
	}
	if (fabs(ay - MARK_EDGE_Y_M) <= MARK_EDGE_W_M / 2 ||
	    (ay <= MARK_CENTRE_W_M / 2 && x - DASH_PERIOD_M * floor(x / DASH_PERIOD_M) < DASH_M))
		take(best, t, 0, 0, 1, HL_SURF_MARKING, ALBEDO_MARKING);
	else
		take(best, t, 0, 0, 1, HL_SURF_ROAD, ALBEDO_ROAD);
}

/* An axis-aligned box [lo, hi] (slab test) with the normal of the entry face. */
static void box(const double o[3], const double d[3], const double lo[3], const double hi[3],
		struct hit *best)
{
	double t0 = -INFINITY, t1 = INFINITY;
	int axis = -1;
	double sign = 0.0;

	for (int i = 0; i < 3; i++) {
		double a, b;

		if (d[i] == 0.0) {
			if (o[i] < lo[i] || o[i] > hi[i])
				return;
			continue;
		}
		a = (lo[i] - o[i]) / d[i];
		b = (hi[i] - o[i]) / d[i];
		if (a > b) {
			double tmp = a;

			a = b;
			b = tmp;
		}
		if (a > t0) {
			t0 = a;
			axis = i;
			sign = d[i] > 0.0 ? -1.0 : 1.0;
		}
		if (b < t1)
			t1 = b;
	}
	if (axis < 0 || t0 > t1 || !(t0 > 1e-6) || t0 >= best->t)
		return;
	take(best, t0, axis == 0 ? sign : 0, axis == 1 ? sign : 0, axis == 2 ? sign : 0,
	     HL_SURF_POST, ALBEDO_POST);
}

/* Whether the ray meets the box [lo, hi] before best: a conservative reject, no hit kept. */
static bool meets(const double o[3], const double d[3], const double lo[3], const double hi[3],
		  const struct hit *best)
{
	double t0 = 1e-6, t1 = best->t;

	for (int i = 0; i < 3; i++) {
		double a, b;

		if (d[i] == 0.0) {
			if (o[i] < lo[i] || o[i] > hi[i])
				return false;
			continue;
		}
		a = (lo[i] - o[i]) / d[i];
		b = (hi[i] - o[i]) / d[i];
		if (a > b) {
			const double tmp = a;

			a = b;
			b = tmp;
		}
		t0 = a > t0 ? a : t0;
		t1 = b < t1 ? b : t1;
	}
	return t0 <= t1;
}

static void posts(const double o[3], const double d[3], struct hit *best)
{
	for (int side = -1; side <= 1; side += 2) {
		/* The row of posts on this side as one box: most rays miss it (sensors). */
		const double row_lo[3] = { POST_STEP_M - POST_SIDE_M, side * POST_Y_M - POST_SIDE_M,
					   -POST_SIDE_M };
		const double row_hi[3] = { HL_ROAD_LENGTH_M + POST_SIDE_M,
					   side * POST_Y_M + POST_SIDE_M,
					   POST_HEIGHT_M + POST_SIDE_M };

		if (!meets(o, d, row_lo, row_hi, best))
			continue;
		for (double x = POST_STEP_M; x <= HL_ROAD_LENGTH_M + 1e-9; x += POST_STEP_M) {
			const double lo[3] = { x - POST_SIDE_M / 2,
					       side * POST_Y_M - POST_SIDE_M / 2, 0.0 };
			const double hi[3] = { x + POST_SIDE_M / 2,
					       side * POST_Y_M + POST_SIDE_M / 2, POST_HEIGHT_M };

			box(o, d, lo, hi, best);
		}
	}
}

int hl_scene_thin_objects(const struct hl_scene *s, struct hl_capsule *ret, int max)
{
	int n = 0;

	if (s->kind != HL_SCENE_ROAD && s->kind != HL_SCENE_BIRD)
		return 0;
	for (double x = POST_STEP_M; x <= HL_ROAD_LENGTH_M + 1e-9; x += POST_STEP_M)
		for (int side = -1; side <= 1 && n < max; side += 2)
			ret[n++] = (struct hl_capsule){
				.a = { x, side * POST_Y_M, 0.0 },
				.b = { x, side * POST_Y_M, POST_HEIGHT_M },
				.r_m = POST_SIDE_M * M_SQRT1_2,
			};
	return n;
}

/* The measuring screen x = D, facing the vehicle. */
static void wall(const struct hl_scene *s, const double o[3], const double d[3], struct hit *best)
{
	const double dist = s->wall_distance_m;
	/* Lines are drawn as seen from the point between the lamps at lamp height. */
	const double cy = (s->lamps[0].pos_m[1] + s->lamps[1].pos_m[1]) / 2;
	const double cz = (s->lamps[0].pos_m[2] + s->lamps[1].pos_m[2]) / 2;
	double t, y, z, h_deg, v_deg;
	bool line = false;

	if (!(d[0] > 0.0) || o[0] >= dist)
		return;
	t = (dist - o[0]) / d[0];
	y = o[1] + t * d[1];
	z = o[2] + t * d[2];
	if (fabs(y) > WALL_HALF_WIDTH_M || z < 0.0 || z > WALL_HEIGHT_M)
		return;
	/* H grows to the right, i.e. towards -y; lines 5° apart (type A, as a goniometer). */
	h_deg = atan2(cy - y, dist) / DEG;
	v_deg = atan2(z - cz, hypot(dist, cy - y)) / DEG;
	line = near_multiple(h_deg, WALL_STEP_DEG, WALL_LINE_DEG / 2) ||
	       near_multiple(v_deg, WALL_STEP_DEG, WALL_LINE_DEG / 2);
	/* Centre lines of the lamps: where each optical axis meets the screen. */
	for (int k = 0; k < 2 && !line; k++) {
		double ax[3], ay[3], az[3], ta, py, pz;

		hl_lamp_basis(&s->lamps[k], ax, ay, az);
		if (!(az[0] > 0.0))
			continue;
		ta = (dist - s->lamps[k].pos_m[0]) / az[0];
		py = s->lamps[k].pos_m[1] + ta * az[1];
		pz = s->lamps[k].pos_m[2] + ta * az[2];
		line = fabs(y - py) <= dist * tan(WALL_LINE_DEG * DEG / 2) ||
		       fabs(z - pz) <= dist * tan(WALL_LINE_DEG * DEG / 2);
	}
	take(best, t, -1, 0, 0, line ? HL_SURF_WALL_LINE : HL_SURF_WALL,
	     line ? ALBEDO_WALL_LINE : ALBEDO_WALL);
}

/* The bounce scene: the floor and the wall behind the lamps. */
static void bounce(const double o[3], const double d[3], struct hit *best)
{
	if (d[2] < 0.0 && o[2] > 0.0) {
		const double t = -o[2] / d[2];
		const double x = o[0] + t * d[0], y = o[1] + t * d[1];

		if (x >= HL_BOUNCE_WALL_X_M && x <= HL_BOUNCE_FLOOR_END_M &&
		    fabs(y) <= HL_BOUNCE_FLOOR_HALF_M)
			take(best, t, 0, 0, 1, HL_SURF_FLOOR, HL_BOUNCE_FLOOR_ALBEDO);
	}
	if (d[0] < 0.0 && o[0] > HL_BOUNCE_WALL_X_M) {
		const double t = (HL_BOUNCE_WALL_X_M - o[0]) / d[0];
		const double y = o[1] + t * d[1], z = o[2] + t * d[2];

		if (fabs(y) <= HL_BOUNCE_WALL_HALF_M && z >= 0.0 && z <= HL_BOUNCE_WALL_HEIGHT_M)
			take(best, t, 1, 0, 0, HL_SURF_WALL, HL_BOUNCE_WALL_ALBEDO);
	}
}

/* From inside the sphere, the far intersection; the normal points to the centre. */
static void sphere(const struct hl_scene *s, const double o[3], const double d[3], struct hit *best)
{
	const double *c = s->lamps[0].pos_m;
	const double r = s->sphere_radius_m;
	double oc[3], a, b, cc, disc, t;

	for (int i = 0; i < 3; i++)
		oc[i] = o[i] - c[i];
	a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
	b = oc[0] * d[0] + oc[1] * d[1] + oc[2] * d[2];
	cc = oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2] - r * r;
	disc = b * b - a * cc;
	if (disc < 0.0)
		return;
	t = (-b + sqrt(disc)) / a;
	if (cc > 0.0) /* outside: the near side, facing out */
		t = (-b - sqrt(disc)) / a;
	{
		const double p[3] = { o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2] };
		const double sgn = cc > 0.0 ? 1.0 : -1.0;

		take(best, t, sgn * (p[0] - c[0]) / r, sgn * (p[1] - c[1]) / r,
		     sgn * (p[2] - c[2]) / r, HL_SURF_SPHERE, ALBEDO_SPHERE);
	}
}

enum hl_surface hl_scene_cast(const struct hl_scene *s, const double o[3], const double d[3],
			      float pos[4], float nrm[4])
{
	struct hit best = { INFINITY, { 0, 0, 0 }, HL_SURF_NONE, 0.0 };

	switch (s->kind) {
	case HL_SCENE_SPHERE:
		sphere(s, o, d, &best);
		break;
	case HL_SCENE_WALL:
		ground(s, o, d, &best);
		wall(s, o, d, &best);
		break;
	case HL_SCENE_ROAD:
	case HL_SCENE_BIRD:
		ground(s, o, d, &best);
		posts(o, d, &best);
		break;
	case HL_SCENE_BOUNCE:
		bounce(o, d, &best);
		break;
	}
	if (best.id == HL_SURF_NONE) {
		memset(pos, 0, sizeof(float) * 4);
		memset(nrm, 0, sizeof(float) * 4);
		return HL_SURF_NONE;
	}
	for (int i = 0; i < 3; i++) {
		pos[i] = (float)(o[i] + best.t * d[i]);
		nrm[i] = (float)best.n[i];
	}
	pos[3] = (float)best.albedo;
	nrm[3] = (float)best.id;
	return best.id;
}

int hl_scene_render(const struct hl_scene *s, const struct hl_camera *cam, struct hl_gbuffer *gb)
{
	if (cam->width != gb->width || cam->height != gb->height)
		return -EINVAL;
	for (int row = 0; row < gb->height; row++)
		for (int col = 0; col < gb->width; col++) {
			const size_t i = 4 * ((size_t)row * gb->width + col);
			double d[3];

			hl_camera_ray(cam, col + 0.5, row + 0.5, d);
			hl_scene_cast(s, cam->pos_m, d, gb->pos + i, gb->nrm + i);
			gb->albedo[i / 4] = gb->pos[i + 3];
		}
	return 0;
}
