/* SPDX-License-Identifier: MIT */
/* The daemon's renderer and outputs: see daemon/live_render.h. */
#include "daemon/live_render.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/clock.h"
#include "daemon/core/frame_pool.h"
#include "daemon/live_log.h"
#include "daemon/out/capture_queue.h"
#include "daemon/out/gpio.h"
#include "daemon/out/http.h"
#include "daemon/out/notify.h"
#include "daemon/out/stream.h"
#include "daemon/status.h"
#include "lamp/preset.h"
#include "render/frame_exr.h"

#define POOL_FRAMES 8

struct hl_live_render {
	struct hl_config cfg; /* lamps.failsafe and render.exposure_ev follow reloads */
	struct hl_live_render_parts parts;
	struct hl_frame_pool *pool;
	struct hl_pipeline *pipe;
	struct hl_verdict_records *records; /* the verdict sets' now and so far; NULL: no sets */
	struct hl_stream *stream;
	struct hl_gpio *gpio;
	struct hl_status *status;
	struct hl_http *http;
	struct hl_capture_queue *captures; /* the one capture writer */
	struct hl_frame_exr_info exr_info; /* camera and lamp poses for /frame.exr */
	uint64_t watchdog_us; /* ping interval, 0 without a watchdog */
	int64_t watchdog_last_ns; /* render thread's */
};

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
	struct hl_live_render *r = ud;
	const int64_t now = hl_clock_monotonic_ns();

	if (r->watchdog_us && now - r->watchdog_last_ns >= (int64_t)r->watchdog_us * 1000) {
		hl_notify_watchdog();
		r->watchdog_last_ns = now;
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
	return hl_status_json(((struct hl_live_render *)ud)->status, buf, size);
}

static int http_metrics(void *ud, char *buf, size_t size)
{
	return hl_status_metrics(((struct hl_live_render *)ud)->status, buf, size);
}

static int http_glare(void *ud, char *buf, size_t size)
{
	return hl_glare_live_json(((struct hl_live_render *)ud)->parts.glare, buf, size);
}

static int http_capture(void *ud, char *path, size_t size)
{
	return hl_capture_queue_submit(((struct hl_live_render *)ud)->captures, HL_CAPTURE_WAIT_MS,
				       path, size);
}

/*
 * The test-only fault switch HDLAMPD_DEBUG_STALL_RENDER_AFTER_FRAMES=N (docs/daemon.md): the
 * render thread hangs after N frames, so that a test sees the systemd watchdog at work.
 */
static int debug_stall(struct hl_live_render *r, bool *config_error)
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
		*config_error = true;
		return -EINVAL;
	}
	hl_pipeline_debug_stall(r->pipe, n);
	hl_live_log(
		"HDLAMPD_DEBUG_STALL_RENDER_AFTER_FRAMES=%llu: test-only fault: the render thread "
		"hangs after %llu frames",
		n, n);
	return 0;
}

