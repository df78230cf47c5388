/* SPDX-License-Identifier: MIT */
/*
 * Moving scenes through the renderer (render/renderer.h, hl_renderer_set_gbuffer): a renderer
 * made on one G-buffer and handed others in turn lights each exactly as a renderer made fresh
 * on it (CPU: bit for bit; GLES: against the CPU within the GLES-vs-CPU tolerance of
 * test_renderer, and bit for bit against a fresh GLES renderer), pixels that become reachable
 * or unreachable included, and no frame allocates.
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "alloc_count.h"
#include "lamp/combine.h"
#include "lamp/model.h"
#include "render/headlight.h"
#include "render/renderer.h"

#define W 320 /* several bands of the headlight pass (16,384 pixels each) */
#define H 180
#define N_PIX (W * H)

/* The G-buffers the tests move between. */
enum {
	ROAD, /* the road scene */
	ROAD_CARS, /* the same with five boxes on and beside it, one higher than the horizon */
	ROAD_CARS_MOVED, /* the boxes elsewhere: some nearer, some farther, one gone */
	WALL_10, /* the wall scene at 10 m */
	WALL_25, /* at 25 m */
	N_SCENES,
};

static struct hl_egl *egl;
static struct hl_lid *lamps[2];
static struct hl_preset *high;
static struct hl_gbuffer *gbs[N_SCENES];
static float *ref[N_SCENES]; /* each scene lit by a fresh CPU renderer */

/* An axis-aligned box on the ground (vehicle frame): x0..x1, y0..y1, 0..height. */
struct box {
	double lo[3], hi[3];
};

/*
 * Ray casts the box into gb over what the camera sees: a pixel takes the face where its ray
 * enters the box when that is nearer than what the pixel holds (a road user in front of the
 * road, or in the sky above the horizon).
 */
static void add_box(struct hl_gbuffer *gb, const struct hl_camera *cam, const struct box *b,
		    float albedo)
{
	for (int row = 0; row < gb->height; row++)
		for (int col = 0; col < gb->width; col++) {
			const size_t i = (size_t)row * gb->width + col;
			double d[3], t_near = -INFINITY, t_far = INFINITY, have;
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
			/* the distance along the ray to what the pixel holds now */
			have = INFINITY;
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
			gb->pos[4 * i + 3] = albedo;
			gb->nrm[4 * i + 3] = (float)HL_SURF_WALL;
			gb->albedo[i] = albedo;
		}
}

static void copy_gbuffer(struct hl_gbuffer *dst, const struct hl_gbuffer *src)
{
	const size_t n = (size_t)src->width * src->height;

	memcpy(dst->pos, src->pos, sizeof(float) * 4 * n);
	memcpy(dst->nrm, src->nrm, sizeof(float) * 4 * n);
	memcpy(dst->albedo, src->albedo, sizeof(float) * n);
}

static void config(struct hl_renderer_config *cfg, enum hl_backend light, bool moving, int threads)
{
	*cfg = (struct hl_renderer_config){ .n_lamps = 2,
					    .combine = HL_BACKEND_CPU,
					    .headlight = light,
					    .egl = egl,
					    .threads = threads,
					    .moving = moving };
	for (int k = 0; k < 2; k++) {
		cfg->lids[k] = lamps[k];
		hl_lamp_pose_default(k, &cfg->poses[k]);
	}
}

static void set_high(struct hl_renderer *r)
{
	float i[HL_HD84_SOURCES];

	for (int k = 0; k < 2; k++) {
		hl_preset_intensities(high, k, i);
		assert_true(hl_renderer_set_currents(r, k, i) >= 0);
	}
}

/* A fresh renderer's frame of gb (lamps on high). */
static void fresh_frame(const struct hl_gbuffer *gb, enum hl_backend light, float *lux)
{
	struct hl_renderer_config cfg;
	struct hl_renderer *r = NULL;

	config(&cfg, light, false, 1);
	assert_int_equal(hl_renderer_new(&cfg, gb, &r), 0);
	set_high(r);
	assert_int_equal(hl_renderer_frame(r, lux), 0);
	hl_renderer_free(r);
}

