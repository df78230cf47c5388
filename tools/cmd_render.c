/* SPDX-License-Identifier: MIT */
/*
 * hdlamp render: a still of a built-in scene lit by the lamp pair, as PNG or EXR. This file
 * sets up the scene and the renderer and writes the still (the image, the lid view's diagram,
 * the road KPIs); the options and usage are in cmd_render_options.c and the sensor-based
 * lighting of --gi sensor in cmd_render_gi.c, so that each part stays a readable size.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/egl.h"
#include "render/frame_exr.h"
#include "render/gi.h"
#include "render/overlay.h"
#include "render/plot.h"
#include "render/renderer.h"
#include "render/road_kpi.h"
#include "render/scene.h"
#include "render/view.h"
#include "tools/cmd_render.h"
#include "tools/commands.h"
#include "tools/render_args.h"
#include "lamp/preset.h"

/* The sensor-based lighting defaults, as hl_gi_config_default() gives them. */
struct hl_gi_config GI_DEFAULTS;

/*
 * The bird scene's labels: distance lines; iso-lux lines with their values (the lux view draws
 * its own lines in white: only their labels then).
 */
static void bird_labels(const struct options *o, const struct hl_camera *cam,
			const struct hl_gbuffer *gb, const float *lux, uint8_t *rgb)
{
	struct hl_overlay_opts ov;

	hl_overlay_defaults(&ov);
	if (o->view == HL_VIEW_LUX || o->have_iso) {
		ov.n_iso = o->lux.n_iso;
		memcpy(ov.iso_lx, o->lux.iso_lx, sizeof(double) * o->lux.n_iso);
	}
	ov.iso_lines = o->view != HL_VIEW_LUX;
	ov.iso_white = o->view == HL_VIEW_LUX;
	if (o->view == HL_VIEW_LUX && o->lux.legend)
		hl_view_lux_legend_box(cam->width, cam->height, ov.keep_clear);
	hl_overlay_draw(cam, gb, lux, &ov, rgb);
}

/* --kpi: the road KPIs of the lamps' current distributions, as one JSON object. */
static int write_kpi(const struct options *o, struct hl_renderer *r, int n_lamps)
{
	struct hl_headlight_lamp lamps[2];
	const float *dense[2] = { NULL, NULL };
	struct hl_road_kpi_options ko;
	struct hl_road_kpi_plan *plan;
	struct hl_road_kpi k;
	FILE *f = stdout;
	int rc;

	hl_road_kpi_defaults(&ko);
	memcpy(ko.levels_lx, o->kpi_levels_lx, sizeof(ko.levels_lx));
	for (int i = 0; i < n_lamps; i++) {
		lamps[i] = (struct hl_headlight_lamp){ o->poses[i], *hl_renderer_grid(r, i) };
		dense[i] = hl_renderer_distribution(r, i);
		if (!dense[i])
			return -EIO;
	}
	rc = hl_road_kpi_new(n_lamps, lamps, &ko, &plan);
	if (rc < 0) {
		fprintf(stderr, "hdlamp render: --kpi: %s\n", strerror(-rc));
		return rc;
	}
	hl_road_kpi_run(plan, dense, &k);
	hl_road_kpi_free(plan);
	if (strcmp(o->kpi, "-") != 0) {
		f = fopen(o->kpi, "we");
		if (!f) {
			rc = -errno;
			fprintf(stderr, "hdlamp render: --kpi '%s': %s\n", o->kpi, strerror(-rc));
			return rc;
		}
	}
	fprintf(f,
		"{\"levels_lx\": [%.10g, %.10g], \"centre_range_m\": [%.4f, %.4f], "
		"\"edge_range_m\": [%.4f, %.4f], \"width_lx\": %.10g, \"width_at_m\": [%.10g, %.10g], "
		"\"width_m\": [%.4f, %.4f]}\n",
		ko.levels_lx[0], ko.levels_lx[1], k.centre_range_m[0], k.centre_range_m[1],
		k.edge_range_m[0], k.edge_range_m[1], ko.levels_lx[0], ko.width_at_m[0],
		ko.width_at_m[1], k.width_m[0], k.width_m[1]);
	rc = fflush(f) != 0 || ferror(f) ? -EIO : 0;
	if (f != stdout && fclose(f) != 0)
		rc = -EIO;
	if (rc < 0)
		fprintf(stderr, "hdlamp render: --kpi '%s': write failed\n", o->kpi);
	return rc;
}