/* The render thread and its frame pool, before the CAN thread starts. */
static int setup_renderer(struct hl_live_render *r, bool *config_error)
{
	const struct hl_live_render_parts *pt = &r->parts;
	uint8_t *dims[HL_FRAME_MAX_LAMPS] = { NULL };
	struct hl_source_scale *scales[HL_FRAME_MAX_LAMPS] = { NULL };
	const struct hl_lid_grid *g = hl_lid_grid(pt->lids[0]);
	const struct hl_frame_shape shape = {
		.width = r->cfg.width,
		.height = r->cfg.height,
		.format = strcmp(r->cfg.view, "hdr") == 0 ? HL_PIXEL_RGBA16F : HL_PIXEL_RGB8,
		.n_lamps = pt->n_lamps,
		.n_sources = pt->n_sources,
		.dist_width = g->width,
		.dist_height = g->height,
		.n_results = hl_verdicts_n_results(pt->verdicts),
		.n_sets = hl_verdicts_n_sets(pt->verdicts),
	};
	const struct hl_pipeline_hooks hooks = { .userdata = r, .alive = on_alive };
	char err[512];
	int rc;

	rc = load_failsafe(&r->cfg, pt->n_lamps, pt->n_sources, dims);
	if (rc == 0)
		rc = source_scales(pt->a, pt->n_lamps, pt->n_sources, scales);
	if (rc == 0)
		rc = hl_frame_pool_new(POOL_FRAMES, &shape, &r->pool);
	if (rc == 0) {
		rc = hl_pipeline_new(&r->cfg, pt->lids, pt->n_lamps,
				     (const struct hl_source_scale *const *)scales,
				     (const uint8_t *const *)dims, pt->ring, r->pool, pt->verdicts,
				     &hooks, &r->pipe);
		if (rc < 0)
			hl_live_log("renderer: %s", strerror(-rc));
		else
			hl_pipeline_set_scene(r->pipe, pt->sc, pt->glare, pt->pose);
		if (rc == 0)
			hl_pipeline_set_osi(r->pipe, pt->osi);
		if (rc == 0 && pt->suite && pt->sc && pt->glare)
			hl_pipeline_set_frame_hook(r->pipe, hl_suite_live_frame, pt->suite);
	}
	if (rc == 0 && pt->verdicts) {
		rc = hl_verdict_records_new(pt->verdicts, &r->records);
		if (rc < 0)
			hl_live_log("verdict records: %s", strerror(-rc));
		else
			hl_pipeline_set_records(r->pipe, r->records);
	}
	for (int l = 0; l < HL_FRAME_MAX_LAMPS; l++) {
		free(dims[l]);
		free(scales[l]);
	}
	if (rc < 0)
		return rc;
	if (r->cfg.gpio_chip[0]) {
		struct hl_gpio_error gerr;

		rc = hl_gpio_new(r->cfg.gpio_chip, r->cfg.gpio_strobe, r->cfg.gpio_trigger,
				 r->cfg.gpio_trigger_edge, r->cfg.gpio_ecu_enable, &r->gpio, &gerr);
		if (rc < 0) {
			hl_live_log("gpio: %s", gerr.msg);
			return rc;
		}
		rc = hl_frame_pool_subscribe(r->pool, strobe, r->gpio);
		if (rc < 0)
			return rc;
	}
	if (pt->loop) {
		rc = hl_frame_pool_subscribe(r->pool, loop_frame, pt->loop);
		if (rc < 0)
			return rc;
	}
	if (hl_notify_watchdog_interval_us(&r->watchdog_us) < 0)
		r->watchdog_us = 0;
	rc = debug_stall(r, config_error);
	if (rc < 0)
		return rc;
	rc = hl_pipeline_start(r->pipe, err, sizeof(err));
	if (rc < 0) {
		hl_live_log("%s", err);
		return rc;
	}
	hl_live_log("renderer: %s", hl_pipeline_describe(r->pipe));
	return 0;
}

