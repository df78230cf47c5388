/* SPDX-License-Identifier: MIT */
/*
 * Resampling a measured distribution onto a LID grid. Every grid sample (H, V), in the grid's
 * angle system (A or B, design.md §4), becomes a lamp-space direction and then the table's own
 * angles (A, B or C); the table is interpolated there (bilinear in its own angles, zero outside
 * its coverage, gonio.h). No angle system is approximated by another: the conversions go
 * through the exact direction vector (render/angles.h, typec.h).
 *
 * Thread-safety: reentrant; tables and grids are only read.
 */
#ifndef HL_IMPORT_RESAMPLE_H
#define HL_IMPORT_RESAMPLE_H

#include "lamp/lid.h"
#include "import/gonio.h"

/*
 * The grid's ends as the decimals they were written as: the shortest decimal that rounds to
 * the stored float (-89.9f is -89.90000153 as a double; here it is -89.9). Sample angles are
 * computed from these, so a table written at -89.9 + j * 0.2 meets the samples exactly.
 */
void hl_resample_grid_ends(const struct hl_lid_grid *grid, double *ret_h_first, double *ret_h_last,
			   double *ret_v_first, double *ret_v_last);

/* Fills dense (grid->width * grid->height floats, row 0 = highest V) with g on the grid. */
void hl_resample(const struct hl_gonio *g, const struct hl_lid_grid *grid, float *dense);

/* The table's own angles of grid sample (col, row), degrees. */
void hl_resample_sample_angles(const struct hl_lid_grid *grid, int col, int row,
			       enum hl_gonio_system system, double *ret_plane_deg,
			       double *ret_in_deg);

#endif
