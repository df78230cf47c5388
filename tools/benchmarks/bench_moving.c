/* SPDX-License-Identifier: MIT */
/*
 * hdlamp-bench-moving: what a moving scene costs the render thread per frame, as one JSON
 * object. A scenario (default the shipped demo drive: the ego on curves among four road users,
 * posts on both edges) at 1280 x 720 from the driver's eye, lit by the HD84 pair (high beam,
 * ten sources changed per lamp per frame as in an ECU cycle), frames 20 ms apart in scenario
 * time. A timed frame is what hdlampd's render thread does with a scenario (daemon/pipeline.c):
 * the world state at the frame's instant (hl_world_at), the new currents, the ray cast of the
 * moving scene into the G-buffer band by band on the renderer's threads
 * (hl_renderer_set_gbuffer_fill with hl_world_scene_render_pixels), only the pixels whose
 * geometry changed relit, the headlight pass, the display tone map and the road users' lamps.
 *   moving_frame          that, on --threads threads (default 2, hdlampd's one per CPU)
 *   moving_frame_1_thread the same on one thread
 *   still_frame           the same frames without a new G-buffer (a still scene)
 *   gles_moving_frame     the GLES headlight pass with the changed rows uploaded again
 *                         (llvmpipe here: for information; a real GPU is another machine)
 * Median, p99, min, max in ms (wall clock), and the calling thread's CPU time; the pixels
 * whose geometry changed per frame. Target: moving_frame median <= 10 ms (CPU).
 */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <GLES3/gl31.h>

#include "base/json_check.h"
#include "lamp/model.h"
#include "render/egl.h"
#include "render/gbuffer_diff.h"
#include "render/renderer.h"
#include "world/scenario.h"
#include "render/scene.h"
#include "world/world.h"
#include "render/world_scene.h"
#include "render/view.h"
#include "tools/benchmarks/bench_stats.h"

#define TARGET_MS 10.0 /* docs/performance.md: a moving 1280 x 720 frame, CPU, median */
#define CHANGED_PER_CYCLE 10 /* sources an ECU cycle typically changes per lamp */
#define FRAME_S 0.02 /* 50 Hz */
#define T0_S 10.0 /* the first frame's scenario time (the demo drive: all road users near) */
#define MAX_EMITTERS (HL_SCN_MAX_ACTORS * HL_SCN_MAX_LAMPS)

/* The moving scene: the scenario, its ray cast, the frame's state, the driver's camera. */
struct scene {
	const struct hl_scenario *sc;
	struct hl_world_scene *ws;
	struct hl_world_raster *raster; /* made per timed run: the first frame draws everything */
	struct hl_world_state st;
	struct hl_camera cam;
	struct hl_gbuffer *gb;
	struct hl_world_emitter em[MAX_EMITTERS];
};

/* Frame f's instant: T0_S + f frames, wrapping at the scenario's end. */
static void scene_at(struct scene *s, int f)
{
	hl_world_at(s->sc, fmod(T0_S + f * FRAME_S, s->sc->duration_s), &s->st);
}

/* The renderer's threads ray cast the frame's bands (as daemon/pipeline.c's world_fill). */
static void scene_fill(void *userdata, struct hl_gbuffer *gb, size_t first, size_t count,
		       uint8_t *changed)
{
	struct scene *s = userdata;

	(void)gb; /* the raster's */
	hl_world_raster_pixels(s->raster, &s->st, first, count, changed);
}

/* The next ECU cycle: CHANGED_PER_CYCLE sources of i take new values. */
static void next_cycle(float *i, int n, unsigned *seed)
{
	for (int j = 0; j < CHANGED_PER_CYCLE; j++)
		i[rand_r(seed) % n] = (float)(rand_r(seed) % 64) / 63.0f;
}

struct pct {
	struct stats s;
	double p99;
	struct stats cpu; /* the calling thread's CPU time */
};

static struct pct summarise(double *t, int n)
{
	struct pct r;

	r.s = hl_bench_summarise(t, n); /* sorts */
	r.p99 = n > 0 ? t[(int)((n - 1) * 0.99 + 0.5)] : -1;
	return r;
}

static void print_pct(FILE *f, const char *name, struct pct p, int threads, const char *end)
{
	fprintf(f,
		"  \"%s\": {\"median_ms\": %.3f, \"p99_ms\": %.3f, \"min_ms\": %.3f, "
		"\"max_ms\": %.3f, \"n\": %d, \"threads\": %d, \"caller_cpu_median_ms\": %.3f, "
		"\"caller_cpu_min_ms\": %.3f}%s\n",
		name, p.s.median, p.p99, p.s.min, p.s.max, p.s.n, threads, p.cpu.median, p.cpu.min,
		end);
}

