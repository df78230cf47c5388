/* SPDX-License-Identifier: MIT */
/* Software in the loop in virtual time: see sil/sil.h. */
#include "sil/sil.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "base/clock.h"
#include "base/share_dir.h"
#include "can/assembler.h"
#include "can/inputs.h"
#include "can/vbus.h"
#include "daemon/core/frame.h"
#include "daemon/core/glare_live.h"
#include "daemon/core/verdict_records.h"
#include "daemon/core/verdicts.h"
#include "daemon/live_log.h"
#include "daemon/live_scene.h"
#include "daemon/live_verdicts.h"
#include "daemon/loop/loop_latency.h"
#include "daemon/loop/loop_report.h"
#include "dbc/database.h"
#include "lamp/combine.h"
#include "lamp/lid.h"
#include "lamp/model.h"
#include "ecu/node.h"
#include "sil/frames.h"
#include "daemon/loop/loop_junit.h"
#include "sil/restbus_node.h"
#include "world/scenario_clock.h"
#include "world/world.h"

#define N_LAMPS 2
#define ECU_PERIOD_NS 20000000 /* the dimming period of docs/design.md §1 */

/* A lamp's newest complete cycle, as the hdlamp node on the bus took it. */
struct lamp_state {
	bool valid, fresh; /* a cycle seen; a cycle newer than the last frame */
	uint64_t seq, last_seq;
	unsigned counter;
	int64_t t_done_ns;
	int64_t mode;
	float *i;
};

struct sil {
	const struct hl_sil_options *o;
	struct hl_config cfg;
	const char *lamp_names[N_LAMPS];
	struct hl_dbc *lamp_db, *input_db;
	struct hl_assembler *a;
	struct hl_inputs_map *map;
	struct hl_lid *lids[N_LAMPS];
	struct hl_verdicts *verdicts;
	struct hl_verdict_records *records;
	struct hl_live_scene *scene;
	const struct hl_scenario *sc;
	struct hl_glare_live *glare;
	struct hl_loop_latency *loop;
	struct hl_vbus *bus;
	struct hl_restbus_node *rb;
	struct hl_ecu_node *ecu;
	struct hl_combiner *comb[N_LAMPS];
	struct lamp_state lamp[N_LAMPS];
	int64_t first_fresh_ns; /* when the oldest fresh cycle waiting for a frame ended */
	int64_t coalesce_ns; /* render.coalesce_ms: how long a fresh cycle waits for the other */
	struct hl_frame frame;
	struct hl_loop_report rep;
	bool asm_error_logged;
	struct hl_sil_frames *frames; /* --frames; NULL: none, or a write failed (frames_failed) */
	bool frames_failed;
};

static void log_msg(const struct sil *s, const char *fmt, const char *a, const char *b)
{
	fprintf(s->o->log, "hdlamp sil: ");
	fprintf(s->o->log, fmt, a, b);
	fputc('\n', s->o->log);
}

/* A shipped database unless the configuration names one. */
static int load_dbc(struct sil *s, const char *path, const char *shipped, const char *key,
		    struct hl_dbc **ret)
{
	char p[HL_CONFIG_PATH + 64];
	struct hl_dbc_error err;
	int rc;

	if (path[0]) {
		snprintf(p, sizeof(p), "%s", path);
	} else if (hl_share_dir("dbc", p, sizeof(p) - 32) == 0) {
		strcat(p, "/");
		strcat(p, shipped);
	} else {
		log_msg(s, "%s: cannot find the shipped databases beside the binary; set it%s", key,
			"");
		return -ENOENT;
	}
	rc = hl_dbc_parse_file(p, ret, &err);
	if (rc < 0) {
		if (err.line > 0)
			fprintf(s->o->log, "hdlamp sil: '%s':%d:%d: %s\n", p, err.line, err.column,
				err.msg);
		else
			fprintf(s->o->log, "hdlamp sil: '%s': %s\n", p, err.msg);
	}
	return rc;
}

