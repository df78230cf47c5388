/* SPDX-License-Identifier: MIT */
/*
 * A lit frame composed into its pixels (hdlampd's render thread, once per frame): the display
 * view tone-mapped band by band while the renderer lights (hl_renderer_frame_pixels()), the
 * road users' lamps drawn over it as glows and the boxes they cover cleared before the buffer
 * is reused, and the HDR view packed into RGBA half floats. Images are row-major, row 0 at the
 * top; the caller owns every buffer.
 *
 * Thread-safety: pure functions of their arguments; hl_compose_display_band() runs on the
 * renderer's threads at once for disjoint bands of one image.
 */
#ifndef HL_RENDER_COMPOSE_H
#define HL_RENDER_COMPOSE_H

#include <stddef.h>
#include <stdint.h>

#include "render/scene.h"
#include "render/world_scene.h"
#include "world/camera.h"
#include "world/world.h"

/* The display pass of one frame: the userdata of hl_compose_display_band(). */
struct hl_compose_display {
	const struct hl_gbuffer *gb;
	double exposure_ev;
	uint8_t *rgb; /* sRGB8, 3 bytes per pixel of gb */
};

/*
 * An hl_renderer_pixels_fn (render/renderer.h) with a struct hl_compose_display: pixels
 * first .. first + count - 1 of lux tone-mapped into its rgb (hl_view_display_range()).
 */
void hl_compose_display_band(void *display, const float *lux, size_t first, size_t count);

/* Blacks out boxes[0 .. n - 1] ((x0, y0, x1, y1), inclusive) of an sRGB8 image width wide. */
void hl_compose_clear_boxes(uint8_t *rgb, int width, const int (*boxes)[4], int n);

/*
 * The road users' lamps of world state w as cam sees them (hl_world_scene_emitters() into
 * scratch, room for max_emitters) drawn into the display view rgb (cam's size) at exposure_ev;
 * the boxes drawn into go to ret_boxes (at most max_boxes), for hl_compose_clear_boxes() when
 * the buffer is used again. Returns how many boxes. Allocates nothing.
 */
int hl_compose_emitters(const struct hl_world_scene *ws, const struct hl_world_state *w,
			const struct hl_camera *cam, double exposure_ev,
			struct hl_world_emitter *scratch, int max_emitters, uint8_t *rgb,
			int (*ret_boxes)[4], int max_boxes);

/*
 * The HDR view of gb lit by lux (hl_view_hdr(): R = G = B = luminance, A = 1 where a surface
 * was hit) into ret_half as IEEE half floats, 4 per pixel; rgba is scratch of 4 floats per
 * pixel.
 */
void hl_compose_hdr(const struct hl_gbuffer *gb, const float *lux, float *rgba, uint16_t *ret_half);

#endif
