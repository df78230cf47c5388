/* SPDX-License-Identifier: MIT */
/*
 * EULUMDAT (.ldt) files, read strictly: one field per line in the order of the format
 * (company, type and symmetry indicators, Mc, Dc, Ng, Dg, five text lines, dimensions, DFF,
 * LORL, conversion factor, tilt, lamp sets field by field, ten direct ratios, Mc C angles,
 * Ng gamma angles, then the intensities plane by plane).
 *
 * Intensities are in cd per 1000 lm of lamp flux: each value is multiplied by the total flux of
 * all lamp sets / 1000 and by the conversion factor, giving cd. (A negative number of lamps
 * marks absolute photometry, where the flux field holds the luminaire's flux; the same
 * scaling then gives the absolute candela.)
 *
 * Symmetry indicators and the planes stored (Mc C angles are always listed):
 *   0  none                       Mc planes, C0 .. C(360 - Dc)
 *   1  about the vertical axis    1 plane
 *   2  about the C0-C180 plane    Mc/2 + 1 planes, C0 .. C180
 *   3  about the C90-C270 plane   Mc/2 + 1 planes, C90 .. C270
 *   4  about both planes          Mc/4 + 1 planes, C0 .. C90
 * and are expanded to the full circle. The result is a type C table (see typec.h).
 */
#ifndef HL_IMPORT_EULUMDAT_H
#define HL_IMPORT_EULUMDAT_H

#include <stddef.h>

#include "import/error.h"
#include "import/gonio.h"

struct hl_eulumdat_info {
	int type_indicator; /* Ityp 0..3 */
	int symmetry; /* Isym 0..4 */
	int n_c_planes; /* Mc */
	int n_gamma; /* Ng */
	int n_planes_stored;
	int n_lamp_sets;
	double lamp_flux_lm; /* sum over the lamp sets */
	double conversion_factor;
	double scale; /* applied to every value: lamp_flux_lm / 1000 * conversion_factor */
};

/*
 * 0, -EBADMSG (err: file, line, what was expected), -ENOMEM. ret_info (optional) receives
 * the header's facts, like *ret only on success. Thread-safety: reentrant.
 */
int hl_eulumdat_parse(const char *buf, size_t len, const char *name, struct hl_gonio **ret,
		      struct hl_eulumdat_info *ret_info, struct hl_import_error *err);
/* The same from a file; also -ENOENT and other -errno of open/read. */
int hl_eulumdat_read(const char *path, struct hl_gonio **ret, struct hl_eulumdat_info *ret_info,
		     struct hl_import_error *err);

#endif
