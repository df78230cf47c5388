/* SPDX-License-Identifier: MIT */
/*
 * The H-V diagram of a distribution, like the papers' intensity plots: candela on a log colour
 * scale (5 decades below the decade above the peak; black below), grid lines every 10° H and
 * 5° V, axes in degrees, a legend, written as an RGB PNG.
 */
#ifndef HL_RENDER_PLOT_H
#define HL_RENDER_PLOT_H

#include <stddef.h>
#include <stdint.h>

#include "lamp/lid.h"

/* Colour of a value t in [0, 1] on the scale (turbo), RGB8. */
void hl_plot_colour(float t, uint8_t ret_rgb[3]);

/* Writes an RGB8 image as PNG. 0 or -errno (-EIO when libpng fails). */
int hl_png_write_rgb(const char *path, const uint8_t *rgb, int w, int h);
/*
 * The same PNG into memory: rows of stride bytes (>= 3 * w). *ret_data is malloc'd (the caller
 * frees it) and holds *ret_size bytes; both untouched on failure. 0, -EINVAL, -ENOMEM, -EIO.
 */
int hl_png_encode_rgb(const uint8_t *rgb, int w, int h, size_t stride, uint8_t **ret_data,
		      size_t *ret_size);

/* Draws dense (grid layout, cd) with title to path. 0, -ENOMEM, -EIO, -errno. */
int hl_plot_lid_png(const struct hl_lid_grid *g, const float *dense, const char *title,
		    const char *path);

#endif
