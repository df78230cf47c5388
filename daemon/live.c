/* SPDX-License-Identifier: MIT */
/*
 * The daemon's one wiring (docs/design.md §2): DBC, assembler, ring and CAN thread for both
 * modes; with the renderer on, the render thread consumes the ring and feeds the frame pool and the
 * outputs; with it off (--no-render), this thread consumes the ring and prints JSON lines.
 */
#include "daemon/live.h"
#include "daemon/live_internal.h"

#include <errno.h>
#include <inttypes.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/signalfd.h>
#include <unistd.h>

#include "can/socket.h"
#include "daemon/core/can_input.h"
#include "daemon/out/capture_queue.h"
#include "base/clock.h"
#include "daemon/core/decode_report.h"
#include "daemon/core/frame_pool.h"
#include "daemon/core/glare_live.h"
#include "daemon/out/gpio.h"
#include "daemon/out/http.h"
#include "daemon/loop/loop_latency.h"
#include "daemon/out/notify.h"
#include "daemon/pipeline.h"
#include "daemon/loop/pose_input.h"
#include "daemon/loop/restbus.h"
#include "daemon/run_report.h"
#include "daemon/status.h"
#include "daemon/out/stream.h"
#include "daemon/core/verdicts.h"
#include "lamp/preset.h"
#include "base/share_dir.h"

#define POOL_FRAMES 8

void hl_live_log(const char *fmt, ...)
{
	va_list ap;

	va_start(ap, fmt);
	fputs("hdlampd: ", stderr);
	vfprintf(stderr, fmt, ap);
	fputc('\n', stderr);
	va_end(ap);
}

/* The pool's subscriber: every published frame to the loop's judge (never blocks). */
static void loop_frame(void *ud, const struct hl_frame *f)
{
	hl_loop_latency_frame(ud, f);
}

/* The pool's subscriber: the strobe toggles with every published frame. */
static void strobe(void *ud, const struct hl_frame *f)
{
	(void)f;
	hl_gpio_strobe(ud); /* counted in the gpio's counters, errors too */
}

/* Render thread hook, every loop turn: the watchdog proves the render loop runs. */
static void on_alive(void *ud)
{
	struct live *lv = ud;
	const int64_t now = hl_clock_monotonic_ns();

	if (lv->watchdog_us && now - lv->watchdog_last_ns >= (int64_t)lv->watchdog_us * 1000) {
		hl_notify_watchdog();
		lv->watchdog_last_ns = now;
	}
}

/* Per lamp, each source's DBC scale (ret[l] malloc'd, n_sources entries; 1, 0 past the lamp's). */
static int source_scales(const struct hl_assembler *a, int n_lamps, int n_sources,
			 struct hl_source_scale *ret[HL_FRAME_MAX_LAMPS])
{
	for (int l = 0; l < n_lamps; l++) {
		ret[l] = malloc(sizeof(*ret[l]) * n_sources);
		if (!ret[l])
			return -ENOMEM;
		for (int k = 0; k < n_sources; k++) {
			const struct hl_dbc_signal *s = hl_assembler_source_signal(a, l, k);

			ret[l][k] = s ? (struct hl_source_scale){ s->factor, s->offset } :
					(struct hl_source_scale){ 1.0, 0.0 };
		}
	}
	return 0;
}

