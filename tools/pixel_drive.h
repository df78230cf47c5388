/* SPDX-License-Identifier: MIT */
/*
 * The pixel lamp's drive (hdlamp scenario for lamps of hdlamp model --sources N): raw 6-bit
 * dimming values of both lamps for each cycle of a phase, so that every cycle differs from the
 * one before and a receiver's mistakes (a page, a slot, a bit, a lamp swapped) show:
 *   glarefree  high beam with an oncoming vehicle's window (4° wide, V -0.3..+2) moving from
 *              H -20 to +20 over the phase; every source whose cell touches it is off;
 *   sweep      low beam with a bright bar three columns wide sweeping from left to right;
 *   ramp       every value 0..63 in every page: left v_k = (k + c) mod 64, right 63 minus it.
 */
#ifndef HL_TOOLS_PIXEL_DRIVE_H
#define HL_TOOLS_PIXEL_DRIVE_H

#include "lamp/model.h"
#include "lamp/preset.h"

enum hl_pixel_phase {
	HL_PIXEL_GLAREFREE,
	HL_PIXEL_SWEEP,
	HL_PIXEL_RAMP,
};

#define HL_PIXEL_WINDOW_W_DEG 4.0f /* the oncoming vehicle's window */
#define HL_PIXEL_BAR_COLS 3 /* the sweep's bar */

/*
 * Fills p (p->n_sources == l->n) with cycle c (0-based) of a phase of n_cycles cycles.
 * 0, -EINVAL (unknown phase, c outside 0..n_cycles-1, sources mismatch).
 */
int hl_pixel_drive(const struct hl_pixel_layout *l, enum hl_pixel_phase phase, int c, int n_cycles,
		   struct hl_preset *p);

/* The centre of the glare-free window in cycle c of n_cycles, degrees H. */
float hl_pixel_drive_window_deg(int c, int n_cycles);

#endif
