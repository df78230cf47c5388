/* SPDX-License-Identifier: MIT */
/*
 * Building a lamp from measured files: each source of the manifest is read (IES, EULUMDAT or
 * CSV), resampled onto the manifest's grid (resample.h) and named.
 * Thread-safety: reentrant.
 */
#ifndef HL_IMPORT_IMPORT_H
#define HL_IMPORT_IMPORT_H

#include "lamp/lid.h"
#include "import/error.h"
#include "import/gonio.h"
#include "import/manifest.h"

/* Reads one measured file in the given format. 0 or the reader's -errno; err says where. */
int hl_import_load(const char *path, enum hl_import_format format, struct hl_gonio **ret,
		   struct hl_import_error *err);

/*
 * The lamp of a manifest: one source per [source N], on its grid, with its names.
 * 0 or -errno of the first failing file (err names it, the line, and the manifest source).
 */
int hl_import_lid(const struct hl_manifest *m, struct hl_lid **ret, struct hl_import_error *err);

#endif
