/* SPDX-License-Identifier: MIT */
/* A 5 x 7 bitmap font for labels on plots (digits, upper case, a little punctuation). */
#ifndef HL_RENDER_FONT_H
#define HL_RENDER_FONT_H

#include <stdint.h>

#define HL_FONT_W 5
#define HL_FONT_H 7
#define HL_FONT_ADVANCE 6 /* pixels per character at scale 1 */

/* Draws text into an RGB8 image (w x h, stride 3 * w), clipped; lower case is drawn as upper. */
void hl_font_draw(uint8_t *rgb, int w, int h, int x, int y, int scale, const char *text,
		  const uint8_t colour[3]);
/* Width in pixels of text at scale. */
int hl_font_width(const char *text, int scale);

#endif