/* lux equals a fresh renderer's frame of gbs[scene]: the CPU reference bit for bit, or with
 * GLES a fresh GLES frame (rendered into fresh) bit for bit. */
static void expect_fresh(enum hl_backend light, int scene, const float *lux, float *fresh)
{
	if (light == HL_BACKEND_CPU) {
		assert_memory_equal(lux, ref[scene], sizeof(float) * N_PIX);
	} else {
		fresh_frame(gbs[scene], HL_BACKEND_GLES, fresh);
		assert_memory_equal(lux, fresh, sizeof(float) * N_PIX);
	}
}

static int setup(void **state)
{
	static const struct box cars[5] = {
		{ { 15.0, -2.65, 0.0 }, { 19.5, -0.85, 1.45 } }, /* preceding, ego lane */
		{ { 30.0, 0.85, 0.0 }, { 34.5, 2.65, 1.45 } }, /* oncoming lane */
		{ { 8.0, -6.0, 0.0 }, { 8.6, -5.4, 1.75 } }, /* pedestrian on the right */
		/* a van beside the road, above the horizon */
		{ { 22.0, 4.5, 0.0 }, { 24.0, 7.0, 4.0 } },
		/* a low trailer: the camera (1.2 m) sees its top, the lamps (0.65 m) cannot */
		{ { 9.0, 0.5, 0.0 }, { 13.0, 3.0, 0.9 } },
	};
	static const struct box moved[3] = {
		{ { 11.0, -2.65, 0.0 }, { 15.5, -0.85, 1.45 } }, /* nearer */
		{ { 45.0, 0.85, 0.0 }, { 49.5, 2.65, 1.45 } }, /* farther */
		{ { 6.0, -5.5, 0.0 }, { 6.6, -4.9, 1.75 } }, /* walked on; the van has gone */
	};
	struct hl_egl_error err;
	struct hl_lamp_pose p[2];
	struct hl_scene s;
	struct hl_camera cam;

	(void)state;
	if (hl_egl_new(&egl, &err) < 0) {
		fprintf(stderr, "no EGL: %s\n", err.msg);
		return -1;
	}
	if (hl_model_hd84(0, &lamps[0]) < 0 || hl_model_hd84(1, &lamps[1]) < 0 ||
	    hl_preset_new(HL_HD84_SOURCES, &high) < 0 ||
	    hl_model_hd84_preset("high", lamps, high) < 0)
		return -1;
	hl_lamp_pose_default(0, &p[0]);
	hl_lamp_pose_default(1, &p[1]);
	for (int j = 0; j < N_SCENES; j++)
		if (hl_gbuffer_new(W, H, &gbs[j]) < 0)
			return -1;
	hl_scene_init(&s, HL_SCENE_ROAD, p);
	hl_scene_default_camera(&s, W, H, &cam);
	if (hl_scene_render(&s, &cam, gbs[ROAD]) < 0)
		return -1;
	copy_gbuffer(gbs[ROAD_CARS], gbs[ROAD]);
	copy_gbuffer(gbs[ROAD_CARS_MOVED], gbs[ROAD]);
	for (int b = 0; b < 5; b++)
		add_box(gbs[ROAD_CARS], &cam, &cars[b], 0.3f);
	for (int b = 0; b < 3; b++)
		add_box(gbs[ROAD_CARS_MOVED], &cam, &moved[b], 0.2f);
	hl_scene_init(&s, HL_SCENE_WALL, p);
	s.wall_distance_m = 10.0;
	hl_scene_default_camera(&s, W, H, &cam);
	if (hl_scene_render(&s, &cam, gbs[WALL_10]) < 0)
		return -1;
	s.wall_distance_m = 25.0;
	if (hl_scene_render(&s, &cam, gbs[WALL_25]) < 0)
		return -1;
	return 0;
}

static int teardown(void **state)
{
	(void)state;
	for (int j = 0; j < N_SCENES; j++) {
		hl_gbuffer_free(gbs[j]);
		free(ref[j]);
	}
	hl_preset_free(high);
	hl_lid_free(lamps[0]);
	hl_lid_free(lamps[1]);
	hl_egl_free(egl);
	return 0;
}