static int load_lamps(struct sil *s)
{
	const char *paths[N_LAMPS] = { s->cfg.lid_left, s->cfg.lid_right };

	for (int l = 0; l < N_LAMPS; l++) {
		struct hl_lid_error err;
		int rc;

		if (s->o->lids) {
			s->lids[l] = s->o->lids[l];
		} else if (!paths[l][0]) {
			rc = hl_model_hd84((enum hl_side)l, &s->lids[l]);
			if (rc < 0) {
				log_msg(s, "the HD84 model: %s%s", strerror(-rc), "");
				return rc;
			}
		} else {
			rc = hl_lid_read(paths[l], &s->lids[l], &err);
			if (rc < 0) {
				log_msg(s, "%s%s", err.msg, "");
				return rc;
			}
		}
		if (hl_lid_is_combined(s->lids[l]) ||
		    hl_lid_n_sources(s->lids[l]) != hl_assembler_n_sources(s->a, l)) {
			fprintf(s->o->log,
				"hdlamp sil: lamps.%s: %d sources%s; the lamp database gives lamp "
				"'%s' %d\n",
				l ? "right" : "left", hl_lid_n_sources(s->lids[l]),
				hl_lid_is_combined(s->lids[l]) ? " (a combined distribution)" : "",
				s->lamp_names[l], hl_assembler_n_sources(s->a, l));
			return -EINVAL;
		}
		s->lamp[l].i = calloc((size_t)hl_lid_n_sources(s->lids[l]), sizeof(float));
		if (!s->lamp[l].i)
			return -ENOMEM;
		rc = hl_combiner_new(s->lids[l], 0, &s->comb[l]);
		if (rc < 0)
			return rc;
	}
	return 0;
}

/* The judged frame at t: the lamps' newest cycles lit, glare, verdicts, records, the judge. */
static void frame(struct sil *s, int64_t t)
{
	struct hl_frame *f = &s->frame;
	struct hl_world_state w;
	const float *dist[N_LAMPS];
	int ml;

	memset(&f->hdr, 0, sizeof(f->hdr));
	f->hdr.magic = HL_FRAME_MAGIC;
	f->hdr.version = HL_FRAME_VERSION;
	f->hdr.header_size = HL_FRAME_HEADER_SIZE;
	f->hdr.seq = s->rep.frames + 1;
	f->hdr.n_lamps = N_LAMPS;
	hl_world_at(s->sc, hl_scenario_clock_at(s->sc, 0, t), &w);
	for (int l = 0; l < N_LAMPS; l++) {
		struct lamp_state *ls = &s->lamp[l];
		const bool stale = !ls->valid || hl_assembler_stale(s->a, l);

		hl_combiner_update(s->comb[l], ls->i); /* held: the last cycle's, 0 before one */
		dist[l] = hl_combiner_result(s->comb[l]);
		if (stale) {
			f->hdr.flags |= HL_FRAME_STALE(l) | HL_FRAME_FAILSAFE(l);
			s->rep.failsafe_frames[l]++;
		}
		if (ls->seq > ls->last_seq + 1)
			s->rep.cycles_not_rendered[l] += ls->seq - ls->last_seq - 1;
		ls->last_seq = ls->seq;
		ls->fresh = false;
		f->hdr.cycle_seq[l] = ls->seq;
		f->hdr.counter[l] = (uint8_t)ls->counter;
		f->hdr.t_lamp_done_ns[l] = ls->t_done_ns;
	}
	f->hdr.t_cycle_done_ns = t;
	f->hdr.t_render_start_ns = t;
	f->hdr.t_render_done_ns = t;
	hl_glare_live_eval(s->glare, &w, HL_SCENE_CLOCK, dist, f->hdr.seq, f);
	if (s->verdicts) {
		ml = hl_verdicts_mode_lamp(s->verdicts);
		f->beam_mode = ml >= 0 && s->lamp[ml].valid ? s->lamp[ml].mode : -1;
		f->hdr.n_sets = (uint8_t)hl_verdicts_n_sets(s->verdicts);
		f->hdr.sets_evaluated = hl_verdicts_active(s->verdicts, f->beam_mode);
		f->hdr.sets_failed =
			hl_verdicts_eval(s->verdicts, f->hdr.sets_evaluated, dist, f->results);
		for (int i = 0; i < hl_verdicts_n_sets(s->verdicts); i++) {
			if (!(f->hdr.sets_evaluated & (1u << i)))
				continue;
			s->rep.verdict_frames[i]++;
			if (f->hdr.sets_failed & (1u << i))
				s->rep.verdict_failed_frames[i]++;
		}
		hl_verdict_records_add(s->records, f);
	}
	hl_loop_latency_frame(s->loop, f);
	if (s->o->on_frame) {
		const struct hl_lid_grid *grids[N_LAMPS] = { hl_lid_grid(s->lids[0]),
							     hl_lid_grid(s->lids[1]) };

		s->o->on_frame(s->o->on_frame_ctx, s->sc, &w, grids, dist);
	}
	if (s->frames) {
		const float *in[N_LAMPS] = { s->lamp[0].i, s->lamp[1].i };
		char err[512];

		if (hl_sil_frames_write(s->frames, f->hdr.seq, w.t_s, in, err, sizeof(err)) < 0) {
			log_msg(s, "--frames: %s; no more frames written%s", err, "");
			hl_sil_frames_free(s->frames);
			s->frames = NULL;
			s->frames_failed = true;
		}
	}
	s->rep.frames++;
	s->first_fresh_ns = INT64_MAX;
}

