/* SPDX-License-Identifier: MIT */
/*
 * hdlamp render --scenario: stills of a scenario's moving scene at given times, lit by the ego
 * lamps (docs/scenarios.md, "How a scenario is rendered"). Per frame: the world state at t, its
 * G-buffer in the ego frame (render/world_scene.h), a renderer made for that G-buffer, the
 * view, and the road users' lamps drawn into the display view.
 */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/egl.h"
#include "render/frame_exr.h"
#include "render/plot.h"
#include "render/renderer.h"
#include "world/scenario.h"
#include "render/view.h"
#include "world/world.h"
#include "render/world_scene.h"
#include "tools/world_arg.h"
#include "tools/commands.h"
#include "tools/preset_arg.h"
#include "tools/render_args.h"
#include "lamp/preset.h"

#define DEFAULT_EXPOSURE_EV 0.0
#define BIRD_EXPOSURE_EV 2.0
#define MAX_FRAMES 100000
#define BIRD_NEAR_M (-10.0) /* the bird's-eye view spans this far behind the ego bumper */
#define BIRD_FAR_M 140.0 /* to this far ahead */
#define MAX_EMITTERS (HL_SCN_MAX_ACTORS * HL_SCN_MAX_LAMPS)

static void usage(FILE *f)
{
	fprintf(f,
		"usage: hdlamp render (--scenario FILE | --world osi:file:TRACE.osi)\n"
		"                     (--at T | --frames A:B:STEP)\n"
		"                     (--lamps DIR | --lid LEFT.lid.exr [--lid RIGHT.lid.exr])\n"
		"                     --out FILE.png|FILE.exr [options]\n"
		"\n"
		"Renders the scenario's moving scene at scenario time T (s), or at A, A + STEP, ... up\n"
		"to B, lit by the ego lamps; the road users' lamps are drawn into the display view.\n"
		"\n"
		"  --scenario FILE      a scenario file (docs/scenarios.md)\n"
		"  --world osi:file:TRACE.osi  the scene of an ASAM OSI trace (docs/osi.md); a\n"
		"                       --scenario beside it lends the ego's lamps, camera, a road\n"
		"  --osi-message M      auto (the trace's file name) | ground-truth | sensor-view\n"
		"  --at T               one still at time T (s)\n"
		"  --frames A:B:STEP    a sequence; frame i (from 0) at A + i STEP goes to\n"
		"                       BASE-NNNN.png (or .exr) for --out BASE.png\n"
		"  --lamps DIR, --lid FILE, --preset NAME|FILE   as hdlamp render (default low)\n"
		"  --scene S            road (default): the driver's camera of the scenario;\n"
		"                       bird: from above the ego, looking down, the road ahead\n"
		"                       running to the right\n"
		"  --view V             display (default) | lux | hdr (.exr only)\n"
		"  --size WxH           image size, default 1280x720\n"
		"  --out FILE           .png (display, lux) or .exr (lux: channel E in lux; hdr:\n"
		"                       RGBA half luminance)\n"
		"  --exposure EV        display exposure, default %.1f (bird: %.1f)\n"
		"  --iso L1,L2,...      iso-lux lines of the lux view, default 1,3,5,10,20,50\n"
		"  --backend B          auto (default) | cpu | gles: where combine and headlight run\n",
		DEFAULT_EXPOSURE_EV, BIRD_EXPOSURE_EV);
}

struct options {
	const char *scenario, *lamps_dir, *lid[2], *preset, *out;
	const char *world, *osi_message; /* --world osi:file:TRACE.osi (tools/world_arg.h) */
	int n_lid;
	double t0_s, t1_s, step_s;
	bool have_at, have_frames, bird;
	enum hl_view_kind view;
	int width, height;
	double exposure_ev;
	struct hl_view_lux_opts lux;
	enum hl_backend backend;
};

