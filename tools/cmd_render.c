/* SPDX-License-Identifier: MIT */
/* hdlamp render: a still of a built-in scene lit by the lamp pair, as PNG or EXR. */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "render/egl.h"
#include "render/frame_exr.h"
#include "render/gi.h"
#include "render/gl_sensor.h"
#include "render/overlay.h"
#include "render/plot.h"
#include "render/renderer.h"
#include "render/road_kpi.h"
#include "render/scene.h"
#include "render/scene_mesh.h"
#include "render/view.h"
#include "tools/commands.h"
#include "tools/preset_arg.h"
#include "tools/render_args.h"
#include "lamp/preset.h"

#define DEFAULT_EXPOSURE_EV 0.0 /* 1 cd/m^2 maps to half of full scale */
#define BIRD_EXPOSURE_EV 2.0 /* from above most of the road is far and dim */
#define SPHERE_EXPOSURE_EV (-3.0) /* 10 m from the lamp the sphere gets up to ~250 lx */

/* The sensor-based lighting defaults, as hl_gi_config_default() gives them. */
static struct hl_gi_config GI_DEFAULTS;
#define GLES_SENSOR_BATCH 128 /* sensors per draw of the GLES sensors */

static void usage(FILE *f)
{
	fprintf(f,
		"usage: hdlamp render (--lamps DIR | --lid LEFT.lid.exr [--lid RIGHT.lid.exr])\n"
		"                     --out FILE.png|FILE.exr [options]\n"
		"\n"
		"Renders a still of a built-in scene lit by the lamps. With --scenario FILE: stills\n"
		"of a scenario's moving scene (hdlamp render --scenario x --help).\n"
		"\n"
		"  --lamps DIR          DIR/hd84_left.lid.exr and DIR/hd84_right.lid.exr\n"
		"  --lid FILE           a lamp file; the first is the left lamp, the second the right\n"
		"                       (one --lid: the left lamp only)\n"
		"  --preset NAME|FILE   low (default), high, glarefree, bend_left, bend_right\n"
		"                       (DIR/NAME.json with --lamps, else the built-in HD84 preset),\n"
		"                       or a preset .json file; ignored for combined distributions\n"
		"  --scene S            sphere | wall | road (default) | bird | bounce\n"
		"  --view V             display (default) | hdr | lux | lid\n"
		"  --size WxH           image size, default 1280x720\n"
		"  --out FILE           .png (display, lux, lid) or .exr (hdr: RGBA half luminance;\n"
		"                       lux: channel E in lux; lid: the combined distribution)\n"
		"  --exposure EV        display exposure, default %.1f (bird: %.1f, sphere: %.1f)\n"
		"  --iso L1,L2,...      iso-lux lines of the lux view, default 1,3,5,10,20,50, and of\n"
		"                       the bird scene's display view, default 1,3,10,30\n"
		"  --no-labels          bird scene: no distance labels, iso-lux lines or their labels\n"
		"  --kpi FILE|-         the road KPIs of the lamps as rendered (range along the lane\n"
		"                       centre and the right road edge, width at 25 and 50 m) as one\n"
		"                       JSON object into FILE; '-': to standard output (which then\n"
		"                       holds only the JSON)\n"
		"  --kpi-levels L1,L2   the KPIs' illuminance levels, lux, default 1,3 (widths: L1)\n"
		"  --wall-distance M    wall scene: distance of the screen, default 25\n"
		"  --camera-pos X,Y,Z   camera position (m, vehicle frame: x fwd, y left, z up)\n"
		"  --camera-dir X,Y,Z   viewing direction\n"
		"  --fov DEG            vertical field of view\n"
		"  --left-pos X,Y,Z     left lamp position, default 0,0.7,0.65\n"
		"  --left-aim YAW,PITCH left lamp aim, degrees (yaw + left, pitch + up), default 0,-0.573\n"
		"  --right-pos, --right-aim  the same for the right lamp (default y -0.7)\n"
		"  --lamp left|right    lid view: which lamp, default left\n"
		"  --backend B          auto (default) | cpu | gles: where combine and headlight run\n"
		"\n"
		"Global illumination (offline; --out FILE.png, display view):\n"
		"  --gi sensor          add the indirect light by sensor-based lighting; writes\n"
		"                       FILE.png (total), FILE-direct.png, FILE-diff.png (indirect lux,\n"
		"                       false colour) and FILE-{direct,indirect,total}.exr (cd/m^2)\n"
		"  --sensor-size N      hemicube front face N x N texels (even), default %d\n"
		"  --tile T             first sensor spacing, power of two; 1 = a sensor per pixel;\n"
		"                       default %d\n"
		"  --dradiance X        refine where neighbouring sensors differ by more than X\n"
		"                       (relative), default %g\n"
		"  --sensor-aa S        S x S samples per texel: CPU rays near thin objects, GLES\n"
		"                       4x multisampling on (S/2 x S/2)-supersampled faces;\n"
		"                       default %d (1 = off)\n"
		"  --sensor-backend B   auto (default) | cpu | gles: where sensors run; auto times\n"
		"                       one batch of each and keeps the faster\n"
		"  --sensor-batch N     sensors per batch, default %d (cpu: sharing a normal) or %d\n"
		"                       (gles: per draw)\n"
		"  --gi-threads N       CPU sensor threads, default %d\n",
		DEFAULT_EXPOSURE_EV, BIRD_EXPOSURE_EV, SPHERE_EXPOSURE_EV, GI_DEFAULTS.sensor_size,
		GI_DEFAULTS.tile, GI_DEFAULTS.dradiance, GI_DEFAULTS.aa_samples, GI_DEFAULTS.batch,
		GLES_SENSOR_BATCH, GI_DEFAULTS.threads);
}

