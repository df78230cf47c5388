/* SPDX-License-Identifier: MIT */
#include "tools/preset_arg.h"

#include <errno.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "lamp/model.h"

static bool is_file(const char *arg)
{
	const size_t n = strlen(arg);

	return (n >= 5 && strcmp(arg + n - 5, ".json") == 0) || strchr(arg, '/');
}

static int builtin(const char *prog, const char *name, struct hl_lid *const *lids, int n_lamps,
		   struct hl_preset **ret)
{
	struct hl_lid *pair[2] = { lids[0], n_lamps > 1 ? lids[1] : lids[0] };
	int rc;

	for (int k = 0; k < n_lamps; k++)
		if (hl_lid_n_sources(lids[k]) != HL_HD84_SOURCES) {
			fprintf(stderr,
				"hdlamp %s: --preset '%s': built-in presets are for HD84 lamps "
				"(%d sources); give a .json file\n",
				prog, name, HL_HD84_SOURCES);
			return -EINVAL;
		}
	rc = hl_preset_new(HL_HD84_SOURCES, ret);
	if (rc == 0)
		rc = hl_model_hd84_preset(name, pair, *ret);
	if (rc < 0) {
		fprintf(stderr, "hdlamp %s: --preset '%s': no such preset\n", prog, name);
		hl_preset_free(*ret);
		*ret = NULL;
	}
	return rc;
}

int hl_tool_preset_load(const char *prog, const char *arg, struct hl_lid *const *lids, int n_lamps,
			struct hl_preset **ret)
{
	struct hl_preset_error err = { 0 };
	int rc;

	*ret = NULL;
	if (!is_file(arg))
		return builtin(prog, arg, lids, n_lamps, ret);
	rc = hl_preset_read(arg, ret, &err);
	if (rc < 0) {
		if (err.line)
			fprintf(stderr, "hdlamp %s: '%s':%d:%d: %s\n", prog, arg, err.line,
				err.column, err.msg);
		else
			fprintf(stderr, "hdlamp %s: '%s': %s\n", prog, arg,
				err.msg[0] ? err.msg : strerror(-rc));
		return rc;
	}
	for (int k = 0; k < n_lamps; k++)
		if (!hl_lid_is_combined(lids[k]) &&
		    hl_lid_n_sources(lids[k]) != (*ret)->n_sources) {
			fprintf(stderr,
				"hdlamp %s: '%s': %d sources per lamp, the %s lamp has %d\n", prog,
				arg, (*ret)->n_sources, hl_side_name(k), hl_lid_n_sources(lids[k]));
			hl_preset_free(*ret);
			*ret = NULL;
			return -EINVAL;
		}
	return 0;
}