/* 0, or an exit code (a negative one: --help was printed). */
static int parse(int argc, char **argv, struct options *o)
{
	enum {
		OPT_SCENARIO = 256,
		OPT_AT,
		OPT_FRAMES,
		OPT_EXPOSURE,
		OPT_ISO,
		OPT_BACKEND,
		OPT_WORLD,
		OPT_OSI_MESSAGE
	};
	static const struct option opts[] = {
		{ "scenario", required_argument, NULL, OPT_SCENARIO },
		{ "world", required_argument, NULL, OPT_WORLD },
		{ "osi-message", required_argument, NULL, OPT_OSI_MESSAGE },
		{ "at", required_argument, NULL, OPT_AT },
		{ "frames", required_argument, NULL, OPT_FRAMES },
		{ "lamps", required_argument, NULL, 'L' },
		{ "lid", required_argument, NULL, 'l' },
		{ "preset", required_argument, NULL, 'p' },
		{ "scene", required_argument, NULL, 's' },
		{ "view", required_argument, NULL, 'v' },
		{ "size", required_argument, NULL, 'S' },
		{ "out", required_argument, NULL, 'o' },
		{ "exposure", required_argument, NULL, OPT_EXPOSURE },
		{ "iso", required_argument, NULL, OPT_ISO },
		{ "backend", required_argument, NULL, OPT_BACKEND },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	double v[3];
	int c, rc;

	*o = (struct options){
		.preset = "low",
		.view = HL_VIEW_DISPLAY,
		.width = 1280,
		.height = 720,
		.exposure_ev = NAN,
	};
	hl_view_lux_defaults(&o->lux);
	optind = 1;
	while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
		switch (c) {
		case OPT_SCENARIO:
			o->scenario = optarg;
			break;
		case OPT_WORLD:
			o->world = optarg;
			break;
		case OPT_OSI_MESSAGE:
			o->osi_message = optarg;
			break;
		case OPT_AT:
			if (hl_render_parse_numbers(optarg, ',', &o->t0_s, 1) < 0)
				return hl_render_bad("--at", optarg, "a time in seconds");
			o->t1_s = o->t0_s;
			o->step_s = 1.0;
			o->have_at = true;
			break;
		case OPT_FRAMES:
			if (hl_render_parse_numbers(optarg, ':', v, 3) < 0 || !(v[2] > 0.0) ||
			    v[1] < v[0] || (v[1] - v[0]) / v[2] >= MAX_FRAMES)
				return hl_render_bad(
					"--frames", optarg,
					"A:B:STEP in seconds, A <= B, STEP > 0, at most 100000 "
					"frames");
			o->t0_s = v[0];
			o->t1_s = v[1];
			o->step_s = v[2];
			o->have_frames = true;
			break;
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
			if (strcmp(optarg, "road") != 0 && strcmp(optarg, "bird") != 0)
				return hl_render_bad("--scene", optarg,
						     "road or bird with --scenario");
			o->bird = strcmp(optarg, "bird") == 0;
			break;
		case 'v':
			rc = hl_view_from_name(optarg);
			if (rc < 0 || rc == HL_VIEW_LID)
				return hl_render_bad("--view", optarg,
						     "display, lux or hdr with --scenario");
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
			break;
		case OPT_BACKEND:
			rc = hl_backend_from_name(optarg);
			if (rc < 0)
				return hl_render_bad("--backend", optarg, "auto, cpu or gles");
			o->backend = rc;
			break;
		case 'h':
			usage(stdout);
			return -1;
		default:
			usage(stderr);
			return HL_EXIT_USAGE;
		}
	}
	if (optind != argc || (!o->scenario && !o->world) || !o->out ||
	    (!o->lamps_dir && !o->n_lid) || (o->lamps_dir && o->n_lid)) {
		usage(stderr);
		return HL_EXIT_USAGE;
	}
	if (o->have_at == o->have_frames) {
		fprintf(stderr,
			"hdlamp render: --scenario or --world needs one of --at T or --frames "
			"A:B:STEP\n");
		return HL_EXIT_USAGE;
	}
	if (!hl_render_ends_with(o->out, ".png") && !hl_render_ends_with(o->out, ".exr"))
		return hl_render_bad("--out", o->out, "a .png or .exr file");
	if (o->view == HL_VIEW_HDR && !hl_render_ends_with(o->out, ".exr"))
		return hl_render_bad("--out", o->out, "an .exr file for the hdr view");
	if (isnan(o->exposure_ev))
		o->exposure_ev = o->bird ? BIRD_EXPOSURE_EV : DEFAULT_EXPOSURE_EV;
	return 0;
}