struct display_job {
	const struct hl_gbuffer *gb;
	uint8_t *rgb;
};

static void display_band(void *userdata, const float *lux, size_t first, size_t count)
{
	const struct display_job *j = userdata;

	hl_view_display_range(j->gb, lux, 0.0, first, count, j->rgb);
}

struct run {
	struct hl_lid *lamps[2];
	float base_i[2][HL_HD84_SOURCES];
	struct hl_egl *egl;
	struct scene *scene;
	float *lux;
	uint8_t *rgb;
	double *t;
	double *cpu; /* the calling thread's CPU time per frame */
};

/* CLOCK_THREAD_CPUTIME_ID in ms: the work of a 1-thread frame, whatever else runs. */
static double thread_cpu_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
	return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

/*
 * frames timed frames (after 5 untimed) of the moving scene on backend light with threads
 * threads; moving false: the same frames without new G-buffers. ret_setup_ms: making the
 * renderer with room for moving scenes. 0 or a negative errno.
 */
static int time_frames(struct run *x, enum hl_backend light, int threads, bool moving, int frames,
		       struct pct *ret, double *ret_setup_ms)
{
	struct hl_renderer_config cfg = { .n_lamps = 2,
					  .combine = HL_BACKEND_CPU,
					  .headlight = light,
					  .egl = x->egl,
					  .threads = threads,
					  .moving = moving,
					  .fill_only = moving }; /* as hdlampd's moving scene */
	struct scene *s = x->scene;
	struct display_job j = { s->gb, x->rgb };
	const size_t n = (size_t)s->gb->width * s->gb->height;
	float i[2][HL_HD84_SOURCES];
	struct hl_renderer *r = NULL;
	unsigned seed = 7;
	double t0, c0;
	int rc;

	for (int k = 0; k < 2; k++) {
		cfg.lids[k] = x->lamps[k];
		cfg.poses[k] = s->sc->ego.lamp[k];
		memcpy(i[k], x->base_i[k], sizeof(i[k]));
	}
	scene_at(s, 0);
	rc = hl_world_scene_render(s->ws, &s->st, &s->cam, s->gb);
	if (rc < 0)
		return rc;
	memset(x->lux, 0, sizeof(float) * n); /* as the frame pool: zeroed once */
	memset(x->rgb, 0, 3 * n);
	t0 = hl_bench_now_ms();
	rc = hl_renderer_new(&cfg, s->gb, &r);
	if (rc == 0)
		rc = hl_world_raster_new(s->ws, &s->cam, s->gb, &s->raster);
	if (rc < 0) {
		hl_renderer_free(r);
		return rc;
	}
	*ret_setup_ms = hl_bench_now_ms() - t0;
	for (int f = -5; f < frames; f++) {
		for (int k = 0; k < 2; k++)
			next_cycle(i[k], HL_HD84_SOURCES, &seed);
		c0 = thread_cpu_ms();
		t0 = hl_bench_now_ms();
		if (moving)
			scene_at(s, f + 6);
		for (int k = 0; k < 2; k++)
			hl_renderer_set_currents(r, k, i[k]);
		if (moving)
			rc = hl_renderer_set_gbuffer_fill(r, s->gb, scene_fill, s);
		if (rc == 0)
			rc = hl_renderer_frame_pixels(r, x->lux, display_band, &j);
		if (light == HL_BACKEND_GLES)
			glFinish(); /* done before it counts */
		if (rc < 0)
			break;
		if (moving) {
			const int ne = hl_world_scene_emitters(s->ws, &s->st, &s->cam, s->em,
							       MAX_EMITTERS);

			hl_world_emitters_draw(&s->cam, s->em, ne, 0.0, x->rgb);
		}
		if (f >= 0) {
			x->t[f] = hl_bench_now_ms() - t0;
			x->cpu[f] = thread_cpu_ms() - c0;
		}
	}
	hl_renderer_free(r);
	hl_world_raster_free(s->raster);
	s->raster = NULL;
	if (rc < 0)
		return rc;
	*ret = summarise(x->t, frames);
	ret->cpu = summarise(x->cpu, frames).s;
	return 0;
}

