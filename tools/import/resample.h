/* SPDX-License-Identifier: MIT */
/*
 * Resampling a measured distribution onto a LID grid. Every grid sample (H, V), in the grid's
 * angle system (A or B, DESIGN.md §4), becomes a lamp-space direction and then the table's own
 * angles (A, B or C); the table is interpolated there (bilinear in its own angles, zero outside
 * its coverage, gonio.h). No angle system is approximated by another: the conversions go
 * through the exact direction vector (render/angles.h, typec.h).
 */
#ifndef HL_IMPORT_RESAMPLE_H
#define HL_IMPORT_RESAMPLE_H

#include "render/lid.h"
#include "tools/import/gonio.h"

/* Fills dense (grid->width * grid->height floats, row 0 = highest V) with g on the grid. */
void hl_resample(const struct hl_gonio *g, const struct hl_lid_grid *grid, float *dense);

/* The table's own angles of grid sample (col, row), degrees. */
void hl_resample_sample_angles(const struct hl_lid_grid *grid, int col, int row,
			       enum hl_gonio_system system, double *ret_plane_deg,
			       double *ret_in_deg);

#endif
