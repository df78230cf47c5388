/* SPDX-License-Identifier: MIT */
/*
 * The synthetic HD84 reference lamp (docs/design.md §1, docs/hd84-model.md) and pixel lamps
 * for scaling work. Both write plain hl_lid objects on the default grid: 900 x 250 samples,
 * 0.2°, H -89.9..+89.9, V -29.9..+19.9, type A.
 */
#ifndef HL_TOOLS_MODEL_H
#define HL_TOOLS_MODEL_H

#include "lamp/lid.h"
#include "lamp/preset.h"

#define HL_HD84_ROW_LEDS 28
#define HL_HD84_MATRIX 84 /* three rows of 28 */
#define HL_HD84_SOURCES 95 /* 84 matrix LEDs + 11 further sources */

/* 1-based indices of the further sources */
enum hl_hd84_extra {
	HL_HD84_APRON = 85,
	HL_HD84_BEND_LEFT,
	HL_HD84_BEND_RIGHT,
	HL_HD84_HB_SPOT,
	HL_HD84_HB_WIDE,
	HL_HD84_LB_BASE,
	HL_HD84_LB_RISE,
	HL_HD84_TOWN,
	HL_HD84_CORNER,
	HL_HD84_MOTORWAY,
	HL_HD84_SIGN,
};

/* The oncoming vehicle's window that the glare-free preset keeps dark, degrees. */
#define HL_GLAREFREE_H_MIN (-6.0f)
#define HL_GLAREFREE_H_MAX (-2.0f)
#define HL_GLAREFREE_V_MIN (-0.3f)
#define HL_GLAREFREE_V_MAX (2.0f)

void hl_model_default_grid(struct hl_lid_grid *ret);

/* The HD84 lamp of one side. 0, -ENOMEM. */
int hl_model_hd84(enum hl_side side, struct hl_lid **ret);

/* A pixel lamp: n matrix sources (1..4096) tiling H -20..+20, V -2..+4. 0, -EINVAL, -ENOMEM. */
int hl_model_pixel(int n, struct hl_lid **ret);

/*
 * Where hl_model_pixel(n) puts its sources: a grid of rows x cols cells tiling H h_min..h_max,
 * V v_min..v_max (degrees); source k (0-based) is the cell of row k / cols (row 0 at the top)
 * and column k % cols (increasing H). The last row may be short: rows * cols >= n.
 */
struct hl_pixel_layout {
	int n, rows, cols;
	float h_min_deg, h_max_deg, v_min_deg, v_max_deg;
};

/* 0 or -EINVAL for n outside 1..HL_LID_MAX_SOURCES. */
int hl_model_pixel_layout(int n, struct hl_pixel_layout *ret);
/* The cell of source k (0-based), degrees. */
void hl_model_pixel_cell(const struct hl_pixel_layout *l, int k, float *ret_h0, float *ret_h1,
			 float *ret_v0, float *ret_v1);

/* Names of the HD84 presets, NULL-terminated: low, high, glarefree, bend_left, bend_right. */
extern const char *const hl_model_preset_names[];

/*
 * Fills an HD84 preset by name. glarefree needs both lamps (it switches off every source that
 * lights the oncoming window). 0 or -EINVAL for an unknown name.
 */
int hl_model_hd84_preset(const char *name, struct hl_lid *const lamps[2], struct hl_preset *p);

/*
 * The high beam with every source that lights H h_min..h_max (degrees), V HL_GLAREFREE_V_MIN..
 * HL_GLAREFREE_V_MAX switched off, from the lamps' data: the glare-free preset for an oncoming
 * vehicle anywhere (the "glarefree" preset is H -6..-2).
 */
void hl_model_hd84_glarefree(struct hl_lid *const lamps[2], float h_min_deg, float h_max_deg,
			     struct hl_preset *p);

#endif
