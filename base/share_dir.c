/* SPDX-License-Identifier: MIT */
#include "base/share_dir.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

int hl_exe_relative(const char *rel, char *buf, size_t size)
{
	char exe[4096];
	const ssize_t n = readlink("/proc/self/exe", exe, sizeof(exe) - 1);
	char *slash;

	if (n < 0)
		return -errno;
	exe[n] = '\0';
	slash = strrchr(exe, '/');
	if (!slash)
		return -ENOENT;
	*slash = '\0'; /* the executable's directory */
	if ((size_t)snprintf(buf, size, "%s/%s", exe, rel) >= size)
		return -ENAMETOOLONG;
	return 0;
}

int hl_share_dir(const char *name, char *buf, size_t size)
{
	char rel[4096];

	if ((size_t)snprintf(rel, sizeof(rel), "../share/hdlamp/%s", name) >= sizeof(rel))
		return -ENAMETOOLONG;
	return hl_exe_relative(rel, buf, size);
}
