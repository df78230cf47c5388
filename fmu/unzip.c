/* SPDX-License-Identifier: MIT */
#include "fmu/unzip.h"

#include <errno.h>
#include <fcntl.h>
#include <ftw.h>
#include <limits.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zip.h>

/* An entry name we write below the directory: relative, no "." or ".." or empty component. */
static bool name_safe(const char *name)
{
	const char *s = name;

	if (!*name || name[0] == '/' || strchr(name, '\\'))
		return false;
	while (*s) {
		const char *end = strchr(s, '/');
		size_t len = end ? (size_t)(end - s) : strlen(s);

		if ((len == 1 && s[0] == '.') || (len == 2 && s[0] == '.' && s[1] == '.'))
			return false;
		if (len == 0)
			return false; /* "a//b" */
		s += len;
		if (*s == '/')
			s++;
	}
	return true;
}

/* mkdir -p of the directories in rel (relative to dir), the last component excluded. */
static int make_parents(const char *dir, const char *rel)
{
	char path[PATH_MAX];
	size_t base = strlen(dir);

	if ((size_t)snprintf(path, sizeof(path), "%s/%s", dir, rel) >= sizeof(path))
		return -ENAMETOOLONG;
	for (char *s = path + base + 1; (s = strchr(s, '/')); s++) {
		*s = '\0';
		if (mkdir(path, 0700) < 0 && errno != EEXIST)
			return -errno;
		*s = '/';
	}
	return 0;
}

static int extract(zip_t *z, zip_int64_t i, const char *dir, const char *name)
{
	char path[PATH_MAX], buf[65536];
	zip_file_t *zf;
	zip_int64_t n;
	int fd, r = 0;

	r = make_parents(dir, name);
	if (r < 0)
		return r;
	snprintf(path, sizeof(path), "%s/%s", dir, name);
	if (name[strlen(name) - 1] == '/') {
		if (mkdir(path, 0700) < 0 && errno != EEXIST)
			return -errno;
		return 0;
	}
	zf = zip_fopen_index(z, (zip_uint64_t)i, 0);
	if (!zf)
		return -EBADMSG;
	/* O_EXCL and O_NOFOLLOW: never through a link, never over an earlier entry */
	fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
	if (fd < 0) {
		r = -errno;
		goto err_close_zf;
	}
	while ((n = zip_fread(zf, buf, sizeof(buf))) > 0) {
		for (zip_int64_t off = 0; off < n;) {
			ssize_t w = write(fd, buf + off, (size_t)(n - off));

			if (w < 0) {
				r = -errno;
				goto err_close_fd;
			}
			off += w;
		}
	}
	if (n < 0)
		r = -EBADMSG; /* a damaged entry: bad CRC, truncated data */
err_close_fd:
	close(fd);
err_close_zf:
	zip_fclose(zf);
	return r;
}

static int remove_one(const char *path, const struct stat *st, int flag, struct FTW *ftw)
{
	(void)st;
	(void)flag;
	(void)ftw;
	return remove(path) < 0 ? -1 : 0;
}

int hl_fmu_unzip_remove(const char *dir)
{
	if (nftw(dir, remove_one, 16, FTW_DEPTH | FTW_PHYS) < 0)
		return errno ? -errno : -EIO;
	return 0;
}

int hl_fmu_unzip(const char *path, char *ret_dir, size_t dir_size, char *err, size_t err_size)
{
	const char *tmp = getenv("TMPDIR");
	char dir[PATH_MAX], abs[PATH_MAX];
	long long total = 0;
	zip_int64_t n;
	zip_t *z;
	int zerr = 0, r = 0;

	z = zip_open(path, ZIP_RDONLY | ZIP_CHECKCONS, &zerr);
	if (!z) {
		zip_error_t ze;

		if (zerr == ZIP_ER_NOENT || zerr == ZIP_ER_OPEN) {
			r = errno ? -errno : -ENOENT;
			snprintf(err, err_size, "'%s': %s", path, strerror(-r));
			return r;
		}
		zip_error_init_with_code(&ze, zerr);
		snprintf(err, err_size, "'%s': not a zip archive (%s)", path,
			 zip_error_strerror(&ze));
		zip_error_fini(&ze);
		return -EBADMSG;
	}
	if ((size_t)snprintf(dir, sizeof(dir), "%s/hl-fmu-XXXXXX", tmp && *tmp ? tmp : "/tmp") >=
		    sizeof(dir) ||
	    !mkdtemp(dir)) {
		r = errno ? -errno : -ENAMETOOLONG;
		snprintf(err, err_size, "'%s': cannot make a directory to unpack it in: %s", path,
			 strerror(-r));
		goto err_close_zip;
	}
	n = zip_get_num_entries(z, 0);
	for (zip_int64_t i = 0; i < n; i++) {
		const char *name = zip_get_name(z, (zip_uint64_t)i, ZIP_FL_ENC_GUESS);
		zip_stat_t st;

		if (!name || zip_stat_index(z, (zip_uint64_t)i, 0, &st) < 0) {
			snprintf(err, err_size, "'%s': entry %lld: unreadable", path, (long long)i);
			r = -EBADMSG;
			goto err_remove;
		}
		if (!name_safe(name)) {
			snprintf(err, err_size,
				 "'%s': entry '%s': refused, an absolute path or one with '..' "
				 "would unpack outside the FMU's directory",
				 path, name);
			r = -EBADMSG;
			goto err_remove;
		}
		total += (st.valid & ZIP_STAT_SIZE) ? (long long)st.size : 0;
		if (total > HL_FMU_UNZIP_MAX_BYTES) {
			snprintf(err, err_size, "'%s': unpacks to more than %lld bytes", path,
				 HL_FMU_UNZIP_MAX_BYTES);
			r = -EFBIG;
			goto err_remove;
		}
		r = extract(z, i, dir, name);
		if (r < 0) {
			snprintf(err, err_size, "'%s': entry '%s': %s", path, name,
				 r == -EBADMSG ? "damaged" : strerror(-r));
			goto err_remove;
		}
	}
	zip_discard(z);
	/* absolute: the FMU gets its resources as a file: URI (a relative $TMPDIR is possible) */
	if (!realpath(dir, abs) || (size_t)snprintf(ret_dir, dir_size, "%s", abs) >= dir_size) {
		hl_fmu_unzip_remove(dir);
		snprintf(err, err_size, "'%s': the directory's name is too long", path);
		return -ENAMETOOLONG;
	}
	return 0;

err_remove:
	hl_fmu_unzip_remove(dir);
err_close_zip:
	zip_discard(z);
	return r;
}
