/* SPDX-License-Identifier: MIT */
/*
 * Labels over a view of the ground (the bird scene): the distance lines with their distance
 * ("10 M", "20 M", ...) and iso-lux lines with their level ("1 LX", "3 LX", ...), drawn into a
 * caller's RGB8 image in the 5 x 7 font (render/font.h) on a black box so they read on any
 * background.
 *
 *   distance labels  centred on the image point of (x, label_y_m, 0) for x = step, 2 step, ...
 *                    up to last_m; a label that would overlap one already drawn is left out
 *   iso-lux lines    the pixels at or above a level next to one below it (4-neighbours), in
 *                    the level's colour (hl_overlay_iso_colour); both sides of the boundary
 *                    when the font scale is 2 or more, so they stay visible in large images
 *   iso-lux labels   "<level> LX" in the line's colour beside the line's farthest point to the
 *                    right of the image (in the bird scene: the farthest forward, the tip of the
 *                    area), moved up or down by up to two label heights when it would cover
 *                    another label, left out when that is not enough (small images)
 *
 * Thread-safety: pure functions of their arguments; any thread. Nothing is allocated.
 */
#ifndef HL_RENDER_OVERLAY_H
#define HL_RENDER_OVERLAY_H

#include <stdbool.h>
#include <stdint.h>

#include "world/camera.h"
#include "render/scene.h"

#define HL_OVERLAY_MAX_ISO 16

struct hl_overlay_opts {
	int n_iso;
	double iso_lx[HL_OVERLAY_MAX_ISO]; /* levels, lux */
	bool iso_lines; /* draw the lines; false when the view drew them already (the lux view) */
	bool iso_white; /* lines and labels white instead of each level's colour */
	double distance_step_m; /* 10; 0 draws no distance labels */
	double distance_last_m; /* the last distance labelled (140: the road's end) */
	double label_y_m; /* lateral position of the distance labels (vehicle frame, y left) */
	int scale; /* font scale; 0: 2 from 960 pixels wide, else 1 */
	int keep_clear[4]; /* x0, y0, x1, y1 (half-open) no label may cover, e.g. a legend */
};

/*
 * 1, 3, 10, 30 lx in colour, lines drawn; the bird scene's distance lines (every 10 m to the
 * road's end, 140 m), labelled at y = 12 m.
 */
void hl_overlay_defaults(struct hl_overlay_opts *ret);

/* The colour of iso level k (0-based, in the order of iso_lx). */
void hl_overlay_iso_colour(int k, uint8_t ret_rgb[3]);

/*
 * Draws into rgb (cam->width x cam->height, 3 bytes per pixel, row 0 at the top) the labels of
 * o. gb is the frame's G-buffer and lux its illuminance (same size; cam the camera gb was
 * rendered with): iso-lux lines are drawn on the ground only (z = 0, normal up), so the lit
 * sides of posts make none.
 */
void hl_overlay_draw(const struct hl_camera *cam, const struct hl_gbuffer *gb, const float *lux,
		     const struct hl_overlay_opts *o, uint8_t *rgb);

#endif