/* Pixels whose geometry changed from each frame to the next (hl_gbuffer_diff, not timed). */
static int changed_pixels(struct scene *s, int frames, double *t, struct stats *ret)
{
	const size_t n = (size_t)s->gb->width * s->gb->height;
	struct hl_gbuffer_diff *d = NULL;
	int rc;

	scene_at(s, 0);
	hl_world_scene_render(s->ws, &s->st, &s->cam, s->gb);
	rc = hl_gbuffer_diff_new(s->gb->width, s->gb->height, s->gb, &d);
	if (rc < 0)
		return rc;
	for (int f = 0; f < frames; f++) {
		scene_at(s, f + 1);
		hl_world_scene_render(s->ws, &s->st, &s->cam, s->gb);
		t[f] = (double)hl_gbuffer_diff_band(d, s->gb, 0, n, false);
	}
	hl_gbuffer_diff_free(d);
	*ret = hl_bench_summarise(t, frames);
	return 0;
}

static void usage(FILE *f)
{
	fprintf(f, "usage: hdlamp-bench-moving [--scenario FILE] [--frames N] [--gles-frames N]\n"
		   "                           [--threads N] [--out FILE.json]\n"
		   "Times a moving 1280x720 scene through hl_renderer as hdlampd renders a\n"
		   "scenario: the ray cast into the G-buffer on the renderer's threads, the\n"
		   "changed pixels relit, the HD84 pair, the display tone map, the road users'\n"
		   "lamps. Default the shipped demo-drive.json, 200 frames (GLES 30; 0 leaves\n"
		   "GLES out), 2 threads. Prints one JSON object (or writes it to --out). Exit 0,\n"
		   "1 on a failure, 2 on a\n"
		   "usage error.\n");
}

