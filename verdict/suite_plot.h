/* SPDX-License-Identifier: MIT */
/*
 * The geometry of a suite plot (hl_suite_plot_svg, verdict/suite_result.h), for readers of the
 * SVG and its tests. Pixel coordinates are written with one decimal ("%.1f").
 *
 * Illuminance against range: the plot box spans x LEFT..RIGHT, y TOP..BOTTOM (pixels, y down).
 *   Range axis (linear, increasing to the right): the variant's range_m rounded out to a step of
 *   1, 2 or 5 x 10^k, the smallest that needs at most X_STEPS steps:
 *     step = that of (hi - lo) / X_STEPS, x_lo = floor(lo / step) step, x_hi = ceil(hi / step) step,
 *     x(r) = LEFT + (r - x_lo) / (x_hi - x_lo) (RIGHT - LEFT).
 *   Illuminance axis (log10, decades): LX_MIN at the bottom, top the decade at or above the
 *   largest finite value of every series and every limit, within LX_TOP_MIN..LX_TOP_MAX:
 *     y(lx) = BOTTOM - log10(lx / LX_MIN) / log10(top / LX_MIN) (BOTTOM - TOP),
 *   lx <= LX_MIN (zero, negative) drawn at BOTTOM, lx >= top at TOP; samples with a NaN range or
 *   illuminance, or a range off the axis, break the line.
 *   Elements: class "series" (a polyline per unbroken run of a series, data-series its index),
 *   "limit" (one horizontal line per bin of the series' role with a limit, at y(max_lx)),
 *   "limit-riser" (the step between adjacent bins), "over" (red overlay of samples whose value as
 *   judged exceeds their bin's limit) and "over-band" (the shaded range of such a stretch).
 *   A sample is in a bin when its range to 0.1 m, as the tables write it, is within from..to.
 *
 * Bird's-eye (has_birdseye): world x to the right, y up (north-up), one scale for both, the
 * bounding box of the edges, the ego and the visibility points, padded by PAD, centred in the
 * same plot box. Elements: "edge", "ego", "vis", "scale".
 */
#ifndef HL_VERDICT_SUITE_PLOT_H
#define HL_VERDICT_SUITE_PLOT_H

#define HL_SUITE_PLOT_WIDTH 880 /* px, the whole document */
#define HL_SUITE_PLOT_HEIGHT 520 /* px */
#define HL_SUITE_PLOT_LEFT 80.0 /* px, x of the range axis's start */
#define HL_SUITE_PLOT_RIGHT 660.0 /* px, x of its end (the legend is to the right) */
#define HL_SUITE_PLOT_TOP 70.0 /* px, y of the top decade */
#define HL_SUITE_PLOT_BOTTOM 450.0 /* px, y of LX_MIN */
#define HL_SUITE_PLOT_X_STEPS 8 /* at most this many tick steps on the range axis */
#define HL_SUITE_PLOT_LX_MIN 0.01 /* lx, the bottom of the log axis */
#define HL_SUITE_PLOT_LX_TOP_MIN 100.0 /* lx, the top decade is at least this */
#define HL_SUITE_PLOT_LX_TOP_MAX 1e6 /* lx, and at most this: larger values clamp to it */
#define HL_SUITE_PLOT_PAD 0.05 /* bird's-eye: the bounding box grown by this share per side */

#endif