/* The frame stream, the status and the HTTP server. */
static int setup_outputs(struct hl_live_render *r)
{
	const struct hl_live_render_parts *pt = &r->parts;
	struct hl_status_sources ss = {
		.input_name = pt->input_name,
		.n_lamps = pt->n_lamps,
		.lamp_names = pt->lamp_names,
		.in = pt->in,
		.ring = pt->ring,
		.pipe = r->pipe,
		.pool = r->pool,
		.gpio = r->gpio,
		.verdicts = pt->verdicts,
		.glare = pt->glare,
		.pose = pt->pose,
		.osi = pt->osi,
		.osi_replay = pt->osi_replay,
		.restbus = pt->restbus,
		.loop = pt->loop,
		.ecu = pt->ecu,
		.suite = pt->suite,
	};
	struct hl_capture_queue_config cq = {
		.dir = r->cfg.capture_dir,
		.slots = r->cfg.capture_queue,
		.pool = r->pool,
		.scene = { .gb = hl_pipeline_gbuffer(r->pipe),
			   .cam = hl_pipeline_camera(r->pipe),
			   .n_lamps = pt->n_lamps,
			   .verdicts = pt->verdicts },
		.log = stderr,
	};
	char err[512];
	int rc = 0;

	for (int l = 0; l < pt->n_lamps; l++) {
		cq.scene.lamp_names[l] = pt->lamp_names[l];
		cq.scene.grids[l] = hl_lid_grid(pt->lids[l]);
	}
	rc = hl_capture_queue_new(&cq, &r->captures);
	if (rc < 0 || (rc = hl_capture_queue_start(r->captures)) < 0) {
		hl_live_log("captures: %s", strerror(-rc));
		return rc;
	}
	if (r->cfg.stream_tcp[0] || r->cfg.stream_unix[0]) {
		rc = hl_stream_new(r->cfg.stream_tcp, r->cfg.stream_unix, r->cfg.stream_raw,
				   r->cfg.stream_max_clients, r->cfg.stream_stall_timeout_ms,
				   r->pool, &r->stream, err, sizeof(err));
		if (rc == 0)
			rc = hl_stream_start(r->stream, r->cfg.rt_priority > 1 ?
								r->cfg.rt_priority - 1 :
								r->cfg.rt_priority);
		if (rc < 0) {
			hl_live_log("%s", err);
			return rc;
		}
		hl_live_log("frame stream on %s%s%s (port %d)", r->cfg.stream_tcp,
			    r->cfg.stream_unix[0] ? " and " : "", r->cfg.stream_unix,
			    hl_stream_tcp_port(r->stream));
	}
	ss.stream = r->stream;
	ss.captures = r->captures;
	if (r->cfg.http_listen[0]) {
		struct hl_http_sources src = {
			.pool = r->pool,
			.exr_info = &r->exr_info,
			.userdata = r,
			.status_json = http_status,
			.metrics = http_metrics,
			.capture = http_capture,
			.glare_json = pt->glare ? http_glare : NULL,
		};

		r->exr_info.camera = hl_pipeline_camera(r->pipe);
		r->exr_info.n_lamps = pt->n_lamps;
		for (int l = 0; l < pt->n_lamps; l++)
			hl_lamp_pose_default(l, &r->exr_info.lamps[l]);
		rc = hl_http_new(r->cfg.http_listen, r->cfg.http_capture, &src, &r->http);
		ss.http = r->http; /* made before the status that reads it, started after */
	}
	rc = rc < 0 ? rc : hl_status_new(&ss, r->cfg.failsafe, &r->status);
	rc = rc < 0 || !r->http ? rc : hl_http_start(r->http);
	if (rc < 0 && r->cfg.http_listen[0] && (!r->http || r->status)) /* not the status' */
		hl_live_log("http.listen '%s': %s", r->cfg.http_listen, strerror(-rc));
	if (rc == 0 && r->http && !hl_http_loopback(r->http))
		hl_live_log(
			"warning: http.listen '%s' is not a loopback address: other hosts can connect",
			r->cfg.http_listen);
	if (rc == 0 && r->http)
		hl_live_log("live view on http://%s/ (port %u)%s", r->cfg.http_listen,
			    hl_http_port(r->http),
			    r->cfg.http_capture ? ", POST /capture allowed" : "");
	return rc;
}

int hl_live_render_new(const struct hl_config *cfg, const struct hl_live_render_parts *parts,
		       struct hl_live_render **ret, bool *ret_config_error)
{
	struct hl_live_render *r = calloc(1, sizeof(*r));
	bool config_error = false;
	int rc;

	if (!r) {
		*ret_config_error = false;
		return -ENOMEM;
	}
	r->cfg = *cfg;
	r->parts = *parts;
	rc = setup_renderer(r, &config_error);
	if (rc == 0)
		rc = setup_outputs(r);
	if (rc < 0) {
		hl_live_render_free(r);
		*ret_config_error = config_error;
		return rc;
	}
	*ret = r;
	return 0;
}

