/* SPDX-License-Identifier: MIT */
/*
 * The built-in procedural scenes and their G-buffer. Scenes are analytic (planes, boxes, a
 * sphere), so the G-buffer is ray cast exactly on the CPU, once per scene and camera; the
 * headlight pass then lights it every frame.
 *
 *   sphere  grey sphere, radius 10 m, centred on the left lamp: the papers' validation scene
 *   wall    white measuring screen across the road at 25 m (or 10 m), lines every 5° of H and V
 *           as seen from the point between the lamps, and the lamps' centre lines
 *   road    straight two-lane road, 3.5 m lanes with markings, 140 m long, white posts every
 *           10 m on both edges
 *   bird    the road seen from above with a 10 m distance grid
 *   bounce  validation of indirect light: a large grey floor lit by the lamps and a white wall
 *           3 m behind them (the lamps cannot light it directly), seen from 8 m ahead
 *
 * Thread-safety: a scene is read-only once made; a G-buffer is filled by one thread.
 */
#ifndef HL_RENDER_SCENE_H
#define HL_RENDER_SCENE_H

#include <stdint.h>

#include "world/camera.h"

enum hl_scene_kind {
	HL_SCENE_SPHERE,
	HL_SCENE_WALL,
	HL_SCENE_ROAD,
	HL_SCENE_BIRD,
	HL_SCENE_BOUNCE,
};

/* Surface ids in the G-buffer. */
enum hl_surface {
	HL_SURF_NONE, /* nothing hit: sky */
	HL_SURF_ROAD,
	HL_SURF_MARKING,
	HL_SURF_SHOULDER,
	HL_SURF_POST,
	HL_SURF_WALL,
	HL_SURF_WALL_LINE,
	HL_SURF_SPHERE,
	HL_SURF_GRID,
	HL_SURF_FLOOR,
	HL_SURF_VEHICLE, /* a road user's body (render/world_scene.h) */
	HL_SURF_PEDESTRIAN,
	HL_SURF_CYCLIST,
};

#define HL_SPHERE_RADIUS_M 10.0
#define HL_WALL_DISTANCE_M 25.0
#define HL_ROAD_LENGTH_M 140.0
#define HL_LANE_WIDTH_M 3.5

/* The bounce scene: floor z = 0 over x in [wall, end], |y| <= half; wall x = HL_BOUNCE_WALL_X_M
 * facing +x, |y| <= HL_BOUNCE_WALL_HALF_M, z in [0, HL_BOUNCE_WALL_HEIGHT_M]. */
#define HL_BOUNCE_WALL_X_M (-3.0)
#define HL_BOUNCE_WALL_HALF_M 6.0
#define HL_BOUNCE_WALL_HEIGHT_M 4.0
#define HL_BOUNCE_FLOOR_END_M 40.0
#define HL_BOUNCE_FLOOR_HALF_M 20.0
#define HL_BOUNCE_FLOOR_ALBEDO 0.5
#define HL_BOUNCE_WALL_ALBEDO 0.8

struct hl_scene {
	enum hl_scene_kind kind;
	struct hl_lamp_pose lamps[2]; /* left, right: the sphere's centre, the wall's lines */
	double wall_distance_m; /* wall: distance of the screen from the vehicle origin */
	double sphere_radius_m;
};

/*
 * G-buffer, one entry per pixel, row 0 at the top. pos: x, y, z (m, vehicle frame), albedo;
 * nrm: unit normal x, y, z, surface id. Pixels that hit nothing have albedo 0 and id 0.
 */
struct hl_gbuffer {
	int width, height;
	float *pos; /* 4 floats per pixel */
	float *nrm; /* 4 floats per pixel */
	float *albedo; /* 1 float per pixel: pos[4 i + 3] packed, for the per-frame views */
};

/*
 * A thin object: the capsule of radius r_m around the segment a-b. Sensors (render/sensor.h)
 * supersample the texels whose cone passes near one, since a point-sampled sensor map misses
 * or catches such objects by chance (aliasing).
 */
struct hl_capsule {
	double a[3], b[3];
	double r_m;
};

#define HL_SCENE_MAX_THIN 64

/* "sphere", "wall", "road", "bird", "bounce" to a kind; -EINVAL otherwise. */
int hl_scene_from_name(const char *name);
/* The kind's name; NULL for a value that is no kind. */
const char *hl_scene_name(enum hl_scene_kind kind);

/* A scene with its defaults and the given lamp poses. */
void hl_scene_init(struct hl_scene *s, enum hl_scene_kind kind, const struct hl_lamp_pose lamps[2]);
/*
 * The scene's default camera at width x height: the driver's eye for road and wall, above the
 * road for bird, at the left lamp looking along its axis for sphere.
 */
void hl_scene_default_camera(const struct hl_scene *s, int width, int height,
			     struct hl_camera *ret);

/* width x height G-buffer. 0, -EINVAL, -ENOMEM. */
int hl_gbuffer_new(int width, int height, struct hl_gbuffer **ret);
void hl_gbuffer_free(struct hl_gbuffer *gb);

/*
 * Ray casts the scene through every pixel of cam into gb (sizes must match: -EINVAL).
 * Allocates nothing.
 */
int hl_scene_render(const struct hl_scene *s, const struct hl_camera *cam, struct hl_gbuffer *gb);

/* The scene's thin objects (the road's posts) into ret; returns how many (at most max). */
int hl_scene_thin_objects(const struct hl_scene *s, struct hl_capsule *ret, int max);

/* Casts one ray (origin o, direction d); fills pos/nrm (4 floats each) and returns the id. */
enum hl_surface hl_scene_cast(const struct hl_scene *s, const double o[3], const double d[3],
			      float ret_pos[4], float ret_nrm[4]);

#endif