static int write_image(const struct options *o, const struct hl_camera *cam,
		       const struct hl_gbuffer *gb, const float *lux, int n_lamps)
{
	const size_t n = (size_t)gb->width * gb->height;
	struct hl_frame_exr_info info = { .camera = cam, .n_lamps = n_lamps };
	struct hl_lid_error err;
	uint8_t *rgb = NULL;
	float *rgba = NULL;
	int rc;

	memcpy(info.lamps, o->poses, sizeof(info.lamps));
	if (hl_render_ends_with(o->out, ".exr")) {
		if (o->view == HL_VIEW_LUX) {
			rc = hl_frame_exr_write_lux(o->out, gb->width, gb->height, lux, &info,
						    &err);
		} else {
			rgba = malloc(sizeof(float) * 4 * n);
			if (!rgba)
				return -ENOMEM;
			hl_view_hdr(gb, lux, rgba);
			rc = hl_frame_exr_write_hdr(o->out, gb->width, gb->height, rgba, &info,
						    &err);
		}
		if (rc < 0)
			fprintf(stderr, "hdlamp render: %s\n", err.msg);
		free(rgba);
		return rc;
	}
	rgb = malloc(3 * n);
	if (!rgb)
		return -ENOMEM;
	if (o->view == HL_VIEW_LUX)
		hl_view_lux(gb, lux, &o->lux, rgb);
	else
		hl_view_display(gb, lux, o->exposure_ev, rgb);
	if (o->scene == HL_SCENE_BIRD && o->labels)
		bird_labels(o, cam, gb, lux, rgb);
	rc = hl_png_write_rgb(o->out, rgb, gb->width, gb->height);
	if (rc < 0)
		fprintf(stderr, "hdlamp render: '%s': %s\n", o->out, strerror(-rc));
	free(rgb);
	return rc;
}

static int write_lid(const struct options *o, struct hl_renderer *r, int n_lamps)
{
	const int k = o->lamp < n_lamps ? o->lamp : 0;
	const float *dense = hl_renderer_distribution(r, k);
	struct hl_lid_error err;
	char title[64];
	int rc;

	if (!dense)
		return -EIO;
	if (o->lamp >= n_lamps) {
		fprintf(stderr, "hdlamp render: --lamp right: only one lamp given\n");
		return -EINVAL;
	}
	if (hl_render_ends_with(o->out, ".exr")) {
		rc = hl_lid_write_combined(hl_renderer_grid(r, k), dense, o->out, &err);
		if (rc < 0)
			fprintf(stderr, "hdlamp render: %s\n", err.msg);
		return rc;
	}
	snprintf(title, sizeof(title), "%s LAMP, %s", hl_side_name(k), o->preset);
	rc = hl_plot_lid_png(hl_renderer_grid(r, k), dense, title, o->out);
	if (rc < 0)
		fprintf(stderr, "hdlamp render: '%s': %s\n", o->out, strerror(-rc));
	return rc;
}