struct options {
	const char *lamps_dir, *lid[2], *preset, *out;
	int n_lid;
	enum hl_scene_kind scene;
	enum hl_view_kind view;
	int width, height;
	double exposure_ev, wall_distance_m, fov_deg;
	double camera_pos[3], camera_dir[3];
	bool have_camera_pos, have_camera_dir;
	struct hl_lamp_pose poses[2];
	struct hl_view_lux_opts lux;
	bool have_iso, labels;
	const char *kpi; /* NULL, a path or "-" */
	double kpi_levels_lx[HL_ROAD_KPI_LEVELS];
	int lamp;
	enum hl_backend backend;
	bool gi;
	struct hl_gi_config gi_cfg;
	enum hl_backend sensor_backend;
	int sensor_batch; /* 0: the backend's default */
};

/* 0, or an exit code. */
static int parse(int argc, char **argv, struct options *o)
{
	enum {
		OPT_ISO = 256,
		OPT_WALL,
		OPT_CAM_POS,
		OPT_CAM_DIR,
		OPT_FOV,
		OPT_LEFT_POS,
		OPT_LEFT_AIM,
		OPT_RIGHT_POS,
		OPT_RIGHT_AIM,
		OPT_LAMP,
		OPT_BACKEND,
		OPT_EXPOSURE,
		OPT_GI,
		OPT_SENSOR_SIZE,
		OPT_TILE,
		OPT_DRADIANCE,
		OPT_SENSOR_AA,
		OPT_GI_THREADS,
		OPT_SENSOR_BACKEND,
		OPT_SENSOR_BATCH,
		OPT_NO_LABELS,
		OPT_KPI,
		OPT_KPI_LEVELS,
	};
	static const struct option opts[] = {
		{ "lamps", required_argument, NULL, 'L' },
		{ "lid", required_argument, NULL, 'l' },
		{ "preset", required_argument, NULL, 'p' },
		{ "scene", required_argument, NULL, 's' },
		{ "view", required_argument, NULL, 'v' },
		{ "size", required_argument, NULL, 'S' },
		{ "out", required_argument, NULL, 'o' },
		{ "exposure", required_argument, NULL, OPT_EXPOSURE },
		{ "iso", required_argument, NULL, OPT_ISO },
		{ "wall-distance", required_argument, NULL, OPT_WALL },
		{ "camera-pos", required_argument, NULL, OPT_CAM_POS },
		{ "camera-dir", required_argument, NULL, OPT_CAM_DIR },
		{ "fov", required_argument, NULL, OPT_FOV },
		{ "left-pos", required_argument, NULL, OPT_LEFT_POS },
		{ "left-aim", required_argument, NULL, OPT_LEFT_AIM },
		{ "right-pos", required_argument, NULL, OPT_RIGHT_POS },
		{ "right-aim", required_argument, NULL, OPT_RIGHT_AIM },
		{ "lamp", required_argument, NULL, OPT_LAMP },
		{ "backend", required_argument, NULL, OPT_BACKEND },
		{ "gi", required_argument, NULL, OPT_GI },
		{ "sensor-size", required_argument, NULL, OPT_SENSOR_SIZE },
		{ "tile", required_argument, NULL, OPT_TILE },
		{ "dradiance", required_argument, NULL, OPT_DRADIANCE },
		{ "sensor-aa", required_argument, NULL, OPT_SENSOR_AA },
		{ "gi-threads", required_argument, NULL, OPT_GI_THREADS },
		{ "sensor-backend", required_argument, NULL, OPT_SENSOR_BACKEND },
		{ "sensor-batch", required_argument, NULL, OPT_SENSOR_BATCH },
		{ "no-labels", no_argument, NULL, OPT_NO_LABELS },
		{ "kpi", required_argument, NULL, OPT_KPI },
		{ "kpi-levels", required_argument, NULL, OPT_KPI_LEVELS },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	double v[3];
	int c, rc;
	char tail;

	*o = (struct options){
		.preset = "low",
		.scene = HL_SCENE_ROAD,
		.view = HL_VIEW_DISPLAY,
		.width = 1280,
		.height = 720,
		.exposure_ev = NAN,
		.wall_distance_m = HL_WALL_DISTANCE_M,
		.labels = true,
		.kpi_levels_lx = { 1.0, 3.0 },
	};
	hl_lamp_pose_default(0, &o->poses[0]);
	hl_lamp_pose_default(1, &o->poses[1]);
	hl_view_lux_defaults(&o->lux);
	hl_gi_config_default(&o->gi_cfg);
	optind = 1;
	while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
		switch (c) {
		case 'L':
			o->lamps_dir = optarg;
			break;
		case 'l':
			if (o->n_lid == 2)
				return hl_render_bad("--lid", optarg, "at most two lamp files");
			o->lid[o->n_lid++] = optarg;
			break;
		case 'p':
			o->preset = optarg;
			break;
		case 's':
			rc = hl_scene_from_name(optarg);
			if (rc < 0)
				return hl_render_bad("--scene", optarg,
						     "sphere, wall, road, bird or bounce");
			o->scene = rc;
			break;
		case 'v':
			rc = hl_view_from_name(optarg);
			if (rc < 0)
				return hl_render_bad("--view", optarg, "display, hdr, lux or lid");
			o->view = rc;
			break;
		case 'S':
			if (hl_render_parse_size(optarg, &o->width, &o->height))
				return HL_EXIT_USAGE;
			break;
		case 'o':
			o->out = optarg;
			break;
		case OPT_EXPOSURE:
			if (hl_render_parse_numbers(optarg, ',', &o->exposure_ev, 1) < 0)
				return hl_render_bad("--exposure", optarg, "a number (EV)");
			break;
		case OPT_ISO:
			if (hl_render_parse_iso(optarg, &o->lux) < 0)
				return hl_render_bad("--iso", optarg,
						     "positive lux levels, comma-separated");
			o->have_iso = true;
			break;
		case OPT_NO_LABELS:
			o->labels = false;
			break;
		case OPT_KPI:
			o->kpi = optarg;
			break;
		case OPT_KPI_LEVELS:
			if (hl_render_parse_numbers(optarg, ',', o->kpi_levels_lx,
						    HL_ROAD_KPI_LEVELS) < 0 ||
			    !(o->kpi_levels_lx[0] > 0.0) || !(o->kpi_levels_lx[1] > 0.0))
				return hl_render_bad("--kpi-levels", optarg,
						     "two positive lux levels L1,L2");
			break;
		case OPT_WALL:
			if (hl_render_parse_numbers(optarg, ',', &o->wall_distance_m, 1) < 0 ||
			    !(o->wall_distance_m > 1.0))
				return hl_render_bad("--wall-distance", optarg, "metres > 1");
			break;
		case OPT_CAM_POS:
			if (hl_render_parse_numbers(optarg, ',', o->camera_pos, 3) < 0)
				return hl_render_bad("--camera-pos", optarg, "X,Y,Z in metres");
			o->have_camera_pos = true;
			break;
		case OPT_CAM_DIR:
			if (hl_render_parse_numbers(optarg, ',', o->camera_dir, 3) < 0 ||
			    (o->camera_dir[0] == 0 && o->camera_dir[1] == 0 &&
			     o->camera_dir[2] == 0))
				return hl_render_bad("--camera-dir", optarg, "X,Y,Z, not zero");
			o->have_camera_dir = true;
			break;
		case OPT_FOV:
			if (hl_render_parse_numbers(optarg, ',', &o->fov_deg, 1) < 0 ||
			    !(o->fov_deg > 1.0 && o->fov_deg < 170.0))
				return hl_render_bad("--fov", optarg, "degrees in 1..170");
			break;
		case OPT_LEFT_POS:
		case OPT_RIGHT_POS:
			if (hl_render_parse_numbers(optarg, ',', o->poses[c == OPT_RIGHT_POS].pos_m,
						    3) < 0)
				return hl_render_bad(c == OPT_LEFT_POS ? "--left-pos" :
									 "--right-pos",
						     optarg, "X,Y,Z in metres");
			break;
		case OPT_LEFT_AIM:
		case OPT_RIGHT_AIM:
			if (hl_render_parse_numbers(optarg, ',', v, 2) < 0 || fabs(v[0]) > 90 ||
			    fabs(v[1]) > 45)
				return hl_render_bad(c == OPT_LEFT_AIM ? "--left-aim" :
									 "--right-aim",
						     optarg, "YAW,PITCH in degrees");
			o->poses[c == OPT_RIGHT_AIM].yaw_deg = v[0];
			o->poses[c == OPT_RIGHT_AIM].pitch_deg = v[1];
			break;
		case OPT_LAMP:
			rc = hl_side_from_name(optarg);
			if (rc < 0)
				return hl_render_bad("--lamp", optarg, "left or right");
			o->lamp = rc;
			break;
		case OPT_BACKEND:
			rc = hl_backend_from_name(optarg);
			if (rc < 0)
				return hl_render_bad("--backend", optarg, "auto, cpu or gles");
			o->backend = rc;
			break;
		case OPT_GI:
			if (strcmp(optarg, "sensor") != 0)
				return hl_render_bad("--gi", optarg, "sensor");
			o->gi = true;
			break;
		case OPT_SENSOR_SIZE:
			if (sscanf(optarg, "%d%c", &o->gi_cfg.sensor_size, &tail) != 1 ||
			    o->gi_cfg.sensor_size < 2 || o->gi_cfg.sensor_size > 512 ||
			    o->gi_cfg.sensor_size % 2)
				return hl_render_bad("--sensor-size", optarg,
						     "an even number in 2..512");
			break;
		case OPT_TILE:
			if (sscanf(optarg, "%d%c", &o->gi_cfg.tile, &tail) != 1 ||
			    o->gi_cfg.tile < 1 || o->gi_cfg.tile > 256 ||
			    (o->gi_cfg.tile & (o->gi_cfg.tile - 1)))
				return hl_render_bad("--tile", optarg, "a power of two in 1..256");
			break;
		case OPT_DRADIANCE:
			if (hl_render_parse_numbers(optarg, ',', &o->gi_cfg.dradiance, 1) < 0 ||
			    !(o->gi_cfg.dradiance > 0.0))
				return hl_render_bad("--dradiance", optarg, "a number > 0");
			break;
		case OPT_SENSOR_AA:
			if (sscanf(optarg, "%d%c", &o->gi_cfg.aa_samples, &tail) != 1 ||
			    o->gi_cfg.aa_samples < 1 || o->gi_cfg.aa_samples > 16)
				return hl_render_bad("--sensor-aa", optarg, "1..16");
			break;
		case OPT_GI_THREADS:
			if (sscanf(optarg, "%d%c", &o->gi_cfg.threads, &tail) != 1 ||
			    o->gi_cfg.threads < 1 || o->gi_cfg.threads > HL_GI_MAX_THREADS)
				return hl_render_bad("--gi-threads", optarg, "1..64");
			break;
		case OPT_SENSOR_BACKEND:
			rc = hl_backend_from_name(optarg);
			if (rc < 0)
				return hl_render_bad("--sensor-backend", optarg,
						     "auto, cpu or gles");
			o->sensor_backend = rc;
			break;
		case OPT_SENSOR_BATCH:
			if (sscanf(optarg, "%d%c", &o->sensor_batch, &tail) != 1 ||
			    o->sensor_batch < 1 || o->sensor_batch > 4096)
				return hl_render_bad("--sensor-batch", optarg, "1..4096");
			break;
		case 'h':
			usage(stdout);
			return -HL_EXIT_OK - 1;
		default:
			usage(stderr);
			return HL_EXIT_USAGE;
		}
	}
	if (optind != argc || !o->out || (!o->lamps_dir && !o->n_lid) ||
	    (o->lamps_dir && o->n_lid)) {
		usage(stderr);
		return HL_EXIT_USAGE;
	}
	if (!hl_render_ends_with(o->out, ".png") && !hl_render_ends_with(o->out, ".exr"))
		return hl_render_bad("--out", o->out, "a .png or .exr file");
	if (o->view == HL_VIEW_HDR && !hl_render_ends_with(o->out, ".exr"))
		return hl_render_bad("--out", o->out, "an .exr file for the hdr view");
	if (o->gi && (o->view != HL_VIEW_DISPLAY || !hl_render_ends_with(o->out, ".png")))
		return hl_render_bad("--out", o->out, "a .png file and the display view with --gi");
	return 0;
}

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

