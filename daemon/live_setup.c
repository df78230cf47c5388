/* SPDX-License-Identifier: MIT */
/* The setup of the daemon's verdicts, scenario, loop latency and restbus (daemon/live_internal.h). */
#include "daemon/live_internal.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "base/share_dir.h"

#define ECU_CYCLE_MS 20.0 /* the dimming period of docs/design.md §1 */

int hl_live_setup_verdicts(struct live *lv)
{
	const struct hl_lid_grid *grids[HL_FRAME_MAX_LAMPS] = { NULL };
	struct hl_lamp_pose poses[HL_FRAME_MAX_LAMPS];
	struct hl_verdicts_mode_source mode = { -1, NULL };
	char err[1024];
	int rc;

	for (int l = 0; l < lv->n_lamps; l++) {
		grids[l] = hl_lid_grid(lv->lids[l]);
		hl_lamp_pose_default(l, &poses[l]); /* as the renderer places them */
		if (mode.lamp < 0 && hl_assembler_mode_signal(lv->a, l))
			mode = (struct hl_verdicts_mode_source){ l, hl_assembler_mode_signal(lv->a,
											     l) };
	}
	rc = hl_verdicts_new(&lv->cfg, lv->n_lamps, lv->lamp_names, grids, poses, &mode,
			     &lv->verdicts, err, sizeof(err));
	if (rc < 0) {
		hl_live_log("%s", err);
		lv->config_error = rc != -ENOMEM;
		return rc;
	}
	for (int i = 0; i < hl_verdicts_n_sets(lv->verdicts); i++) {
		const struct hl_regulation *reg = hl_verdicts_set(lv->verdicts, i);

		hl_live_log("verdict: set '%s' (%d requirements, %s): %s", reg->id,
			    reg->n_requirements,
			    reg->applies == HL_REG_PAIR_HALF ? "half the pair's sum" : "each lamp",
			    reg->title);
	}
	if (mode.lamp >= 0)
		hl_live_log("verdict: beam mode from signal %s of lamp '%s'%s", mode.signal->name,
			    lv->lamp_names[mode.lamp],
			    lv->cfg.verdict_modes[0] ?
				    "" :
				    " (verdict.modes is empty: every set on every frame)");
	return 0;
}

/*
 * The scenario (scene.scenario), the glare plan on the lamps' grids under scene.glare_set, and
 * the pose input (pose.listen). A bad file or set is a configuration error (exit 2).
 */
int hl_live_setup_scene(struct live *lv)
{
	const struct hl_lid_grid *grids[2];
	struct hl_regulation_error rerr = { 0, 0, "" };
	struct hl_json_error jerr;
	char msg[1024];
	int rc;

	if (!lv->cfg.scenario[0])
		return 0;
	lv->config_error = true; /* until it is all set up */
	rc = hl_scenario_read(lv->cfg.scenario, &lv->sc, &jerr);
	if (rc < 0) {
		hl_json_error_format(&jerr, msg, sizeof(msg));
		hl_live_log("scene.scenario: %s", msg);
		return rc;
	}
	if (lv->n_lamps != 2) {
		hl_live_log(
			"scene.scenario '%s': the glare at the road users' eyes takes two lamps; "
			"can.lamps has %d",
			lv->cfg.scenario, lv->n_lamps);
		return -EINVAL;
	}
	rc = hl_regulation_load(lv->cfg.regulations, lv->cfg.glare_set, &lv->glare_reg, &rerr);
	if (rc < 0) {
		if (rc == -ENOENT)
			hl_live_log("scene.glare_set: no set '%s' in '%s' (no file '%s/%s.json'; "
				    "verdict.regulations names the directory)",
				    lv->cfg.glare_set, lv->cfg.regulations, lv->cfg.regulations,
				    lv->cfg.glare_set);
		else
			hl_live_log("scene.glare_set '%s': %s", lv->cfg.glare_set,
				    rerr.msg[0] ? rerr.msg : strerror(-rc));
		return rc;
	}
	grids[0] = hl_lid_grid(lv->lids[0]);
	grids[1] = hl_lid_grid(lv->lids[1]);
	rc = hl_glare_live_new(lv->sc, lv->glare_reg, grids, lv->cfg.glare_history, &lv->glare);
	if (rc < 0) {
		hl_live_log("scene.glare_set '%s': %s", lv->cfg.glare_set,
			    rc == -EINVAL ?
				    "not a glare table: expected a set on half the pair's sum "
				    "with \"Oncoming D m\" or \"Preceding D m\" rows" :
				    strerror(-rc));
		return rc;
	}
	hl_live_log(
		"scene: '%s' (%s): %d road users, %.1f s, its clock on %s; glare limits from '%s'",
		lv->cfg.scenario, lv->sc->title, lv->sc->n_actors, lv->sc->duration_s,
		lv->cfg.replay[0] ? "the log's time" : "CLOCK_MONOTONIC", lv->glare_reg->id);
	if (lv->cfg.pose_listen[0]) {
		rc = hl_pose_input_new(lv->cfg.pose_listen, lv->sc, stderr, &lv->pose, msg,
				       sizeof(msg));
		if (rc < 0) {
			hl_live_log("%s", msg);
			lv->config_error = rc == -EINVAL;
			return rc;
		}
		hl_live_log("pose input on %s (port %u)", lv->cfg.pose_listen,
			    hl_pose_input_port(lv->pose));
	}
	lv->config_error = false;
	return 0;
}

