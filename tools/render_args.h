/* SPDX-License-Identifier: MIT */
/*
 * What `hdlamp render` and `hdlamp render --scenario` share: their argument checks and how they
 * load the lamps and the preset (docs/cli.md). Errors are printed as "hdlamp render: ...".
 */
#ifndef HL_TOOLS_RENDER_ARGS_H
#define HL_TOOLS_RENDER_ARGS_H

#include <stdbool.h>

#include "lamp/lid.h"
#include "lamp/preset.h"
#include "render/view.h"

bool hl_render_ends_with(const char *s, const char *suffix);

/* Prints "hdlamp render: OPT 'ARG': expected EXPECTED" and returns HL_EXIT_USAGE. */
int hl_render_bad(const char *opt, const char *arg, const char *expected);

/* n >= 1 finite numbers separated by sep, nothing else; 0 or -EINVAL. */
int hl_render_parse_numbers(const char *s, char sep, double *out, int n);

/* --size WxH, 2..8192 each: 0, or the usage error printed and HL_EXIT_USAGE. */
int hl_render_parse_size(const char *arg, int *ret_width, int *ret_height);

/* Positive lux levels, comma-separated, at most HL_VIEW_MAX_ISO: 0 or -EINVAL. */
int hl_render_parse_iso(const char *s, struct hl_view_lux_opts *o);

/*
 * The lamps: lamps_dir/hd84_left.lid.exr and _right (n_lamps 2), or the n_lid files lid[].
 * Unless every lamp file is a combined distribution, the preset's currents too: a file,
 * lamps_dir/NAME.json, or a built-in HD84 preset (tools/preset_arg.h). 0 or -errno, reported.
 */
int hl_render_load_lamps(const char *lamps_dir, const char *const lid[2], int n_lid,
			 const char *preset, struct hl_lid *lids[2], int *n_lamps,
			 struct hl_preset **ret_preset);

#endif
