/* SPDX-License-Identifier: MIT */
/*
 * The moving scene of a scenario at one instant, ray cast into a G-buffer (docs/scenarios.md,
 * "How a scenario is rendered"). The G-buffer is in the EGO VEHICLE FRAME (ISO 8855: x forward,
 * y left, z up, origin on the ground below the centre of the front bumper), where the driver's
 * camera and the ego lamps stay fixed: the ground is z = 0 in every frame and, as the car
 * moves, only the albedo and surface id of ground pixels change. The renderer's per-pixel lamp
 * terms of ground pixels (position and normal) therefore stay valid.
 *
 * In the world: the ground; the road from the scenario (straight and arc segments, lanes, edge
 * and separator lines, solid or dashed) classified by each ground point's road coordinates
 * (hl_road_project()); the shoulder beyond the edges, up to HL_WORLD_GROUND_HALF_M from the
 * centre line (farther: nothing, as the built-in road scene); the posts on both edges as thin
 * upright boxes; each road user's body as an oriented box. Albedos are the built-in road
 * scene's, so a standing ego on a straight road looks like the `road` scene.
 *
 * The road users' lamps are point emitters: hl_world_scene_emitters() projects them for a
 * camera (pixel, distance, whether they face it and are not hidden by a body) and
 * hl_world_emitters_draw() adds them to a display view as small discs carrying their
 * illuminance I / r^2 at the camera.
 *
 * Thread-safety: hl_world_scene_new()/_free() on one thread; hl_world_scene_render_rows() or
 * _render_pixels() of disjoint bands may run on several threads at once for the same state and
 * camera (each call reads the state, the scenario and the camera and writes only its pixels). Nothing here
 * allocates after _new(); a band's call keeps its objects on the stack (about 64 KB).
 */
#ifndef HL_RENDER_WORLD_SCENE_H
#define HL_RENDER_WORLD_SCENE_H

#include <stdbool.h>
#include <stdint.h>

#include "world/camera.h"
#include "world/scenario.h"
#include "render/scene.h"
#include "world/world.h"
#include "render/world_ground.h" /* HL_WORLD_GROUND_HALF_M */

#define HL_WORLD_POST_RANGE_M 600.0 /* posts farther along the road than this are not drawn */
#define HL_WORLD_MAX_OBJECTS 512 /* bodies and posts one row band can see */
#define HL_WORLD_POST_SIDE_M 0.12 /* a post's square cross-section, as the road scene's */

struct hl_world_scene;

/* sc must outlive the object. 0, -ENOMEM. */
int hl_world_scene_new(const struct hl_scenario *sc, struct hl_world_scene **ret);
void hl_world_scene_free(struct hl_world_scene *ws);

/*
 * Ray casts rows row0 .. row0 + nrows - 1 of cam (ego frame; its width and height must be
 * gb's) into gb for the state st: pos and normal in the ego frame, albedo, surface id. 0, or
 * -EINVAL (sizes, rows out of range).
 */
int hl_world_scene_render_rows(struct hl_world_scene *ws, const struct hl_world_state *st,
			       const struct hl_camera *cam, struct hl_gbuffer *gb, int row0,
			       int nrows);
/*
 * The same for pixels first .. first + count - 1 (row-major, row 0 at the top). 0, or -EINVAL.
 */
int hl_world_scene_render_pixels(struct hl_world_scene *ws, const struct hl_world_state *st,
				 const struct hl_camera *cam, struct hl_gbuffer *gb, size_t first,
				 size_t count);

/*
 * A sequence of frames of one camera into one G-buffer (hdlampd's moving scene): the raster
 * remembers what it drew in each pixel, so a pixel of the ground that stays the same surface
 * (most of them: in the ego frame the ground's pixels keep their position and normal, only the
 * road's markings slide by) is neither read nor written again. gb must be written by nothing
 * else while the raster lives. hl_world_raster_pixels() of disjoint ranges may run on several
 * threads at once (hl_renderer_set_gbuffer_fill()); it also says for each pixel of the range
 * whether its position, normal or hit/miss differ from what gb held before, bit for bit (1)
 * or not (0), the rule of render/gbuffer_diff.h (changed: one byte per pixel of the image, may
 * be NULL). The first frame writes every pixel. ws, cam's copy and gb must outlive the raster.
 */
struct hl_world_raster;

/* 0, -EINVAL (cam's size is not gb's), -ENOMEM. */
int hl_world_raster_new(struct hl_world_scene *ws, const struct hl_camera *cam,
			struct hl_gbuffer *gb, struct hl_world_raster **ret);
void hl_world_raster_free(struct hl_world_raster *r);
struct hl_gbuffer *hl_world_raster_gbuffer(const struct hl_world_raster *r);
/* Pixels first .. + count - 1 of the raster's G-buffer for the state st. 0, -EINVAL. */
int hl_world_raster_pixels(struct hl_world_raster *r, const struct hl_world_state *st, size_t first,
			   size_t count, uint8_t *changed);

/* Every row. */
int hl_world_scene_render(struct hl_world_scene *ws, const struct hl_world_state *st,
			  const struct hl_camera *cam, struct hl_gbuffer *gb);

/*
 * Objects (bodies, posts) a row band could not consider because more than
 * HL_WORLD_MAX_OBJECTS covered it, summed over every call since _new.
 */
unsigned long hl_world_scene_objects_dropped(const struct hl_world_scene *ws);

/* A point in the world frame into the ego frame of pose ego (and back). */
void hl_world_to_ego(const struct hl_body_pose *ego, const double world[3], double ret[3]);
void hl_ego_to_world(const struct hl_body_pose *ego, const double local[3], double ret[3]);

/* A road user's lamp as the camera sees it. */
struct hl_world_emitter {
	int actor, lamp; /* indices in the scenario */
	double x_px, y_px; /* image point (col + 0.5, row + 0.5 is a pixel's centre) */
	double distance_m; /* from the camera */
	double illuminance_lx; /* at the camera: intensity / distance^2 when visible, else 0 */
	double rgb[3]; /* linear colour, max component 1 */
	bool visible; /* lit, in front of the camera and in the image, facing it, not hidden */
};

/*
 * Every lamp of every road user (in the scenario's order) into ret (at most max); returns how
 * many were written. cam in the ego frame. A headlamp shines into its body's forward half
 * space, a tail lamp into the backward one; a lamp is hidden when a body lies on the line from
 * the camera to it (more than 5 cm before it).
 */
int hl_world_scene_emitters(const struct hl_world_scene *ws, const struct hl_world_state *st,
			    const struct hl_camera *cam, struct hl_world_emitter *ret, int max);

/*
 * Adds the visible emitters to a display view (sRGB8, 3 bytes per pixel, width x height as
 * the camera, tone mapped as hl_view_display() with exposure_ev): each a small disc whose
 * luminance integrates over its pixels to the emitter's illuminance at the camera, so its
 * brightness and glow follow I / r^2.
 */
void hl_world_emitters_draw(const struct hl_camera *cam, const struct hl_world_emitter *e, int n,
			    double exposure_ev, uint8_t *rgb);
/*
 * The pixel boxes hl_world_emitters_draw() with the same arguments writes into: (x0, y0, x1,
 * y1) inclusive per drawn emitter, at most max; returns how many. A display buffer reused for
 * a later frame whose pass writes only lit pixels must clear them first.
 */
int hl_world_emitters_boxes(const struct hl_camera *cam, const struct hl_world_emitter *e, int n,
			    double exposure_ev, int (*ret)[4], int max);

#endif