/* The camera of the frames, in the ego frame. */
static void frame_camera(const struct options *o, const struct hl_scenario *sc,
			 struct hl_camera *ret)
{
	if (!o->bird) {
		*ret = sc->ego.camera;
	} else {
		const double half_span = (BIRD_FAR_M - BIRD_NEAR_M) / 2 + 2.0;
		const double aspect = (double)o->width / o->height;

		*ret = (struct hl_camera){ .fov_y_deg = 30.0 };
		ret->pos_m[0] = BIRD_NEAR_M + half_span - 2.0;
		ret->pos_m[2] = half_span / (tan(ret->fov_y_deg * M_PI / 360.0) * aspect);
		ret->dir[2] = -1.0;
		ret->up[1] = 1.0;
	}
	ret->width = o->width;
	ret->height = o->height;
}

/* BASE-NNNN.EXT for frame i of a sequence; the path itself for a still. */
static void frame_path(const struct options *o, int i, char *buf, size_t size)
{
	const size_t n = strlen(o->out) - 4;

	if (o->have_at)
		snprintf(buf, size, "%s", o->out);
	else
		snprintf(buf, size, "%.*s-%04d%s", (int)n, o->out, i, o->out + n);
}

struct frame_bufs {
	struct hl_gbuffer *gb;
	float *lux, *rgba, *cur;
	uint8_t *rgb;
};

static int write_frame(const struct options *o, const char *path, const struct hl_scenario *sc,
		       struct hl_world_scene *ws, const struct hl_world_state *st,
		       const struct hl_camera *cam, struct frame_bufs *b, int n_lamps)
{
	const struct hl_gbuffer *gb = b->gb;
	struct hl_frame_exr_info info = { .camera = cam, .n_lamps = n_lamps };
	struct hl_world_emitter em[MAX_EMITTERS];
	struct hl_lid_error err;
	char t_text[32];
	int rc, n;

	memcpy(info.lamps, sc->ego.lamp, sizeof(info.lamps));
	snprintf(t_text, sizeof(t_text), "%.6f", st->t_s);
	info.n_meta = 1;
	info.meta_names[0] = "hdlamp:scenarioTime";
	info.meta_values[0] = t_text;
	if (hl_render_ends_with(path, ".exr")) {
		if (o->view == HL_VIEW_LUX) {
			rc = hl_frame_exr_write_lux(path, gb->width, gb->height, b->lux, &info,
						    &err);
		} else {
			hl_view_hdr(gb, b->lux, b->rgba);
			rc = hl_frame_exr_write_hdr(path, gb->width, gb->height, b->rgba, &info,
						    &err);
		}
		if (rc < 0)
			fprintf(stderr, "hdlamp render: %s\n", err.msg);
		return rc;
	}
	if (o->view == HL_VIEW_LUX) {
		hl_view_lux(gb, b->lux, &o->lux, b->rgb);
	} else {
		hl_view_display(gb, b->lux, o->exposure_ev, b->rgb);
		n = hl_world_scene_emitters(ws, st, cam, em, MAX_EMITTERS);
		hl_world_emitters_draw(cam, em, n, o->exposure_ev, b->rgb);
	}
	rc = hl_png_write_rgb(path, b->rgb, gb->width, gb->height);
	if (rc < 0)
		fprintf(stderr, "hdlamp render: '%s': %s\n", path, strerror(-rc));
	return rc;
}

/* One frame at t: 0, or -errno (reported). */
static int render_frame(const struct options *o, const struct hl_scenario *sc,
			struct hl_world_scene *ws, struct hl_egl *egl, struct hl_lid *const lids[2],
			int n_lamps, const struct hl_preset *preset, double t, const char *path,
			struct frame_bufs *b)
{
	struct hl_renderer_config cfg = { .n_lamps = n_lamps, .egl = egl };
	struct hl_renderer *r = NULL;
	struct hl_world_state st;
	struct hl_camera cam;
	int rc;

