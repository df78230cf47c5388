/* SPDX-License-Identifier: MIT */
/*
 * The scenes as triangles (render/scene_mesh.c) against the analytic caster they follow: rays
 * from visible points of each scene (as sensors cast them) and from its camera hit the same
 * surface with the same albedo at the same place, through the mesh and through hl_scene_cast.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

#include "render/hemicube.h"
#include "render/scene.h"
#include "render/scene_mesh.h"
#include "render/sensor.h"

/* A fixed pseudo-random sequence in [0, 1). */
static double next(uint64_t *s)
{
	*s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
	return (double)(*s >> 11) / 9007199254740992.0;
}

struct tally {
	double tol_rel; /* position tolerance, relative to the distance */
	size_t rays, hits, id_mismatch, far_off, cut;
	double worst_m;
};

static void cast_both(const struct hl_scene *s, const struct hl_scene_mesh *m, const double o[3],
		      const double d[3], struct tally *t)
{
	float pa[4], na[4], pm[4], nm[4];
	const enum hl_surface a = hl_scene_cast(s, o, d, pa, na);
	const enum hl_surface b = hl_scene_mesh_cast(m, o, d, pm, nm);
	double dist = 0.0, range = 0.0;

	t->rays++;
	/* Unlit ground behind the lamps that the mesh leaves out: the same black as the sky. */
	if (a != HL_SURF_NONE && b == HL_SURF_NONE && pa[0] < HL_SCENE_MESH_BACK_M) {
		t->cut++;
		return;
	}
	if (a != b || pa[3] != pm[3]) {
		if (t->id_mismatch < 5)
			printf("  o (%.3f, %.3f, %.3f) d (%.4f, %.4f, %.4f): caster %d (%.3f, %.3f, "
			       "%.3f), mesh %d (%.3f, %.3f, %.3f)\n",
			       o[0], o[1], o[2], d[0], d[1], d[2], a, pa[0], pa[1], pa[2], b, pm[0],
			       pm[1], pm[2]);
		t->id_mismatch++;
		return;
	}
	if (a == HL_SURF_NONE)
		return;
	t->hits++;
	for (int k = 0; k < 3; k++) {
		dist += ((double)pa[k] - pm[k]) * ((double)pa[k] - pm[k]);
		range += ((double)pa[k] - o[k]) * ((double)pa[k] - o[k]);
	}
	dist = sqrt(dist);
	/* Float positions: a few ulps of the coordinates, or the sphere's chords. */
	if (dist > 1e-3 + t->tol_rel * sqrt(range))
		t->far_off++;
	t->worst_m = fmax(t->worst_m, dist);
}

