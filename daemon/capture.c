/* SPDX-License-Identifier: MIT */
#include "daemon/capture.h"

#include <errno.h>
#include <inttypes.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

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

/* The frame's verdicts as a JSON object (malloc'd), or NULL. */
static char *verdict_json(const struct hl_verdicts *v, const struct hl_frame *f)
{
	char *text = NULL;
	size_t size = 0;
	FILE *m = open_memstream(&text, &size);

	if (!m)
		return NULL;
	fprintf(m, "{\"frame\":%" PRIu64 ",", f->hdr.seq);
	hl_verdicts_json(v, f, NULL, NULL, m);
	fputs("}\n", m);
	if (fclose(m) != 0) {
		free(text);
		return NULL;
	}
	return text;
}

int hl_capture_write(const char *dir, const struct hl_frame *f, const struct hl_capture_scene *sc,
		     char *ret_path, size_t path_size, char *err, size_t err_size)
{
	const struct hl_frame_header *h = &f->hdr;
	struct hl_frame_exr_info info = { .camera = sc->cam, .n_lamps = sc->n_lamps };
	char path[1024], file[1200], v[8][96], name[2][64];
	char *dims[2] = { NULL, NULL }, *verdict = NULL;
	struct hl_lid_error lerr = { "" };
	float *rgba = NULL;
	int rc = 0;

	if (mkdir(dir, 0755) < 0 && errno != EEXIST) {
		snprintf(err, err_size, "capture.dir '%s': %s", dir, strerror(errno));
		return -errno;
	}
	snprintf(path, sizeof(path), "%s/frame-%08" PRIu64, dir, h->seq);
	if (mkdir(path, 0755) < 0 && errno != EEXIST) {
		snprintf(err, err_size, "'%s': %s", path, strerror(errno));
		return -errno;
	}
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
		FILE *vf;

		verdict = verdict_json(sc->verdicts, f);
		if (!verdict) {
			rc = -ENOMEM;
			goto out;
		}
		snprintf(file, sizeof(file), "%s/verdict.json", path);
		vf = fopen(file, "we");
		if (!vf) {
			rc = -errno;
		} else {
			const bool written = fputs(verdict, vf) >= 0;

			if (fclose(vf) != 0 || !written)
				rc = -EIO;
		}
		if (rc < 0) {
			snprintf(err, err_size, "'%s': %s", file, strerror(-rc));
			goto out_no_msg;
		}
		info.meta_names[info.n_meta] = "hdlamp:verdict";
		info.meta_values[info.n_meta++] = verdict;
	}
	rgba = malloc(sizeof(float) * 4 * h->width * h->height);
	if (!rgba) {
		rc = -ENOMEM;
		goto out;
	}
	hl_view_hdr(sc->gb, f->lux, rgba);
	snprintf(file, sizeof(file), "%s/hdr.exr", path);
	rc = hl_frame_exr_write_hdr(file, (int)h->width, (int)h->height, rgba, &info, &lerr);
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
	else
		snprintf(ret_path, path_size, "%s", path);
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
