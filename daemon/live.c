/* SPDX-License-Identifier: MIT */
#include "daemon/live.h"

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

#include "daemon/clock.h"
#include "daemon/can_input.h"
#include "daemon/capture.h"
#include "daemon/frame_pool.h"
#include "daemon/gpio.h"
#include "daemon/http.h"
#include "daemon/notify.h"
#include "daemon/pipeline.h"
#include "daemon/stream.h"
#include "lamp/preset.h"

#define POOL_FRAMES 8

struct live {
	struct hl_config cfg;
	const struct hl_live_args *args;
	struct hl_dbc *db;
	struct hl_assembler *a;
	struct hl_lid *lids[HL_FRAME_MAX_LAMPS];
	int n_lamps;
	struct hl_ring *ring;
	struct hl_frame_pool *pool;
	struct hl_pipeline *pipe;
	struct hl_stream *stream;
	struct hl_can_input *in;
	struct hl_gpio *gpio;
	struct hl_http *http;
	struct hl_frame_exr_info exr_info; /* camera and lamp poses for /frame.exr */
	uint64_t watchdog_us; /* ping interval, 0 without a watchdog */
	int64_t watchdog_last_ns; /* render thread's */
	pthread_mutex_t capture_lock;
	uint64_t captures, capture_errors, reloads;
};

