/* SPDX-License-Identifier: MIT */
/*
 * hdlamp-bench-moving: what a moving scene costs the render thread per frame, as one JSON
 * object. The road scene at 1280 x 720 from the driver's eye, lit by the HD84 pair (high beam,
 * ten sources changed per lamp per frame as in an ECU cycle), with road users moving in it:
 * a preceding car, a car overtaking, an oncoming car closing at 30 m/s, a cyclist the ego
 * passes, a pedestrian crossing, and delineator posts sliding by at the ego's 15 m/s, each ray cast into the
 * G-buffer as a box before the frame (not timed: in hdlampd that is the scene's job). A timed
 * frame is what the render thread does: the new currents, hl_renderer_set_gbuffer() with the
 * frame's G-buffer, the headlight pass (only the pixels whose geometry changed recomputed) and
 * the display tone map (render/view.c) band by band as hdlampd runs it.
 *   moving_frame          that, on --threads threads (default 2, hdlampd's one per CPU)
 *   moving_frame_1_thread the same on one thread
 *   still_frame           the same frames without new G-buffers (today's still scene)
 *   gles_moving_frame     the GLES headlight pass with the changed rows uploaded again
 *                         (llvmpipe here: for information; a real GPU is another machine)
 * Median, p99, min, max in ms (wall clock), and the calling thread's CPU time (on one thread:
 * the whole frame's work, however busy the machine); the changed pixels per frame. Target:
 * moving_frame median <= 10 ms (CPU).
 */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <GLES3/gl31.h>

#include "lamp/model.h"
#include "render/egl.h"
#include "render/gbuffer_diff.h"
#include "render/renderer.h"
#include "render/scene.h"
#include "render/view.h"
#include "tools/benchmarks/bench_stats.h"

#define TARGET_MS 10.0 /* issue 16: a moving 1280 x 720 frame, CPU, median */
#define CHANGED_PER_CYCLE 10 /* sources an ECU cycle typically changes per lamp */
#define FRAME_S 0.02 /* 50 Hz */
#define EGO_MPS 15.0
#define MAX_BOXES 32

/* An axis-aligned box on the ground, vehicle frame (m), with its reflectance. */
struct box {
	double lo[3], hi[3];
	float albedo;
};

struct rect {
	int x0, y0, x1, y1; /* half-open pixel rectangle */
};

struct scene {
	const struct hl_camera *cam;
	const struct hl_gbuffer *base; /* the road without road users */
	struct hl_gbuffer *live; /* what this frame's G-buffer is */
	struct rect drawn[MAX_BOXES]; /* where the last frame's boxes were */
	int n_drawn;
};

/* Where the road users and the posts are at time t (s). */
static int boxes_at(double t, struct box *b)
{
	int n = 0;
	const double slide = fmod(EGO_MPS * t, 10.0);
	double x;

	/* preceding car in the ego lane, slowly nearer */
	b[n++] =
		(struct box){ { 13.0 - 0.5 * t, -2.65, 0 }, { 17.5 - 0.5 * t, -0.85, 1.45 }, 0.3f };
	/* a car overtaking in the left lane, 8 m -> 32 m at 6 m/s relative */
	x = 8.0 + fmod(6.0 * t, 24.0);
	b[n++] = (struct box){ { x - 4.5, 0.85, 0 }, { x, 2.65, 1.45 }, 0.3f };
	/* oncoming car: 60 m -> 8 m, again and again */
	x = 8.0 + fmod(52.0 - 30.0 * t + 520.0, 52.0);
	b[n++] = (struct box){ { x - 4.5, 0.85, 0 }, { x, 2.65, 1.45 }, 0.3f };
	/* cyclist on the right edge, passed at 10 m/s relative */
	x = 6.0 + fmod(40.0 - 10.0 * t + 400.0, 40.0);
	b[n++] = (struct box){ { x - 1.8, -3.8, 0 }, { x, -3.2, 1.75 }, 0.2f };
	/* pedestrian crossing at 25 m, 1.5 m/s from the right */
	x = -6.0 + fmod(1.5 * t, 12.0);
	b[n++] = (struct box){ { 25.0, x - 0.25, 0 }, { 25.3, x + 0.25, 1.75 }, 0.2f };
	/* posts on both edges every 10 m up to 80 m, sliding toward the ego */
	for (int k = 1; k <= 8 && n + 2 <= MAX_BOXES; k++)
		for (int side = -1; side <= 1; side += 2) {
			const double px = 10.0 * k - slide, py = 4.25 * side;

			b[n++] = (struct box){ { px - 0.05, py - 0.05, 0 },
					       { px + 0.05, py + 0.05, 1.0 },
					       0.8f };
		}
	return n;
}

/* The pixels box b can cover: its corners projected, one pixel more; all when it is behind. */
static struct rect box_rect(const struct hl_camera *cam, const struct box *b)
{
	struct rect r = { cam->width, cam->height, 0, 0 };

