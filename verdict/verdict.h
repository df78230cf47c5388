/* SPDX-License-Identifier: MIT */
/*
 * The verdict evaluator (docs/verdicts.md): a regulation set (verdict/regulation.h) checked on a
 * distribution on a LID grid. hl_verdict_new() turns every requirement into a plan once: the
 * positions it is measured at (a point, every 0.1° along a segment, a 0.1° lattice over a zone
 * and its edges) and, for each position, the weights of the grid samples that make the mean
 * intensity over the regulation's receiver there (receiver averaging of the bilinear grid, by
 * a fixed quadrature). A frame (hl_verdict_eval) is then only weighted sums: no allocation, no
 * trigonometry.
 *
 * Traffic: right-hand as the files are written; left-hand mirrors every H. Aim: a shift
 * (dh, dv) of the beam, applied as value(h, v) = I(h - dh, v - dv); mounted is (0, 0) for a
 * bare lamp file, the lamp's pose in the daemon, and the regulation's aim comes from
 * hl_verdict_find_cutoff().
 *
 * Positions outside the grid are not measured: they are left out and counted (n_outside); a
 * requirement with no measured position has value NaN and fails.
 *
 * Thread-safety: a verdict is built by one thread and read-only afterwards; hl_verdict_eval()
 * may run on several threads at once with their own result arrays.
 */
#ifndef HL_VERDICT_VERDICT_H
#define HL_VERDICT_VERDICT_H

#include <stdbool.h>
#include <stddef.h>

#include "lamp/lid.h"
#include "verdict/regulation.h"

enum hl_traffic {
	HL_TRAFFIC_RIGHT,
	HL_TRAFFIC_LEFT,
};

struct hl_verdict_options {
	enum hl_traffic traffic;
	double aim_h_deg, aim_v_deg; /* the shift of the beam, degrees */
};

/* One requirement's outcome on one distribution. */
struct hl_req_result {
	double value_cd; /* the point's mean, the sum, the segment's or zone's deciding extreme */
	double at_h_deg, at_v_deg; /* where the deciding value is (in the regulation's frame) */
	double min_cd, max_cd; /* the limits in cd (relative ones resolved), NaN when absent */
	double margin; /* (value - min) / min or (max - value) / max, the smaller; < 0 fails */
	int n_outside; /* positions outside the measured grid */
	bool pass;
};

struct hl_verdict;

/*
 * Plans reg on grid. 0, -EINVAL (bad options), -ENOMEM. reg must outlive the verdict.
 */
int hl_verdict_new(const struct hl_regulation *reg, const struct hl_lid_grid *grid,
		   const struct hl_verdict_options *opts, struct hl_verdict **ret);
void hl_verdict_free(struct hl_verdict *v);

const struct hl_regulation *hl_verdict_regulation(const struct hl_verdict *v);

/*
 * Evaluates on a (width * height floats, cd) or, with b not NULL, on half the sum (a + b) / 2
 * of two distributions on the same grid. Writes reg->n_requirements results; returns whether
 * every requirement passed. Allocates nothing.
 */
bool hl_verdict_eval(const struct hl_verdict *v, const float *a, const float *b,
		     struct hl_req_result *ret);

/*
 * A distribution's highest sample and its index (row-major on the grid): what every Imax
 * requirement of a frame reads. Computing it once per distribution and frame and handing it to
 * hl_verdict_eval_peak() saves a scan of the whole grid per set.
 */
struct hl_verdict_peak {
	float value_cd;
	size_t index;
};

/* The peak of a, or of (a + b) / 2 with b not NULL (n samples). */
void hl_verdict_peak(size_t n, const float *a, const float *b, struct hl_verdict_peak *ret);
/*
 * Copies n samples from src to dst and finds their peak on the way: a frame that copies its
 * distributions anyway gets the peak for almost nothing (the copy is memory-bound).
 */
void hl_verdict_copy_peak(float *restrict dst, const float *restrict src, size_t n,
			  struct hl_verdict_peak *ret);
/* Whether the set has an Imax requirement (reads the peak). */
bool hl_verdict_needs_peak(const struct hl_verdict *v);
/*
 * hl_verdict_eval() with the peak of the same a (and b) given; NULL computes it (as
 * hl_verdict_eval() does).
 */
bool hl_verdict_eval_peak(const struct hl_verdict *v, const float *a, const float *b,
			  const struct hl_verdict_peak *peak, struct hl_req_result *ret);

/* The receiver's mean intensity at (h, v) of a dense distribution: the same quadrature. */
double hl_verdict_receiver_mean(const struct hl_lid_grid *grid, const float *dense,
				enum hl_receiver_shape shape, double size_deg, double h_deg,
				double v_deg);

/* The cut-off found on a vertical scan (R149 Annex, cut-off quality and vertical aim). */
struct hl_cutoff {
	double v_deg; /* inflection point of log I at scan_h (the position of the largest G) */
	double g; /* sharpness G = log10 I(b) - log10 I(b + 0.1°) at that position */
	double v_lin_deg[3]; /* the inflection points at the three linearity scans */
	double linearity_deg; /* their largest vertical distance */
	bool sharp_ok, linear_ok;
};

/*
 * Scans at reg's aim_scan_h_deg (mirrored for left-hand traffic) from v_lo to v_hi upward in
 * 0.05° steps, receiver means at each step, and finds the largest G. 0, or -ENOENT when the
 * scan finds no cut-off (no step where the intensity falls by G > 0 with both values > 0).
 */
int hl_verdict_find_cutoff(const struct hl_regulation *reg, const struct hl_lid_grid *grid,
			   const float *dense, enum hl_traffic traffic, struct hl_cutoff *ret);

#endif
