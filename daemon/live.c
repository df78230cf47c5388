/* SPDX-License-Identifier: MIT */
/*
 * The daemon's one wiring (docs/design.md §2): DBC, assembler, ring and CAN thread for both
 * modes; with the renderer on, the render thread consumes the ring and feeds the frame pool and the
 * outputs; with it off (--no-render), this thread consumes the ring and prints JSON lines.
 */
#include "daemon/live.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/signalfd.h>
#include <unistd.h>

#include "base/clock.h"
#include "can/assembler.h"
#include "daemon/core/can_input.h"
#include "daemon/core/decode_report.h"
#include "daemon/core/ring.h"
#include "daemon/core/verdicts.h"
#include "daemon/live_ecu.h"
#include "daemon/live_log.h"
#include "daemon/live_loop.h"
#include "daemon/live_render.h"
#include "daemon/live_restbus.h"
#include "daemon/live_scene.h"
#include "daemon/live_verdicts.h"
#include "daemon/out/notify.h"
#include "daemon/pipeline.h"
#include "daemon/run_report.h"
#include "dbc/database.h"
#include "lamp/lid.h"
#include "world/scenario_clock.h"

struct live {
	struct hl_config cfg;
	const struct hl_live_args *args;
	const char *input_name; /* the interface or the replayed log */
	struct hl_dbc *db;
	struct hl_assembler *a;
	const char *lamp_names[HL_RING_MAX_LAMPS]; /* the assembler's */
	int n_lamps;
	struct hl_ring *ring;
	struct hl_can_input *in;
	/* decode-only: this thread is the ring's consumer */
	struct hl_snapshot *snap;
	struct hl_decode_seen seen;
	/* the renderer's (NULL when decode-only) */
	struct hl_lid *lids[HL_FRAME_MAX_LAMPS];
	struct hl_verdicts *verdicts; /* the regulation sets and road KPIs per frame */
	/* the moving scene (scene.scenario): its glare per frame, poses from a simulator */
	struct hl_live_scene *scene;
	const struct hl_scenario *sc; /* the scene's parts (NULL without one) */
	struct hl_glare_live *glare;
	struct hl_pose_input *pose;
	struct hl_osi_input *osi; /* scene.world osi:udp: */
	/* the loop's latency and glare verdict (a scenario with a restbus or a report) */
	struct hl_live_loop *loop_judge;
	struct hl_loop_latency *loop; /* loop_judge's */
	struct hl_restbus *restbus; /* restbus.interface: the ECU's inputs from the scenario */
	struct hl_live_render *render; /* the renderer and the outputs */
	struct hl_live_ecu *ecu; /* ecu.model: the ECU in process on the virtual bus */
	bool config_error; /* setup failed on the configuration: exit 2 */
};

/* SIGHUP: re-read the configuration; the CAN thread runs on, so no cycle is lost. */
static void reload(struct live *lv)
{
	struct hl_config next;
	struct hl_config_error err;

	hl_config_defaults(&next);
	if (lv->args->config_path && hl_config_load(&next, lv->args->config_path, &err) < 0) {
		hl_live_log("reload: %s; keeping the running configuration", err.msg);
		return;
	}
	for (int i = 0; i < lv->args->n_overrides; i++)
		if (hl_config_set_arg(&next, lv->args->overrides[i], "command line", &err) < 0) {
			hl_live_log("reload: %s", err.msg);
			return;
		}
	hl_live_render_reload(lv->render, &next);
}

/* DBC and assembler: the lamps and how their cycles come in (both modes). */
static int setup_input(struct live *lv, int *ret_n_sources)
{
	struct hl_dbc_error derr;
	struct hl_asm_error aerr;
	int rc, n_src = 1;

	rc = hl_dbc_parse_file_flags(lv->cfg.dbc, lv->cfg.dbc_strict ? HL_DBC_STRICT : 0, &lv->db,
				     &derr);
	if (rc < 0) {
		if (derr.line)
			hl_live_log("'%s':%d:%d: %s", lv->cfg.dbc, derr.line, derr.column,
				    derr.msg);
		else
			hl_live_log("'%s': %s", lv->cfg.dbc, derr.msg);
		return rc;
	}
	for (int i = 0; i < hl_dbc_n_warnings(lv->db); i++) {
		int line, col;
		const char *w = hl_dbc_warning(lv->db, i, &line, &col);

		hl_live_log("'%s':%d:%d: warning: %s", lv->cfg.dbc, line, col, w);
	}
	/* replays run on the log's timeline (0 = first frame); a live bus on CLOCK_MONOTONIC */
	rc = hl_assembler_new(lv->db, (const char *const *)lv->args->lamp_names, lv->args->n_lamps,
			      lv->cfg.timeout_ms,
			      lv->cfg.interface[0] ? hl_clock_monotonic_ns() : 0, &lv->a, &aerr);
	if (rc < 0) {
		hl_live_log("'%s': %s", lv->cfg.dbc, aerr.msg);
		return rc;
	}
	lv->n_lamps = hl_assembler_n_lamps(lv->a);
	for (int l = 0; l < lv->n_lamps; l++) {
		lv->lamp_names[l] = hl_assembler_lamp_name(lv->a, l);
		if (hl_assembler_n_sources(lv->a, l) > n_src)
			n_src = hl_assembler_n_sources(lv->a, l);
	}
	*ret_n_sources = n_src;
	return 0;
}

