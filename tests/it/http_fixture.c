/* SPDX-License-Identifier: MIT */
/*
 * hl-http-fixture: a TEST FIXTURE, not the daemon. It serves daemon/http.c with real frames
 * from the project's renderer (the road scene lit by the HD84 lamp pair, display view, CPU
 * stages) so the browser test can run before hdlampd wires the server in. The beam alternates
 * between the low and high presets every --switch-ms, so the image and the counters change.
 * Prints "listening on http://HOST:PORT/" on stdout once the server is up; SIGINT or SIGTERM
 * stop it (exit 0).
 */
#include <errno.h>
#include <getopt.h>
#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "daemon/frame_pool.h"
#include "daemon/http.h"
#include "daemon/prom.h"
#include "render/frame_exr.h"
#include "render/renderer.h"
#include "render/scene.h"
#include "render/view.h"
#include "tools/preset.h"

#define N_FRAMES 4

static volatile sig_atomic_t stop;

static void on_signal(int sig)
{
	(void)sig;
	stop = 1;
}

struct fixture {
	struct hl_frame_pool *pool;
	struct hl_http *_Atomic http;
	struct hl_frame_exr_info exr_info;
	const char *capture_dir;
	atomic_int beam; /* 0 low, 1 high */
	atomic_uint_fast64_t switches, captures;
	atomic_uint_fast64_t render_us; /* last frame */
	pthread_mutex_t lock; /* the histogram */
	struct hl_prom_histogram render_ms;
};

static const char *const beams[] = { "low", "high" };

