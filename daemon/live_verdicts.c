/* SPDX-License-Identifier: MIT */
/* The daemon's live verdicts: see daemon/live_verdicts.h. */
#include "daemon/live_verdicts.h"

#include <errno.h>

#include "daemon/live_log.h"

int hl_live_verdicts_new(const struct hl_config *cfg, const struct hl_assembler *a, int n_lamps,
			 const char *const *lamp_names, const struct hl_lid_grid *const *grids,
			 struct hl_verdicts **ret, bool *ret_config_error)
{
	struct hl_lamp_pose poses[HL_FRAME_MAX_LAMPS];
	struct hl_verdicts_mode_source mode = { -1, NULL };
	struct hl_verdicts *v;
	char err[1024];
	int rc;

	for (int l = 0; l < n_lamps; l++) {
		hl_lamp_pose_default(l, &poses[l]); /* as the renderer places them */
		if (mode.lamp < 0 && hl_assembler_mode_signal(a, l))
			mode = (struct hl_verdicts_mode_source){ l,
								 hl_assembler_mode_signal(a, l) };
	}
	rc = hl_verdicts_new(cfg, n_lamps, lamp_names, grids, poses, &mode, &v, err, sizeof(err));
	if (rc < 0) {
		hl_live_log("%s", err);
		*ret_config_error = rc != -ENOMEM;
		return rc;
	}
	for (int i = 0; i < hl_verdicts_n_sets(v); i++) {
		const struct hl_regulation *reg = hl_verdicts_set(v, i);

		hl_live_log("verdict: set '%s' (%d requirements, %s): %s", reg->id,
			    reg->n_requirements,
			    reg->applies == HL_REG_PAIR_HALF ? "half the pair's sum" : "each lamp",
			    reg->title);
	}
	if (mode.lamp >= 0)
		hl_live_log(
			"verdict: beam mode from signal %s of lamp '%s'%s", mode.signal->name,
			lamp_names[mode.lamp],
			cfg->verdict_modes[0] ?
				" (the sets of each mode as verdict.modes says)" :
				" (each set in its own beam's modes; verdict.modes may say otherwise)");
	else
		hl_live_log("verdict: no beam-mode signal in the lamp database: every set on every "
			    "frame");
	*ret = v;
	return 0;
}