/* The fail-safe preset's raw values per lamp, or NULL when the mode is not a preset. */
static int load_failsafe(const struct hl_config *cfg, int n_lamps, int n_sources,
			 uint8_t *ret[HL_FRAME_MAX_LAMPS])
{
	struct hl_preset_error perr;
	struct hl_preset *p;
	char path[HL_CONFIG_PATH + HL_CONFIG_NAME + 8];
	int rc;

	ret[0] = ret[1] = NULL;
	if (cfg->failsafe != HL_FAILSAFE_PRESET)
		return 0;
	snprintf(path, sizeof(path), "%s/%s.json", cfg->presets[0] ? cfg->presets : ".",
		 cfg->failsafe_preset);
	rc = hl_preset_read(path, &p, &perr);
	if (rc < 0) {
		/* line and column only where the file has them (not for one that cannot open) */
		hl_live_log("lamps.failsafe preset '%s': '%s'%s%.0d%s%.0d: %s",
			    cfg->failsafe_preset, path, perr.line ? ":" : "", perr.line,
			    perr.line ? ":" : "", perr.column, perr.msg);
		return rc;
	}
	if (p->n_sources != n_sources) {
		hl_live_log(
			"lamps.failsafe preset '%s': %d values per lamp; the lamps have %d sources",
			path, p->n_sources, n_sources);
		hl_preset_free(p);
		return -EINVAL;
	}
	for (int l = 0; l < n_lamps; l++) {
		ret[l] = malloc(n_sources);
		if (ret[l])
			memcpy(ret[l], p->dim[l], n_sources);
	}
	hl_preset_free(p);
	return 0;
}

/*
 * HTTP callbacks, on the server's threads: the status locks what it reads (daemon/status.h);
 * captures go through the queue and wait for their result.
 */
static int http_status(void *ud, char *buf, size_t size)
{
	return hl_status_json(((struct live *)ud)->status, buf, size);
}

static int http_metrics(void *ud, char *buf, size_t size)
{
	return hl_status_metrics(((struct live *)ud)->status, buf, size);
}

static int http_glare(void *ud, char *buf, size_t size)
{
	return hl_glare_live_json(((struct live *)ud)->glare, buf, size);
}

static int http_capture(void *ud, char *path, size_t size)
{
	return hl_capture_queue_submit(((struct live *)ud)->captures, HL_CAPTURE_WAIT_MS, path,
				       size);
}

