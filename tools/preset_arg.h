/* SPDX-License-Identifier: MIT */
/*
 * The --preset argument of the hdlamp commands that light lamps (render, glare): a preset file
 * (a name ending in .json or a path with '/', docs/rendering.md, --preset) or a built-in HD84 preset by name
 * (lamp/model.h: low, high, glarefree, bend_left, bend_right).
 */
#ifndef HL_TOOLS_PRESET_ARG_H
#define HL_TOOLS_PRESET_ARG_H

#include "lamp/lid.h"
#include "lamp/preset.h"

/*
 * Loads arg for n_lamps lamps (1 or 2; one lamp plays both sides of a built-in preset); every
 * lamp that is not combined must have the preset's number of sources. Errors go to stderr,
 * prefixed "hdlamp PROG:", naming the file (line and column when known) or the name and what
 * was expected. 0, -EINVAL, -ENOENT, -ENOMEM, or the reader's -errno.
 */
int hl_tool_preset_load(const char *prog, const char *arg, struct hl_lid *const *lids, int n_lamps,
			struct hl_preset **ret);

#endif