int hl_cmd_render(int argc, char **argv)
{
	struct options o;
	struct hl_lid *lids[2] = { NULL, NULL };
	struct hl_preset *preset = NULL;
	struct hl_egl *egl = NULL;
	struct hl_egl_error eerr = { "" };
	struct hl_gbuffer *gb = NULL;
	struct hl_renderer *r = NULL;
	struct hl_renderer_config cfg = { 0 };
	struct hl_scene scene;
	struct hl_camera cam;
	float *lux = NULL, *cur = NULL;
	int n_lamps = 0, rc, status = HL_EXIT_FAIL;

	/* The moving scene of a scenario has its own options (cmd_render_scenario.c). */
	for (int i = 1; i < argc && strcmp(argv[i], "--") != 0; i++)
		if (strcmp(argv[i], "--scenario") == 0 ||
		    strncmp(argv[i], "--scenario=", 11) == 0 || strcmp(argv[i], "--world") == 0 ||
		    strncmp(argv[i], "--world=", 8) == 0)
			return hl_cmd_render_scenario(argc, argv);
	hl_gi_config_default(&GI_DEFAULTS);
	rc = parse(argc, argv, &o);
	if (rc)
		return rc < 0 ? HL_EXIT_OK : rc;
	if (isnan(o.exposure_ev))
		o.exposure_ev = o.scene == HL_SCENE_BIRD   ? BIRD_EXPOSURE_EV :
				o.scene == HL_SCENE_SPHERE ? SPHERE_EXPOSURE_EV :
							     DEFAULT_EXPOSURE_EV;
	/* The renderer needs a GL context even when both stages run on the CPU: fail early. */
	rc = hl_egl_new(&egl, &eerr);
	if (rc < 0) {
		fprintf(stderr, "hdlamp render: no EGL/GLES 3.1 context: %s\n", eerr.msg);
		return HL_EXIT_FAIL;
	}
	fprintf(stderr, "hdlamp render: EGL %s, %s, %s\n", hl_egl_platform(egl),
		hl_egl_renderer(egl), hl_egl_version(egl));
	if (hl_render_load_lamps(o.lamps_dir, o.lid, o.n_lid, o.preset, lids, &n_lamps, &preset) <
	    0)
		goto out;

	hl_scene_init(&scene, o.scene, o.poses);
	scene.wall_distance_m = o.wall_distance_m;
	hl_scene_default_camera(&scene, o.width, o.height, &cam);
	if (o.have_camera_pos)
		memcpy(cam.pos_m, o.camera_pos, sizeof(cam.pos_m));
	if (o.have_camera_dir)
		memcpy(cam.dir, o.camera_dir, sizeof(cam.dir));
	if (o.fov_deg > 0.0)
		cam.fov_y_deg = o.fov_deg;
	rc = hl_gbuffer_new(o.width, o.height, &gb);
	if (rc == 0)
		rc = hl_scene_render(&scene, &cam, gb);
	lux = malloc(sizeof(float) * (size_t)o.width * o.height);
	if (rc < 0 || !lux) {
		fprintf(stderr, "hdlamp render: out of memory\n");
		goto out;
	}

	cfg.n_lamps = n_lamps;
	cfg.lids[0] = lids[0];
	cfg.lids[1] = lids[1];
	memcpy(cfg.poses, o.poses, sizeof(cfg.poses));
	cfg.combine = o.backend;
	cfg.headlight = o.backend;
	cfg.egl = egl;
	rc = hl_renderer_new(&cfg, gb, &r);
	if (rc < 0) {
		fprintf(stderr, "hdlamp render: cannot set up the renderer: %s\n", strerror(-rc));
		goto out;
	}
	fprintf(stderr, "hdlamp render: combine on %s, headlight pass on %s\n",
		hl_backend_name(hl_renderer_combine_backend(r)),
		hl_backend_name(hl_renderer_headlight_backend(r)));
	for (int k = 0; k < n_lamps && preset; k++) {
		cur = realloc(cur, sizeof(float) * preset->n_sources);
		if (!cur)
			goto out;
		hl_preset_intensities(preset, k, cur);
		if (hl_renderer_set_currents(r, k, cur) < 0) {
			fprintf(stderr, "hdlamp render: bad currents for the %s lamp\n",
				hl_side_name(k));
			goto out;
		}
	}
	rc = hl_renderer_frame(r, lux);
	if (rc < 0) {
		fprintf(stderr, "hdlamp render: frame failed: %s\n", strerror(-rc));
		goto out;
	}
	if (o.kpi && write_kpi(&o, r, n_lamps) < 0)
		goto out;
	if (o.gi)
		rc = run_gi(&o, egl, &scene, &cam, gb, r, lux, n_lamps);
	else
		rc = o.view == HL_VIEW_LID ? write_lid(&o, r, n_lamps) :
					     write_image(&o, &cam, gb, lux, n_lamps);
	if (rc == 0) {
		if (!o.kpi || strcmp(o.kpi, "-") != 0)
			printf("%s\n", o.out);
		status = HL_EXIT_OK;
	}
out:
	free(cur);
	free(lux);
	hl_renderer_free(r);
	hl_gbuffer_free(gb);
	hl_preset_free(preset);
	hl_lid_free(lids[0]);
	hl_lid_free(lids[1]);
	hl_egl_free(egl);
	return status;
}