	for (int c = 0; c < 8; c++) {
		const double p[3] = { c & 1 ? b->hi[0] : b->lo[0], c & 2 ? b->hi[1] : b->lo[1],
				      c & 4 ? b->hi[2] : b->lo[2] };
		double x, y;

		if (hl_camera_project(cam, p, &x, &y) < 0)
			return (struct rect){ 0, 0, cam->width, cam->height };
		r.x0 = fmin(r.x0, floor(x) - 1);
		r.y0 = fmin(r.y0, floor(y) - 1);
		r.x1 = fmax(r.x1, ceil(x) + 1);
		r.y1 = fmax(r.y1, ceil(y) + 1);
	}
	r.x0 = r.x0 < 0 ? 0 : r.x0;
	r.y0 = r.y0 < 0 ? 0 : r.y0;
	r.x1 = r.x1 > cam->width ? cam->width : r.x1;
	r.y1 = r.y1 > cam->height ? cam->height : r.y1;
	return r;
}

/* Ray casts box b over rect r of gb: a pixel takes the face its ray enters if it is nearer. */
static void cast_box(struct hl_gbuffer *gb, const struct hl_camera *cam, const struct box *b,
		     struct rect r)
{
	for (int row = r.y0; row < r.y1; row++)
		for (int col = r.x0; col < r.x1; col++) {
			const size_t i = (size_t)row * gb->width + col;
			double d[3], t_near = -INFINITY, t_far = INFINITY, have = INFINITY;
			int axis = -1;

			hl_camera_ray(cam, col + 0.5, row + 0.5, d);
			for (int a = 0; a < 3; a++) {
				double t0, t1;

				if (d[a] == 0.0) {
					if (cam->pos_m[a] < b->lo[a] || cam->pos_m[a] > b->hi[a])
						t_near = INFINITY;
					continue;
				}
				t0 = (b->lo[a] - cam->pos_m[a]) / d[a];
				t1 = (b->hi[a] - cam->pos_m[a]) / d[a];
				if (t0 > t1) {
					const double t = t0;

					t0 = t1;
					t1 = t;
				}
				if (t0 > t_near) {
					t_near = t0;
					axis = a;
				}
				t_far = t1 < t_far ? t1 : t_far;
			}
			if (axis < 0 || t_near > t_far || t_near <= 0.0)
				continue;
			if (gb->nrm[4 * i + 3] != (float)HL_SURF_NONE) {
				double dd = 0.0, dp = 0.0;

				for (int a = 0; a < 3; a++) {
					dd += d[a] * d[a];
					dp += (gb->pos[4 * i + a] - cam->pos_m[a]) * d[a];
				}
				have = dp / dd;
			}
			if (t_near >= have)
				continue;
			for (int a = 0; a < 3; a++) {
				gb->pos[4 * i + a] = (float)(cam->pos_m[a] + t_near * d[a]);
				gb->nrm[4 * i + a] = a == axis ? (d[a] > 0.0 ? -1.0f : 1.0f) : 0.0f;
			}
			gb->pos[4 * i + 3] = b->albedo;
			gb->nrm[4 * i + 3] = (float)HL_SURF_WALL;
			gb->albedo[i] = b->albedo;
		}
}

/* The scene at frame f into s->live: last frame's boxes wiped, this frame's cast. */
static void scene_frame(struct scene *s, int f)
{
	struct box b[MAX_BOXES];
	const int n = boxes_at(f * FRAME_S, b);
	const int w = s->live->width;

	for (int k = 0; k < s->n_drawn; k++) {
		const struct rect r = s->drawn[k];

		for (int y = r.y0; y < r.y1 && r.x1 > r.x0; y++) {
			const size_t i = (size_t)y * w + r.x0, len = r.x1 - r.x0;

			memcpy(s->live->pos + 4 * i, s->base->pos + 4 * i, sizeof(float) * 4 * len);
			memcpy(s->live->nrm + 4 * i, s->base->nrm + 4 * i, sizeof(float) * 4 * len);
			memcpy(s->live->albedo + i, s->base->albedo + i, sizeof(float) * len);
		}
	}
	for (int k = 0; k < n; k++) {
		s->drawn[k] = box_rect(s->cam, &b[k]);
		cast_box(s->live, s->cam, &b[k], s->drawn[k]);
	}
	s->n_drawn = n;
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
					  .moving = moving };
	struct display_job j = { x->scene->live, x->rgb };
	const size_t n = (size_t)x->scene->live->width * x->scene->live->height;
	float i[2][HL_HD84_SOURCES];
	struct hl_renderer *r = NULL;
	unsigned seed = 7;
	double t0, c0;
	int rc;

	for (int k = 0; k < 2; k++) {
		cfg.lids[k] = x->lamps[k];
		hl_lamp_pose_default(k, &cfg.poses[k]);
		memcpy(i[k], x->base_i[k], sizeof(i[k]));
	}
	x->scene->n_drawn = 0;
	scene_frame(x->scene, 0);
	memset(x->lux, 0, sizeof(float) * n); /* as the frame pool: zeroed once */
	memset(x->rgb, 0, 3 * n);
	t0 = hl_bench_now_ms();
	rc = hl_renderer_new(&cfg, x->scene->live, &r);
	if (rc < 0)
		return rc;
	*ret_setup_ms = hl_bench_now_ms() - t0;
	for (int f = -5; f < frames; f++) {
		if (moving)
			scene_frame(x->scene, f + 6);
		for (int k = 0; k < 2; k++)
			next_cycle(i[k], HL_HD84_SOURCES, &seed);
		c0 = thread_cpu_ms();
		t0 = hl_bench_now_ms();
		for (int k = 0; k < 2; k++)
			hl_renderer_set_currents(r, k, i[k]);
		if (moving)
			rc = hl_renderer_set_gbuffer(r, x->scene->live);
		if (rc == 0)
			rc = hl_renderer_frame_pixels(r, x->lux, display_band, &j);
		if (light == HL_BACKEND_GLES)
			glFinish(); /* done before it counts */
		if (rc < 0)
			break;
		if (f >= 0) {
			x->t[f] = hl_bench_now_ms() - t0;
			x->cpu[f] = thread_cpu_ms() - c0;
		}
	}
	hl_renderer_free(r);
	if (rc < 0)
		return rc;
	*ret = summarise(x->t, frames);
	ret->cpu = summarise(x->cpu, frames).s;
	return 0;
}