/*
 * The loop's judge (daemon/loop/loop_latency.h): with a scenario and a restbus, a report, an end or
 * event lines asked for. loop.events opens here (a bad path is a configuration error).
 */
int hl_live_setup_loop(struct live *lv)
{
	struct hl_loop_latency_config lc = {
		.sc = lv->sc,
		.ecu_cycle_ms = ECU_CYCLE_MS,
		.reaction_ms = lv->cfg.loop_reaction_ms,
		.camera = lv->cfg.restbus_interface[0] != '\0',
	};
	int rc;

	if (!lv->sc || !(lv->cfg.restbus_interface[0] || lv->cfg.loop_report[0] ||
			 lv->cfg.loop_exit_at_end || lv->cfg.loop_events[0]))
		return 0;
	if (strcmp(lv->cfg.loop_events, "-") == 0) {
		lc.events = stdout;
	} else if (lv->cfg.loop_events[0]) {
		lv->loop_events = fopen(lv->cfg.loop_events, "we");
		if (!lv->loop_events) {
			hl_live_log("loop.events '%s': %s; expected a file it can write",
				    lv->cfg.loop_events, strerror(errno));
			lv->config_error = true;
			return -errno;
		}
		lc.events = lv->loop_events;
	}
	rc = hl_loop_latency_new(&lc, &lv->loop);
	if (rc < 0) {
		hl_live_log("loop: %s", strerror(-rc));
		return rc;
	}
	hl_live_log(
		"loop: glare over a road user's limit allowed %g ms after it enters the camera's "
		"view%s",
		lc.reaction_ms, lc.camera ? "" : " (no restbus: none allowed)");
	return 0;
}

/*
 * The restbus (restbus.interface): the input database (restbus.dbc, or the shipped
 * hd84_inputs.dbc), the camera. A bad database or camera is a configuration error (exit 2).
 */
int hl_live_setup_restbus(struct live *lv)
{
	char dbc[HL_CONFIG_PATH + 32], msg[1024];
	const char *sw = lv->cfg.restbus_light_switch;
	struct hl_restbus_config rc_cfg = {
		.iface = lv->cfg.restbus_interface,
		.dbc = dbc,
		.sc = lv->sc,
		.pose = lv->pose,
		.cam = { .pos_m = { lv->cfg.restbus_camera_pos_m[0],
				    lv->cfg.restbus_camera_pos_m[1],
				    lv->cfg.restbus_camera_pos_m[2] },
			 .fov_h_deg = lv->cfg.restbus_fov_deg[0],
			 .fov_v_deg = lv->cfg.restbus_fov_deg[1],
			 .range_m = lv->cfg.restbus_range_m },
		.light_switch = strcmp(sw, "off") == 0	? HL_SWITCH_OFF :
				strcmp(sw, "low") == 0	? HL_SWITCH_LOW :
				strcmp(sw, "high") == 0 ? HL_SWITCH_HIGH :
							  HL_SWITCH_AUTO,
		.adb_enable = lv->cfg.restbus_adb_enable,
		.rt_priority = lv->cfg.rt_priority > 1 ? lv->cfg.rt_priority - 1 :
							 lv->cfg.rt_priority,
		.log = stderr,
		.loop = lv->loop,
	};
	int rc;

	if (!lv->cfg.restbus_interface[0] || !lv->sc)
		return 0;
	if (lv->cfg.restbus_dbc[0]) {
		snprintf(dbc, sizeof(dbc), "%s", lv->cfg.restbus_dbc);
	} else if (hl_share_dir("dbc", dbc, sizeof(dbc) - 20) == 0) {
		strcat(dbc, "/hd84_inputs.dbc");
	} else {
		hl_live_log("restbus.dbc: cannot find the shipped databases beside the binary; set "
			    "restbus.dbc");
		lv->config_error = true;
		return -ENOENT;
	}
	rc = hl_restbus_new(&rc_cfg, &lv->restbus, msg, sizeof(msg));
	if (rc < 0) {
		hl_live_log("%s", msg);
		lv->config_error = rc == -EINVAL || rc == -ENOENT;
		return rc;
	}
	hl_live_log("restbus on '%s' from '%s': camera at %g,%g,%g m, field of view %g x %g deg, "
		    "range %g m; light switch %s, ADB %s",
		    lv->cfg.restbus_interface, dbc, rc_cfg.cam.pos_m[0], rc_cfg.cam.pos_m[1],
		    rc_cfg.cam.pos_m[2], rc_cfg.cam.fov_h_deg, rc_cfg.cam.fov_v_deg,
		    rc_cfg.cam.range_m, sw, lv->cfg.restbus_adb_enable ? "enabled" : "disabled");
	return 0;
}
