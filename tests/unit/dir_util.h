/* SPDX-License-Identifier: MIT */
/* Tests' helpers for directories of captures: removing them, listing them. */
#ifndef HL_TESTS_DIR_UTIL_H
#define HL_TESTS_DIR_UTIL_H

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Removes dir and the capture directories in it (two levels, as captures are). */
static inline void remove_dir(const char *dir)
{
	char path[1024], file[1300];
	DIR *d = opendir(dir);
	struct dirent *e;

	while (d && (e = readdir(d))) {
		DIR *sub;
		struct dirent *f;

		if (e->d_name[0] == '.' && (!e->d_name[1] || e->d_name[1] == '.'))
			continue;
		snprintf(path, sizeof(path), "%s/%s", dir, e->d_name);
		sub = opendir(path);
		while (sub && (f = readdir(sub))) {
			snprintf(file, sizeof(file), "%s/%s", path, f->d_name);
			unlink(file);
		}
		if (sub)
			closedir(sub);
		rmdir(path);
	}
	if (d)
		closedir(d);
	rmdir(dir);
}

/* The names in dir, sorted, joined with spaces. */
static inline void list_dir(const char *dir, char *out, size_t size)
{
	struct dirent **names;
	const int n = scandir(dir, &names, NULL, alphasort);
	size_t at = 0;

	out[0] = '\0';
	for (int i = 0; i < n; i++) {
		if (strcmp(names[i]->d_name, ".") != 0 && strcmp(names[i]->d_name, "..") != 0)
			at += (size_t)snprintf(out + at, size - at, "%s%s", at ? " " : "",
					       names[i]->d_name);
		free(names[i]);
	}
	free(n >= 0 ? names : NULL);
}

#endif
