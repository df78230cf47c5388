/* SPDX-License-Identifier: MIT */
/*
 * Writing a LID source back out as a goniometer table: IES LM-63-2019 (photometric type 1 = C,
 * 2 = B or 3 = A) or CSV (csv.h), so a source or a combined distribution can go to another
 * tool and round trips can be tested.
 *
 * Sampling (hl_export_sample): the table's angles are
 *   - fine: every step_deg over the region where the source is lit (its non-zero samples,
 *     converted to the table's angles, plus a margin of two grid steps and two table steps);
 *     when the table's system is the grid's and step_deg is the grid step, these are exactly
 *     the grid's sample angles, so the values are the grid's own;
 *   - coarse: every 5 degrees over the format's full range (A, B: H and V -90..90; C: C 0..360,
 *     gamma 0..180), so the file covers what readers expect; outside the lit region these are 0.
 *   - refined: when the table's directions are not the grid's (B for an A grid; A or C for a
 *     B grid), intervals where linear interpolation would miss the light by more than 0.1 %
 *     (of the value, at least of 1 % of the peak) are cut into up to 16 parts.
 * Values are the LID between its samples (a Catmull-Rom spline through them, clamped at 0:
 * exact at the samples) at each table direction, converted exactly through the direction
 * vector.
 *
 * Thread-safety: reentrant; the lid is only read.
 */
#ifndef HL_IMPORT_EXPORT_H
#define HL_IMPORT_EXPORT_H

#include <stdio.h>

#include "lamp/lid.h"
#include "import/gonio.h"

#define HL_EXPORT_COARSE_DEG 5.0 /* step of the frame outside the lit region, degrees */
#define HL_EXPORT_MAX_ANGLES 100000 /* per axis, as the IES and CSV readers accept */
#define HL_EXPORT_MAX_VALUES (16L << 20) /* per table, as the IES and CSV readers accept */

/*
 * Source k (0-based) of lid as a table in the given system. step_deg <= 0 picks the default:
 * the grid step (the smaller of H and V) when system is the grid's, a quarter of it otherwise.
 * Returns 0, -EINVAL (bad k or step), -EFBIG (the table would exceed HL_EXPORT_MAX_ANGLES or
 * HL_EXPORT_MAX_VALUES: choose a coarser step), -ENOMEM.
 */
int hl_export_sample(const struct hl_lid *lid, int k, enum hl_gonio_system system, double step_deg,
		     struct hl_gonio **ret);

struct hl_export_meta {
	const char *name; /* [LUMCAT], CSV comment; may be NULL */
	const char *origin; /* [LUMINAIRE], e.g. "source 3 of hd84_left.lid.exr"; may be NULL */
	const char *issue_date; /* [ISSUEDATE], e.g. "2026-11-21"; may be NULL */
};

/* Writes g as IES LM-63-2019 with TILT=NONE, absolute photometry. 0 or -errno (write). */
int hl_export_ies(const struct hl_gonio *g, const struct hl_export_meta *meta, FILE *f);
/* Writes g as CSV: header row system letter + column angles, rows by decreasing row angle. */
int hl_export_csv(const struct hl_gonio *g, const struct hl_export_meta *meta, FILE *f);

#endif