/*
 * A frame when every live lamp (valid, not stale) has a fresh cycle, or at once with
 * render.coalesce_ms 0; else the run loop makes it when the window ends (as the daemon's render
 * thread waits for the other lamp's cycle of the same ECU period, daemon/pipeline.c).
 */
static void maybe_frame(struct sil *s, int64_t t)
{
	bool any = false, lagging = false;

	for (int l = 0; l < N_LAMPS; l++) {
		if (s->lamp[l].fresh)
			any = true;
		else if (s->lamp[l].valid && !hl_assembler_stale(s->a, l))
			lagging = true;
	}
	if (any && (!lagging || s->coalesce_ns == 0))
		frame(s, t);
}

/* The hdlamp node: every frame the bus delivers. */
static void deliver(void *ctx, const struct hl_vbus_frame *vf)
{
	struct sil *s = ctx;
	struct canfd_frame cf = { .len = vf->len };
	struct hl_cycle cyc;
	struct hl_asm_events ev;
	int rc;

	hl_restbus_node_delivered(s->rb, vf);
	cf.can_id = vf->can_id & HL_DBC_EFF_FLAG ? (vf->can_id & ~HL_DBC_EFF_FLAG) | CAN_EFF_FLAG :
						   vf->can_id;
	if (vf->brs)
		cf.flags |= CANFD_BRS;
	memcpy(cf.data, vf->data, vf->len);
	rc = hl_assembler_feed(s->a, &cf, vf->t_ns, vf->t_ns, &cyc, &ev);
	if (rc != 1)
		return;
	{
		struct lamp_state *ls = &s->lamp[cyc.lamp];

		if (cyc.lamp >= N_LAMPS)
			return;
		memcpy(ls->i, cyc.i, sizeof(float) * (size_t)cyc.n_sources);
		ls->valid = true;
		ls->fresh = true;
		ls->seq = cyc.seq;
		ls->counter = cyc.counter;
		ls->t_done_ns = vf->t_ns;
		ls->mode = cyc.mode;
		if (s->first_fresh_ns == INT64_MAX)
			s->first_fresh_ns = vf->t_ns;
		maybe_frame(s, vf->t_ns);
	}
}

