/* SPDX-License-Identifier: MIT */
/*
 * hdlamp render's usage and options (without --scenario, which cmd_render_scenario.c reads):
 * apart from the rendering (cmd_render.c) because the option table and its checks are long.
 */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "render/gi.h"
#include "render/renderer.h"
#include "render/scene.h"
#include "render/view.h"
#include "tools/cmd_render.h"
#include "tools/commands.h"
#include "tools/render_args.h"

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

/* 0, or an exit code. */
int parse(int argc, char **argv, struct options *o)
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
