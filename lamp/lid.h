/* SPDX-License-Identifier: MIT */
/*
 * A lamp's luminous intensity distributions (LIDs): one candela grid per light source over
 * (H, V) at full current (docs/design.md §4/§5). Each source is stored only over its
 * non-zero bounding box, so a matrix LED that lights a few degrees costs a few kilobytes and a
 * combine touches only what is lit.
 *
 * Grid: column j is at h_first_deg + j * (h_last_deg - h_first_deg) / (width - 1); row 0 is the
 * highest V (v_last_deg), row height - 1 the lowest (v_first_deg). Dense buffers handed in and out
 * are width * height floats, row-major in that order.
 *
 * Thread-safety: an hl_lid is built by one thread; once built it is read-only and may be read
 * from any number of threads.
 */
#ifndef HL_RENDER_LID_H
#define HL_RENDER_LID_H

#include <stdbool.h>
#include <stddef.h>

#define HL_LID_MAX_SOURCES 4096

enum hl_angles {
	HL_ANGLES_A, /* turn about the vertical axis, then elevate */
	HL_ANGLES_B, /* tilt about the horizontal axis, then turn */
};

struct hl_lid_grid {
	int width; /* H samples */
	int height; /* V samples */
	enum hl_angles angles;
	float h_first_deg, h_last_deg; /* H of column 0 and of column width - 1 */
	float v_first_deg, v_last_deg; /* V of row height - 1 (lowest) and of row 0 (highest) */
};

/* Half-open box of samples: columns [x0, x1), rows [y0, y1). Empty when x0 == x1. */
struct hl_lid_box {
	int x0, y0, x1, y1;
};

/* Human-readable reason for a failed load or save; always names the file. */
struct hl_lid_error {
	char msg[512];
};

struct hl_lid;

/*
 * A lamp with n_sources sources, all zero, on the given grid. A "combined" lid holds one
 * distribution (channel "I" in files) instead of sources "src0001"...
 * Returns 0, -EINVAL for a bad grid or count, -ENOMEM.
 */
int hl_lid_new(int n_sources, const struct hl_lid_grid *grid, bool combined, struct hl_lid **ret);
void hl_lid_free(struct hl_lid *lid);

/* Validates a grid: sizes >= 2, first < last, angles inside the sphere. 0 or -EINVAL. */
int hl_lid_grid_check(const struct hl_lid_grid *grid);

/*
 * Sets source k (0-based) from a dense width * height buffer, which it copies over its
 * non-zero box. Values must be finite and >= 0: -EINVAL otherwise (nothing changed).
 * Allocates; for building lamps, not for the per-frame path.
 */
int hl_lid_set_source(struct hl_lid *lid, int k, const float *dense);
/* Name of source k (copied); NULL clears it. 0, -EINVAL, -ENOMEM. */
int hl_lid_set_name(struct hl_lid *lid, int k, const char *name);

const struct hl_lid_grid *hl_lid_grid(const struct hl_lid *lid);
int hl_lid_n_sources(const struct hl_lid *lid);
bool hl_lid_is_combined(const struct hl_lid *lid);
/* Name of source k or NULL; owned by the lid. */
const char *hl_lid_name(const struct hl_lid *lid, int k);

/*
 * Source k over its box: returns the first sample (row-major, stride box width), owned by the
 * lid, NULL for an empty box. *ret_box receives the box.
 */
const float *hl_lid_source(const struct hl_lid *lid, int k, struct hl_lid_box *ret_box);
/* Highest sample of source k, cd. */
float hl_lid_peak_cd(const struct hl_lid *lid, int k);
/* Writes source k densely into out (width * height floats). */
void hl_lid_source_dense(const struct hl_lid *lid, int k, float *out);

/* Angles of a sample, degrees. */
float hl_lid_grid_h_deg(const struct hl_lid_grid *grid, int col);
float hl_lid_grid_v_deg(const struct hl_lid_grid *grid, int row);

/*
 * Bilinear lookup of a dense grid at (h_deg, v_deg): samples at texel centres, zero outside
 * the measured range (no smearing of edge values).
 */
float hl_lid_grid_lookup(const struct hl_lid_grid *grid, const float *dense, float h_deg,
			 float v_deg);

/* True when a and b sample the same directions: size, angle system and extents all equal. */
bool hl_lid_grid_equal(const struct hl_lid_grid *a, const struct hl_lid_grid *b);

/*
 * Files (OpenEXR, docs/lid-files.md). Reading accepts FLOAT or HALF channels and validates
 * everything; writing stores FLOAT channels, ZIP compressed.
 * Read returns 0, -ENOENT (no such file), -EBADMSG (not a valid LID file), -EINVAL
 * (inconsistent grid attributes), -ENOMEM. err (optional) says what and where.
 */
int hl_lid_read(const char *path, struct hl_lid **ret, struct hl_lid_error *err);
/* Write returns 0, -ENOMEM, the failed open or write's -errno (-ENOSPC, -EFBIG, ...) or -EIO. */
int hl_lid_write(const struct hl_lid *lid, const char *path, struct hl_lid_error *err);

/* Writes one dense distribution as a combined LID file (channel "I"). */
int hl_lid_write_combined(const struct hl_lid_grid *grid, const float *dense, const char *path,
			  struct hl_lid_error *err);

#endif