int main(int argc, char **argv)
{
	static const struct option opts[] = {
		{ "scenario", required_argument, NULL, 's' },
		{ "frames", required_argument, NULL, 'n' },
		{ "gles-frames", required_argument, NULL, 'g' },
		{ "threads", required_argument, NULL, 't' },
		{ "out", required_argument, NULL, 'o' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	const int w = 1280, h = 720;
	int frames = 200, gles_frames = 30, threads = 2, c, rc = 1;
	const char *out_path = NULL;
	struct hl_egl_error eerr;
	struct hl_preset *p = NULL;
	const char *scn_path = NULL;
	char path[4096], msg[1024];
	struct hl_json_error jerr;
	struct hl_scenario *sc = NULL;
	struct scene scene = { 0 };
	struct run x = { 0 };
	struct pct moving, moving1, still, gles = { { -1, -1, -1, 0 }, -1, { -1, -1, -1, 0 } };
	struct stats changed;
	double setup_moving, setup_moving1, setup_still, setup_gles = -1;
	FILE *f = NULL;

	while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
		switch (c) {
		case 'n':
			frames = atoi(optarg);
			if (frames < 3 || frames > 100000) {
				fprintf(stderr, "hdlamp-bench-moving: --frames: 3..100000\n");
				return 2;
			}
			break;
		case 'g':
			gles_frames = atoi(optarg);
			if (gles_frames < 0 || gles_frames > 100000 ||
			    (gles_frames > 0 && gles_frames < 3)) {
				fprintf(stderr,
					"hdlamp-bench-moving: --gles-frames: 0 or 3..100000\n");
				return 2;
			}
			break;
		case 't':
			threads = atoi(optarg);
			if (threads < 1 || threads > 16) {
				fprintf(stderr, "hdlamp-bench-moving: --threads: 1..16\n");
				return 2;
			}
			break;
		case 's':
			scn_path = optarg;
			break;
		case 'o':
			out_path = optarg;
			break;
		case 'h':
			usage(stdout);
			return 0;
		default:
			usage(stderr);
			return 2;
		}
	}
	if (optind != argc) {
		usage(stderr);
		return 2;
	}
	if (gles_frames > 0 && hl_egl_new(&x.egl, &eerr) < 0) {
		fprintf(stderr, "hdlamp-bench-moving: no EGL: %s\n", eerr.msg);
		return 1;
	}
	if (hl_model_hd84(HL_SIDE_LEFT, &x.lamps[0]) < 0 ||
	    hl_model_hd84(HL_SIDE_RIGHT, &x.lamps[1]) < 0 ||
	    hl_preset_new(HL_HD84_SOURCES, &p) < 0 ||
	    hl_model_hd84_preset("high", x.lamps, p) < 0) {
		fprintf(stderr, "hdlamp-bench-moving: cannot build the HD84 lamps\n");
		goto out;
	}
	hl_preset_intensities(p, HL_SIDE_LEFT, x.base_i[0]);
	hl_preset_intensities(p, HL_SIDE_RIGHT, x.base_i[1]);
	if (!scn_path) {
		if (hl_scenario_default_dir(path, sizeof(path) - 32) < 0) {
			fprintf(stderr, "hdlamp-bench-moving: cannot find the shipped scenarios\n");
			goto out;
		}
		strcat(path, "/demo-drive.json");
		scn_path = path;
	}
	if (hl_scenario_read(scn_path, &sc, &jerr) < 0) {
		fprintf(stderr, "hdlamp-bench-moving: %s\n",
			hl_json_error_format(&jerr, msg, sizeof(msg)));
		goto out;
	}
	scene.sc = sc;
	scene.cam = sc->ego.camera;
	scene.cam.width = w;
	scene.cam.height = h;
	x.lux = malloc(sizeof(float) * w * h);
	x.rgb = malloc(3 * (size_t)w * h);
	x.t = malloc(sizeof(double) * (frames > gles_frames ? frames : gles_frames));
	x.cpu = malloc(sizeof(double) * (frames > gles_frames ? frames : gles_frames));
	if (!x.lux || !x.rgb || !x.t || !x.cpu || hl_gbuffer_new(w, h, &scene.gb) < 0 ||
	    hl_world_scene_new(sc, &scene.ws) < 0) {
		fprintf(stderr, "hdlamp-bench-moving: out of memory\n");
		goto out;
	}
	x.scene = &scene;

	fprintf(stderr, "changed pixels...\n");
	if (changed_pixels(&scene, frames, x.t, &changed) < 0)
		goto out;
	fprintf(stderr, "moving frames...\n");
	if (time_frames(&x, HL_BACKEND_CPU, threads, true, frames, &moving, &setup_moving) < 0 ||
	    time_frames(&x, HL_BACKEND_CPU, 1, true, frames, &moving1, &setup_moving1) < 0 ||
	    time_frames(&x, HL_BACKEND_CPU, threads, false, frames, &still, &setup_still) < 0) {
		fprintf(stderr, "hdlamp-bench-moving: a CPU frame failed\n");
		goto out;
	}
	if (gles_frames > 0) {
		fprintf(stderr, "GLES moving frames...\n");
		if (time_frames(&x, HL_BACKEND_GLES, threads, true, gles_frames, &gles,
				&setup_gles) < 0) {
			fprintf(stderr, "hdlamp-bench-moving: a GLES frame failed\n");
			goto out;
		}
	}
	f = hl_bench_open_json("hdlamp-bench-moving", out_path);
	if (!f)
		goto out;
	fprintf(f,
		"{\n  \"what\": \"moving scene %dx%d of %s (%d road users) from t = %.1f s at "
		"50 Hz, HD84 pair high beam (10 sources changed per lamp per frame); timed: world "
		"state + currents + ray cast on the renderer's threads + changed pixels relit + "
		"headlight pass + display tone map + road users' lamps\",\n",
		w, h, scn_path, sc->n_actors, T0_S);
	fprintf(f,
		"  \"changed_pixels\": {\"median\": %.0f, \"min\": %.0f, \"max\": %.0f, "
		"\"median_fraction\": %.4f},\n",
		changed.median, changed.min, changed.max, changed.median / ((double)w * h));
	print_pct(f, "moving_frame", moving, threads, ",");
	print_pct(f, "moving_frame_1_thread", moving1, 1, ",");
	print_pct(f, "still_frame", still, threads, ",");
	if (gles_frames > 0)
		print_pct(f, "gles_moving_frame", gles, threads, ",");
	fprintf(f,
		"  \"setup_ms\": {\"moving\": %.1f, \"moving_1_thread\": %.1f, \"still\": %.1f, "
		"\"gles_moving\": %.1f},\n",
		setup_moving, setup_moving1, setup_still, setup_gles);
	fprintf(f, "  \"gles_renderer\": \"%s\",\n", x.egl ? hl_egl_renderer(x.egl) : "");
	fprintf(f, "  \"target_median_ms\": %.1f,\n  \"met\": %s\n}\n", TARGET_MS,
		moving.s.median <= TARGET_MS ? "true" : "false");
	rc = 0;
out:
	if (f && f != stdout && fclose(f) != 0)
		rc = 1;
	hl_preset_free(p);
	hl_lid_free(x.lamps[0]);
	hl_lid_free(x.lamps[1]);
	hl_gbuffer_free(scene.gb);
	hl_world_scene_free(scene.ws);
	hl_scenario_free(sc);
	free(x.lux);
	free(x.rgb);
	free(x.t);
	free(x.cpu);
	hl_egl_free(x.egl);
	return rc;
}
