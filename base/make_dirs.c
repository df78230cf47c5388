/* SPDX-License-Identifier: MIT */
/* A directory and its missing parents: see base/make_dirs.h. */
#include "base/make_dirs.h"

#include <errno.h>
#include <string.h>
#include <sys/stat.h>

int hl_make_dirs(const char *dir)
{
	char p[4096];
	struct stat st;
	size_t n = strlen(dir);

	if (n == 0 || n >= sizeof(p))
		return -ENAMETOOLONG;
	memcpy(p, dir, n + 1);
	for (char *c = p + 1; *c; c++) {
		if (*c != '/')
			continue;
		*c = '\0';
		if (mkdir(p, 0777) < 0 && errno != EEXIST)
			return -errno;
		*c = '/';
	}
	if (mkdir(p, 0777) < 0 && errno != EEXIST)
		return -errno;
	if (stat(p, &st) < 0)
		return -errno;
	return S_ISDIR(st.st_mode) ? 0 : -ENOTDIR;
}