static int setup(struct sil *s)
{
	const struct hl_sil_options *o = s->o;
	const struct hl_lid_grid *grids[N_LAMPS];
	struct hl_asm_error aerr;
	bool cerr = false;
	char msg[1024] = "";
	int rc;

	s->lamp_names[0] = "left";
	s->lamp_names[1] = "right";
	s->first_fresh_ns = INT64_MAX;
	s->coalesce_ns = llround(s->cfg.coalesce_ms * 1e6);
	rc = load_dbc(s, s->cfg.dbc, "hd84.dbc", "can.dbc", &s->lamp_db);
	if (rc < 0)
		return rc;
	rc = hl_assembler_new(s->lamp_db, s->lamp_names, N_LAMPS, s->cfg.timeout_ms, 0, &s->a,
			      &aerr);
	if (rc < 0) {
		log_msg(s, "the lamp database: %s%s", aerr.msg, "");
		return rc;
	}
	rc = load_lamps(s);
	if (rc < 0)
		return rc;
	rc = load_dbc(s, s->cfg.restbus_dbc, "hd84_inputs.dbc", "restbus.dbc", &s->input_db);
	if (rc == 0) {
		rc = hl_inputs_map_new(s->input_db, &s->map, msg, sizeof(msg));
		if (rc < 0)
			log_msg(s, "the input database: %s%s", msg, "");
	}
	if (rc < 0)
		return rc;
	for (int l = 0; l < N_LAMPS; l++)
		grids[l] = hl_lid_grid(s->lids[l]);
	rc = hl_live_verdicts_new(&s->cfg, s->a, N_LAMPS, s->lamp_names, grids, &s->verdicts,
				  &cerr);
	if (rc == 0 && s->verdicts)
		rc = hl_verdict_records_new(s->verdicts, &s->records);
	if (rc == 0)
		rc = hl_live_scene_new(&s->cfg, N_LAMPS, grids, &s->scene, &cerr);
	if (rc < 0)
		return rc;
	s->sc = hl_live_scene_scenario(s->scene);
	s->glare = hl_live_scene_glare(s->scene);
	if (!s->sc) {
		log_msg(s, "no scenario: give one%s%s", "", "");
		return -EINVAL;
	}
	{
		const struct hl_loop_latency_config lc = {
			.sc = s->sc,
			.ecu_cycle_ms = ECU_PERIOD_NS / 1e6,
			.reaction_ms = s->cfg.loop_reaction_ms,
			.camera = true,
		};

		rc = hl_loop_latency_new(&lc, &s->loop);
		if (rc < 0)
			return rc;
	}
	if (s->verdicts) {
		s->frame.n_results = hl_verdicts_n_results(s->verdicts);
		s->frame.results =
			calloc((size_t)s->frame.n_results + 1, sizeof(*s->frame.results));
		if (!s->frame.results)
			return -ENOMEM;
	}
	{
		const struct hl_vbus_config bc = { .bitrate = o->bitrate,
						   .data_bitrate = o->data_bitrate,
						   .name = "vbus0" };

		rc = hl_vbus_new(&bc, &s->bus);
		if (rc < 0) {
			log_msg(s, "the virtual bus: %s%s", strerror(-rc), "");
			return rc;
		}
	}
	if (o->frames) {
		rc = hl_sil_frames_new(&s->cfg, s->lids, s->sc, o->frames, &s->frames, msg,
				       sizeof(msg));
		if (rc < 0) {
			log_msg(s, "--frames '%s': %s", o->frames, msg);
			return rc;
		}
	}
	if (o->trace) {
		rc = hl_vbus_trace(s->bus, o->trace, 0);
		if (rc < 0) {
			fprintf(s->o->log, "hdlamp sil: --trace '%s': %s\n", o->trace,
				strerror(-rc));
			return rc;
		}
	}
	rc = hl_vbus_attach(s->bus, "hdlamp", deliver, s);
	if (rc < 0)
		return rc;
	{
		const char *sw = s->cfg.restbus_light_switch;
		const struct hl_restbus_node_config rc_cfg = {
			.sc = s->sc,
			.map = s->map,
			.cam = { .pos_m = { s->cfg.restbus_camera_pos_m[0],
					    s->cfg.restbus_camera_pos_m[1],
					    s->cfg.restbus_camera_pos_m[2] },
				 .fov_h_deg = s->cfg.restbus_fov_deg[0],
				 .fov_v_deg = s->cfg.restbus_fov_deg[1],
				 .range_m = s->cfg.restbus_range_m },
			.light_switch = strcmp(sw, "off") == 0	? HL_SWITCH_OFF :
					strcmp(sw, "low") == 0	? HL_SWITCH_LOW :
					strcmp(sw, "high") == 0 ? HL_SWITCH_HIGH :
								  HL_SWITCH_AUTO,
			.adb_enable = s->cfg.restbus_adb_enable,
			.loop = s->loop,
		};

		rc = hl_restbus_node_new(&rc_cfg, s->bus, &s->rb);
		if (rc < 0) {
			log_msg(s, "the restbus: %s%s", strerror(-rc), "");
			return rc;
		}
	}
	{
		struct hl_ecu_config ref = o->ref;
		struct hl_ecu_node_config ec = {
			.ecu = o->ecu,
			.ref = &ref,
			.n_lamps = N_LAMPS,
			.lids = s->lids,
			.lamp_names = s->lamp_names,
			.map = s->map,
			.a = s->a,
			.period_ns = ECU_PERIOD_NS,
			.late_ms = o->late_ms,
			.stuck_counter = o->stuck_counter,
			.bad_crc = o->bad_crc,
			.log = o->log,
		};

		if (!o->ref_timeouts_set) /* 3 of each input's cycle time, as hdlamp ecu */
			for (int i = 0; i < hl_inputs_map_n_messages(s->map); i++) {
				const struct hl_inputs_message *m =
					hl_inputs_map_message(s->map, i);
				const int64_t t = 3 * (int64_t)m->cycle_ms * 1000000;

				if (!m->cycle_ms)
					continue;
				if (m->kind == HL_INPUTS_VEHICLE)
					ref.vehicle_timeout_ns = t;
				else
					ref.objects_timeout_ns = t;
			}
		msg[0] = '\0';
		rc = hl_ecu_node_new(&ec, s->bus, &s->ecu, msg, sizeof(msg));
		if (rc < 0) {
			log_msg(s, "%s%s", msg, "");
			return rc;
		}
	}
	return 0;
}