/* Each scene lit by a renderer made fresh on it, and what the changes between them hold. */
static void dynamic_references_differ_where_the_scenes_do(void **state)
{
	size_t lit[N_SCENES] = { 0 }, gained = 0, lost = 0, moved_lit = 0;

	(void)state;
	for (int j = 0; j < N_SCENES; j++) {
		ref[j] = malloc(sizeof(float) * N_PIX);
		assert_non_null(ref[j]);
		fresh_frame(gbs[j], HL_BACKEND_CPU, ref[j]);
		for (int i = 0; i < N_PIX; i++)
			lit[j] += ref[j][i] > 0.0f;
	}
	for (int i = 0; i < N_PIX; i++) {
		gained += ref[ROAD][i] == 0.0f && ref[ROAD_CARS][i] > 0.0f;
		lost += ref[ROAD][i] > 0.0f && ref[ROAD_CARS][i] == 0.0f;
		moved_lit += ref[ROAD][i] > 0.0f && ref[ROAD_CARS][i] > 0.0f &&
			     ref[ROAD][i] != ref[ROAD_CARS][i];
	}
	printf("lit pixels: road %zu, with cars %zu, cars moved %zu, wall 10 m %zu, 25 m %zu; "
	       "road -> cars: %zu become lit, %zu dark, %zu change\n",
	       lit[ROAD], lit[ROAD_CARS], lit[ROAD_CARS_MOVED], lit[WALL_10], lit[WALL_25], gained,
	       lost, moved_lit);
	/* the sequences below cross all three kinds of change */
	assert_true(gained > 100);
	assert_true(lost > 100);
	assert_true(moved_lit > 1000);
	assert_true(lit[WALL_10] > (size_t)N_PIX / 4);
}

/* What frame_pixels() handed out in one frame. */
struct seen {
	uint8_t count[N_PIX];
};

static void record(void *userdata, const float *lux, size_t first, size_t count)
{
	struct seen *s = userdata;

	(void)lux;
	for (size_t i = first; i < first + count; i++)
		s->count[i]++;
}

static const int sequences[][7] = {
	{ ROAD, ROAD_CARS, ROAD, -1 },
	{ ROAD, ROAD_CARS, ROAD_CARS_MOVED, ROAD_CARS, ROAD_CARS_MOVED, ROAD, -1 },
	{ ROAD_CARS, ROAD, ROAD_CARS, -1 },
	{ WALL_25, WALL_10, WALL_25, ROAD, WALL_10, -1 },
	{ ROAD, WALL_10, ROAD_CARS, ROAD, -1 },
};
#define N_SEQUENCES (sizeof(sequences) / sizeof(sequences[0]))

/*
 * CPU: a renderer made on a sequence's first G-buffer and handed the others in turn gives,
 * frame by frame, exactly the frame of a renderer made fresh on each (frame() and
 * frame_pixels() into two buffers zeroed once and used in turn, as the daemon's frame pool:
 * pixels that went dark are zero again in both). The new G-buffer arrives in the same object
 * the renderer was made on (new contents), on 1 and 2 threads, with and without config moving.
 */
