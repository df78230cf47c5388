/* SPDX-License-Identifier: MIT */
/*
 * IES LM-63 photometric files (1991, 1995, 2002, 2019), read strictly.
 *
 * Accepted: the format line (IESNA91, IESNA:LM-63-1995, IESNA:LM-63-2002, IES:LM-63-2019), a
 * keyword block of "[KEYWORD] text" lines with "[MORE]" continuations, TILT=NONE, then the
 * numbers, separated by blanks, commas or line breaks and wrapped anywhere.
 * Refused with a message: TILT=INCLUDE and TILT=<file> (lamp-tilt tables, -ENOTSUP), anything
 * that is not a finite decimal number where one is expected, counts that do not match, angles
 * that do not increase or leave their range, negative candela values, trailing data.
 *
 * Candela values are multiplied by the candela multiplier and the ballast factor (and, before
 * 2019, the ballast-lamp photometric factor). Absolute photometry (lumens per lamp -1) and
 * relative photometry both give candela as the file states them.
 *
 * Photometric types: 1 = C, 2 = B, 3 = A. The horizontal angles are the table's planes
 * (C, or H for A and B), the vertical angles the in-plane angles (gamma, or V). Symmetric data
 * are mirrored as LM-63 defines: type C with the last horizontal angle 0 (one plane: rotational
 * symmetry), 90 (quadrant symmetry), 180 (symmetry about the C0-C180 plane), first 90 and last
 * 270 (symmetry about the C90-C270 plane), above 180 (full, closed at 360); types A and B with
 * the first horizontal angle 0 (lateral symmetry about H = 0). A vertical range that does not
 * reach the poles means no light outside it (zero), not a mirror.
 */
#ifndef HL_IMPORT_IES_H
#define HL_IMPORT_IES_H

#include <stddef.h>

#include "import/error.h"
#include "import/gonio.h"

struct hl_ies_info {
	char version[24]; /* "IESNA:LM-63-2002", ... */
	int photometric_type; /* 1 = C, 2 = B, 3 = A */
	int n_vertical, n_horizontal; /* as in the file, before mirroring */
	int n_lamps;
	double lumens_per_lamp; /* -1: absolute photometry */
	double candela_multiplier, ballast_factor, ballast_lamp_factor;
	double scale; /* the product applied to every candela value */
};

/*
 * Parses an IES file held in buf[0..len); name is used in messages only.
 * Returns 0, -EBADMSG (malformed; err says file, line, column and what was expected),
 * -ENOTSUP (valid LM-63 that hdlamp does not take: tilt tables), -ENOMEM.
 * ret_info (optional) receives what the header said; like *ret, only on success.
 * Thread-safety: reentrant (no shared state).
 */
int hl_ies_parse(const char *buf, size_t len, const char *name, struct hl_gonio **ret,
		 struct hl_ies_info *ret_info, struct hl_import_error *err);
/* The same from a file; also -ENOENT and other -errno of open/read. */
int hl_ies_read(const char *path, struct hl_gonio **ret, struct hl_ies_info *ret_info,
		struct hl_import_error *err);

#endif
