/* SPDX-License-Identifier: MIT */
/*
 * An FMU archive unpacked into a private directory of its own (docs/fmu.md, "The archive"):
 * mkdtemp under $TMPDIR (or /tmp), every entry written below it and nowhere else. An entry
 * whose name is absolute or has a ".." component is refused ("zip slip"), as is an archive
 * that would unpack to more than HL_FMU_UNZIP_MAX_BYTES. Symbolic links are never made: an
 * entry is a regular file or a directory.
 *
 * Thread-safety: any thread; nothing shared.
 */
#ifndef HL_FMU_UNZIP_H
#define HL_FMU_UNZIP_H

#include <stddef.h>

#define HL_FMU_UNZIP_MAX_BYTES (1024LL * 1024 * 1024) /* bytes unpacked, all entries */

/*
 * Unpacks the zip archive path into a new directory, whose absolute path goes to ret_dir
 * (dir_size bytes; PATH_MAX is enough). 0; -EBADMSG (not a zip, a refused entry), -EFBIG,
 * -errno of the file system; err names path and the entry. On failure nothing is left behind.
 */
int hl_fmu_unzip(const char *path, char *ret_dir, size_t dir_size, char *err, size_t err_size);

/* Removes dir and everything below it, links not followed. 0 or -errno of the first failure. */
int hl_fmu_unzip_remove(const char *dir);

#endif
