/* SPDX-License-Identifier: MIT */
/*
 * A file replaced whole or not at all: written beside its path as PATH.tmp, flushed, and
 * renamed over PATH, so a reader never sees half a report (hdlampd's and hdlamp sil's run
 * reports, JUnit files). On any failure the temporary file is removed and PATH is untouched.
 */
#ifndef HL_BASE_FILE_REPLACE_H
#define HL_BASE_FILE_REPLACE_H

#include <stdio.h>

/* write(ctx, f) writes the content. 0, -ENAMETOOLONG, -EIO (a write failed), -errno. */
int hl_file_replace(const char *path, void (*write)(void *ctx, FILE *f), void *ctx);
/* The same for content already in memory (a page composed whole). */
int hl_file_replace_bytes(const char *path, const void *buf, size_t len);

#endif
