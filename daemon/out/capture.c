/* SPDX-License-Identifier: MIT */
#include "daemon/out/capture.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <inttypes.h>
#include <limits.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "render/frame_exr.h"
#include "render/view.h"

static char *join_dims(const uint8_t *d, int n)
{
	char *s = malloc((size_t)n * 3 + 1);
	size_t at = 0;

	if (!s)
		return NULL;
	s[0] = '\0';
	for (int k = 0; k < n; k++)
		at += (size_t)sprintf(s + at, "%s%u", k ? "," : "", d[k]);
	return s;
}

/* text into a new file. 0 or -errno. */
static int write_text(const char *file, const char *text)
{
	const int fd = open(file, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
	size_t left = strlen(text);
	int rc = 0;

	if (fd < 0)
		return -errno;
	while (left > 0 && rc == 0) {
		const ssize_t n = write(fd, text, left);

		if (n < 0 && errno != EINTR)
			rc = -errno;
		else if (n > 0) {
			text += n;
			left -= (size_t)n;
		}
	}
	if (close(fd) < 0 && rc == 0)
		rc = -errno;
	return rc;
}

/* The frame's verdicts as a JSON object (malloc'd), or NULL. */
static char *verdict_json(const struct hl_verdicts *v, const struct hl_frame *f)
{
	char *text = NULL;
	size_t size = 0;
	FILE *m = open_memstream(&text, &size);

	if (!m)
		return NULL;
	fprintf(m, "{\"frame\":%" PRIu64 ",", f->hdr.seq);
	hl_verdicts_json(v, f, NULL, m);
	fputs("}\n", m);
	if (fclose(m) != 0) {
		free(text);
		return NULL;
	}
	return text;
}

/* Every file of the capture into the directory path. */
static int write_files(const char *path, const struct hl_frame *f,
		       const struct hl_capture_scene *sc, char *err, size_t err_size)
{
	const struct hl_frame_header *h = &f->hdr;
	struct hl_frame_exr_info info = { .camera = sc->cam, .n_lamps = sc->n_lamps };
	char file[PATH_MAX + 64], v[8][96], name[2][64];
	char *dims[2] = { NULL, NULL }, *verdict = NULL;
	struct hl_lid_error lerr = { "" };
	float *rgba = NULL;
	int rc = 0;

	for (int l = 0; l < sc->n_lamps; l++)
		hl_lamp_pose_default(l, &info.lamps[l]);
	snprintf(v[0], sizeof(v[0]), "%" PRIu64, h->seq);
	snprintf(v[1], sizeof(v[1]), "%" PRIu64 ",%" PRIu64, h->cycle_seq[0], h->cycle_seq[1]);
	snprintf(v[2], sizeof(v[2]), "%u,%u", h->counter[0], h->counter[1]);
	snprintf(v[3], sizeof(v[3]), "0x%x", h->flags);
	snprintf(v[4], sizeof(v[4]), "%" PRId64, h->t_cycle_rx_ns);
	snprintf(v[5], sizeof(v[5]), "%" PRId64, h->t_cycle_done_ns);
	snprintf(v[6], sizeof(v[6]), "%" PRId64, h->t_render_done_ns);
	{
		static const char *const names[7] = { "hdlamp:frameSeq",     "hdlamp:cycleSeq",
						      "hdlamp:counter",	     "hdlamp:flags",
						      "hdlamp:tCycleRxNs",   "hdlamp:tCycleDoneNs",
						      "hdlamp:tRenderDoneNs" };

		for (int k = 0; k < 7; k++) {
			info.meta_names[info.n_meta] = names[k];
			info.meta_values[info.n_meta++] = v[k];
		}
	}
	for (int l = 0; l < sc->n_lamps; l++) {
		dims[l] = join_dims(f->dims[l], f->n_sources);
		if (!dims[l]) {
			rc = -ENOMEM;
			goto out;
		}
		snprintf(name[l], sizeof(name[l]), "hdlamp:dims.%s", sc->lamp_names[l]);
		info.meta_names[info.n_meta] = name[l];
		info.meta_values[info.n_meta++] = dims[l];
	}
	if (sc->verdicts) {
		verdict = verdict_json(sc->verdicts, f);
		if (!verdict) {
			rc = -ENOMEM;
			goto out;
		}
		snprintf(file, sizeof(file), "%s/verdict.json", path);
		rc = write_text(file, verdict);
		if (rc < 0) {
			snprintf(err, err_size, "'%s': %s", file, strerror(-rc));
			goto out_no_msg;
		}
		info.meta_names[info.n_meta] = "hdlamp:verdict";
		info.meta_values[info.n_meta++] = verdict;
	}
	/* the luminance needs the frame's G-buffer: a still scene's (a moving one has none) */
	if (sc->gb) {
		rgba = malloc(sizeof(float) * 4 * h->width * h->height);
		if (!rgba) {
			rc = -ENOMEM;
			goto out;
		}
		hl_view_hdr(sc->gb, f->lux, rgba);
		snprintf(file, sizeof(file), "%s/hdr.exr", path);
		rc = hl_frame_exr_write_hdr(file, (int)h->width, (int)h->height, rgba, &info,
					    &lerr);
	}
	if (rc == 0) {
		snprintf(file, sizeof(file), "%s/lux.exr", path);
		rc = hl_frame_exr_write_lux(file, (int)h->width, (int)h->height, f->lux, &info,
					    &lerr);
	}
	for (int l = 0; l < sc->n_lamps && rc == 0; l++) {
		const size_t n = (size_t)sc->grids[l]->width * sc->grids[l]->height;
		float *d = malloc(sizeof(float) * n);

		if (!d) {
			rc = -ENOMEM;
			break;
		}
		/* incremental combining leaves float noise of ~1e-5 cd below zero where every source
		 * is off; a LID file holds intensities >= 0 */
		for (size_t i = 0; i < n; i++)
			d[i] = f->dist[l][i] > 0.0f ? f->dist[l][i] : 0.0f;
		snprintf(file, sizeof(file), "%s/%s.lid.exr", path, sc->lamp_names[l]);
		rc = hl_lid_write_combined(sc->grids[l], d, file, &lerr);
		free(d);
	}
	if (rc < 0)
		snprintf(err, err_size, "%s", lerr.msg);
out:
	if (rc == -ENOMEM)
		snprintf(err, err_size, "out of memory");
out_no_msg:
	free(verdict);
	free(rgba);
	free(dims[0]);
	free(dims[1]);
	return rc;
}

/* Removes the directory path and the files in it (a capture's, or one a dead daemon left). */
static void remove_tree(const char *path)
{
	DIR *d = opendir(path);
	struct dirent *e;

	if (d) {
		while ((e = readdir(d)))
			if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0)
				unlinkat(dirfd(d), e->d_name, 0);
		closedir(d);
	}
	rmdir(path);
}