static void teardown(struct sil *s)
{
	hl_sil_frames_free(s->frames);
	hl_ecu_node_free(s->ecu);
	hl_restbus_node_free(s->rb);
	hl_vbus_free(s->bus);
	for (int l = 0; l < N_LAMPS; l++) {
		hl_combiner_free(s->comb[l]);
		free(s->lamp[l].i);
		if (!s->o->lids)
			hl_lid_free(s->lids[l]);
	}
	free(s->frame.results);
	hl_loop_latency_free(s->loop);
	hl_verdict_records_free(s->records);
	hl_verdicts_free(s->verdicts);
	hl_live_scene_free(s->scene);
	hl_inputs_map_free(s->map);
	hl_assembler_free(s->a);
	hl_dbc_free(s->input_db);
	hl_dbc_free(s->lamp_db);
}

static int64_t min64(int64_t a, int64_t b)
{
	return a < b ? a : b;
}

/* The discrete-event loop to t_end. 0, or the ECU's error (-errno, *err says what). */
static int run(struct sil *s, int64_t t_end, char *err, size_t err_size)
{
	for (;;) {
		int64_t t = min64(hl_vbus_next(s->bus), hl_restbus_node_next(s->rb));
		int rc;

		t = min64(t, min64(hl_ecu_node_next_step(s->ecu), hl_ecu_node_next_send(s->ecu)));
		if (s->first_fresh_ns != INT64_MAX)
			t = min64(t, s->first_fresh_ns + s->coalesce_ns);
		t = min64(t, hl_assembler_next_deadline(s->a));
		if (t > t_end)
			break;
		hl_vbus_run_until(s->bus, t); /* deliveries first: what ends at t is there at t */
		if (hl_assembler_expire(s->a, t))
			maybe_frame(s, t);
		if (s->first_fresh_ns != INT64_MAX && t >= s->first_fresh_ns + s->coalesce_ns)
			frame(s,
			      t); /* the other lamp's cycle did not come within render.coalesce_ms */
		if (hl_restbus_node_next(s->rb) == t)
			hl_restbus_node_run(s->rb, t);
		if (hl_ecu_node_next_step(s->ecu) == t || hl_ecu_node_next_send(s->ecu) == t) {
			rc = hl_ecu_node_run(s->ecu, t, err, err_size);
			if (rc < 0)
				return rc;
		}
	}
	hl_vbus_run_until(s->bus, t_end);
	return 0;
}