/* The lamps' LID files, which the renderer lights. */
static int load_lids(struct live *lv)
{
	const char *lid_paths[HL_FRAME_MAX_LAMPS] = { lv->cfg.lid_left, lv->cfg.lid_right };
	struct hl_lid_error lerr;
	int rc;

	for (int l = 0; l < lv->n_lamps; l++) {
		if (!lid_paths[l][0]) {
			hl_live_log(
				"lamps.%s: no LID file configured (make one with 'hdlamp model --out DIR')",
				l ? "right" : "left");
			return -EINVAL;
		}
		rc = hl_lid_read(lid_paths[l], &lv->lids[l], &lerr);
		if (rc < 0) {
			hl_live_log("%s", lerr.msg);
			return rc;
		}
		if (hl_lid_n_sources(lv->lids[l]) != hl_assembler_n_sources(lv->a, l) &&
		    !hl_lid_is_combined(lv->lids[l])) {
			hl_live_log("'%s' has %d sources; the DBC gives lamp '%s' %d", lid_paths[l],
				    hl_lid_n_sources(lv->lids[l]), lv->lamp_names[l],
				    hl_assembler_n_sources(lv->a, l));
			return -EINVAL;
		}
	}
	return 0;
}

/* The renderer's parts: the verdicts, the moving scene, the loop's judge, the restbus. */
static int setup_parts(struct live *lv)
{
	const struct hl_lid_grid *grids[HL_FRAME_MAX_LAMPS] = { NULL };
	int rc;

	for (int l = 0; l < lv->n_lamps; l++)
		grids[l] = hl_lid_grid(lv->lids[l]);
	rc = hl_live_verdicts_new(&lv->cfg, lv->a, lv->n_lamps, lv->lamp_names, grids,
				  &lv->verdicts, &lv->config_error);
	if (rc == 0)
		rc = hl_live_scene_new(&lv->cfg, lv->n_lamps, grids, &lv->scene, &lv->config_error);
	if (rc < 0)
		return rc;
	lv->sc = hl_live_scene_scenario(lv->scene);
	lv->glare = hl_live_scene_glare(lv->scene);
	lv->pose = hl_live_scene_pose(lv->scene);
	lv->osi = hl_live_scene_osi(lv->scene);
	rc = hl_live_loop_new(&lv->cfg, lv->sc, &lv->loop_judge, &lv->config_error);
	if (rc < 0)
		return rc;
	lv->loop = hl_live_loop_latency(lv->loop_judge);
	return hl_live_restbus_new(&lv->cfg, lv->sc, lv->pose, lv->osi, lv->loop, &lv->restbus,
				   &lv->config_error);
}

/* The renderer and the outputs, then the threads that feed it besides the CAN thread. */
static int setup_renderer(struct live *lv, int n_src)
{
	const struct hl_live_render_parts parts = {
		.input_name = lv->input_name,
		.a = lv->a,
		.n_lamps = lv->n_lamps,
		.n_sources = n_src,
		.lamp_names = lv->lamp_names,
		.lids = lv->lids,
		.ring = lv->ring,
		.in = lv->in,
		.verdicts = lv->verdicts,
		.sc = lv->sc,
		.glare = lv->glare,
		.pose = lv->pose,
		.osi = lv->osi,
		.osi_replay = hl_live_scene_osi_replay(lv->scene),
		.restbus = lv->restbus,
		.loop = lv->loop,
		.ecu = lv->ecu,
		.suite = lv->args->suite,
	};
	int rc;

	rc = hl_live_render_new(&lv->cfg, &parts, &lv->render, &lv->config_error);
	if (rc == 0 && lv->pose) {
		rc = hl_pose_input_start(lv->pose);
		if (rc < 0)
			hl_live_log("cannot start the pose input: %s", strerror(-rc));
	}
	if (rc == 0 && lv->osi) {
		rc = hl_osi_input_start(lv->osi);
		if (rc < 0)
			hl_live_log("cannot start the OSI input: %s", strerror(-rc));
	}
	if (rc == 0 && lv->restbus) {
		/* on the render thread's scenario clock */
		rc = hl_restbus_start(lv->restbus,
				      hl_pipeline_scene_t0_ns(hl_live_render_pipeline(lv->render)));
		if (rc < 0)
			hl_live_log("cannot start the restbus: %s", strerror(-rc));
	}
	return rc;
}