static int64_t now_ns(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

static int status_json(void *userdata, char *buf, size_t size)
{
	struct fixture *fx = userdata;
	struct hl_frame_pool_counts pc;
	struct hl_http_counts hc = { 0 };
	struct hl_http *http = atomic_load(&fx->http);
	const int beam = atomic_load(&fx->beam);
	int n;

	hl_frame_pool_counts(fx->pool, &pc);
	if (http)
		hl_http_counts(http, &hc);
	n = snprintf(buf, size,
		     "{\"source\":\"hl-http-fixture\",\"beam\":\"%s\",\"beam_switches\":%llu,"
		     "\"render_ms\":%.2f,\"frames\":{\"published\":%llu,\"no_free_frame\":%llu},"
		     "\"lamps\":[{\"name\":\"left\",\"preset\":\"%s\",\"frames\":%llu,"
		     "\"stale\":false},{\"name\":\"right\",\"preset\":\"%s\",\"frames\":%llu,"
		     "\"stale\":false}],"
		     "\"http\":{\"requests\":%llu,\"errors\":%llu,\"mjpeg_clients\":%llu,"
		     "\"mjpeg_frames_sent\":%llu,\"mjpeg_frames_skipped\":%llu},"
		     "\"captures\":%llu}",
		     beams[beam], (unsigned long long)atomic_load(&fx->switches),
		     atomic_load(&fx->render_us) / 1000.0, (unsigned long long)pc.published,
		     (unsigned long long)pc.no_free_frame, beams[beam],
		     (unsigned long long)pc.published, beams[beam],
		     (unsigned long long)pc.published, (unsigned long long)hc.requests,
		     (unsigned long long)hc.errors, (unsigned long long)hc.mjpeg_clients,
		     (unsigned long long)hc.mjpeg_frames_sent,
		     (unsigned long long)hc.mjpeg_frames_skipped,
		     (unsigned long long)atomic_load(&fx->captures));
	return n < 0 ? -EIO : ((size_t)n >= size ? -ENOBUFS : n);
}

static int metrics(void *userdata, char *buf, size_t size)
{
	struct fixture *fx = userdata;
	struct hl_frame_pool_counts pc;
	struct hl_http_counts hc = { 0 };
	struct hl_http *http = atomic_load(&fx->http);
	struct hl_prom_histogram h;
	struct hl_prom p;

	hl_frame_pool_counts(fx->pool, &pc);
	if (http)
		hl_http_counts(http, &hc);
	pthread_mutex_lock(&fx->lock);
	h = fx->render_ms;
	pthread_mutex_unlock(&fx->lock);
	hl_prom_init(&p, buf, size);
	hl_prom_family(&p, "hdlamp_frames_published_total", HL_PROM_COUNTER, "Frames published.");
	hl_prom_counter(&p, "hdlamp_frames_published_total", NULL, pc.published);
	hl_prom_family(&p, "hdlamp_beam_high", HL_PROM_GAUGE, "1 while the high beam is on.");
	for (int l = 0; l < 2; l++)
		hl_prom_gauge(&p, "hdlamp_beam_high",
			      (const char *const[]){ "lamp", l ? "right" : "left", NULL },
			      atomic_load(&fx->beam));
	hl_prom_family(&p, "hdlamp_http_requests_total", HL_PROM_COUNTER, "HTTP requests.");
	hl_prom_counter(&p, "hdlamp_http_requests_total", NULL, hc.requests);
	hl_prom_family(&p, "hdlamp_http_mjpeg_frames_skipped_total", HL_PROM_COUNTER,
		       "Frames MJPEG clients skipped.");
	hl_prom_counter(&p, "hdlamp_http_mjpeg_frames_skipped_total", NULL,
			hc.mjpeg_frames_skipped);
	hl_prom_family(&p, "hdlamp_render_ms", HL_PROM_HISTOGRAM, "Render time per frame, ms.");
	hl_prom_histogram(&p, "hdlamp_render_ms", NULL, &h);
	return hl_prom_end(&p);
}

static int capture(void *userdata, char *path, size_t size)
{
	struct fixture *fx = userdata;
	struct hl_frame *f = hl_frame_pool_get(fx->pool, 0, 0);
	struct hl_lid_error err;
	int rc;

	if (!f)
		return -EAGAIN;
	snprintf(path, size, "%s/capture-%06llu-lux.exr", fx->capture_dir,
		 (unsigned long long)f->hdr.seq);
	rc = hl_frame_exr_write_lux(path, (int)f->hdr.width, (int)f->hdr.height, f->lux,
				    &fx->exr_info, &err);
	hl_frame_pool_release(fx->pool, f);
	if (rc < 0) {
		fprintf(stderr, "hl-http-fixture: capture: %s\n", err.msg);
		return rc;
	}
	atomic_fetch_add(&fx->captures, 1);
	return 0;
}

static void usage(FILE *f)
{
	fprintf(f,
		"usage: hl-http-fixture --lamps DIR [--listen HOST:PORT] [--size WxH]\n"
		"                       [--period-ms MS] [--switch-ms MS] [--capture-dir DIR]\n"
		"A test fixture: serves the HTTP live view with frames of the road scene lit by\n"
		"DIR/hd84_{left,right}.lid.exr, DIR/low.json and DIR/high.json alternating.\n"
		"  --listen     default 127.0.0.1:0 (a free port)\n"
		"  --size       default 640x360\n"
		"  --period-ms  frame period, default 100\n"
		"  --switch-ms  beam switch period, default 1000\n"
		"  --capture-dir  enables POST /capture, writing lux EXRs there\n");
}

int main(int argc, char **argv)
{
	static const struct option opts[] = {
		{ "lamps", required_argument, NULL, 'L' },
		{ "listen", required_argument, NULL, 'l' },
		{ "size", required_argument, NULL, 's' },
		{ "period-ms", required_argument, NULL, 'p' },
		{ "switch-ms", required_argument, NULL, 'w' },
		{ "capture-dir", required_argument, NULL, 'c' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	const char *lamps = NULL, *listen = "127.0.0.1:0";
	int width = 640, height = 360, period_ms = 100, switch_ms = 1000, c, rc, status = 1;
	struct fixture fx = { .render_ms = { 0 } };
	struct hl_lid *lids[2] = { NULL, NULL };
	struct hl_preset *presets[2] = { NULL, NULL };
	struct hl_renderer *r = NULL;
	struct hl_renderer_config cfg = { 0 };
	struct hl_gbuffer *gb = NULL;
	struct hl_scene scene;
	struct hl_camera cam;
	struct hl_http *http = NULL;
	struct hl_http_sources src = { 0 };
	struct hl_frame_shape shape;
	static const double bounds_ms[] = { 5, 10, 20, 50, 100, 200, 500 };
	float cur[2][512];
	char path[4096], tail;
	int64_t t0;
	uint64_t rendered = 0;
	int beam = -1;

	while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
		switch (c) {
		case 'L':
			lamps = optarg;
			break;
		case 'l':
			listen = optarg;
			break;
		case 's':
			if (sscanf(optarg, "%dx%d%c", &width, &height, &tail) != 2 || width < 16 ||
			    height < 16 || width > 4096 || height > 4096) {
				fprintf(stderr, "hl-http-fixture: --size '%s': expected WxH\n",
					optarg);
				return 2;
			}
			break;
		case 'p':
			period_ms = atoi(optarg);
			break;
		case 'w':
			switch_ms = atoi(optarg);
			break;
		case 'c':
			fx.capture_dir = optarg;
			break;
		case 'h':
			usage(stdout);
			return 0;
		default:
			usage(stderr);
			return 2;
		}
	}
	if (!lamps || optind != argc || period_ms < 1 || switch_ms < 1) {
		usage(stderr);
		return 2;
	}

	for (int k = 0; k < 2; k++) {
		struct hl_lid_error err;
		struct hl_preset_error perr = { 0 };

		snprintf(path, sizeof(path), "%s/hd84_%s.lid.exr", lamps, k ? "right" : "left");
		if (hl_lid_read(path, &lids[k], &err) < 0) {
			fprintf(stderr, "hl-http-fixture: %s\n", err.msg);
			goto out;
		}
		snprintf(path, sizeof(path), "%s/%s.json", lamps, beams[k]);
		if (hl_preset_read(path, &presets[k], &perr) < 0) {
			fprintf(stderr, "hl-http-fixture: '%s': %s\n", path, perr.msg);
			goto out;
		}
		if (presets[k]->n_sources > (int)(sizeof(cur[0]) / sizeof(cur[0][0])) ||
		    presets[k]->n_sources != hl_lid_n_sources(lids[k])) {
			fprintf(stderr, "hl-http-fixture: '%s': wrong number of sources\n", path);
			goto out;
		}
	}
	hl_lamp_pose_default(0, &cfg.poses[0]);
	hl_lamp_pose_default(1, &cfg.poses[1]);
	hl_scene_init(&scene, HL_SCENE_ROAD, cfg.poses);
	hl_scene_default_camera(&scene, width, height, &cam);
	if (hl_gbuffer_new(width, height, &gb) < 0 || hl_scene_render(&scene, &cam, gb) < 0) {
		fprintf(stderr, "hl-http-fixture: cannot render the scene\n");
		goto out;
	}
	cfg.n_lamps = 2;
	cfg.lids[0] = lids[0];
	cfg.lids[1] = lids[1];
	cfg.combine = HL_BACKEND_CPU;
	cfg.headlight = HL_BACKEND_CPU;
	rc = hl_renderer_new(&cfg, gb, &r);
	if (rc < 0) {
		fprintf(stderr, "hl-http-fixture: renderer: %s\n", strerror(-rc));
		goto out;
	}
	shape = (struct hl_frame_shape){ .width = width,
					 .height = height,
					 .format = HL_PIXEL_RGB8,
					 .n_lamps = 2,
					 .n_sources = hl_lid_n_sources(lids[0]),
					 .dist_width = 1,
					 .dist_height = 1 };
	if (hl_frame_pool_new(N_FRAMES, &shape, &fx.pool) < 0)
		goto out;
	pthread_mutex_init(&fx.lock, NULL);
	hl_prom_histogram_init(&fx.render_ms, bounds_ms, 7);
	fx.exr_info = (struct hl_frame_exr_info){ .camera = &cam, .n_lamps = 2 };
	memcpy(fx.exr_info.lamps, cfg.poses, sizeof(fx.exr_info.lamps));
	if (fx.capture_dir)
		mkdir(fx.capture_dir, 0755);

	src.pool = fx.pool;
	src.exr_info = &fx.exr_info;
	src.userdata = &fx;
	src.status_json = status_json;
	src.metrics = metrics;
	src.capture = capture;
	rc = hl_http_new(listen, fx.capture_dir != NULL, &src, &http);
	if (rc < 0) {
		fprintf(stderr, "hl-http-fixture: cannot listen on '%s': %s\n", listen,
			strerror(-rc));
		goto out;
	}
	atomic_store(&fx.http, http);
	{
		char host[256];
		const char *colon = strrchr(listen, ':');

		snprintf(host, sizeof(host), "%.*s", (int)(colon - listen), listen);
		printf("listening on http://%s:%u/\n", host, hl_http_port(http));
		fflush(stdout);
	}
	signal(SIGINT, on_signal);
	signal(SIGTERM, on_signal);

	t0 = now_ns();
	while (!stop) {
		const int64_t start = now_ns();
		const int b = (int)(((start - t0) / 1000000 / switch_ms) % 2);
		struct hl_frame *f = hl_frame_pool_acquire(fx.pool);
		struct timespec ts;

		if (b != beam) {
			for (int k = 0; k < 2; k++) {
				hl_preset_intensities(presets[b], k, cur[k]);
				hl_renderer_set_currents(r, k, cur[k]);
			}
			if (beam >= 0)
				atomic_fetch_add(&fx.switches, 1);
			beam = b;
			atomic_store(&fx.beam, b);
		}
		if (f) {
			f->hdr.t_render_start_ns = start;
			rc = hl_renderer_frame(r, f->lux);
			if (rc < 0) {
				fprintf(stderr, "hl-http-fixture: frame: %s\n", strerror(-rc));
				hl_frame_pool_discard(fx.pool, f);
				goto out;
			}
			hl_view_display(gb, f->lux, 0.0, f->pixels);
			f->hdr.t_render_done_ns = now_ns();
			rendered++;
			for (int k = 0; k < 2; k++) {
				f->hdr.cycle_seq[k] = rendered;
				memcpy(f->dims[k], presets[b]->dim[k], (size_t)shape.n_sources);
			}
			atomic_store(&fx.render_us,
				     (uint64_t)((f->hdr.t_render_done_ns - start) / 1000));
			pthread_mutex_lock(&fx.lock);
			hl_prom_histogram_observe(&fx.render_ms,
						  (double)(f->hdr.t_render_done_ns - start) / 1e6);
			pthread_mutex_unlock(&fx.lock);
			hl_frame_pool_publish(fx.pool, f);
		}
		ts.tv_sec = period_ms / 1000;
		ts.tv_nsec = (long)(period_ms % 1000) * 1000000;
		nanosleep(&ts, NULL);
	}
	status = 0;
out:
	atomic_store(&fx.http, NULL);
	hl_http_free(http);
	hl_frame_pool_free(fx.pool);
	hl_renderer_free(r);
	hl_gbuffer_free(gb);
	for (int k = 0; k < 2; k++) {
		hl_preset_free(presets[k]);
		hl_lid_free(lids[k]);
	}
	return status;
}