static void gi_progress(void *userdata, size_t done, size_t estimated)
{
	(void)userdata;
	fprintf(stderr, "\rhdlamp render: gi: sensors %zu / ~%zu", done, estimated);
}

/* BASE-suffix from --out BASE.png. */
static void derived(const char *out, const char *suffix, char *buf, size_t size)
{
	snprintf(buf, size, "%.*s-%s", (int)(strlen(out) - 4), out, suffix);
}

static int write_exr_luminance(const char *path, const struct hl_gbuffer *gb, const float *lux,
			       struct hl_frame_exr_info *info, float *rgba)
{
	struct hl_lid_error err;
	int rc;

	hl_view_hdr(gb, lux, rgba);
	rc = hl_frame_exr_write_hdr(path, gb->width, gb->height, rgba, info, &err);
	if (rc < 0)
		fprintf(stderr, "hdlamp render: %s\n", err.msg);
	return rc;
}

static int write_png(const char *path, const uint8_t *rgb, int w, int h)
{
	const int rc = hl_png_write_rgb(path, rgb, w, h);

	if (rc < 0)
		fprintf(stderr, "hdlamp render: '%s': %s\n", path, strerror(-rc));
	return rc;
}

/* The GLES sensors over the scene's mesh; NULL with the reason in log when they cannot run. */
static struct hl_gl_sensor *gles_sensors(const struct options *o, const struct hl_egl *egl,
					 const struct hl_scene *scene,
					 const struct hl_sensor_scene *field, char *log,
					 size_t log_size)
{
	struct hl_gl_sensor_config gcfg;
	struct hl_scene_mesh *mesh;
	struct hl_gl_sensor *gs = NULL;
	int rc = hl_scene_mesh_new(scene, &mesh);

	if (rc < 0) {
		snprintf(log, log_size, "no scene mesh: %s", strerror(-rc));
		return NULL;
	}
	hl_gl_sensor_config_for(egl, o->gi_cfg.sensor_size, o->gi_cfg.aa_samples,
				o->sensor_batch ? o->sensor_batch : GLES_SENSOR_BATCH, &gcfg);
	rc = hl_gl_sensor_new(egl, mesh, field->n_lamps, field->lamps, &gcfg, &gs, log, log_size);
	hl_scene_mesh_free(mesh);
	for (int k = 0; rc == 0 && k < field->n_lamps; k++)
		rc = hl_gl_sensor_upload(gs, k, field->dense[k]);
	if (rc < 0) {
		if (gs)
			snprintf(log, log_size, "cannot upload the distributions");
		hl_gl_sensor_free(gs);
		return NULL;
	}
	return gs;
}