static int setup(struct live *lv)
{
	int rc, n_src;

	/* ecu.model: the virtual bus first, so that the CAN input and the restbus open it */
	rc = hl_live_ecu_new(&lv->cfg, lv->args->trace, &lv->ecu, &lv->config_error);
	if (rc < 0)
		return rc;
	if (lv->ecu) {
		if (!lv->args->render) {
			hl_live_log("ecu.model lights the renderer's lamps: not with --no-render");
			lv->config_error = true;
			return -EINVAL;
		}
		snprintf(lv->cfg.interface, sizeof(lv->cfg.interface), "%s", HL_CONFIG_VBUS);
		snprintf(lv->cfg.restbus_interface, sizeof(lv->cfg.restbus_interface), "%s",
			 HL_CONFIG_VBUS);
		lv->input_name = lv->cfg.interface;
	}
	rc = setup_input(lv, &n_src);
	if (rc == 0 && lv->args->render)
		rc = load_lids(lv);
	if (rc == 0 && lv->args->render)
		rc = setup_parts(lv);
	if (rc == 0 && !lv->args->render &&
	    (lv->cfg.loop_report[0] || lv->cfg.loop_junit[0] || lv->cfg.loop_exit_at_end ||
	     lv->cfg.loop_events[0])) {
		hl_live_log("loop.report, loop.exit_at_end and loop.events judge rendered frames: "
			    "not with --no-render");
		lv->config_error = true;
		rc = -EINVAL;
	}
	if (rc == 0 && !lv->args->render && lv->cfg.scenario[0])
		hl_live_log("scene.scenario '%s': not used with --no-render (no light to judge)%s",
			    lv->cfg.scenario,
			    lv->cfg.pose_listen[0] ? "; pose.listen neither" : "");
	if (rc == 0)
		rc = hl_ring_new(lv->args->ring_slots, lv->n_lamps, n_src, &lv->ring);
	if (rc == 0 && !lv->args->render)
		rc = hl_snapshot_new(lv->ring, &lv->snap);
	if (rc < 0)
		return rc;
	{
		struct hl_can_input_config icfg = {
			.iface = lv->cfg.interface[0] ? lv->cfg.interface : NULL,
			.replay = lv->cfg.replay[0] ? lv->cfg.replay : NULL,
			.replay_fast = lv->cfg.replay_fast,
			.replay_loop = lv->cfg.replay_loop,
			.replay_passes = (uint64_t)lv->cfg.replay_passes,
			.log = stderr,
			.rt_priority = lv->cfg.rt_priority,
		};

		rc = hl_can_input_new(&icfg, lv->a, lv->ring, &lv->in);
		if (rc < 0) {
			hl_live_log("'%s': %s", lv->input_name, strerror(-rc));
			return rc;
		}
	}
	if (lv->args->render) {
		rc = setup_renderer(lv, n_src);
		if (rc < 0)
			return rc;
	} else {
		struct hl_input_status st;

		/* the input's initial state, so that the first link event is a change */
		hl_can_input_status(lv->in, &st);
		lv->seen.status = st.link_up ? HL_INPUT_LINK_UP : 0;
		lv->seen.link_errno = st.link_errno;
	}
	rc = hl_can_input_start(lv->in);
	if (rc < 0)
		hl_live_log("cannot start the CAN thread: %s", strerror(-rc));
	if (rc == 0)
		rc = hl_live_ecu_start(lv->ecu, &lv->cfg, lv->a, lv->lids, lv->lamp_names,
				       &lv->config_error);
	return rc;
}

