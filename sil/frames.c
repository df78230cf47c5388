/* SPDX-License-Identifier: MIT */
/* The judged frames of hdlamp sil as images: see sil/frames.h. */
#include "sil/frames.h"

#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "render/compose.h"
#include "render/plot.h"
#include "render/renderer.h"
#include "render/view.h"
#include "render/workers.h"
#include "render/world_scene.h"
#include "world/world.h"

#define N_LAMPS 2
#define MAX_EMITTERS (HL_SCN_MAX_ACTORS * HL_SCN_MAX_LAMPS)

struct hl_sil_frames {
	const struct hl_scenario *sc;
	char *dir;
	enum hl_view_kind view;
	double exposure_ev;
	struct hl_view_lux_opts lux_opts;
	struct hl_camera cam;
	struct hl_world_state world; /* the frame's instant, read by world_fill on every thread */
	struct hl_world_scene *ws;
	struct hl_gbuffer *gb;
	struct hl_world_raster *raster;
	struct hl_renderer *r;
	/*
	 * The renderer writes only the pixels a lamp can reach (render/renderer.h): lux and rgb
	 * are zeroed once and only ever used for this, as a frame of the daemon's pool.
	 */
	float *lux;
	uint8_t *rgb;
	struct hl_world_emitter emitters[MAX_EMITTERS];
	int boxes[MAX_EMITTERS][4]; /* the glows drawn into rgb by the last frame */
	int n_boxes;
};

/* The renderer's threads ray cast the moving scene band by band, as the daemon's world_fill. */
static void world_fill(void *userdata, struct hl_gbuffer *gb, size_t first, size_t count,
		       uint8_t *changed)
{
	const struct hl_sil_frames *fr = userdata;

	(void)gb; /* the raster's */
	hl_world_raster_pixels(fr->raster, &fr->world, first, count, changed);
}

static int render_threads(const struct hl_config *cfg)
{
	long n = cfg->render_threads;

	if (n == 0) /* one per CPU, as hdlampd */
		n = sysconf(_SC_NPROCESSORS_ONLN);
	return n < 1 ? 1 : n > HL_WORKERS_MAX_THREADS ? HL_WORKERS_MAX_THREADS : (int)n;
}

int hl_sil_frames_new(const struct hl_config *cfg, struct hl_lid *const lids[2],
		      const struct hl_scenario *sc, const char *dir, struct hl_sil_frames **ret,
		      char *err, size_t err_size)
{
	struct hl_sil_frames *fr = calloc(1, sizeof(*fr));
	struct hl_renderer_config rc_cfg = {
		.n_lamps = N_LAMPS,
		.lids = { lids[0], lids[1] },
		/* the CPU stages: the same bits every run (sil/frames.h) */
		.combine = HL_BACKEND_CPU,
		.headlight = HL_BACKEND_CPU,
		.threads = render_threads(cfg),
		.moving = true,
		.fill_only = true,
	};
	const size_t n_px = (size_t)cfg->width * cfg->height;
	int rc;

	if (!fr) {
		snprintf(err, err_size, "out of memory");
		return -ENOMEM;
	}
	fr->sc = sc;
	fr->exposure_ev = cfg->exposure_ev;
	hl_view_lux_defaults(&fr->lux_opts);
	rc = hl_view_from_name(cfg->view);
	if (rc != HL_VIEW_DISPLAY && rc != HL_VIEW_LUX) {
		snprintf(err, err_size, "render.view '%s': frames are PNG images: display or lux",
			 cfg->view);
		rc = -EINVAL;
		goto err;
	}
	fr->view = rc;
	/* the driver's camera and the ego lamps, fixed in the ego frame (render/world_scene.h) */
	fr->cam = sc->ego.camera;
	fr->cam.width = cfg->width;
	fr->cam.height = cfg->height;
	memcpy(rc_cfg.poses, sc->ego.lamp, sizeof(rc_cfg.poses));
	fr->dir = strdup(dir);
	fr->lux = calloc(n_px, sizeof(float));
	fr->rgb = calloc(n_px, 3);
	if (!fr->dir || !fr->lux || !fr->rgb) {
		rc = -ENOMEM;
		snprintf(err, err_size, "out of memory");
		goto err;
	}
	hl_world_at(sc, 0.0, &fr->world);
	rc = hl_world_scene_new(sc, &fr->ws);
	if (rc == 0)
		rc = hl_gbuffer_new(cfg->width, cfg->height, &fr->gb);
	if (rc == 0)
		rc = hl_world_scene_render(fr->ws, &fr->world, &fr->cam, fr->gb);
	if (rc == 0)
		rc = hl_world_raster_new(fr->ws, &fr->cam, fr->gb, &fr->raster);
	if (rc < 0) {
		snprintf(err, err_size, "the scenario's scene: %s", strerror(-rc));
		goto err;
	}
	rc = hl_renderer_new(&rc_cfg, fr->gb, &fr->r);
	if (rc < 0) {
		snprintf(err, err_size, "cannot set up the renderer: %s", strerror(-rc));
		goto err;
	}
	*ret = fr;
	return 0;
err:
	hl_sil_frames_free(fr);
	return rc;
}

