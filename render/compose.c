/* SPDX-License-Identifier: MIT */
/* A lit frame composed into its pixels: see render/compose.h. */
#include "render/compose.h"

#include <string.h>

#include "render/pixel.h"
#include "render/view.h"

void hl_compose_display_band(void *display, const float *lux, size_t first, size_t count)
{
	const struct hl_compose_display *j = display;

	hl_view_display_range(j->gb, lux, j->exposure_ev, first, count, j->rgb);
}

/*
 * The display pass rewrites only the pixels the ego lamps reach, so the road users' lamps drawn
 * when this buffer last held a frame are blacked out first, and written again after it.
 */
void hl_compose_clear_boxes(uint8_t *rgb, int width, const int (*boxes)[4], int n)
{
	for (int k = 0; k < n; k++) {
		const int *b = boxes[k];

		for (int y = b[1]; y <= b[3]; y++)
			memset(rgb + 3 * ((size_t)y * width + b[0]), 0,
			       3 * (size_t)(b[2] - b[0] + 1));
	}
}

int hl_compose_emitters(const struct hl_world_scene *ws, const struct hl_world_state *w,
			const struct hl_camera *cam, double exposure_ev,
			struct hl_world_emitter *scratch, int max_emitters, uint8_t *rgb,
			int (*ret_boxes)[4], int max_boxes)
{
	/* the road users' lamps, as the driver sees them */
	const int n = hl_world_scene_emitters(ws, w, cam, scratch, max_emitters);

	hl_world_emitters_draw(cam, scratch, n, exposure_ev, rgb);
	return hl_world_emitters_boxes(cam, scratch, n, exposure_ev, ret_boxes, max_boxes);
}

void hl_compose_hdr(const struct hl_gbuffer *gb, const float *lux, float *rgba, uint16_t *ret_half)
{
	const size_t n = (size_t)gb->width * gb->height * 4;

	hl_view_hdr(gb, lux, rgba);
	for (size_t i = 0; i < n; i++)
		ret_half[i] = hl_pixel_half_from_float(rgba[i]);
}