/*
 * --gi sensor: the indirect illuminance of the G-buffer's points by sensor-based lighting, then
 * the total (direct + indirect) as the display view and the files beside it.
 */
static int run_gi(struct options *o, const struct hl_egl *egl, const struct hl_scene *scene,
		  const struct hl_camera *cam, const struct hl_gbuffer *gb, struct hl_renderer *r,
		  const float *direct, int n_lamps)
{
	struct hl_gi_sensors cpu = { .fn = hl_sensor_scene_radiance };
	struct hl_gi_sensors gles = { .batch = hl_gl_sensor_gi_batch };
	const struct hl_gi_sensors *sensors = &cpu;
	struct hl_gi_config cpu_cfg, gles_cfg;
	const struct hl_gi_config *cfg = &cpu_cfg;
	struct hl_gl_sensor *gs = NULL;
	enum hl_backend backend = o->sensor_backend;
	char log[1024] = "", how[96];
	const size_t n = (size_t)gb->width * gb->height;
	struct hl_capsule thin[HL_SCENE_MAX_THIN];
	struct hl_sensor_scene field = { .scene = scene, .n_lamps = n_lamps };
	struct hl_frame_exr_info info = { .camera = cam, .n_lamps = n_lamps };
	struct hl_gi_stats st;
	struct hl_view_lux_opts diff_opts;
	char path[4096], gi_desc[160];
	float *ind = malloc(sizeof(float) * n), *total = malloc(sizeof(float) * n);
	float *rgba = malloc(sizeof(float) * 4 * n);
	uint8_t *rgb = malloc(3 * n);
	int rc = -ENOMEM;

	if (!ind || !total || !rgba || !rgb) {
		fprintf(stderr, "hdlamp render: out of memory\n");
		goto out;
	}
	for (int k = 0; k < n_lamps; k++) {
		field.lamps[k] = (struct hl_headlight_lamp){ o->poses[k], *hl_renderer_grid(r, k) };
		field.dense[k] = hl_renderer_distribution(r, k);
		if (!field.dense[k]) {
			rc = -EIO;
			goto out;
		}
	}
	o->gi_cfg.thin = thin;
	o->gi_cfg.n_thin = hl_scene_thin_objects(scene, thin, HL_SCENE_MAX_THIN);
	o->gi_cfg.progress = gi_progress;
	cpu.field = &field;
	cpu_cfg = o->gi_cfg;
	cpu_cfg.batch = o->sensor_batch ? o->sensor_batch : GI_DEFAULTS.batch;
	gles_cfg = o->gi_cfg;
	gles_cfg.batch = o->sensor_batch ? o->sensor_batch : GLES_SENSOR_BATCH;
	if (backend != HL_BACKEND_CPU) {
		gs = gles_sensors(o, egl, scene, &field, log, sizeof(log));
		if (!gs && backend == HL_BACKEND_GLES) {
			fprintf(stderr,
				"hdlamp render: --sensor-backend gles: no GLES sensors: %s\n", log);
			rc = -ENOTSUP;
			goto out;
		}
		if (!gs) {
			fprintf(stderr, "hdlamp render: gi: no GLES sensors (%s): sensors on cpu\n",
				log);
			backend = HL_BACKEND_CPU;
		}
		gles.userdata = gs;
	}
	if (backend == HL_BACKEND_AUTO) {
		struct hl_gi_config tc = cpu_cfg, tg = gles_cfg;
		double ms_cpu = 0.0, ms_gles = 0.0;

		tc.progress = tg.progress = NULL;
		rc = hl_gi_time_batch(&tc, &cpu, gb, &ms_cpu);
		if (rc == 0)
			rc = hl_gi_time_batch(&tg, &gles, gb, &ms_gles);
		if (rc < 0) {
			fprintf(stderr, "hdlamp render: gi: timing the sensors failed: %s\n",
				strerror(-rc));
			goto out;
		}
		backend = ms_gles < ms_cpu ? HL_BACKEND_GLES : HL_BACKEND_CPU;
		fprintf(stderr,
			"hdlamp render: gi: one batch: cpu %.3f ms per sensor (%d threads, batch %d), "
			"gles %.3f ms per sensor (batch %d): sensors on %s\n",
			ms_cpu, cpu_cfg.threads, cpu_cfg.batch, ms_gles, gles_cfg.batch,
			hl_backend_name(backend));
	}
	if (backend == HL_BACKEND_GLES) {
		struct hl_gl_sensor_config gcfg;

		sensors = &gles;
		cfg = &gles_cfg;
		hl_gl_sensor_config_for(egl, cfg->sensor_size, cfg->aa_samples, cfg->batch, &gcfg);
		snprintf(how, sizeof(how), "gles, batch %d, %d samples x %dx%d sub-texels",
			 cfg->batch, gcfg.msaa, gcfg.supersample, gcfg.supersample);
	} else {
		snprintf(how, sizeof(how), "cpu, %d threads", cfg->threads);
	}
	rc = hl_gi_run_sensors(cfg, sensors, gb, ind, &st);
	fputc('\n', stderr);
	if (rc < 0) {
		fprintf(stderr, "hdlamp render: gi failed: %s\n", strerror(-rc));
		goto out;
	}
	fprintf(stderr,
		"hdlamp render: gi: %zu sensors for %zu surface pixels (%.1fx fewer than one per "
		"pixel), %d passes, %zu batches, %dx%d hemicube (%d texels, aa %d), %.3f ms per "
		"sensor (%s), sensors %.0f ms, total %.0f ms\n",
		st.sensors, st.surface_pixels,
		st.sensors ? (double)st.surface_pixels / st.sensors : 0.0, st.levels, st.batches,
		cfg->sensor_size, cfg->sensor_size, 3 * cfg->sensor_size * cfg->sensor_size,
		cfg->aa_samples, st.sensors ? st.sensor_ms / st.sensors : 0.0, how, st.sensor_ms,
		st.total_ms);
	for (size_t i = 0; i < n; i++)
		total[i] = direct[i] + ind[i];

	memcpy(info.lamps, o->poses, sizeof(info.lamps));
	snprintf(gi_desc, sizeof(gi_desc),
		 "sensor size=%d tile=%d dradiance=%g aa=%d sensors=%zu backend=%s",
		 o->gi_cfg.sensor_size, o->gi_cfg.tile, o->gi_cfg.dradiance, o->gi_cfg.aa_samples,
		 st.sensors, hl_backend_name(backend));
	info.n_meta = 2;
	info.meta_names[0] = "hdlamp:gi";
	info.meta_values[0] = gi_desc;
	info.meta_names[1] = "hdlamp:component";
	{
		static const char *const comp[] = { "direct", "indirect", "total" };
		const float *src[] = { direct, ind, total };

		for (int c = 0; c < 3; c++) {
			char name[32];

			snprintf(name, sizeof(name), "%s.exr", comp[c]);
			derived(o->out, name, path, sizeof(path));
			info.meta_values[1] = comp[c];
			rc = write_exr_luminance(path, gb, src[c], &info, rgba);
			if (rc < 0)
				goto out;
		}
	}
	hl_view_display(gb, direct, o->exposure_ev, rgb);
	derived(o->out, "direct.png", path, sizeof(path));
	if ((rc = write_png(path, rgb, gb->width, gb->height)) < 0)
		goto out;
	/* The difference total - direct is the indirect illuminance: false colour, lux. */
	hl_view_lux_defaults(&diff_opts);
	diff_opts.min_lx = 0.001;
	diff_opts.max_lx = 10.0;
	diff_opts.n_iso = 0;
	for (size_t i = 0; i < n; i++)
		rgba[i] = total[i] - direct[i];
	hl_view_lux(gb, rgba, &diff_opts, rgb);
	derived(o->out, "diff.png", path, sizeof(path));
	if ((rc = write_png(path, rgb, gb->width, gb->height)) < 0)
		goto out;
	hl_view_display(gb, total, o->exposure_ev, rgb);
	rc = write_png(o->out, rgb, gb->width, gb->height);
out:
	hl_gl_sensor_free(gs);
	free(ind);
	free(total);
	free(rgba);
	free(rgb);
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
		if (strcmp(argv[i], "--scenario") == 0 || strncmp(argv[i], "--scenario=", 11) == 0)
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
