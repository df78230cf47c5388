/* SPDX-License-Identifier: MIT */
/*
 * What the files of hdlamp render's stills share (cmd_render.c, cmd_render_options.c,
 * cmd_render_gi.c): the options and their defaults; not for the other commands (render --scenario
 * shares tools/render_args.h instead). Errors are printed as "hdlamp render: ...".
 */
#ifndef HL_TOOLS_CMD_RENDER_H
#define HL_TOOLS_CMD_RENDER_H

#include <stdbool.h>

#include "render/gi.h"
#include "render/renderer.h"
#include "render/road_kpi.h"
#include "render/scene.h"
#include "render/view.h"

#define DEFAULT_EXPOSURE_EV 0.0 /* 1 cd/m^2 maps to half of full scale */
#define BIRD_EXPOSURE_EV 2.0 /* from above most of the road is far and dim */
#define SPHERE_EXPOSURE_EV (-3.0) /* 10 m from the lamp the sphere gets up to ~250 lx */

/* The sensor-based lighting defaults, as hl_gi_config_default() gives them (cmd_render.c sets
 * them before the options are read). */
extern struct hl_gi_config GI_DEFAULTS;
#define GLES_SENSOR_BATCH 128 /* sensors per draw of the GLES sensors */

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

/* cmd_render_options.c: 0, an exit code, or -HL_EXIT_OK - 1 after --help. */
int parse(int argc, char **argv, struct options *o);

/* cmd_render_gi.c: --gi sensor on the still's G-buffer and direct light; 0 or -errno,
 * reported. */
int run_gi(struct options *o, const struct hl_egl *egl, const struct hl_scene *scene,
	   const struct hl_camera *cam, const struct hl_gbuffer *gb, struct hl_renderer *r,
	   const float *direct, int n_lamps);

#endif