static void teardown(struct live *lv)
{
	hl_live_ecu_stop(lv->ecu); /* the bus's thread: nothing is delivered any more */
	if (lv->in)
		hl_can_input_stop(lv->in);
	hl_live_render_free(lv->render); /* the outputs and the render thread that read the rest */
	hl_verdicts_free(lv->verdicts); /* after the pipeline and the status that read it */
	hl_restbus_free(lv->restbus); /* after the status; before the pose and scenario it reads */
	hl_live_loop_free(lv->loop_judge); /* after the restbus and the status that use it */
	hl_live_scene_free(lv->scene); /* after the pipeline and the status that read it */
	hl_can_input_free(lv->in);
	hl_snapshot_free(lv->snap);
	hl_ring_free(lv->ring);
	for (int l = 0; l < HL_FRAME_MAX_LAMPS; l++)
		hl_lid_free(lv->lids[l]);
	hl_assembler_free(lv->a);
	hl_dbc_free(lv->db);
	hl_live_ecu_free(lv->ecu); /* after the CAN input's and the restbus's ports */
}

/* STATUS= for systemctl status: per lamp its cycles and state, the frames. */
static void notify_status(struct live *lv, const struct hl_input_status *st)
{
	struct hl_pipeline_counts pc;
	char line[256];
	int n = 0;

	hl_pipeline_counts(hl_live_render_pipeline(lv->render), &pc);
	for (int l = 0; l < lv->n_lamps && n < (int)sizeof(line); l++)
		n += snprintf(line + n, sizeof(line) - n, "%s: %" PRIu64 " cycles%s; ",
			      lv->lamp_names[l], st->lamps[l].cycles,
			      st->stale[l] ? " (stale, fail-safe)" : "");
	if (n < (int)sizeof(line))
		snprintf(line + n, sizeof(line) - n, "%" PRIu64 " frames, bus %s", pc.frames,
			 st->link_up ? st->bus : "down");
	hl_notify_status("%s", line);
}

/* Logs link and stale changes (the event loop's view, once per wake). */
static void log_changes(struct live *lv, struct hl_input_status *prev)
{
	struct hl_input_status st;

	hl_can_input_status(lv->in, &st);
	if (st.link_up != prev->link_up)
		hl_live_log("can: '%s': %s%s%s",
			    lv->cfg.interface[0] ? lv->cfg.interface : lv->cfg.replay,
			    st.link_up ? "up" : "down", st.link_up ? "" : ": ",
			    st.link_up ? "" : strerror(st.link_errno));
	for (int l = 0; l < lv->n_lamps; l++)
		if (st.stale[l] != prev->stale[l])
			hl_live_log("lamp '%s': %s", lv->lamp_names[l],
				    st.stale[l] ? "stale, fail-safe on" :
						  "recovered, fail-safe off");
	*prev = st;
}

/* Decode-only: prints every snapshot the ring holds; true after the replay's last. */
static bool print_pending(struct live *lv)
{
	bool done = false;

	while (!done && hl_ring_pop(lv->ring, lv->snap))
		done = hl_decode_report(lv->input_name, lv->args->print_cycles, lv->a, lv->snap,
					&lv->seen);
	return done;
}

/* The renderer's turn of the event loop: logs, sd_notify; true when a finite replay ended. */
static bool watch(struct live *lv, struct hl_input_status *prev, bool *ready, int64_t *status_ns)
{
	const int64_t now = hl_clock_monotonic_ns();

	log_changes(lv, prev);
	/* READY once the lamps are loaded, the renderer is up and the bus is open */
	if (!*ready && prev->link_up) {
		hl_notify_ready("running");
		*ready = true;
	}
	if (now - *status_ns >= 1000000000) {
		*status_ns = now;
		notify_status(lv, prev);
	}
	return prev->done;
}

/* loop.exit_at_end on a live bus: the scenario's duration has passed on its clock (with a
 * margin of END_MARGIN_NS, so the frames of its last instant are rendered and judged). */
#define END_MARGIN_NS 100000000LL
static bool scenario_over(struct live *lv)
{
	const int64_t t0 = hl_pipeline_scene_t0_ns(hl_live_render_pipeline(lv->render));

	return lv->cfg.loop_exit_at_end && lv->sc && !lv->cfg.replay[0] && !lv->pose && t0 > 0 &&
	       hl_scenario_clock_over(lv->sc, t0, hl_clock_monotonic_ns(), END_MARGIN_NS);
}

/* The run's end: the loop finished, the report written, the exit code (run_report.h). */
static int report(struct live *lv, const char *end, int code)
{
	const struct hl_run_report_sources src = {
		.scenario_path = lv->cfg.scenario,
		.sc = lv->sc,
		.glare_set = lv->cfg.glare_set,
		.n_lamps = lv->n_lamps,
		.lamp_names = lv->lamp_names,
		.in = lv->in,
		.ring = lv->ring,
		.pipe = hl_live_render_pipeline(lv->render),
		.verdicts = lv->verdicts,
		.loop = lv->loop,
		.restbus = lv->restbus,
		.end = end,
		.ecu = hl_live_ecu_name(lv->ecu),
		.ecu_error = hl_live_ecu_error_text(lv->ecu),
	};

	return hl_run_report_end(&src, lv->cfg.loop_report, lv->cfg.loop_junit,
				 lv->cfg.loop_exit_at_end, code);
}

