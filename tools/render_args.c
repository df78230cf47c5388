/* SPDX-License-Identifier: MIT */
#include "tools/render_args.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lamp/model.h"
#include "tools/commands.h"
#include "tools/preset_arg.h"

bool hl_render_ends_with(const char *s, const char *suffix)
{
	const size_t n = strlen(s), m = strlen(suffix);

	return n >= m && strcmp(s + n - m, suffix) == 0;
}

int hl_render_bad(const char *opt, const char *arg, const char *expected)
{
	fprintf(stderr, "hdlamp render: %s '%s': expected %s\n", opt, arg, expected);
	return HL_EXIT_USAGE;
}

int hl_render_parse_numbers(const char *s, char sep, double *out, int n)
{
	char *end = NULL;

	if (n < 1)
		return -EINVAL;
	for (int i = 0; i < n; i++) {
		errno = 0;
		out[i] = strtod(s, &end);
		if (errno || end == s || !isfinite(out[i]))
			return -EINVAL;
		if (i < n - 1) {
			if (*end != sep)
				return -EINVAL;
			s = end + 1;
		}
	}
	return *end ? -EINVAL : 0;
}

int hl_render_parse_size(const char *arg, int *ret_width, int *ret_height)
{
	char tail;

	if (sscanf(arg, "%dx%d%c", ret_width, ret_height, &tail) != 2 || *ret_width < 2 ||
	    *ret_height < 2 || *ret_width > 8192 || *ret_height > 8192)
		return hl_render_bad("--size", arg, "WxH, 2..8192 each");
	return 0;
}

int hl_render_parse_iso(const char *s, struct hl_view_lux_opts *o)
{
	char *end;

	o->n_iso = 0;
	while (*s) {
		double v;

		if (o->n_iso == HL_VIEW_MAX_ISO)
			return -EINVAL;
		errno = 0;
		v = strtod(s, &end);
		if (errno || end == s || !(v > 0.0) || !isfinite(v) || (*end && *end != ','))
			return -EINVAL;
		o->iso_lx[o->n_iso++] = v;
		s = *end ? end + 1 : end;
	}
	return o->n_iso ? 0 : -EINVAL;
}

int hl_render_load_lamps(const char *lamps_dir, const char *const lid[2], int n_lid,
			 const char *preset, struct hl_lid *lids[2], int *n_lamps,
			 struct hl_preset **ret_preset)
{
	char path[4096];
	int rc;

	*n_lamps = lamps_dir ? 2 : n_lid;
	for (int k = 0; k < *n_lamps; k++) {
		struct hl_lid_error err;

		if (lamps_dir)
			snprintf(path, sizeof(path), "%s/hd84_%s.lid.exr", lamps_dir,
				 hl_side_name(k));
		else
			snprintf(path, sizeof(path), "%s", lid[k]);
		rc = hl_lid_read(path, &lids[k], &err);
		if (rc < 0) {
			fprintf(stderr, "hdlamp render: %s\n", err.msg);
			return rc;
		}
	}
	if (hl_lid_is_combined(lids[0]) && (*n_lamps == 1 || hl_lid_is_combined(lids[1])))
		return 0;
	/* A file, DIR/NAME.json, or a built-in HD84 preset. */
	if (lamps_dir && !hl_render_ends_with(preset, ".json") && !strchr(preset, '/'))
		snprintf(path, sizeof(path), "%s/%s.json", lamps_dir, preset);
	else
		snprintf(path, sizeof(path), "%s", preset);
	return hl_tool_preset_load("render", path, lids, *n_lamps, ret_preset);
}