static void dynamic_cpu_frames_equal_fresh_renderers(void **state)
{
	static struct seen seen;
	struct hl_gbuffer *live = NULL;
	float *lux = malloc(sizeof(float) * N_PIX);
	float *pool[2] = { calloc(N_PIX, sizeof(float)), calloc(N_PIX, sizeof(float)) };
	size_t frames = 0;

	(void)state;
	assert_non_null(ref[ROAD]);
	assert_int_equal(hl_gbuffer_new(W, H, &live), 0);
	for (size_t q = 0; q < N_SEQUENCES; q++) {
		for (int v = 0; v < 4; v++) {
			const bool moving = v & 1;
			const int threads = 1 + (v >> 1);
			struct hl_renderer_config cfg;
			struct hl_renderer *r = NULL;

			memset(pool[0], 0, sizeof(float) * N_PIX);
			memset(pool[1], 0, sizeof(float) * N_PIX);
			copy_gbuffer(live, gbs[sequences[q][0]]);
			config(&cfg, HL_BACKEND_CPU, moving, threads);
			assert_int_equal(hl_renderer_new(&cfg, live, &r), 0);
			set_high(r);
			assert_int_equal(hl_renderer_frame_pixels(r, pool[0], record, &seen), 0);
			for (int s = 1; sequences[q][s] >= 0; s++) {
				const int scene = sequences[q][s];

				copy_gbuffer(live, gbs[scene]);
				assert_int_equal(hl_renderer_set_gbuffer(r, live), 0);
				memset(seen.count, 0, sizeof(seen.count));
				assert_int_equal(
					hl_renderer_frame_pixels(r, pool[s & 1], record, &seen), 0);
				for (int i = 0; i < N_PIX; i++) {
					assert_true(pool[s & 1][i] == ref[scene][i]);
					assert_true(seen.count[i] <= 1);
					if (ref[scene][i] > 0.0f)
						assert_int_equal(seen.count[i], 1);
				}
				/* and again without a new G-buffer, into the other buffer */
				assert_int_equal(hl_renderer_frame_pixels(r, pool[(s + 1) & 1],
									  record, &seen),
						 0);
				assert_memory_equal(pool[(s + 1) & 1], ref[scene],
						    sizeof(float) * N_PIX);
				/* frame() writes every pixel */
				for (int i = 0; i < N_PIX; i++)
					lux[i] = -1.0f;
				assert_int_equal(hl_renderer_frame(r, lux), 0);
				assert_memory_equal(lux, ref[scene], sizeof(float) * N_PIX);
				frames++;
			}
			hl_renderer_free(r);
		}
	}
	printf("%zu moving frames equal fresh renderers bit for bit\n", frames);
	hl_gbuffer_free(live);
	free(lux);
	free(pool[0]);
	free(pool[1]);
}

/*
 * The CPU pass's moving layout on its own: the pixel-lamp pairs a lamp reaches after updates
 * are those of a pass made fresh, and the frame is the same.
 */
static void dynamic_headlight_update_keeps_the_work_count(void **state)
{
	struct hl_headlight_lamp hl[2];
	struct hl_headlight *moved = NULL, *fresh = NULL;
	float *dense[2], *a = malloc(sizeof(float) * N_PIX), *b = malloc(sizeof(float) * N_PIX);
	uint8_t *all = malloc(N_PIX);
	float cur[HL_HD84_SOURCES];
	static const int seq[] = { ROAD_CARS, ROAD_CARS_MOVED, WALL_10, ROAD };

	(void)state;
	memset(all, 1, N_PIX);
	for (int k = 0; k < 2; k++) {
		const struct hl_lid_grid *g = hl_lid_grid(lamps[k]);

		hl_lamp_pose_default(k, &hl[k].pose);
		hl[k].grid = *g;
		dense[k] = malloc(sizeof(float) * g->width * g->height);
		hl_preset_intensities(high, k, cur);
		hl_combine_sparse(lamps[k], cur, dense[k]);
	}
	assert_int_equal(hl_headlight_new(gbs[ROAD], 2, hl, &moved), 0);
	assert_int_equal(hl_headlight_make_moving(moved), 0);
	assert_int_equal(hl_headlight_make_moving(moved), 0); /* once is enough */
	for (size_t s = 0; s < sizeof(seq) / sizeof(seq[0]); s++) {
		assert_int_equal(hl_headlight_new(gbs[seq[s]], 2, hl, &fresh), 0);
		for (size_t c = 0; c < hl_headlight_chunks(moved); c++)
			hl_headlight_update_chunk(moved, gbs[seq[s]], c, all);
		assert_int_equal(hl_headlight_work(moved), hl_headlight_work(fresh));
		hl_headlight_run(moved, (const float *const *)dense, a);
		hl_headlight_run(fresh, (const float *const *)dense, b);
		assert_memory_equal(a, b, sizeof(float) * N_PIX);
		hl_headlight_free(fresh);
	}
	hl_headlight_free(moved);
	free(dense[0]);
	free(dense[1]);
	free(a);
	free(b);
	free(all);
}

