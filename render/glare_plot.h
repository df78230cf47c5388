/* SPDX-License-Identifier: MIT */
/*
 * The glare timeline (docs/scenarios.md, "Glare at road users' eyes"): the rows of
 * hl_glare_eval() over scenario time drawn as an RGB image, one colour per road user labelled
 * with its id.
 *
 * Top panel: the intensity toward the eye on half the pair's sum (cd, log scale), what the ADB
 * glare limit applies to, with each road user's limit as a dashed step line in its colour.
 * Bottom panel: the illuminance at the eye E = sum I / r^2 (lux, log scale). Values at or below
 * a panel's lowest decade (0 behind the lamps) lie on its bottom edge. Where a road user
 * is over its limit, its curves are drawn in the failure colour HL_GLARE_PLOT_FAIL_RGB. Under the
 * panels, one status track per road user along the same time axis: HL_GLARE_PLOT_FAIL_RGB where
 * it fails, HL_GLARE_PLOT_PASS_RGB where it passes, grey where its class has no limit. Each
 * frame owns the time from halfway after the previous frame to halfway before the next.
 *
 * Thread-safety: pure functions of their arguments.
 */
#ifndef HL_RENDER_GLARE_PLOT_H
#define HL_RENDER_GLARE_PLOT_H

#include <stdint.h>

#include "verdict/glare.h"
#include "world/scenario.h"

/* The image's size in pixels for n road users. */
#define HL_GLARE_PLOT_W 1000
#define HL_GLARE_PLOT_H(n) (572 + 14 * (n))
#define HL_GLARE_PLOT_FAIL_RGB \
	{                      \
		255, 50, 50    \
	}
#define HL_GLARE_PLOT_PASS_RGB \
	{                      \
		60, 230, 90    \
	}

/*
 * rows: n_frames frames of sc->n_actors results each, frame after frame as hl_glare_eval()
 * fills them, times increasing; title: the first line (NULL: none). *ret_rgb is malloc'd
 * (*ret_w x *ret_h, stride 3 * *ret_w; the caller frees it); untouched on failure.
 * 0, -EINVAL (no frame or road user, times not increasing), -ENOMEM.
 */
int hl_glare_plot_rgb(const struct hl_scenario *sc, const struct hl_glare_result *rows,
		      int n_frames, const char *title, uint8_t **ret_rgb, int *ret_w, int *ret_h);

/* The same image written as a PNG to path. 0, -EINVAL, -ENOMEM, -EIO, -errno. */
int hl_glare_plot_png(const struct hl_scenario *sc, const struct hl_glare_result *rows,
		      int n_frames, const char *title, const char *path);

#endif