void hl_sil_frames_free(struct hl_sil_frames *fr)
{
	if (!fr)
		return;
	hl_renderer_free(fr->r);
	hl_world_raster_free(fr->raster);
	hl_gbuffer_free(fr->gb);
	hl_world_scene_free(fr->ws);
	free(fr->lux);
	free(fr->rgb);
	free(fr->dir);
	free(fr);
}

/* The PNG of fr->rgb to path. 0 or -errno. */
static int write_png(const struct hl_sil_frames *fr, const char *path)
{
	uint8_t *png = NULL;
	size_t size = 0;
	FILE *f;
	int rc;

	/* libpng writes no tIME chunk unless asked: the same pixels are the same bytes */
	rc = hl_png_encode_rgb(fr->rgb, fr->cam.width, fr->cam.height, (size_t)fr->cam.width * 3,
			       &png, &size);
	if (rc < 0)
		return rc;
	f = fopen(path, "wbe");
	if (!f) {
		rc = -errno;
		free(png);
		return rc;
	}
	rc = fwrite(png, 1, size, f) == size ? 0 : -EIO;
	if (fclose(f) != 0 && rc == 0)
		rc = -errno;
	free(png);
	return rc;
}

int hl_sil_frames_write(struct hl_sil_frames *fr, uint64_t seq, double t_s,
			const float *const intensities[2], char *err, size_t err_size)
{
	char path[4096];
	int rc;

	hl_world_at(fr->sc, t_s, &fr->world);
	for (int l = 0; l < N_LAMPS; l++) {
		rc = hl_renderer_set_currents(fr->r, l, intensities[l]);
		if (rc < 0) {
			snprintf(err, err_size, "frame %" PRIu64 ": the %s lamp's intensities: %s",
				 seq, l ? "right" : "left", strerror(-rc));
			return rc;
		}
	}
	/* the moving scene at the frame's instant: only what changed is lit anew */
	rc = hl_renderer_set_gbuffer_fill(fr->r, fr->gb, world_fill, fr);
	if (rc == 0 && fr->view == HL_VIEW_DISPLAY) {
		/* tone mapped band by band, as the daemon's display view */
		struct hl_compose_display j = { fr->gb, fr->exposure_ev, fr->rgb };

		hl_compose_clear_boxes(fr->rgb, fr->cam.width, fr->boxes, fr->n_boxes);
		fr->n_boxes = 0;
		rc = hl_renderer_frame_pixels(fr->r, fr->lux, hl_compose_display_band, &j);
		if (rc == 0)
			fr->n_boxes = hl_compose_emitters(fr->ws, &fr->world, &fr->cam,
							  fr->exposure_ev, fr->emitters,
							  MAX_EMITTERS, fr->rgb, fr->boxes,
							  MAX_EMITTERS);
	} else if (rc == 0) {
		rc = hl_renderer_frame(fr->r, fr->lux);
		if (rc == 0)
			hl_view_lux(fr->gb, fr->lux, &fr->lux_opts, fr->rgb);
	}
	if (rc < 0) {
		snprintf(err, err_size, "frame %" PRIu64 " at %.3f s: %s", seq, t_s, strerror(-rc));
		return rc;
	}
	snprintf(path, sizeof(path), "%s/frame-%06" PRIu64 ".png", fr->dir, seq);
	rc = write_png(fr, path);
	if (rc < 0) {
		snprintf(err, err_size, "'%s': %s", path, strerror(-rc));
		return rc;
	}
	return 0;
}