/*
 * GLES: the same sequences through the GLES headlight pass (rows uploaded again, terms
 * redrawn): each frame within test_renderer's GLES-vs-CPU tolerance of the fresh CPU frame,
 * and bit for bit the frame of a GLES renderer made fresh on that G-buffer.
 */
static void dynamic_gles_frames_match(void **state)
{
	struct hl_gbuffer *live = NULL;
	float *lux = malloc(sizeof(float) * N_PIX), *fresh = malloc(sizeof(float) * N_PIX);
	double worst = 0.0;

	(void)state;
	assert_non_null(ref[ROAD]);
	assert_int_equal(hl_gbuffer_new(W, H, &live), 0);
	for (size_t q = 0; q < N_SEQUENCES; q++) {
		struct hl_renderer_config cfg;
		struct hl_renderer *r = NULL;

		copy_gbuffer(live, gbs[sequences[q][0]]);
		config(&cfg, HL_BACKEND_GLES, q & 1, 2);
		assert_int_equal(hl_renderer_new(&cfg, live, &r), 0);
		assert_int_equal(hl_renderer_headlight_backend(r), HL_BACKEND_GLES);
		set_high(r);
		assert_int_equal(hl_renderer_frame(r, lux), 0);
		for (int s = 1; sequences[q][s] >= 0; s++) {
			const int scene = sequences[q][s];
			double peak = 0.0;

			copy_gbuffer(live, gbs[scene]);
			assert_int_equal(hl_renderer_set_gbuffer(r, live), 0);
			assert_int_equal(hl_renderer_frame(r, lux), 0);
			fresh_frame(gbs[scene], HL_BACKEND_GLES, fresh);
			assert_memory_equal(lux, fresh, sizeof(float) * N_PIX);
			for (int i = 0; i < N_PIX; i++)
				peak = ref[scene][i] > peak ? ref[scene][i] : peak;
			for (int i = 0; i < N_PIX; i++) {
				const double e = fabs(lux[i] - ref[scene][i]) /
						 (1e-3 * peak + ref[scene][i]);

				worst = e > worst ? e : worst;
			}
		}
		hl_renderer_free(r);
	}
	printf("GLES moving frames: max rel. difference to fresh CPU frames %.2e\n", worst);
	assert_true(worst < 5e-3);
	hl_gbuffer_free(live);
	free(lux);
	free(fresh);
}

/* A fill (hl_renderer_fill_fn) that copies src's pixels and says which changed, by the rule. */
struct fill_src {
	const struct hl_gbuffer *src;
	size_t filled; /* pixels filled this frame (atomic: several threads) */
};

static void fill_copy(void *userdata, struct hl_gbuffer *gb, size_t first, size_t count,
		      uint8_t *changed)
{
	struct fill_src *f = userdata;

	for (size_t i = first; i < first + count; i++) {
		const bool had = gb->nrm[4 * i + 3] != (float)HL_SURF_NONE;
		const bool has = f->src->nrm[4 * i + 3] != (float)HL_SURF_NONE;
		const bool moved = memcmp(gb->pos + 4 * i, f->src->pos + 4 * i, 12) != 0 ||
				   memcmp(gb->nrm + 4 * i, f->src->nrm + 4 * i, 12) != 0;

		changed[i] = had != has || (has && moved);
		memcpy(gb->pos + 4 * i, f->src->pos + 4 * i, sizeof(float) * 4);
		memcpy(gb->nrm + 4 * i, f->src->nrm + 4 * i, sizeof(float) * 4);
		gb->albedo[i] = f->src->albedo[i];
	}
	__atomic_fetch_add(&f->filled, count, __ATOMIC_RELAXED);
}

/*
 * hl_renderer_set_gbuffer_fill: the renderer fills the G-buffer band by band on its threads
 * and relights what the fill says changed. Frames equal fresh renderers (CPU bit for bit; GLES
 * bit for bit against fresh GLES), with fills and plain hand-overs mixed (the diff's copy is
 * then stale and must not be trusted; with fill_only it never held anything) and a fill into another G-buffer object (everything
 * relit); every pixel is filled exactly once per frame.
 */
