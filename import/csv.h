/* SPDX-License-Identifier: MIT */
/*
 * CSV goniometer tables, as spreadsheets and goniophotometer software export them:
 *
 *   # comment lines start with '#'; blank lines are skipped
 *   A,  -10, -9.8, ..., 10        <- header: the angle system, then the column angles
 *   5,  0.0, 12.5, ..., 0.0       <- one row per row angle: the angle, then one value per column
 *   4.8, ...
 *
 * The first cell of the header states the angle system: A or B (columns H, rows V, degrees)
 * or C (columns C, rows gamma, degrees; see typec.h). Cells are separated by commas; blanks
 * around a cell are ignored. Values are luminous intensities in cd, finite and >= 0. Column
 * and row angles must each be strictly monotonic, increasing or decreasing, and inside the
 * system's ranges (gonio.h); at least two of each. There is no symmetry: outside the table the
 * intensity is zero (a type C table spanning exactly 0..360 wraps).
 */
#ifndef HL_IMPORT_CSV_H
#define HL_IMPORT_CSV_H

#include <stddef.h>

#include "import/error.h"
#include "import/gonio.h"

/*
 * 0, -EBADMSG (err: file, line, column, what was expected), -ENOMEM.
 * Thread-safety: reentrant.
 */
int hl_csv_parse(const char *buf, size_t len, const char *name, struct hl_gonio **ret,
		 struct hl_import_error *err);
/* The same from a file; also -ENOENT and other -errno of open/read. */
int hl_csv_read(const char *path, struct hl_gonio **ret, struct hl_import_error *err);

#endif