	frame_camera(o, sc, &cam);
	hl_world_at(sc, t, &st);
	rc = hl_world_scene_render(ws, &st, &cam, b->gb);
	if (rc < 0) {
		fprintf(stderr, "hdlamp render: cannot ray cast the scene: %s\n", strerror(-rc));
		return rc;
	}
	cfg.lids[0] = lids[0];
	cfg.lids[1] = lids[1];
	memcpy(cfg.poses, sc->ego.lamp, sizeof(cfg.poses));
	cfg.combine = o->backend;
	cfg.headlight = o->backend;
	rc = hl_renderer_new(&cfg, b->gb, &r);
	if (rc < 0) {
		fprintf(stderr, "hdlamp render: cannot set up the renderer: %s\n", strerror(-rc));
		return rc;
	}
	for (int k = 0; k < n_lamps && preset; k++) {
		hl_preset_intensities(preset, k, b->cur);
		if (hl_renderer_set_currents(r, k, b->cur) < 0) {
			fprintf(stderr, "hdlamp render: bad currents for the %s lamp\n",
				hl_side_name(k));
			rc = -EINVAL;
			goto out;
		}
	}
	rc = hl_renderer_frame(r, b->lux);
	if (rc < 0) {
		fprintf(stderr, "hdlamp render: frame at %g s failed: %s\n", t, strerror(-rc));
		goto out;
	}
	rc = write_frame(o, path, sc, ws, &st, &cam, b, n_lamps);
	if (rc == 0)
		printf("%s\n", path);
out:
	hl_renderer_free(r);
	return rc;
}

int hl_cmd_render_scenario(int argc, char **argv)
{
	struct options o;
	struct hl_scenario *sc = NULL;
	struct hl_world_scene *ws = NULL;
	struct hl_lid *lids[2] = { NULL, NULL };
	struct hl_preset *preset = NULL;
	struct hl_egl *egl = NULL;
	struct hl_egl_error eerr = { "" };
	struct hl_json_error jerr;
	struct frame_bufs b = { 0 };
	char msg[1024], path[4096];
	int n_lamps = 0, rc, status = HL_EXIT_FAIL, n_frames;

	rc = parse(argc, argv, &o);
	if (rc)
		return rc < 0 ? HL_EXIT_OK : rc;
	if (o.scenario) {
		rc = hl_scenario_read(o.scenario, &sc, &jerr);
		if (rc < 0) {
			fprintf(stderr, "hdlamp render: %s\n",
				hl_json_error_format(&jerr, msg, sizeof(msg)));
			return HL_EXIT_FAIL;
		}
	}
	if (o.world && hl_tool_world_load("hdlamp render", o.world, o.osi_message, sc, &sc) < 0)
		return HL_EXIT_FAIL;
	rc = hl_egl_new(&egl, &eerr);
	if (rc < 0) {
		fprintf(stderr, "hdlamp render: no EGL/GLES 3.1 context: %s\n", eerr.msg);
		goto out;
	}
	fprintf(stderr, "hdlamp render: EGL %s, %s, %s\n", hl_egl_platform(egl),
		hl_egl_renderer(egl), hl_egl_version(egl));
	if (hl_render_load_lamps(o.lamps_dir, o.lid, o.n_lid, o.preset, lids, &n_lamps, &preset) <
	    0)
		goto out;
	rc = hl_world_scene_new(sc, &ws);
	if (rc == 0)
		rc = hl_gbuffer_new(o.width, o.height, &b.gb);
	b.lux = malloc(sizeof(float) * (size_t)o.width * o.height);
	b.rgba = malloc(sizeof(float) * 4 * (size_t)o.width * o.height);
	b.rgb = malloc(3 * (size_t)o.width * o.height);
	b.cur = malloc(sizeof(float) * (preset ? preset->n_sources : 1));
	if (rc < 0 || !b.lux || !b.rgba || !b.rgb || !b.cur) {
		fprintf(stderr, "hdlamp render: out of memory\n");
		goto out;
	}
	n_frames = (int)floor((o.t1_s - o.t0_s) / o.step_s + 1e-9) + 1;
	for (int i = 0; i < n_frames; i++) {
		frame_path(&o, i, path, sizeof(path));
		if (render_frame(&o, sc, ws, egl, lids, n_lamps, preset, o.t0_s + i * o.step_s,
				 path, &b) < 0)
			goto out;
	}
	if (hl_world_scene_objects_dropped(ws))
		fprintf(stderr,
			"hdlamp render: %lu objects not drawn (more than %d in a row band)\n",
			hl_world_scene_objects_dropped(ws), HL_WORLD_MAX_OBJECTS);
	status = HL_EXIT_OK;
out:
	free(b.lux);
	free(b.rgba);
	free(b.rgb);
	free(b.cur);
	hl_gbuffer_free(b.gb);
	hl_world_scene_free(ws);
	hl_preset_free(preset);
	hl_lid_free(lids[0]);
	hl_lid_free(lids[1]);
	hl_egl_free(egl);
	hl_scenario_free(sc);
	return status;
}