static void fill_report(struct sil *s, const char *end)
{
	struct hl_restbus_node_counts rc;

	s->rep.scenario_path = s->cfg.scenario;
	s->rep.sc = s->sc;
	s->rep.glare_set = s->cfg.glare_set;
	s->rep.end = end;
	s->rep.ecu = hl_ecu_node_name(s->ecu);
	s->rep.n_lamps = N_LAMPS;
	s->rep.lamp_names = s->lamp_names;
	s->rep.snapshots_pushed = s->rep.frames;
	s->rep.verdicts = s->verdicts;
	s->rep.records = s->records;
	s->rep.loop = s->loop;
	for (int l = 0; l < N_LAMPS; l++)
		s->rep.lamp[l] = *hl_assembler_lamp_counters(s->a, l);
	hl_restbus_node_counts(s->rb, &rc);
	s->rep.have_restbus = true;
	s->rep.restbus.camera_cycles = rc.camera_cycles;
	s->rep.restbus.vehicle_cycles = rc.vehicle_cycles;
	s->rep.restbus.tx_full = rc.tx_full;
	s->rep.restbus.tx_errors = rc.encode_errors;
}

int hl_sil_run(const struct hl_sil_options *o)
{
	struct sil *s = calloc(1, sizeof(*s));
	char err[1024] = "";
	const char *end = "scenario_end";
	int64_t wall0, wall1;
	int rc, code;

	if (!s)
		return 1;
	s->o = o;
	s->cfg = *o->cfg;
	hl_live_log_prefix("hdlamp sil");
	rc = setup(s);
	if (rc < 0) {
		teardown(s);
		free(s);
		return rc == -ENOMEM ? 1 : 2;
	}
	/* the wall clock is read for the log's speed line only: nothing of it reaches the report */
	wall0 = hl_clock_monotonic_ns();
	rc = run(s, (int64_t)llround(s->sc->duration_s * 1e9), err, sizeof(err));
	wall1 = hl_clock_monotonic_ns();
	if (rc < 0) {
		fprintf(o->log, "hdlamp sil: the ECU: %s\n", err);
		end = "ecu_error";
	}
	hl_loop_latency_finish(s->loop);
	fill_report(s, end);
	if (rc < 0)
		s->rep.ecu_error = err;
	code = rc < 0 || s->frames_failed ? 1 : hl_loop_report_passed(&s->rep) ? 0 : 3;
	if (o->report) {
		const int wr = hl_loop_report_write(&s->rep, o->report);

		if (wr < 0) {
			fprintf(o->log, "hdlamp sil: --report '%s': %s\n", o->report,
				strerror(-wr));
			code = 1;
		}
	}
	if (o->junit) {
		const int wr = hl_loop_junit_write(&s->rep, rc < 0 ? err : NULL, o->junit);

		if (wr < 0) {
			fprintf(o->log, "hdlamp sil: --junit '%s': %s\n", o->junit, strerror(-wr));
			code = 1;
		}
	}
	if (o->quiet)
		goto out;
	fprintf(o->log,
		"hdlamp sil: the loop ran %.3f s of the scenario in %.3f s (%.0f x real time; the "
		"setup before it not counted)\n",
		s->sc->duration_s, (double)(wall1 - wall0) / 1e9,
		s->sc->duration_s / fmax((double)(wall1 - wall0) / 1e9, 1e-9));
	fprintf(o->log, "hdlamp sil: %s, %s: %" PRIu64 " frames judged, verdict %s%s%s\n",
		s->cfg.scenario, hl_ecu_node_name(s->ecu), s->rep.frames,
		rc < 0	  ? "not reached (the ECU failed)" :
		code == 0 ? "held" :
			    "FAILED",
		o->report ? "; report in " : "", o->report ? o->report : "");
out:
	teardown(s);
	free(s);
	return code;
}