/* SIGHUP: re-read the configuration; the CAN thread runs on, so no cycle is lost. */
static void reload(struct live *lv)
{
	struct hl_config next;
	struct hl_config_error err;
	uint8_t *dims[HL_FRAME_MAX_LAMPS] = { NULL };

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
	if (load_failsafe(&next, lv->n_lamps, hl_assembler_n_sources(lv->a, 0), dims) < 0)
		return;
	hl_pipeline_set_failsafe(lv->pipe, next.failsafe, (const uint8_t *const *)dims);
	hl_pipeline_set_exposure(lv->pipe, next.exposure_ev);
	lv->cfg.failsafe = next.failsafe;
	lv->cfg.exposure_ev = next.exposure_ev;
	memcpy(lv->cfg.failsafe_preset, next.failsafe_preset, sizeof(next.failsafe_preset));
	hl_status_reloaded(lv->status, next.failsafe); /* what HTTP threads read, locked */
	free(dims[0]);
	free(dims[1]);
	hl_live_log(
		"reloaded: lamps.failsafe and render.exposure_ev applied; other keys take effect at restart");
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

/* The verdict sets and road KPIs on the lamps' grids at their mounted poses. */
/*
 * The test-only fault switch HDLAMPD_DEBUG_STALL_RENDER_AFTER_FRAMES=N (docs/daemon.md): the
 * render thread hangs after N frames, so that a test sees the systemd watchdog at work.
 */
static int debug_stall(struct live *lv)
{
	const char *v = getenv("HDLAMPD_DEBUG_STALL_RENDER_AFTER_FRAMES");
	char *end;
	unsigned long long n;

	if (!v)
		return 0;
	errno = 0;
	n = strtoull(v, &end, 10);
	if (!*v || *end || errno || n == 0 || v[0] == '-') {
		hl_live_log(
			"HDLAMPD_DEBUG_STALL_RENDER_AFTER_FRAMES '%s': expected a frame count > 0",
			v);
		lv->config_error = true;
		return -EINVAL;
	}
	hl_pipeline_debug_stall(lv->pipe, n);
	hl_live_log(
		"HDLAMPD_DEBUG_STALL_RENDER_AFTER_FRAMES=%llu: test-only fault: the render thread "
		"hangs after %llu frames",
		n, n);
	return 0;
}

/* The render thread and its frame pool, before the CAN thread starts. */
static int setup_renderer(struct live *lv, int n_src)
{
	uint8_t *dims[HL_FRAME_MAX_LAMPS] = { NULL };
	struct hl_source_scale *scales[HL_FRAME_MAX_LAMPS] = { NULL };
	const struct hl_lid_grid *g = hl_lid_grid(lv->lids[0]);
	const struct hl_frame_shape shape = {
		.width = lv->cfg.width,
		.height = lv->cfg.height,
		.format = strcmp(lv->cfg.view, "hdr") == 0 ? HL_PIXEL_RGBA16F : HL_PIXEL_RGB8,
		.n_lamps = lv->n_lamps,
		.n_sources = n_src,
		.dist_width = g->width,
		.dist_height = g->height,
		.n_results = hl_verdicts_n_results(lv->verdicts),
		.n_sets = hl_verdicts_n_sets(lv->verdicts),
	};
	const struct hl_pipeline_hooks hooks = { .userdata = lv, .alive = on_alive };
	char err[512];
	int rc;

	rc = load_failsafe(&lv->cfg, lv->n_lamps, n_src, dims);
	if (rc == 0)
		rc = source_scales(lv->a, lv->n_lamps, n_src, scales);
	if (rc == 0)
		rc = hl_frame_pool_new(POOL_FRAMES, &shape, &lv->pool);
	if (rc == 0) {
		rc = hl_pipeline_new(&lv->cfg, lv->lids, lv->n_lamps,
				     (const struct hl_source_scale *const *)scales,
				     (const uint8_t *const *)dims, lv->ring, lv->pool, lv->verdicts,
				     &hooks, &lv->pipe);
		if (rc < 0)
			hl_live_log("renderer: %s", strerror(-rc));
		else
			hl_pipeline_set_scene(lv->pipe, lv->sc, lv->glare, lv->pose);
	}
	for (int l = 0; l < HL_FRAME_MAX_LAMPS; l++) {
		free(dims[l]);
		free(scales[l]);
	}
	if (rc < 0)
		return rc;
	if (lv->cfg.gpio_chip[0]) {
		struct hl_gpio_error gerr;

		rc = hl_gpio_new(lv->cfg.gpio_chip, lv->cfg.gpio_strobe, lv->cfg.gpio_trigger,
				 lv->cfg.gpio_trigger_edge, lv->cfg.gpio_ecu_enable, &lv->gpio,
				 &gerr);
		if (rc < 0) {
			hl_live_log("gpio: %s", gerr.msg);
			return rc;
		}
		rc = hl_frame_pool_subscribe(lv->pool, strobe, lv->gpio);
		if (rc < 0)
			return rc;
	}
	if (lv->loop) {
		rc = hl_frame_pool_subscribe(lv->pool, loop_frame, lv->loop);
		if (rc < 0)
			return rc;
	}
	if (hl_notify_watchdog_interval_us(&lv->watchdog_us) < 0)
		lv->watchdog_us = 0;
	rc = debug_stall(lv);
	if (rc < 0)
		return rc;
	rc = hl_pipeline_start(lv->pipe, err, sizeof(err));
	if (rc < 0) {
		hl_live_log("%s", err);
		return rc;
	}
	hl_live_log("renderer: %s", hl_pipeline_describe(lv->pipe));
	return 0;
}

/* The frame stream, the status and the HTTP server. */
static int setup_outputs(struct live *lv)
{
	struct hl_status_sources ss = {
		.input_name = lv->input_name,
		.n_lamps = lv->n_lamps,
		.lamp_names = lv->lamp_names,
		.in = lv->in,
		.ring = lv->ring,
		.pipe = lv->pipe,
		.pool = lv->pool,
		.gpio = lv->gpio,
		.verdicts = lv->verdicts,
		.glare = lv->glare,
		.pose = lv->pose,
		.restbus = lv->restbus,
		.loop = lv->loop,
	};
	struct hl_capture_queue_config cq = {
		.dir = lv->cfg.capture_dir,
		.slots = lv->cfg.capture_queue,
		.pool = lv->pool,
		.scene = { .gb = hl_pipeline_gbuffer(lv->pipe),
			   .cam = hl_pipeline_camera(lv->pipe),
			   .n_lamps = lv->n_lamps,
			   .verdicts = lv->verdicts },
		.log = stderr,
	};
	char err[512];
	int rc = 0;

	for (int l = 0; l < lv->n_lamps; l++) {
		cq.scene.lamp_names[l] = lv->lamp_names[l];
		cq.scene.grids[l] = hl_lid_grid(lv->lids[l]);
	}
	rc = hl_capture_queue_new(&cq, &lv->captures);
	if (rc < 0 || (rc = hl_capture_queue_start(lv->captures)) < 0) {
		hl_live_log("captures: %s", strerror(-rc));
		return rc;
	}
	if (lv->cfg.stream_tcp[0] || lv->cfg.stream_unix[0]) {
		rc = hl_stream_new(lv->cfg.stream_tcp, lv->cfg.stream_unix, lv->cfg.stream_raw,
				   lv->cfg.stream_max_clients, lv->cfg.stream_stall_timeout_ms,
				   lv->pool, &lv->stream, err, sizeof(err));
		if (rc == 0)
			rc = hl_stream_start(lv->stream, lv->cfg.rt_priority > 1 ?
								 lv->cfg.rt_priority - 1 :
								 lv->cfg.rt_priority);
		if (rc < 0) {
			hl_live_log("%s", err);
			return rc;
		}
		hl_live_log("frame stream on %s%s%s (port %d)", lv->cfg.stream_tcp,
			    lv->cfg.stream_unix[0] ? " and " : "", lv->cfg.stream_unix,
			    hl_stream_tcp_port(lv->stream));
	}
	ss.stream = lv->stream;
	ss.captures = lv->captures;
	if (lv->cfg.http_listen[0]) {
		struct hl_http_sources src = {
			.pool = lv->pool,
			.exr_info = &lv->exr_info,
			.userdata = lv,
			.status_json = http_status,
			.metrics = http_metrics,
			.capture = http_capture,
			.glare_json = lv->glare ? http_glare : NULL,
		};

		lv->exr_info.camera = hl_pipeline_camera(lv->pipe);
		lv->exr_info.n_lamps = lv->n_lamps;
		for (int l = 0; l < lv->n_lamps; l++)
			hl_lamp_pose_default(l, &lv->exr_info.lamps[l]);
		rc = hl_http_new(lv->cfg.http_listen, lv->cfg.http_capture, &src, &lv->http);
		ss.http = lv->http; /* made before the status that reads it, started after */
	}
	rc = rc < 0 ? rc : hl_status_new(&ss, lv->cfg.failsafe, &lv->status);
	rc = rc < 0 || !lv->http ? rc : hl_http_start(lv->http);
	if (rc < 0 && lv->cfg.http_listen[0] && (!lv->http || lv->status)) /* not the status' */
		hl_live_log("http.listen '%s': %s", lv->cfg.http_listen, strerror(-rc));
	if (rc == 0 && lv->http && !hl_http_loopback(lv->http))
		hl_live_log(
			"warning: http.listen '%s' is not a loopback address: other hosts can connect",
			lv->cfg.http_listen);
	if (rc == 0 && lv->http)
		hl_live_log("live view on http://%s/ (port %u)%s", lv->cfg.http_listen,
			    hl_http_port(lv->http),
			    lv->cfg.http_capture ? ", POST /capture allowed" : "");
	return rc;
}

static int setup(struct live *lv)
{
	int rc, n_src;

	rc = setup_input(lv, &n_src);
	if (rc == 0 && lv->args->render)
		rc = load_lids(lv);
	if (rc == 0 && lv->args->render)
		rc = hl_live_setup_verdicts(lv);
	if (rc == 0 && lv->args->render)
		rc = hl_live_setup_scene(lv);
	if (rc == 0 && lv->args->render)
		rc = hl_live_setup_loop(lv);
	if (rc == 0 && lv->args->render)
		rc = hl_live_setup_restbus(lv);
	if (rc == 0 && !lv->args->render &&
	    (lv->cfg.loop_report[0] || lv->cfg.loop_exit_at_end || lv->cfg.loop_events[0])) {
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
		if (rc == 0)
			rc = setup_outputs(lv);
		if (rc == 0 && lv->pose) {
			rc = hl_pose_input_start(lv->pose);
			if (rc < 0)
				hl_live_log("cannot start the pose input: %s", strerror(-rc));
		}
		if (rc == 0 && lv->restbus) {
			/* on the render thread's scenario clock */
			rc = hl_restbus_start(lv->restbus, hl_pipeline_scene_t0_ns(lv->pipe));
			if (rc < 0)
				hl_live_log("cannot start the restbus: %s", strerror(-rc));
		}
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
	return rc;
}

static void teardown(struct live *lv)
{
	if (lv->in)
		hl_can_input_stop(lv->in);
	if (lv->pool)
		hl_frame_pool_close(lv->pool);
	hl_http_stop(lv->http);
	hl_capture_queue_free(lv->captures); /* before the G-buffer, grids and verdicts it reads */
	hl_pipeline_free(lv->pipe); /* stopped first: nothing publishes any more */
	hl_stream_free(lv->stream);
	if (lv->gpio)
		hl_frame_pool_unsubscribe(lv->pool, strobe, lv->gpio);
	hl_gpio_free(lv->gpio);
	hl_status_free(lv->status);
	hl_http_free(lv->http); /* after the status that reads its counters */
	hl_verdicts_free(lv->verdicts); /* after the pipeline and the status that read it */
	hl_restbus_free(lv->restbus); /* after the status; before the pose and scenario it reads */
	if (lv->loop && lv->pool)
		hl_frame_pool_unsubscribe(lv->pool, loop_frame, lv->loop);
	hl_loop_latency_free(lv->loop); /* after the restbus and the status that use it */
	if (lv->loop_events)
		fclose(lv->loop_events);
	hl_pose_input_free(lv->pose); /* after the pipeline and the status that read them */
	hl_glare_live_free(lv->glare);
	hl_regulation_free(lv->glare_reg);
	hl_scenario_free(lv->sc);
	hl_can_input_free(lv->in);
	hl_frame_pool_free(lv->pool);
	hl_snapshot_free(lv->snap);
	hl_ring_free(lv->ring);
	for (int l = 0; l < HL_FRAME_MAX_LAMPS; l++)
		hl_lid_free(lv->lids[l]);
	hl_assembler_free(lv->a);
	hl_dbc_free(lv->db);
}

/* STATUS= for systemctl status: per lamp its cycles and state, the frames. */
static void notify_status(struct live *lv, const struct hl_input_status *st)
{
	struct hl_pipeline_counts pc;
	char line[256];
	int n = 0;

	hl_pipeline_counts(lv->pipe, &pc);
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
	const int64_t t0 = hl_pipeline_scene_t0_ns(lv->pipe);

	return lv->cfg.loop_exit_at_end && lv->sc && !lv->cfg.replay[0] && !lv->pose && t0 > 0 &&
	       hl_clock_monotonic_ns() >= t0 + (int64_t)(lv->sc->duration_s * 1e9) + END_MARGIN_NS;
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
		.pipe = lv->pipe,
		.verdicts = lv->verdicts,
		.loop = lv->loop,
		.restbus = lv->restbus,
		.end = end,
	};

	return hl_run_report_end(&src, lv->cfg.loop_report, lv->cfg.loop_exit_at_end, code);
}

/* The status as one JSON line on stdout (at exit), in a buffer as large as it needs. */
static void print_status(struct hl_status *st)
{
	size_t size = 1 << 16;
	char *buf = NULL;
	int n = -ENOBUFS;

	while (n == -ENOBUFS && size <= (16u << 20)) {
		char *b = realloc(buf, size);

		if (!b)
			break;
		buf = b;
		n = hl_status_json(st, buf, size);
		size *= 2;
	}
	if (n > 0)
		printf("%s\n", buf);
	free(buf);
}

int hl_live_run(const struct hl_config *cfg, const struct hl_live_args *args)
{
	struct live lv = { .cfg = *cfg, .args = args };
	struct hl_input_status prev = { .link_up = false };
	int64_t status_ns = 0;
	bool ready = false, done = false;
	const char *end = "signal";
	sigset_t mask;
	char msg[256]; /* a capture's answer: the queue logs it */
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
			{ .fd = lv.gpio ? hl_gpio_trigger_fd(lv.gpio) : -1, .events = POLLIN },
			/* decode-only: this thread is the ring's consumer */
			{ .fd = lv.pipe ? -1 : hl_ring_wake_fd(lv.ring), .events = POLLIN },
		};
		struct signalfd_siginfo si;

		done = lv.pipe ? watch(&lv, &prev, &ready, &status_ns) : print_pending(&lv);
		if (done)
			end = "replay_end";
		if (lv.loop && !lv.restbus) /* no restbus thread: this one judges the frames */
			hl_loop_latency_drain(lv.loop, INFINITY);
		if (!done && lv.pipe && scenario_over(&lv)) {
			end = "scenario_end";
			done = true;
		}
		if (done) {
			/* a finite replay ended: let the last frame out, then stop */
			if (lv.pipe)
				hl_clock_sleep_until_ns(hl_clock_monotonic_ns() + 200000000, NULL);
			code = 0;
			break;
		}
		if (poll(pfd, 3, lv.pipe ? (lv.cfg.loop_exit_at_end ? 20 : 200) : 100) <= 0)
			continue;
		if (pfd[2].revents & POLLIN)
			hl_ring_wait(lv.ring, 0); /* reset: the next turn pops what came */
		if (pfd[1].revents & POLLIN) {
			unsigned edges = 0;

			if (hl_gpio_read_trigger(lv.gpio, &edges) == 0 && edges > 0)
				hl_capture_queue_submit(lv.captures, 0, msg, sizeof(msg));
		}
		if (!(pfd[0].revents & POLLIN) || read(sfd, &si, sizeof(si)) != sizeof(si))
			continue;
		if (si.ssi_signo == SIGHUP) {
			hl_notify_reloading();
			reload(&lv);
			hl_notify_ready("running (reloaded)");
		} else if (si.ssi_signo == SIGUSR1) { /* the queue logs what becomes of it */
			hl_capture_queue_submit(lv.captures, 0, msg, sizeof(msg));
		} else {
			if (lv.pipe)
				hl_live_log("%s: stopping", strsignal((int)si.ssi_signo));
			code = 0;
			break;
		}
	}
	if (args->render)
		hl_notify_stopping();
	if (rc == 0 && lv.pipe) {
		/* quiesce, then report: the counters no longer move */
		hl_can_input_stop(lv.in);
		hl_frame_pool_close(lv.pool);
		hl_http_stop(lv.http); /* freed after the status that reads it */
		if (lv.captures) /* what was asked for is written and counted */
			hl_capture_queue_stop(lv.captures);
		hl_pipeline_stop(lv.pipe);
		hl_restbus_stop(lv.restbus);
		hl_pose_input_stop(lv.pose);
		if (lv.stream)
			hl_stream_stop(lv.stream);
		if (lv.loop)
			code = report(&lv, end, code);
		print_status(lv.status);
	} else if (rc == 0) {
		hl_can_input_stop(lv.in); /* joined: everything it pushed is in the ring */
		if (!done)
			print_pending(&lv);
		hl_decode_summary(lv.a, lv.ring, lv.in);
	}
	if (rc < 0 && lv.config_error)
		code = 2;
	teardown(&lv);
	if (sfd >= 0)
		close(sfd);
	return code;
}