/* Pixels whose geometry changed from each frame to the next (hl_gbuffer_diff, not timed). */
static int changed_pixels(struct scene *s, int frames, double *t, struct stats *ret)
{
	const size_t n = (size_t)s->live->width * s->live->height;
	struct hl_gbuffer_diff *d = NULL;
	int rc;

	s->n_drawn = 0;
	scene_frame(s, 0);
	rc = hl_gbuffer_diff_new(s->live->width, s->live->height, s->live, &d);
	if (rc < 0)
		return rc;
	for (int f = 0; f < frames; f++) {
		scene_frame(s, f + 1);
		t[f] = (double)hl_gbuffer_diff_band(d, s->live, 0, n, false);
	}
	hl_gbuffer_diff_free(d);
	*ret = hl_bench_summarise(t, frames);
	return 0;
}

static void usage(FILE *f)
{
	fprintf(f,
		"usage: hdlamp-bench-moving [--frames N] [--gles-frames N] [--threads N]\n"
		"                           [--out FILE.json]\n"
		"Times a moving 1280x720 road scene through hl_renderer on this machine: road\n"
		"users and posts moving as boxes, a new G-buffer every frame, the HD84 pair,\n"
		"the display tone map. Default 200 frames (GLES 30; 0 leaves GLES out), 2 threads.\n"
		"Prints one JSON object (or writes it to --out). Exit 0, 1 on a failure, 2 on a\n"
		"usage error.\n");
}

int main(int argc, char **argv)
{
	static const struct option opts[] = {
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
	struct hl_gbuffer *base = NULL, *live = NULL;
	struct hl_lamp_pose poses[2];
	struct hl_scene road;
	struct hl_camera cam;
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
	for (int k = 0; k < 2; k++)
		hl_lamp_pose_default(k, &poses[k]);
	hl_scene_init(&road, HL_SCENE_ROAD, poses);
	hl_scene_default_camera(&road, w, h, &cam);
	x.lux = malloc(sizeof(float) * w * h);
	x.rgb = malloc(3 * (size_t)w * h);
	x.t = malloc(sizeof(double) * (frames > gles_frames ? frames : gles_frames));
	x.cpu = malloc(sizeof(double) * (frames > gles_frames ? frames : gles_frames));
	if (!x.lux || !x.rgb || !x.t || !x.cpu || hl_gbuffer_new(w, h, &base) < 0 ||
	    hl_gbuffer_new(w, h, &live) < 0 || hl_scene_render(&road, &cam, base) < 0) {
		fprintf(stderr, "hdlamp-bench-moving: out of memory\n");
		goto out;
	}
	memcpy(live->pos, base->pos, sizeof(float) * 4 * w * h);
	memcpy(live->nrm, base->nrm, sizeof(float) * 4 * w * h);
	memcpy(live->albedo, base->albedo, sizeof(float) * w * h);
	scene = (struct scene){ .cam = &cam, .base = base, .live = live };
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
		"{\n  \"what\": \"moving road scene %dx%d, HD84 pair high beam (10 sources changed "
		"per lamp per frame), road users and posts as boxes; timed: currents + "
		"set_gbuffer + headlight pass + display tone map\",\n",
		w, h);
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
	hl_gbuffer_free(base);
	hl_gbuffer_free(live);
	free(x.lux);
	free(x.rgb);
	free(x.t);
	free(x.cpu);
	hl_egl_free(x.egl);
	return rc;
}