/* fsync of path (a file or a directory). 0 or -errno. */
static int sync_path(const char *path)
{
	const int fd = open(path, O_RDONLY | O_CLOEXEC);
	int rc = 0;

	if (fd < 0)
		return -errno;
	if (fsync(fd) < 0)
		rc = -errno;
	close(fd);
	return rc;
}

/* Every file of the directory path on disk, then the directory itself (a full disk may only
 * say so here). */
static int sync_files(const char *path, char *err, size_t err_size)
{
	char file[PATH_MAX + 256];
	DIR *d = opendir(path);
	struct dirent *e;
	int rc = 0;

	if (!d) {
		rc = -errno;
		snprintf(err, err_size, "'%s': %s", path, strerror(-rc));
		return rc;
	}
	while (rc == 0 && (e = readdir(d))) {
		if (e->d_name[0] == '.')
			continue;
		snprintf(file, sizeof(file), "%s/%s", path, e->d_name);
		rc = sync_path(file);
	}
	closedir(d);
	if (rc == 0) {
		snprintf(file, sizeof(file), "%s", path);
		rc = sync_path(path);
	}
	if (rc < 0)
		snprintf(err, err_size, "'%s': cannot sync: %s", file, strerror(-rc));
	return rc;
}

/*
 * Renames tmp to the first free name of frame-NNNNNNNN, frame-NNNNNNNN-2, ... in dir, never
 * over an existing one. 0 and ret_path, or -errno.
 */
static int publish(const char *dir, const char *tmp, uint64_t seq, char *ret_path, size_t size,
		   char *err, size_t err_size)
{
	char path[PATH_MAX + 64];

	for (int k = 1; k <= HL_CAPTURE_MAX_SAME_FRAME; k++) {
		int rc = 0;

		if (k == 1)
			snprintf(path, sizeof(path), "%s/frame-%08" PRIu64, dir, seq);
		else
			snprintf(path, sizeof(path), "%s/frame-%08" PRIu64 "-%d", dir, seq, k);
		if (renameat2(AT_FDCWD, tmp, AT_FDCWD, path, RENAME_NOREPLACE) < 0) {
			rc = -errno;
			/* a file system without RENAME_NOREPLACE: the check is ours, one writer */
			if (rc == -EINVAL || rc == -ENOSYS) {
				struct stat st;

				if (lstat(path, &st) == 0)
					rc = -EEXIST;
				else if (rename(tmp, path) == 0)
					rc = 0;
				else
					rc = -errno;
			}
		}
		if (rc == -EEXIST)
			continue;
		if (rc < 0) {
			snprintf(err, err_size, "'%s': cannot rename to '%s': %s", tmp, path,
				 strerror(-rc));
			return rc;
		}
		rc = sync_path(dir); /* the new name on disk */
		if (rc < 0) {
			snprintf(err, err_size, "'%s': cannot sync: %s", dir, strerror(-rc));
			remove_tree(path);
			return rc;
		}
		snprintf(ret_path, size, "%s", path);
		return 0;
	}
	snprintf(err, err_size, "'%s': %d captures of frame %" PRIu64 " exist already", dir,
		 HL_CAPTURE_MAX_SAME_FRAME, seq);
	return -EEXIST;
}

int hl_capture_write(const char *dir, const struct hl_frame *f, const struct hl_capture_scene *sc,
		     char *ret_path, size_t path_size, char *err, size_t err_size)
{
	char tmp[PATH_MAX];
	int rc = 0;

	if (mkdir(dir, 0755) < 0 && errno != EEXIST) {
		rc = -errno;
		snprintf(err, err_size, "capture.dir '%s': cannot create: %s", dir, strerror(-rc));
		return rc;
	}
	snprintf(tmp, sizeof(tmp), "%s/.tmp-frame-%08" PRIu64 "-%ld", dir, f->hdr.seq,
		 (long)getpid());
	if (mkdir(tmp, 0755) < 0) {
		rc = -errno;
		if (rc == -EEXIST) { /* left by a daemon of the same pid that died writing it */
			remove_tree(tmp);
			rc = mkdir(tmp, 0755) < 0 ? -errno : 0;
		}
		if (rc < 0) {
			snprintf(err, err_size, "'%s': cannot create: %s", tmp, strerror(-rc));
			return rc;
		}
	}
	rc = write_files(tmp, f, sc, err, err_size);
	if (rc == 0)
		rc = sync_files(tmp, err, err_size);
	if (rc == 0)
		rc = publish(dir, tmp, f->hdr.seq, ret_path, path_size, err, err_size);
	if (rc < 0)
		remove_tree(tmp); /* nothing of a failed capture stays */
	return rc;
}