static void dynamic_fill_frames_equal_fresh_renderers(void **state)
{
	struct hl_gbuffer *live = NULL, *other = NULL;
	float *lux = malloc(sizeof(float) * N_PIX), *fresh = malloc(sizeof(float) * N_PIX);
	size_t frames = 0;

	(void)state;
	assert_non_null(ref[ROAD]);
	assert_int_equal(hl_gbuffer_new(W, H, &live), 0);
	assert_int_equal(hl_gbuffer_new(W, H, &other), 0);
	for (size_t q = 0; q < N_SEQUENCES; q++) {
		/* CPU moving, CPU not moving on 2 threads, GLES moving, CPU fill_only on 2 */
		for (int v = 0; v < 4; v++) {
			const enum hl_backend light = v == 2 ? HL_BACKEND_GLES : HL_BACKEND_CPU;
			struct hl_renderer_config cfg;
			struct hl_renderer *r = NULL;

			copy_gbuffer(live, gbs[sequences[q][0]]);
			config(&cfg, light, v != 1, 1 + (v & 1));
			cfg.fill_only = v == 3;
			assert_int_equal(hl_renderer_new(&cfg, live, &r), 0);
			assert_int_equal(hl_renderer_set_gbuffer_fill(r, live, NULL, NULL),
					 -EINVAL);
			set_high(r);
			assert_int_equal(hl_renderer_frame(r, lux), 0);
			for (int s = 1; sequences[q][s] >= 0; s++) {
				const int scene = sequences[q][s];
				struct fill_src f = { gbs[scene], 0 };
				/*
				 * step 3 (with fill_only step 1, before any fill) hands a plain
				 * G-buffer, step 4 fills another object, step 5 live again: both
				 * relight everything
				 */
				const int plain = v == 3 ? 1 : 3;
				struct hl_gbuffer *gb = s == 4 ? other : live;

				if (s == plain) {
					copy_gbuffer(live, gbs[scene]);
					assert_int_equal(hl_renderer_set_gbuffer(r, live), 0);
				} else {
					assert_int_equal(
						hl_renderer_set_gbuffer_fill(r, gb, fill_copy, &f),
						0);
				}
				assert_int_equal(hl_renderer_frame(r, lux), 0);
				if (s != plain)
					assert_int_equal(f.filled, N_PIX);
				expect_fresh(light, scene, lux, fresh);
				frames++;
			}
			hl_renderer_free(r);
		}
	}
	printf("%zu filled frames equal fresh renderers\n", frames);
	hl_gbuffer_free(live);
	hl_gbuffer_free(other);
	free(lux);
	free(fresh);
}

/*
 * What hdlampd does before the first cycle of a moving scenario (daemon/pipeline.c's warm-up):
 * a frame with the lamps dark filled from one scene, then the lamps on and a fill from
 * another. The dark frame lights nothing, and the lit one equals a fresh renderer's frame of
 * its scene (CPU with fill_only on 2 threads and moving on 1, bit for bit; GLES against fresh
 * GLES).
 */
static void dynamic_dark_warm_up_frame_then_lit_frame_equals_fresh(void **state)
{
	struct hl_gbuffer *live = NULL;
	float *lux = malloc(sizeof(float) * N_PIX), *fresh = malloc(sizeof(float) * N_PIX);

	(void)state;
	assert_non_null(ref[ROAD_CARS_MOVED]);
	assert_int_equal(hl_gbuffer_new(W, H, &live), 0);
	for (int v = 0; v < 3; v++) {
		const enum hl_backend light = v == 2 ? HL_BACKEND_GLES : HL_BACKEND_CPU;
		struct fill_src warm = { gbs[ROAD_CARS], 0 }, lit = { gbs[ROAD_CARS_MOVED], 0 };
		struct hl_renderer_config cfg;
		struct hl_renderer *r = NULL;

		copy_gbuffer(live, gbs[ROAD]);
		config(&cfg, light, true, v == 1 ? 1 : 2);
		cfg.fill_only = v == 0;
		assert_int_equal(hl_renderer_new(&cfg, live, &r), 0);
		assert_int_equal(hl_renderer_set_gbuffer_fill(r, live, fill_copy, &warm), 0);
		assert_int_equal(hl_renderer_frame(r, lux), 0);
		assert_int_equal(warm.filled, N_PIX);
		for (size_t i = 0; i < N_PIX; i++)
			assert_true(lux[i] == 0.0f);
		set_high(r);
		assert_int_equal(hl_renderer_set_gbuffer_fill(r, live, fill_copy, &lit), 0);
		assert_int_equal(hl_renderer_frame(r, lux), 0);
		assert_int_equal(lit.filled, N_PIX);
		expect_fresh(light, ROAD_CARS_MOVED, lux, fresh);
		hl_renderer_free(r);
	}
	hl_gbuffer_free(live);
	free(lux);
	free(fresh);
}

