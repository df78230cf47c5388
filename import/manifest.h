/* SPDX-License-Identifier: MIT */
/*
 * The import manifest: which measured file becomes which source of a lamp, on which grid.
 * An INI file:
 *
 *   # comments start with '#' or ';' (whole lines only)
 *   [grid]                  optional; every key optional, defaults as docs/design.md §1/§4
 *   angles = A              A or B: the LID's angle system              (default A)
 *   h = -89.9, 89.9         first and last H sample, degrees            (default -89.9, 89.9)
 *   v = -29.9, 19.9         first and last V sample, degrees            (default -29.9, 19.9)
 *   step = 0.2              sample spacing in H and V, degrees          (default 0.2)
 *
 *   [source 1]              one section per source, 1-based, 1..N without gaps
 *   file = low_beam.ies     relative to the manifest's folder (or absolute)
 *   name = low_beam         the source's name in the LID file (no line breaks)
 *   format = ies            optional: ies, ldt or csv; else from the file's extension
 *
 * Keys are "key = value"; blanks around keys and values are ignored. Unknown sections or keys,
 * repeated keys or sections, missing file or name, gaps in the numbering and ranges that are
 * not a whole number of steps are errors that name the manifest, the line and what was
 * expected.
 */
#ifndef HL_IMPORT_MANIFEST_H
#define HL_IMPORT_MANIFEST_H

#include <stddef.h>

#include "lamp/lid.h"
#include "import/error.h"

enum hl_import_format {
	HL_IMPORT_IES,
	HL_IMPORT_LDT,
	HL_IMPORT_CSV,
};

struct hl_manifest;

/*
 * Parses a manifest held in buf[0..len); name is for messages, base_dir (may be NULL for the
 * current directory) resolves relative file names.
 * 0, -EBADMSG (err: manifest, line, column, expected), -ENOMEM.
 * Thread-safety: reentrant; a manifest is read-only once parsed.
 */
int hl_manifest_parse(const char *buf, size_t len, const char *name, const char *base_dir,
		      struct hl_manifest **ret, struct hl_import_error *err);
/* The same from a file, relative names resolved against its folder; also -errno of open. */
int hl_manifest_read(const char *path, struct hl_manifest **ret, struct hl_import_error *err);
void hl_manifest_free(struct hl_manifest *m);

const struct hl_lid_grid *hl_manifest_grid(const struct hl_manifest *m);
int hl_manifest_n_sources(const struct hl_manifest *m);
/* Source k (0-based): resolved file path, name, format, manifest line. Owned by m. */
const char *hl_manifest_file(const struct hl_manifest *m, int k);
const char *hl_manifest_name(const struct hl_manifest *m, int k);
enum hl_import_format hl_manifest_format(const struct hl_manifest *m, int k);
int hl_manifest_line(const struct hl_manifest *m, int k);

/* "ies", "ldt", "csv" (case-insensitive) to a format; -EINVAL for anything else. */
int hl_import_format_from_name(const char *name);
/* The format of a path by its extension (.ies, .ldt, .csv; case-insensitive); -EINVAL. */
int hl_import_format_from_path(const char *path);

#endif
