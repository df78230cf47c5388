/* SPDX-License-Identifier: MIT */
/* The daemon's moving scene: see daemon/live_scene.h. */
#include "daemon/live_scene.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "daemon/live_log.h"

struct hl_live_scene {
	struct hl_scenario *sc;
	struct hl_regulation *glare_reg;
	struct hl_glare_live *glare;
	struct hl_pose_input *pose; /* NULL: no pose input */
};

/*
 * The scenario (scene.scenario), the glare plan on the lamps' grids under scene.glare_set, and
 * the pose input (pose.listen). A bad file or set is a configuration error (exit 2).
 */
static int setup(struct hl_live_scene *s, const struct hl_config *cfg, int n_lamps,
		 const struct hl_lid_grid *const *grids, bool *config_error)
{
	struct hl_regulation_error rerr = { 0, 0, "" };
	struct hl_json_error jerr;
	char msg[1024];
	int rc;

	*config_error = true; /* until it is all set up */
	rc = hl_scenario_read(cfg->scenario, &s->sc, &jerr);
	if (rc < 0) {
		hl_json_error_format(&jerr, msg, sizeof(msg));
		hl_live_log("scene.scenario: %s", msg);
		return rc;
	}
	if (n_lamps != 2) {
		hl_live_log(
			"scene.scenario '%s': the glare at the road users' eyes takes two lamps; "
			"can.lamps has %d",
			cfg->scenario, n_lamps);
		return -EINVAL;
	}
	rc = hl_regulation_load(cfg->regulations, cfg->glare_set, &s->glare_reg, &rerr);
	if (rc < 0) {
		if (rc == -ENOENT)
			hl_live_log("scene.glare_set: no set '%s' in '%s' (no file '%s/%s.json'; "
				    "verdict.regulations names the directory)",
				    cfg->glare_set, cfg->regulations, cfg->regulations,
				    cfg->glare_set);
		else
			hl_live_log("scene.glare_set '%s': %s", cfg->glare_set,
				    rerr.msg[0] ? rerr.msg : strerror(-rc));
		return rc;
	}
	rc = hl_glare_live_new(s->sc, s->glare_reg, grids, cfg->glare_history, &s->glare);
	if (rc < 0) {
		hl_live_log("scene.glare_set '%s': %s", cfg->glare_set,
			    rc == -EINVAL ?
				    "not a glare table: expected a set on half the pair's sum "
				    "with \"Oncoming D m\" or \"Preceding D m\" rows" :
				    strerror(-rc));
		return rc;
	}
	hl_live_log(
		"scene: '%s' (%s): %d road users, %.1f s, its clock on %s; glare limits from '%s'",
		cfg->scenario, s->sc->title, s->sc->n_actors, s->sc->duration_s,
		cfg->replay[0]	  ? "the log's time" :
		cfg->interface[0] ? "CLOCK_MONOTONIC" :
				    "the virtual time of software in the loop",
		s->glare_reg->id);
	if (cfg->pose_listen[0]) {
		rc = hl_pose_input_new(cfg->pose_listen, s->sc, stderr, &s->pose, msg, sizeof(msg));
		if (rc < 0) {
			hl_live_log("%s", msg);
			*config_error = rc == -EINVAL;
			return rc;
		}
		hl_live_log("pose input on %s (port %u)", cfg->pose_listen,
			    hl_pose_input_port(s->pose));
	}
	*config_error = false;
	return 0;
}

int hl_live_scene_new(const struct hl_config *cfg, int n_lamps,
		      const struct hl_lid_grid *const *grids, struct hl_live_scene **ret,
		      bool *ret_config_error)
{
	struct hl_live_scene *s;
	bool config_error;
	int rc;

	if (!cfg->scenario[0]) {
		*ret = NULL;
		return 0;
	}
	s = calloc(1, sizeof(*s));
	if (!s) {
		*ret_config_error = false;
		return -ENOMEM;
	}
	rc = setup(s, cfg, n_lamps, grids, &config_error);
	if (rc < 0) {
		hl_live_scene_free(s);
		*ret_config_error = config_error;
		return rc;
	}
	*ret = s;
	return 0;
}

void hl_live_scene_free(struct hl_live_scene *s)
{
	if (!s)
		return;
	hl_pose_input_free(s->pose); /* after the pipeline and the status that read them */
	hl_glare_live_free(s->glare);
	hl_regulation_free(s->glare_reg);
	hl_scenario_free(s->sc);
	free(s);
}

const struct hl_scenario *hl_live_scene_scenario(const struct hl_live_scene *s)
{
	return s ? s->sc : NULL;
}

struct hl_glare_live *hl_live_scene_glare(const struct hl_live_scene *s)
{
	return s ? s->glare : NULL;
}

struct hl_pose_input *hl_live_scene_pose(const struct hl_live_scene *s)
{
	return s ? s->pose : NULL;
}
