/* SPDX-License-Identifier: MIT */
/* The daemon's moving scene: see daemon/live_scene.h. */
#include "daemon/live_scene.h"

#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "daemon/live_log.h"

struct hl_live_scene {
	struct hl_scenario *sc;
	struct hl_regulation *glare_reg;
	struct hl_glare_live *glare;
	struct hl_pose_input *pose; /* NULL: no pose input */
	struct hl_scenario *base; /* scene.world with scene.scenario: the lamps, camera, road */
	struct hl_osi_input *osi; /* scene.world osi:udp: */
	struct hl_osi_replay_report *osi_replay; /* scene.world osi:file: */
};

/* The kind of OSI message scene.world_message names; NULL for auto on a trace (its name). */
static const enum hl_osi_kind *world_kind(const struct hl_config *cfg, bool udp,
					  enum hl_osi_kind *buf)
{
	if (hl_osi_kind_parse(cfg->world_message, buf) == 0)
		return buf;
	if (!udp)
		return NULL;
	*buf = HL_OSI_GROUND_TRUTH; /* what esmini sends (docs/osi.md) */
	return buf;
}

/* Logs what a trace held beside its messages taken: each reason's count and first fault. */
static void log_replay(const char *path, const struct hl_osi_replay_report *rep)
{
	hl_live_log("scene.world 'osi:file:%s': %zu %s messages, %zu taken", path, rep->messages,
		    hl_osi_kind_name(rep->kind), rep->taken);
	for (int r = 1; r < HL_OSI_REASONS; r++)
		if (rep->counts[r])
			hl_live_log("scene.world 'osi:file:%s': %" PRIu64 " %s; the first, message "
				    "%zu: %s",
				    path, rep->counts[r], hl_osi_reason_name(r), rep->first[r],
				    rep->why[r][0] ? rep->why[r] : "(an object)");
}

/* The world of scene.world into s->sc (cfg->scenario, if any, already in s->base). */
static int world(struct hl_live_scene *s, const struct hl_config *cfg)
{
	struct hl_osi_spec spec;
	enum hl_osi_kind kind_buf;
	const enum hl_osi_kind *kind;
	char msg[1024];
	int rc;

	if (hl_osi_spec_parse(cfg->world, &spec, msg, sizeof(msg)) < 0) {
		hl_live_log("scene.world %s", msg);
		return -EINVAL;
	}
	kind = world_kind(cfg, spec.udp, &kind_buf);
	if (!spec.udp) {
		s->osi_replay = calloc(1, sizeof(*s->osi_replay));
		if (!s->osi_replay)
			return -ENOMEM;
		rc = hl_osi_replay_load(spec.path, kind, s->base, &s->sc, s->osi_replay, msg,
					sizeof(msg));
		if (rc < 0) {
			hl_live_log("scene.world: %s", msg);
			return rc;
		}
		log_replay(spec.path, s->osi_replay);
		return 0;
	}
	rc = hl_osi_input_new(spec.listen, *kind, s->base, cfg->world_timeout_s, stderr, &s->osi,
			      msg, sizeof(msg));
	if (rc < 0) {
		hl_live_log("%s", msg);
		return rc;
	}
	hl_live_log("scene.world 'osi:%s' (port %u): waiting up to %g s for the first %s",
		    spec.listen, hl_osi_input_port(s->osi), cfg->world_wait_s,
		    hl_osi_kind_name(*kind));
	rc = hl_osi_input_first(s->osi, cfg->world_wait_s, msg, sizeof(msg));
	if (rc < 0) {
		hl_live_log("%s", msg);
		return rc;
	}
	s->sc = malloc(sizeof(*s->sc));
	if (!s->sc)
		return -ENOMEM;
	*s->sc = *hl_osi_input_scenario(s->osi);
	return 0;
}

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
	if (cfg->scenario[0]) {
		rc = hl_scenario_read(cfg->scenario, &s->base, &jerr);
		if (rc < 0) {
			hl_json_error_format(&jerr, msg, sizeof(msg));
			hl_live_log("scene.scenario: %s", msg);
			return rc;
		}
	}
	if (cfg->world[0]) {
		rc = world(s, cfg);
		if (rc < 0) {
			*config_error = rc != -ENOMEM && rc != -ETIMEDOUT;
			return rc;
		}
	} else {
		s->sc = s->base;
		s->base = NULL;
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
		cfg->world[0] ? cfg->world : cfg->scenario, s->sc->title, s->sc->n_actors,
		s->sc->duration_s,
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

	if (!cfg->scenario[0] && !cfg->world[0]) {
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
	hl_osi_input_free(s->osi);
	free(s->osi_replay);
	hl_scenario_free(s->base);
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

struct hl_osi_input *hl_live_scene_osi(const struct hl_live_scene *s)
{
	return s ? s->osi : NULL;
}

const struct hl_osi_replay_report *hl_live_scene_osi_replay(const struct hl_live_scene *s)
{
	return s ? s->osi_replay : NULL;
}
