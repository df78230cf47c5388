/* SPDX-License-Identifier: MIT */
/*
 * A directory and its missing parents, as mkdir -p: the output directories of hdlamp sil
 * --frames and hdlamp suite run --out.
 */
#ifndef HL_BASE_MAKE_DIRS_H
#define HL_BASE_MAKE_DIRS_H

/* 0 (made, or already a directory), -ENOTDIR (it exists and is not one), -ENAMETOOLONG, or the
 * -errno of the first mkdir that failed. */
int hl_make_dirs(const char *dir);

#endif
