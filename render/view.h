/* SPDX-License-Identifier: MIT */
/*
 * Views of a lit frame, into caller-owned buffers (row 0 at the top):
 *   luminance  albedo * E / pi, cd/m^2 (diffuse surfaces)
 *   hdr        linear luminance as RGBA floats (R = G = B = L, A = 1 where a surface was hit)
 *   display    tone-mapped sRGB8: L * 2^EV through x / (1 + x), then the sRGB curve
 *   lux        illuminance in false colour (turbo) on a log scale, iso-lux lines, a legend
 * The lid view (H-V diagram of a combined distribution) is hl_plot_lid_png() in render/plot.h.
 *
 * Thread-safety: pure functions of their arguments; any thread.
 */
#ifndef HL_RENDER_VIEW_H
#define HL_RENDER_VIEW_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "render/scene.h"

enum hl_view_kind {
	HL_VIEW_DISPLAY,
	HL_VIEW_HDR,
	HL_VIEW_LUX,
	HL_VIEW_LID,
};

#define HL_VIEW_MAX_ISO 16

struct hl_view_lux_opts {
	double min_lx, max_lx; /* colour scale; below min is black */
	int n_iso;
	double iso_lx[HL_VIEW_MAX_ISO]; /* iso-lux levels, drawn as white lines */
	bool legend;
};

/* "display", "hdr", "lux", "lid"; -EINVAL otherwise. */
int hl_view_from_name(const char *name);
const char *hl_view_name(enum hl_view_kind kind);

/* Scale 0.1 .. 1000 lx, iso lines at 1, 3, 5, 10, 20, 50 lx, with a legend. */
void hl_view_lux_defaults(struct hl_view_lux_opts *ret);

void hl_view_luminance(const struct hl_gbuffer *gb, const float *lux, float *ret_cd_m2);
void hl_view_hdr(const struct hl_gbuffer *gb, const float *lux, float *ret_rgba);
/* ret_rgb: 3 bytes per pixel. */
void hl_view_display(const struct hl_gbuffer *gb, const float *lux, double exposure_ev,
		     uint8_t *ret_rgb);
/* The display view of pixels first .. first + count - 1 only (ret_rgb: the whole image). */
void hl_view_display_range(const struct hl_gbuffer *gb, const float *lux, double exposure_ev,
			   size_t first, size_t count, uint8_t *ret_rgb);
/*
 * The pixels the lux view's legend covers in a w x h image: x0, y0, x1, y1 (half-open; all 0
 * when the image is too small for a legend).
 */
void hl_view_lux_legend_box(int w, int h, int ret_box[4]);
/* ret_rgb: 3 bytes per pixel. lux of a width x height image; gb marks the sky (id 0). */
void hl_view_lux(const struct hl_gbuffer *gb, const float *lux, const struct hl_view_lux_opts *opts,
		 uint8_t *ret_rgb);

#endif
