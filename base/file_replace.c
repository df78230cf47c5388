/* SPDX-License-Identifier: MIT */
/* A file replaced whole or not at all: see base/file_replace.h. */
#include "base/file_replace.h"

#include <errno.h>
#include <stdio.h>
#include <unistd.h>

int hl_file_replace(const char *path, void (*write)(void *ctx, FILE *f), void *ctx)
{
	char tmp[4200];
	FILE *f;
	int rc = 0;

	if (snprintf(tmp, sizeof(tmp), "%s.tmp", path) >= (int)sizeof(tmp))
		return -ENAMETOOLONG;
	f = fopen(tmp, "we");
	if (!f)
		return -errno;
	write(ctx, f);
	if (fflush(f) != 0 || ferror(f))
		rc = -EIO;
	if (fclose(f) != 0 && rc == 0)
		rc = -errno;
	if (rc == 0 && rename(tmp, path) < 0)
		rc = -errno;
	if (rc < 0)
		unlink(tmp);
	return rc;
}

struct bytes {
	const void *buf;
	size_t len;
};

static void put_bytes(void *ctx, FILE *f)
{
	const struct bytes *b = ctx;

	fwrite(b->buf, 1, b->len, f);
}

int hl_file_replace_bytes(const char *path, const void *buf, size_t len)
{
	struct bytes b = { buf, len };

	return hl_file_replace(path, put_bytes, &b);
}