static void log_msg(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static void log_msg(const char *fmt, ...)
{
	va_list ap;

	va_start(ap, fmt);
	fputs("hdlampd: ", stderr);
	vfprintf(stderr, fmt, ap);
	fputc('\n', stderr);
	va_end(ap);
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
		log_msg("lamps.failsafe preset '%s': '%s':%d:%d: %s", cfg->failsafe_preset, path,
			perr.line, perr.column, perr.msg);
		return rc;
	}
	if (p->n_sources != n_sources) {
		log_msg("lamps.failsafe preset '%s': %d values per lamp; the lamps have %d sources",
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

int hl_live_status_json(struct live *lv, char *buf, size_t size);
int hl_live_metrics(struct live *lv, char *buf, size_t size);

int hl_live_status_json(struct live *lv, char *buf, size_t size)
{
	FILE *f = fmemopen(buf, size, "w");
	struct hl_input_status st;
	struct hl_pipeline_counts pc;
	struct hl_stream_counts sc = { 0 };
	struct hl_ring_counts rc;
	struct hl_frame_pool_counts fc;
	long n;

	if (!f)
		return -errno;
	hl_can_input_status(lv->in, &st);
	hl_pipeline_counts(lv->pipe, &pc);
	if (lv->stream)
		hl_stream_counts(lv->stream, &sc);
	hl_ring_counts(lv->ring, &rc);
	hl_frame_pool_counts(lv->pool, &fc);
	fprintf(f,
		"{\"renderer\":\"%s\",\"input\":{\"source\":\"%s\",\"link\":\"%s\",\"bus\":\"%s\"},\"lamps\":[",
		hl_pipeline_describe(lv->pipe),
		lv->cfg.interface[0] ? lv->cfg.interface : lv->cfg.replay,
		st.link_up ? "up" : "down", st.bus);
	for (int l = 0; l < lv->n_lamps; l++) {
		const struct hl_lamp_counters *c = &st.lamps[l];

		fprintf(f,
			"%s{\"name\":\"%s\",\"stale\":%s,\"failsafe\":%s,\"cycles\":%" PRIu64
			",\"crc_errors\":%" PRIu64 ",\"incomplete\":%" PRIu64
			",\"lost_cycles\":%" PRIu64 ",\"repeated_frames\":%" PRIu64
			",\"stale_events\":%" PRIu64 ",\"failsafe_frames\":%" PRIu64
			",\"cycles_not_rendered\":%" PRIu64 "}",
			l ? "," : "", hl_assembler_lamp_name(lv->a, l),
			st.stale[l] ? "true" : "false", st.stale[l] ? "true" : "false", c->cycles,
			c->crc_errors, c->incomplete, c->lost_cycles, c->repeated_frames,
			c->stale_events, pc.failsafe_frames[l], pc.cycles_not_rendered[l]);
	}
	fprintf(f,
		"],\"failsafe_mode\":\"%s\",\"frames\":{\"rendered\":%" PRIu64
		",\"published\":%" PRIu64 ",\"not_published\":%" PRIu64
		",\"render_ms_last\":%.3f,\"render_ms_max\":%.3f},"
		"\"ring\":{\"pushed\":%" PRIu64 ",\"consumed\":%" PRIu64 ",\"superseded\":%" PRIu64
		",\"dropped\":%" PRIu64 "},\"stream\":{\"clients\":%" PRIu64
		",\"frames_sent\":%" PRIu64 ",\"frames_skipped\":%" PRIu64 "},\"captures\":%" PRIu64
		",\"reloads\":%" PRIu64,
		lv->cfg.failsafe == HL_FAILSAFE_HOLD ? "hold" :
		lv->cfg.failsafe == HL_FAILSAFE_DARK ? "dark" :
						       "preset",
		pc.frames + pc.not_published, fc.published, pc.not_published, pc.render_ms_last,
		pc.render_ms_max, rc.pushed, rc.consumed, rc.superseded, rc.dropped, sc.clients,
		sc.frames_sent, sc.frames_skipped, lv->captures, lv->reloads);
	if (lv->gpio) {
		struct hl_gpio_counts gc;

		hl_gpio_counts(lv->gpio, &gc);
		fprintf(f,
			",\"gpio\":{\"strobe_toggles\":%" PRIu64 ",\"strobe_errors\":%" PRIu64
			",\"trigger_edges\":%" PRIu64 ",\"trigger_lost\":%" PRIu64 "}",
			gc.strobe_toggles, gc.strobe_errors, gc.trigger_edges, gc.trigger_lost);
	}
	fputc('}', f);
	n = ftell(f);
	fclose(f);
	return n >= (long)size - 1 ? -ENOBUFS : (int)n;
}

int hl_live_metrics(struct live *lv, char *buf, size_t size)
{
	static const double edges[7] = { 1, 2, 5, 10, 20, 50, 100 };
	FILE *f = fmemopen(buf, size, "w");
	struct hl_input_status st;
	struct hl_pipeline_counts pc;
	struct hl_stream_counts sc = { 0 };
	struct hl_ring_counts rc;
	uint64_t cum = 0;
	long n;

	if (!f)
		return -errno;
	hl_can_input_status(lv->in, &st);
	hl_pipeline_counts(lv->pipe, &pc);
	if (lv->stream)
		hl_stream_counts(lv->stream, &sc);
	hl_ring_counts(lv->ring, &rc);
#define LAMP_COUNTER(name, field, help)                                                  \
	fprintf(f, "# HELP hdlamp_" name " " help "\n# TYPE hdlamp_" name " counter\n"); \
	for (int l = 0; l < lv->n_lamps; l++)                                            \
		fprintf(f, "hdlamp_" name "{lamp=\"%s\"} %" PRIu64 "\n",                 \
			hl_assembler_lamp_name(lv->a, l), st.lamps[l].field);
	LAMP_COUNTER("cycles_total", cycles, "Complete lamp cycles.")
	LAMP_COUNTER("crc_errors_total", crc_errors, "Frames dropped for a wrong E2E CRC.")
	LAMP_COUNTER("incomplete_cycles_total", incomplete, "Cycles abandoned for a missing part.")
	LAMP_COUNTER("lost_cycles_total", lost_cycles, "Alive counter values never seen.")
	LAMP_COUNTER("duplicate_frames_total", repeated_frames, "Repeated frames ignored.")
	LAMP_COUNTER("stale_events_total", stale_events, "Times the lamp became stale.")
#undef LAMP_COUNTER
	fprintf(f, "# HELP hdlamp_cycles_not_rendered_total Complete cycles no rendered frame "
		   "showed.\n# TYPE hdlamp_cycles_not_rendered_total counter\n");
	for (int l = 0; l < lv->n_lamps; l++)
		fprintf(f, "hdlamp_cycles_not_rendered_total{lamp=\"%s\"} %" PRIu64 "\n",
			hl_assembler_lamp_name(lv->a, l), pc.cycles_not_rendered[l]);
	fprintf(f, "# HELP hdlamp_lamp_stale Whether the lamp is stale (fail-safe active).\n"
		   "# TYPE hdlamp_lamp_stale gauge\n");
	for (int l = 0; l < lv->n_lamps; l++)
		fprintf(f, "hdlamp_lamp_stale{lamp=\"%s\"} %d\n", hl_assembler_lamp_name(lv->a, l),
			st.stale[l]);
	fprintf(f,
		"# HELP hdlamp_bus_state The CAN input's state (1 for the current one).\n"
		"# TYPE hdlamp_bus_state gauge\nhdlamp_bus_state{state=\"%s\"} 1\n",
		st.bus);
	fprintf(f,
		"# HELP hdlamp_link_up Whether the CAN input is open.\n"
		"# TYPE hdlamp_link_up gauge\nhdlamp_link_up %d\n",
		st.link_up);
	fprintf(f,
		"# HELP hdlamp_ring_snapshots_total Ring snapshots by fate.\n"
		"# TYPE hdlamp_ring_snapshots_total counter\n"
		"hdlamp_ring_snapshots_total{fate=\"consumed\"} %" PRIu64 "\n"
		"hdlamp_ring_snapshots_total{fate=\"superseded\"} %" PRIu64 "\n"
		"hdlamp_ring_snapshots_total{fate=\"dropped\"} %" PRIu64 "\n",
		rc.consumed, rc.superseded, rc.dropped);
	fprintf(f,
		"# HELP hdlamp_kernel_drops_total Frames the kernel dropped (SO_RXQ_OVFL).\n"
		"# TYPE hdlamp_kernel_drops_total counter\nhdlamp_kernel_drops_total %" PRIu64 "\n",
		st.kernel_drops);
	fprintf(f,
		"# HELP hdlamp_frames_total Frames rendered and published.\n"
		"# TYPE hdlamp_frames_total counter\nhdlamp_frames_total %" PRIu64 "\n",
		pc.frames);
	fprintf(f,
		"# HELP hdlamp_stream_frames_skipped_total Frames slow stream clients skipped.\n"
		"# TYPE hdlamp_stream_frames_skipped_total counter\n"
		"hdlamp_stream_frames_skipped_total %" PRIu64 "\n",
		sc.frames_skipped);
	fprintf(f, "# HELP hdlamp_render_ms Time to render a frame (ms).\n"
		   "# TYPE hdlamp_render_ms histogram\n");
	for (int b = 0; b < 8; b++) {
		cum += pc.render_ms_buckets[b];
		if (b < 7)
			fprintf(f, "hdlamp_render_ms_bucket{le=\"%g\"} %" PRIu64 "\n", edges[b],
				cum);
		else
			fprintf(f, "hdlamp_render_ms_bucket{le=\"+Inf\"} %" PRIu64 "\n", cum);
	}
	fprintf(f, "hdlamp_render_ms_sum %.6f\nhdlamp_render_ms_count %" PRIu64 "\n",
		pc.render_ms_sum, cum);
	n = ftell(f);
	fclose(f);
	return n >= (long)size - 1 ? -ENOBUFS : (int)n;
}

/* Writes a capture of the newest frame (any thread). */
int hl_live_capture(struct live *lv, char *path, size_t size);
int hl_live_capture(struct live *lv, char *path, size_t size)
{
	struct hl_capture_scene sc = {
		.gb = hl_pipeline_gbuffer(lv->pipe),
		.cam = hl_pipeline_camera(lv->pipe),
		.n_lamps = lv->n_lamps,
	};
	struct hl_frame *f;
	char err[512];
	int rc;

	for (int l = 0; l < lv->n_lamps; l++) {
		sc.lamp_names[l] = hl_assembler_lamp_name(lv->a, l);
		sc.grids[l] = hl_lid_grid(lv->lids[l]);
	}
	f = hl_frame_pool_get(lv->pool, 0, 1000);
	if (!f) {
		log_msg("capture: no frame rendered yet");
		return -EAGAIN;
	}
	pthread_mutex_lock(&lv->capture_lock);
	rc = hl_capture_write(lv->cfg.capture_dir, f, &sc, path, size, err, sizeof(err));
	if (rc < 0)
		lv->capture_errors++;
	else
		lv->captures++;
	pthread_mutex_unlock(&lv->capture_lock);
	hl_frame_pool_release(lv->pool, f);
	if (rc < 0)
		log_msg("capture failed: %s", err);
	else
		log_msg("capture written to '%s'", path);
	return rc;
}

/* HTTP callbacks (the server's threads; everything they read is locked or atomic). */
static int http_status(void *ud, char *buf, size_t size)
{
	return hl_live_status_json(ud, buf, size);
}

static int http_metrics(void *ud, char *buf, size_t size)
{
	return hl_live_metrics(ud, buf, size);
}

static int http_capture(void *ud, char *path, size_t size)
{
	return hl_live_capture(ud, path, size);
}

/* SIGHUP: re-read the configuration; the CAN thread runs on, so no cycle is lost. */
static void reload(struct live *lv)
{
	struct hl_config next;
	struct hl_config_error err;
	uint8_t *dims[HL_FRAME_MAX_LAMPS] = { NULL };

	hl_config_defaults(&next);
	if (lv->args->config_path && hl_config_load(&next, lv->args->config_path, &err) < 0) {
		log_msg("reload: %s; keeping the running configuration", err.msg);
		return;
	}
	for (int i = 0; i < lv->args->n_overrides; i++)
		if (hl_config_set_arg(&next, lv->args->overrides[i], "command line", &err) < 0) {
			log_msg("reload: %s", err.msg);
			return;
		}
	if (load_failsafe(&next, lv->n_lamps, hl_assembler_n_sources(lv->a, 0), dims) < 0)
		return;
	hl_pipeline_set_failsafe(lv->pipe, next.failsafe, (const uint8_t *const *)dims);
	hl_pipeline_set_exposure(lv->pipe, next.exposure_ev);
	lv->cfg.failsafe = next.failsafe;
	lv->cfg.exposure_ev = next.exposure_ev;
	memcpy(lv->cfg.failsafe_preset, next.failsafe_preset, sizeof(next.failsafe_preset));
	lv->reloads++;
	free(dims[0]);
	free(dims[1]);
	log_msg("reloaded: lamps.failsafe and render.exposure_ev applied; other keys take effect at restart");
}

static int setup(struct live *lv)
{
	struct hl_dbc_error derr;
	struct hl_asm_error aerr;
	struct hl_lid_error lerr;
	char *names[HL_ASM_MAX_LAMPS], lamps[HL_CONFIG_NAME], err[512];
	const char *lid_paths[HL_FRAME_MAX_LAMPS] = { lv->cfg.lid_left, lv->cfg.lid_right };
	uint8_t *dims[HL_FRAME_MAX_LAMPS] = { NULL };
	struct hl_source_scale *scales[HL_FRAME_MAX_LAMPS] = { NULL };
	int n = 0, rc, n_src = 0;

	rc = hl_dbc_parse_file(lv->cfg.dbc, &lv->db, &derr);
	if (rc < 0) {
		log_msg("'%s':%d:%d: %s", lv->cfg.dbc, derr.line, derr.column, derr.msg);
		return rc;
	}
	snprintf(lamps, sizeof(lamps), "%s", lv->cfg.lamps);
	for (char *save = NULL, *t = strtok_r(lamps, ",", &save); t && n < HL_ASM_MAX_LAMPS;
	     t = strtok_r(NULL, ",", &save))
		names[n++] = t;
	if (n < 1 || n > HL_FRAME_MAX_LAMPS) {
		log_msg("can.lamps '%s': the renderer takes one or two lamps", lv->cfg.lamps);
		return -EINVAL;
	}
	rc = hl_assembler_new(lv->db, (const char *const *)names, n, lv->cfg.timeout_ms,
			      lv->cfg.interface[0] ? hl_clock_monotonic_ns() : 0, &lv->a, &aerr);
	if (rc < 0) {
		log_msg("'%s': %s", lv->cfg.dbc, aerr.msg);
		return rc;
	}
	lv->n_lamps = n;
	for (int l = 0; l < n; l++) {
		if (!lid_paths[l][0]) {
			log_msg("lamps.%s: no LID file configured (make one with 'hdlamp model --out DIR')",
				l ? "right" : "left");
			return -EINVAL;
		}
		rc = hl_lid_read(lid_paths[l], &lv->lids[l], &lerr);
		if (rc < 0) {
			log_msg("%s", lerr.msg);
			return rc;
		}
		if (hl_lid_n_sources(lv->lids[l]) != hl_assembler_n_sources(lv->a, l) &&
		    !hl_lid_is_combined(lv->lids[l])) {
			log_msg("'%s' has %d sources; the DBC gives lamp '%s' %d", lid_paths[l],
				hl_lid_n_sources(lv->lids[l]), names[l],
				hl_assembler_n_sources(lv->a, l));
			return -EINVAL;
		}
		if (hl_assembler_n_sources(lv->a, l) > n_src)
			n_src = hl_assembler_n_sources(lv->a, l);
	}
	rc = load_failsafe(&lv->cfg, n, n_src, dims);
	if (rc < 0)
		return rc;
	rc = source_scales(lv->a, n, n_src, scales);
	if (rc == 0)
		rc = hl_ring_new(lv->args->ring_slots, n, n_src, &lv->ring);
	if (rc == 0) {
		const struct hl_lid_grid *g = hl_lid_grid(lv->lids[0]);
		struct hl_frame_shape shape = {
			.width = lv->cfg.width,
			.height = lv->cfg.height,
			.format = strcmp(lv->cfg.view, "hdr") == 0 ? HL_PIXEL_RGBA16F :
								     HL_PIXEL_RGB8,
			.n_lamps = n,
			.n_sources = n_src,
			.dist_width = g->width,
			.dist_height = g->height,
		};

		rc = hl_frame_pool_new(POOL_FRAMES, &shape, &lv->pool);
	}
	if (rc == 0) {
		struct hl_can_input_config icfg = {
			.iface = lv->cfg.interface[0] ? lv->cfg.interface : NULL,
			.replay = lv->cfg.replay[0] ? lv->cfg.replay : NULL,
			.replay_fast = lv->cfg.replay_fast,
			.replay_loop = lv->cfg.replay_loop,
			.log = stderr,
		};

		rc = hl_can_input_new(&icfg, lv->a, lv->ring, &lv->in);
		if (rc < 0)
			log_msg("'%s': %s", icfg.iface ? icfg.iface : icfg.replay, strerror(-rc));
	}
	if (rc == 0) {
		struct hl_pipeline_hooks hooks = { .userdata = lv, .alive = on_alive };

		rc = hl_pipeline_new(&lv->cfg, lv->lids, n,
				     (const struct hl_source_scale *const *)scales,
				     (const uint8_t *const *)dims, lv->ring, lv->pool, &hooks,
				     &lv->pipe);
		if (rc < 0)
			log_msg("render.view '%s': expected display, lux or hdr", lv->cfg.view);
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
			log_msg("gpio: %s", gerr.msg);
			return rc;
		}
		rc = hl_frame_pool_subscribe(lv->pool, strobe, lv->gpio);
		if (rc < 0)
			return rc;
	}
	if (hl_notify_watchdog_interval_us(&lv->watchdog_us) < 0)
		lv->watchdog_us = 0;
	rc = hl_pipeline_start(lv->pipe, err, sizeof(err));
	if (rc < 0) {
		log_msg("%s", err);
		return rc;
	}
	log_msg("renderer: %s", hl_pipeline_describe(lv->pipe));
	if (lv->cfg.stream_tcp[0] || lv->cfg.stream_unix[0]) {
		rc = hl_stream_new(lv->cfg.stream_tcp, lv->cfg.stream_unix, lv->cfg.stream_raw,
				   lv->cfg.stream_max_clients, lv->pool, &lv->stream, err,
				   sizeof(err));
		if (rc == 0)
			rc = hl_stream_start(lv->stream);
		if (rc < 0) {
			log_msg("%s", err);
			return rc;
		}
		log_msg("frame stream on %s%s%s (port %d)", lv->cfg.stream_tcp,
			lv->cfg.stream_unix[0] ? " and " : "", lv->cfg.stream_unix,
			hl_stream_tcp_port(lv->stream));
	}
	if (lv->cfg.http_listen[0]) {
		struct hl_http_sources src = {
			.pool = lv->pool,
			.exr_info = &lv->exr_info,
			.userdata = lv,
			.status_json = http_status,
			.metrics = http_metrics,
			.capture = http_capture,
		};

		lv->exr_info.camera = hl_pipeline_camera(lv->pipe);
		lv->exr_info.n_lamps = lv->n_lamps;
		for (int l = 0; l < lv->n_lamps; l++)
			hl_lamp_pose_default(l, &lv->exr_info.lamps[l]);
		rc = hl_http_new(lv->cfg.http_listen, lv->cfg.http_capture, &src, &lv->http);
		if (rc < 0) {
			log_msg("http.listen '%s': %s", lv->cfg.http_listen, strerror(-rc));
			return rc;
		}
		log_msg("live view on http://%s/ (port %u)%s", lv->cfg.http_listen,
			hl_http_port(lv->http),
			lv->cfg.http_capture ? ", POST /capture allowed" : "");
	}
	rc = hl_can_input_start(lv->in);
	if (rc < 0)
		log_msg("cannot start the CAN thread: %s", strerror(-rc));
	return rc;
}

static void teardown(struct live *lv)
{
	if (lv->in)
		hl_can_input_stop(lv->in);
	if (lv->pool)
		hl_frame_pool_close(lv->pool);
	hl_http_free(lv->http);
	hl_pipeline_free(lv->pipe); /* stopped first: nothing publishes any more */
	hl_stream_free(lv->stream);
	if (lv->gpio)
		hl_frame_pool_unsubscribe(lv->pool, strobe, lv->gpio);
	hl_gpio_free(lv->gpio);
	hl_can_input_free(lv->in);
	hl_frame_pool_free(lv->pool);
	hl_ring_free(lv->ring);
	hl_lid_free(lv->lids[0]);
	hl_lid_free(lv->lids[1]);
	hl_assembler_free(lv->a);
	hl_dbc_free(lv->db);
	pthread_mutex_destroy(&lv->capture_lock);
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
			      hl_assembler_lamp_name(lv->a, l), st->lamps[l].cycles,
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
		log_msg("can: '%s': %s%s%s",
			lv->cfg.interface[0] ? lv->cfg.interface : lv->cfg.replay,
			st.link_up ? "up" : "down", st.link_up ? "" : ": ",
			st.link_up ? "" : strerror(st.link_errno));
	for (int l = 0; l < lv->n_lamps; l++)
		if (st.stale[l] != prev->stale[l])
			log_msg("lamp '%s': %s", hl_assembler_lamp_name(lv->a, l),
				st.stale[l] ? "stale, fail-safe on" : "recovered, fail-safe off");
	*prev = st;
}

int hl_live_run(const struct hl_config *cfg, const struct hl_live_args *args)
{
	struct live lv = { .cfg = *cfg, .args = args };
	struct hl_input_status prev = { .link_up = false };
	int64_t status_ns = 0;
	bool ready = false;
	sigset_t mask;
	int sfd, rc, code = 1;
	char buf[1 << 16];

	pthread_mutex_init(&lv.capture_lock, NULL);
	/* signals arrive through a signalfd here; every thread inherits the mask */
	sigemptyset(&mask);
	sigaddset(&mask, SIGINT);
	sigaddset(&mask, SIGTERM);
	sigaddset(&mask, SIGHUP);
	sigaddset(&mask, SIGUSR1);
	pthread_sigmask(SIG_BLOCK, &mask, NULL);
	signal(SIGPIPE, SIG_IGN);
	sfd = signalfd(-1, &mask, SFD_CLOEXEC | SFD_NONBLOCK);
	rc = sfd < 0 ? -errno : setup(&lv);
	while (rc == 0) {
		struct pollfd pfd[2] = { { .fd = sfd, .events = POLLIN },
					 { .fd = lv.gpio ? hl_gpio_trigger_fd(lv.gpio) : -1,
					   .events = POLLIN } };
		struct signalfd_siginfo si;
		int64_t now;

		log_changes(&lv, &prev);
		now = hl_clock_monotonic_ns();
		/* READY once the lamps are loaded, the renderer is up and the bus is open */
		if (!ready && prev.link_up) {
			hl_notify_ready("running");
			ready = true;
		}
		if (now - status_ns >= 1000000000) {
			status_ns = now;
			notify_status(&lv, &prev);
		}
		if (prev.done) {
			/* a finite replay ended: let the last frame out, then stop */
			hl_clock_sleep_until_ns(hl_clock_monotonic_ns() + 200000000);
			code = 0;
			break;
		}
		if (poll(pfd, lv.gpio && pfd[1].fd >= 0 ? 2 : 1, 200) <= 0)
			continue;
		if (pfd[1].revents & POLLIN) {
			unsigned edges = 0;
			char path[1024];

			if (hl_gpio_read_trigger(lv.gpio, &edges) == 0 && edges > 0)
				hl_live_capture(&lv, path, sizeof(path));
		}
		if (!(pfd[0].revents & POLLIN) || read(sfd, &si, sizeof(si)) != sizeof(si))
			continue;
		if (si.ssi_signo == SIGHUP) {
			hl_notify_reloading();
			reload(&lv);
			hl_notify_ready("running (reloaded)");
		} else if (si.ssi_signo == SIGUSR1) {
			char path[1024];

			hl_live_capture(&lv, path, sizeof(path));
		} else {
			log_msg("%s: stopping", strsignal((int)si.ssi_signo));
			code = 0;
			break;
		}
	}
	hl_notify_stopping();
	if (rc == 0) {
		/* quiesce, then report: the counters no longer move */
		hl_can_input_stop(lv.in);
		hl_frame_pool_close(lv.pool);
		hl_http_free(lv.http);
		lv.http = NULL;
		hl_pipeline_stop(lv.pipe);
		if (lv.stream)
			hl_stream_stop(lv.stream);
		if (hl_live_status_json(&lv, buf, sizeof(buf)) > 0)
			printf("%s\n", buf);
	}
	teardown(&lv);
	if (sfd >= 0)
		close(sfd);
	return code;
}