/*
 * No frame of a moving scene allocates: with config moving from the start, without it after
 * the first hl_renderer_set_gbuffer() (which makes the room).
 */
static void dynamic_frames_allocate_nothing(void **state)
{
	static float lux[N_PIX];
	static struct seen seen;
	static const int seq[] = { ROAD_CARS, ROAD_CARS_MOVED, WALL_10, ROAD, ROAD };

	(void)state;
	for (int moving = 0; moving <= 1; moving++) {
		struct hl_renderer_config cfg;
		struct hl_renderer *r = NULL;

		config(&cfg, HL_BACKEND_CPU, moving, 2);
		assert_int_equal(hl_renderer_new(&cfg, gbs[ROAD], &r), 0);
		set_high(r);
		assert_int_equal(hl_renderer_frame(r, lux), 0);
		if (!moving) {
			assert_int_equal(hl_renderer_set_gbuffer(r, gbs[ROAD_CARS]), 0);
			assert_int_equal(hl_renderer_frame(r, lux), 0);
		}
		allocs = 0;
		for (size_t s = 0; s < sizeof(seq) / sizeof(seq[0]); s++) {
			assert_int_equal(hl_renderer_set_gbuffer(r, gbs[seq[s]]), 0);
			if (s & 1)
				assert_int_equal(hl_renderer_frame_pixels(r, lux, record, &seen),
						 0);
			else
				assert_int_equal(hl_renderer_frame(r, lux), 0);
		}
		if (HL_COUNT_ALLOCS)
			assert_int_equal(allocs, 0);
		allocs = -1;
		assert_memory_equal(lux, ref[ROAD], sizeof(float) * N_PIX);
		hl_renderer_free(r);
	}
}

static void dynamic_set_gbuffer_checks_the_size(void **state)
{
	struct hl_renderer_config cfg;
	struct hl_renderer *r = NULL;
	struct hl_gbuffer *other = NULL;
	static float lux[N_PIX];

	(void)state;
	config(&cfg, HL_BACKEND_CPU, false, 1);
	assert_int_equal(hl_renderer_new(&cfg, gbs[ROAD], &r), 0);
	assert_int_equal(hl_gbuffer_new(W, H - 1, &other), 0);
	assert_int_equal(hl_renderer_set_gbuffer(r, other), -EINVAL);
	assert_int_equal(hl_renderer_set_gbuffer(r, NULL), -EINVAL);
	/* refused: the next frame still lights the road */
	set_high(r);
	assert_int_equal(hl_renderer_frame(r, lux), 0);
	assert_memory_equal(lux, ref[ROAD], sizeof(float) * N_PIX);
	hl_gbuffer_free(other);
	hl_renderer_free(r);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(dynamic_references_differ_where_the_scenes_do),
		cmocka_unit_test(dynamic_cpu_frames_equal_fresh_renderers),
		cmocka_unit_test(dynamic_headlight_update_keeps_the_work_count),
		cmocka_unit_test(dynamic_gles_frames_match),
		cmocka_unit_test(dynamic_fill_frames_equal_fresh_renderers),
		cmocka_unit_test(dynamic_dark_warm_up_frame_then_lit_frame_equals_fresh),
		cmocka_unit_test(dynamic_frames_allocate_nothing),
		cmocka_unit_test(dynamic_set_gbuffer_checks_the_size),
	};

	return cmocka_run_group_tests(tests, setup, teardown);
}
