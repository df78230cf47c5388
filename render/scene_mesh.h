/* SPDX-License-Identifier: MIT */
/*
 * The built-in scenes (render/scene.h) as triangle meshes, for rasterising them into sensor
 * maps (render/gl_sensor.h). The analytic caster stays the definition; the mesh follows it:
 *
 *   planes     cut into cells along every edge of their paint (road markings, the bird's grid,
 *              the wall's 5° lines and the lamps' centre lines), so that no cell straddles two
 *              materials; each cell takes its albedo and surface id from hl_scene_cast at its
 *              centre, so the two cannot disagree on what is painted where. The wall's lines
 *              of constant V are curves: chords over columns narrow enough that a chord is
 *              within 1 mm of the curve.
 *   posts      boxes, their five visible faces.
 *   sphere     a latitude-longitude grid of triangles whose vertices lie on the sphere; each
 *              carries the sphere (centre, signed radius) so that a renderer can put the lit
 *              point back on the true surface (chord error otherwise ~0.1 % in r^2).
 *
 * Triangles are one-sided: the side the normal points to is the visible one, as in the caster
 * (the ground is hit from above only, the sphere from inside). Parts of unbounded planes that
 * no lamp can light (the wall scene's ground behind the lamps) are cut at HL_SCENE_MESH_BACK_M:
 * with a black sky, unlit ground and nothing look the same.
 *
 * Thread-safety: a mesh is read-only once made; any thread.
 */
#ifndef HL_RENDER_SCENE_MESH_H
#define HL_RENDER_SCENE_MESH_H

#include <stddef.h>

#include "render/scene.h"

#define HL_SCENE_MESH_BACK_M (-50.0) /* wall scene: the ground starts here (x, m) */

struct hl_scene_mesh_vertex {
	float pos[3]; /* m, vehicle frame */
	float nrm[3]; /* unit, the visible side */
	float albedo;
	float id; /* enum hl_surface */
	float sphere[4]; /* centre (m), signed radius (< 0: normal towards the centre); 0: flat */
};

struct hl_scene_mesh {
	size_t n_vertices; /* three per triangle */
	struct hl_scene_mesh_vertex *v;
};

/* The scene as triangles. 0, -ENOMEM. */
int hl_scene_mesh_new(const struct hl_scene *s, struct hl_scene_mesh **ret);
/* An empty mesh (nothing but sky), for tests of a sensor's normalisation. 0, -ENOMEM. */
int hl_scene_mesh_new_empty(struct hl_scene_mesh **ret);
void hl_scene_mesh_free(struct hl_scene_mesh *m);

/*
 * The nearest front-facing triangle along the ray o + t d (t > 1e-6), brute force over all
 * triangles: a reference to check the mesh against hl_scene_cast, not for hot paths. Fills
 * pos (x, y, z, albedo) and nrm (x, y, z, id) like hl_scene_cast, sphere triangles projected
 * onto their sphere; returns the id (HL_SURF_NONE: nothing hit, pos and nrm zero).
 */
enum hl_surface hl_scene_mesh_cast(const struct hl_scene_mesh *m, const double o[3],
				   const double d[3], float ret_pos[4], float ret_nrm[4]);

#endif