int hl_live_run(const struct hl_config *cfg, const struct hl_live_args *args)
{
	struct live lv = { .cfg = *cfg, .args = args };
	struct hl_input_status prev = { .link_up = false };
	int64_t status_ns = 0;
	bool ready = false, done = false;
	const char *end = "signal";
	sigset_t mask;
	int sfd, rc, code = 1;

	lv.input_name = cfg->interface[0] ? cfg->interface : cfg->replay;
	/* signals arrive through a signalfd here; every thread inherits the mask */
	sigemptyset(&mask);
	sigaddset(&mask, SIGINT);
	sigaddset(&mask, SIGTERM);
	if (args->render) { /* reload and capture; decode-only keeps their default actions */
		sigaddset(&mask, SIGHUP);
		sigaddset(&mask, SIGUSR1);
	}
	pthread_sigmask(SIG_BLOCK, &mask, NULL);
	signal(SIGPIPE, SIG_IGN);
	signal(SIGXFSZ,
	       SIG_IGN); /* a capture over RLIMIT_FSIZE fails with EFBIG, the daemon runs on */
	sfd = signalfd(-1, &mask, SFD_CLOEXEC | SFD_NONBLOCK);
	rc = sfd < 0 ? -errno : setup(&lv);
	while (rc == 0) {
		struct pollfd pfd[3] = {
			{ .fd = sfd, .events = POLLIN },
			{ .fd = lv.render ? hl_live_render_trigger_fd(lv.render) : -1,
			  .events = POLLIN },
			/* decode-only: this thread is the ring's consumer */
			{ .fd = lv.render ? -1 : hl_ring_wake_fd(lv.ring), .events = POLLIN },
		};
		struct signalfd_siginfo si;

		done = lv.render ? watch(&lv, &prev, &ready, &status_ns) : print_pending(&lv);
		if (done)
			end = "replay_end";
		if (lv.loop && !lv.restbus) /* no restbus thread: this one judges the frames */
			hl_loop_latency_drain(lv.loop, INFINITY);
		if (!done && hl_live_ecu_error(lv.ecu)) {
			end = "ecu_error"; /* logged by the ECU's thread */
			code = 1;
			break;
		}
		if (!done && lv.render && scenario_over(&lv)) {
			end = "scenario_end";
			done = true;
		}
		if (done) {
			/* a finite replay ended: let the last frame out, then stop */
			if (lv.render)
				hl_clock_sleep_until_ns(hl_clock_monotonic_ns() + 200000000, NULL);
			code = 0;
			break;
		}
		if (poll(pfd, 3, lv.render ? (lv.cfg.loop_exit_at_end ? 20 : 200) : 100) <= 0)
			continue;
		if (pfd[2].revents & POLLIN)
			hl_ring_wait(lv.ring, 0); /* reset: the next turn pops what came */
		if (pfd[1].revents & POLLIN)
			hl_live_render_trigger(lv.render);
		if (!(pfd[0].revents & POLLIN) || read(sfd, &si, sizeof(si)) != sizeof(si))
			continue;
		if (si.ssi_signo == SIGHUP) {
			hl_notify_reloading();
			reload(&lv);
			hl_notify_ready("running (reloaded)");
		} else if (si.ssi_signo == SIGUSR1) { /* the queue logs what becomes of it */
			hl_live_render_capture(lv.render);
		} else {
			if (lv.render)
				hl_live_log("%s: stopping", strsignal((int)si.ssi_signo));
			code = 0;
			break;
		}
	}
	if (args->render)
		hl_notify_stopping();
	if (rc == 0 && lv.render) {
		/* quiesce, then report: the counters no longer move */
		hl_live_ecu_stop(lv.ecu);
		hl_can_input_stop(lv.in);
		hl_live_render_stop(lv.render);
		if (lv.loop)
			code = report(&lv, end, code);
		hl_live_render_print_status(lv.render);
	} else if (rc == 0) {
		hl_can_input_stop(lv.in); /* joined: everything it pushed is in the ring */
		if (!done)
			print_pending(&lv);
		hl_decode_summary(lv.a, lv.ring, lv.in);
	}
	if (rc < 0 && lv.config_error)
		code = 2;
	if (args->ret_end)
		*args->ret_end = rc < 0 ? "setup_error" : end;
	teardown(&lv);
	if (sfd >= 0)
		close(sfd);
	return code;
}
