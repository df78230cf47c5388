/* SPDX-License-Identifier: MIT */
/*
 * Pixel conversions shared by the views, the EXR writer and the outputs: the sRGB transfer curve
 * to 8 bits, the display tone map of a luminance, and IEEE 754 half floats (RGBA16F frames,
 * EXR HALF channels).
 *
 * Thread-safety: pure functions, any thread.
 */
#ifndef HL_RENDER_PIXEL_H
#define HL_RENDER_PIXEL_H

#include <stdint.h>

/* Linear [0, 1] to an sRGB 8-bit level, rounded to nearest; <= 0 and NaN give 0, >= 1 255. */
uint8_t hl_pixel_srgb8(float linear);

/*
 * A luminance (cd/m²) to the display view's sRGB 8-bit level at exposure 0: L / π through
 * x / (1 + x), then the sRGB curve. <= 0 and NaN give 0.
 */
uint8_t hl_pixel_display8(float luminance);

/* Float to half: round to nearest even, overflow to ±inf, NaN stays NaN (quiet). */
uint16_t hl_pixel_half_from_float(float f);
/* Half to float (exact: every half is a float). */
float hl_pixel_half_to_float(uint16_t h);

#endif