void hl_live_render_free(struct hl_live_render *r)
{
	if (!r)
		return;
	if (r->pool)
		hl_frame_pool_close(r->pool);
	hl_http_stop(r->http);
	hl_capture_queue_free(r->captures); /* before the G-buffer, grids and verdicts it reads */
	hl_pipeline_free(r->pipe); /* stopped first: nothing publishes any more */
	hl_stream_free(r->stream);
	if (r->gpio)
		hl_frame_pool_unsubscribe(r->pool, strobe, r->gpio);
	hl_gpio_free(r->gpio);
	hl_status_free(r->status);
	hl_verdict_records_free(r->records); /* after the pipeline and the status that use them */
	hl_http_free(r->http); /* after the status that reads its counters */
	if (r->parts.loop && r->pool)
		hl_frame_pool_unsubscribe(r->pool, loop_frame, r->parts.loop);
	hl_frame_pool_free(r->pool);
	free(r);
}

struct hl_pipeline *hl_live_render_pipeline(const struct hl_live_render *r)
{
	return r->pipe;
}

int hl_live_render_trigger_fd(const struct hl_live_render *r)
{
	return r->gpio ? hl_gpio_trigger_fd(r->gpio) : -1;
}

void hl_live_render_trigger(struct hl_live_render *r)
{
	char msg[256]; /* a capture's answer: the queue logs it */
	unsigned edges = 0;

	if (hl_gpio_read_trigger(r->gpio, &edges) == 0 && edges > 0)
		hl_capture_queue_submit(r->captures, 0, msg, sizeof(msg));
}

void hl_live_render_capture(struct hl_live_render *r)
{
	char msg[256]; /* a capture's answer: the queue logs it */

	hl_capture_queue_submit(r->captures, 0, msg, sizeof(msg));
}

void hl_live_render_reload(struct hl_live_render *r, const struct hl_config *next)
{
	uint8_t *dims[HL_FRAME_MAX_LAMPS] = { NULL };

	if (load_failsafe(next, r->parts.n_lamps, hl_assembler_n_sources(r->parts.a, 0), dims) < 0)
		return;
	hl_pipeline_set_failsafe(r->pipe, next->failsafe, (const uint8_t *const *)dims);
	hl_pipeline_set_exposure(r->pipe, next->exposure_ev);
	r->cfg.failsafe = next->failsafe;
	r->cfg.exposure_ev = next->exposure_ev;
	memcpy(r->cfg.failsafe_preset, next->failsafe_preset, sizeof(next->failsafe_preset));
	hl_status_reloaded(r->status, next->failsafe); /* what HTTP threads read, locked */
	free(dims[0]);
	free(dims[1]);
	hl_live_log(
		"reloaded: lamps.failsafe and render.exposure_ev applied; other keys take effect at restart");
}

void hl_live_render_stop(struct hl_live_render *r)
{
	hl_frame_pool_close(r->pool);
	hl_http_stop(r->http); /* freed after the status that reads it */
	if (r->captures) /* what was asked for is written and counted */
		hl_capture_queue_stop(r->captures);
	hl_pipeline_stop(r->pipe);
	hl_restbus_stop(r->parts.restbus);
	hl_pose_input_stop(r->parts.pose);
	hl_osi_input_stop(r->parts.osi);
	if (r->stream)
		hl_stream_stop(r->stream);
}

void hl_live_render_print_status(struct hl_live_render *r)
{
	size_t size = 1 << 16;
	char *buf = NULL;
	int n = -ENOBUFS;

	while (n == -ENOBUFS && size <= (16u << 20)) {
		char *b = realloc(buf, size);

		if (!b)
			break;
		buf = b;
		n = hl_status_json(r->status, buf, size);
		size *= 2;
	}
	if (n > 0)
		printf("%s\n", buf);
	free(buf);
}
