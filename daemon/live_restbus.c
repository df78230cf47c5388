/* SPDX-License-Identifier: MIT */
/* The daemon's restbus: see daemon/live_restbus.h. */
#include "daemon/live_restbus.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "base/share_dir.h"
#include "daemon/live_log.h"

/*
 * The restbus (restbus.interface): the input database (restbus.dbc, or the shipped
 * hd84_inputs.dbc), the camera. A bad database or camera is a configuration error (exit 2).
 */
int hl_live_restbus_new(const struct hl_config *cfg, const struct hl_scenario *sc,
			struct hl_pose_input *pose, struct hl_osi_input *osi,
			struct hl_loop_latency *loop, struct hl_restbus **ret,
			bool *ret_config_error)
{
	char dbc[HL_CONFIG_PATH + 32], msg[1024];
	const char *sw = cfg->restbus_light_switch;
	struct hl_restbus_config rc_cfg = {
		.iface = cfg->restbus_interface,
		.dbc = dbc,
		.sc = sc,
		.pose = pose,
		.osi = osi,
		.cam = { .pos_m = { cfg->restbus_camera_pos_m[0], cfg->restbus_camera_pos_m[1],
				    cfg->restbus_camera_pos_m[2] },
			 .fov_h_deg = cfg->restbus_fov_deg[0],
			 .fov_v_deg = cfg->restbus_fov_deg[1],
			 .range_m = cfg->restbus_range_m },
		.light_switch = strcmp(sw, "off") == 0	? HL_SWITCH_OFF :
				strcmp(sw, "low") == 0	? HL_SWITCH_LOW :
				strcmp(sw, "high") == 0 ? HL_SWITCH_HIGH :
							  HL_SWITCH_AUTO,
		.adb_enable = cfg->restbus_adb_enable,
		.rt_priority = cfg->rt_priority > 1 ? cfg->rt_priority - 1 : cfg->rt_priority,
		.log = stderr,
		.loop = loop,
	};
	struct hl_restbus *rb;
	int rc;

	if (!cfg->restbus_interface[0] || !sc) {
		*ret = NULL;
		return 0;
	}
	if (cfg->restbus_dbc[0]) {
		snprintf(dbc, sizeof(dbc), "%s", cfg->restbus_dbc);
	} else if (hl_share_dir("dbc", dbc, sizeof(dbc) - 20) == 0) {
		strcat(dbc, "/hd84_inputs.dbc");
	} else {
		hl_live_log("restbus.dbc: cannot find the shipped databases beside the binary; set "
			    "restbus.dbc");
		*ret_config_error = true;
		return -ENOENT;
	}
	rc = hl_restbus_new(&rc_cfg, &rb, msg, sizeof(msg));
	if (rc < 0) {
		hl_live_log("%s", msg);
		*ret_config_error = rc == -EINVAL || rc == -ENOENT;
		return rc;
	}
	hl_live_log("restbus on '%s' from '%s': camera at %g,%g,%g m, field of view %g x %g deg, "
		    "range %g m; light switch %s, ADB %s",
		    cfg->restbus_interface, dbc, rc_cfg.cam.pos_m[0], rc_cfg.cam.pos_m[1],
		    rc_cfg.cam.pos_m[2], rc_cfg.cam.fov_h_deg, rc_cfg.cam.fov_v_deg,
		    rc_cfg.cam.range_m, sw, cfg->restbus_adb_enable ? "enabled" : "disabled");
	*ret = rb;
	return 0;
}