static void check_scene(enum hl_scene_kind kind, double wall_distance_m, double tol_rel,
			double max_far)
{
	const int w = 48, h = 27;
	struct hl_lamp_pose poses[2];
	struct hl_scene scene;
	struct hl_camera cam;
	struct hl_gbuffer *gb;
	struct hl_scene_mesh *m;
	struct tally t = { .tol_rel = tol_rel };
	uint64_t seed = 12345 + kind;
	size_t n_points = 0;

	hl_lamp_pose_default(0, &poses[0]);
	hl_lamp_pose_default(1, &poses[1]);
	hl_scene_init(&scene, kind, poses);
	scene.wall_distance_m = wall_distance_m;
	hl_scene_default_camera(&scene, w, h, &cam);
	assert_int_equal(hl_gbuffer_new(w, h, &gb), 0);
	assert_int_equal(hl_scene_render(&scene, &cam, gb), 0);
	assert_int_equal(hl_scene_mesh_new(&scene, &m), 0);
	assert_true(m->n_vertices > 0 && m->n_vertices % 3 == 0);
	/* The camera's own rays. */
	for (int row = 0; row < h; row++)
		for (int col = 0; col < w; col++) {
			double d[3];

			hl_camera_ray(&cam, col + 0.5, row + 0.5, d);
			cast_both(&scene, m, cam.pos_m, d, &t);
		}
	/* From visible points, as sensors look: 40 directions over each point's hemisphere. */
	for (size_t i = 0; i < (size_t)w * h; i += 3) {
		const float *p = gb->pos + 4 * i, *n = gb->nrm + 4 * i;
		double nn[3], tt[3], bb[3], o[3];

		if (n[3] == (float)HL_SURF_NONE)
			continue;
		n_points++;
		for (int k = 0; k < 3; k++) {
			nn[k] = n[k];
			o[k] = p[k] + HL_SENSOR_OFFSET_M * n[k];
		}
		hl_hemicube_frame(nn, tt, bb);
		for (int r = 0; r < 40; r++) {
			/* Cosine-distributed, as the sensor's weights are. */
			const double u = next(&seed), phi = 2 * M_PI * next(&seed);
			const double st = sqrt(u), ct = sqrt(1.0 - u);
			double d[3];

			for (int k = 0; k < 3; k++)
				d[k] = st * cos(phi) * tt[k] + st * sin(phi) * bb[k] + ct * nn[k];
			cast_both(&scene, m, o, d, &t);
		}
	}
	printf("%s: %zu triangles; %zu rays (%zu sensor points), %zu hits: %zu disagree on the "
	       "surface, %zu hit it elsewhere (> 1 mm + %g of the distance), %zu on the ground "
	       "behind x = %g m; largest distance %.2e m\n",
	       hl_scene_name(kind), m->n_vertices / 3, t.rays, n_points, t.hits, t.id_mismatch,
	       t.far_off, tol_rel, t.cut, HL_SCENE_MESH_BACK_M, t.worst_m);
	assert_true(n_points > 100);
	assert_true(t.hits > 500);
	/* Edges of paint and of objects are exact; a ray grazing an edge may fall either side. */
	assert_true(t.id_mismatch * 1000 <= t.rays);
	assert_true(t.far_off <= max_far * t.rays);
	hl_scene_mesh_free(m);
	hl_gbuffer_free(gb);
}

static void scene_mesh_road_matches_caster(void **state)
{
	(void)state;
	check_scene(HL_SCENE_ROAD, HL_WALL_DISTANCE_M, 1e-5, 1e-3);
}

static void scene_mesh_bird_matches_caster(void **state)
{
	(void)state;
	check_scene(HL_SCENE_BIRD, HL_WALL_DISTANCE_M, 1e-5, 1e-3);
}

static void scene_mesh_wall_matches_caster(void **state)
{
	(void)state;
	check_scene(HL_SCENE_WALL, HL_WALL_DISTANCE_M, 1e-5, 1e-3);
	check_scene(HL_SCENE_WALL, 10.0, 1e-5, 1e-3);
}

static void scene_mesh_bounce_matches_caster(void **state)
{
	(void)state;
	check_scene(HL_SCENE_BOUNCE, HL_WALL_DISTANCE_M, 1e-5, 1e-3);
}

static void scene_mesh_sphere_matches_caster(void **state)
{
	(void)state;
	/*
	 * Chords: along a grazing ray the hit moves by the sagitta (12 mm) over the grazing angle;
	 * 1 in 50 rays from points on the sphere may land more than 5 % of their length away.
	 */
	check_scene(HL_SCENE_SPHERE, HL_WALL_DISTANCE_M, 0.05, 0.02);
}

static void scene_mesh_empty_hits_nothing(void **state)
{
	struct hl_scene_mesh *m;
	const double o[3] = { 0, 0, 1 }, d[3] = { 0, 0, -1 };
	float p[4], n[4];

	(void)state;
	assert_int_equal(hl_scene_mesh_new_empty(&m), 0);
	assert_int_equal(m->n_vertices, 0);
	assert_int_equal(hl_scene_mesh_cast(m, o, d, p, n), HL_SURF_NONE);
	hl_scene_mesh_free(m);
	hl_scene_mesh_free(NULL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(scene_mesh_road_matches_caster),
		cmocka_unit_test(scene_mesh_bird_matches_caster),
		cmocka_unit_test(scene_mesh_wall_matches_caster),
		cmocka_unit_test(scene_mesh_bounce_matches_caster),
		cmocka_unit_test(scene_mesh_sphere_matches_caster),
		cmocka_unit_test(scene_mesh_empty_hits_nothing),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
