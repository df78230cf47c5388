/* SPDX-License-Identifier: MIT */
/* Scenes, the camera and the lamp poses: exact geometry of the built-in scenes. */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "world/camera.h"
#include "render/scene.h"

static void default_poses(struct hl_lamp_pose poses[2])
{
	hl_lamp_pose_default(0, &poses[0]);
	hl_lamp_pose_default(1, &poses[1]);
}

static void lamp_default_poses_are_left_right_and_one_percent_down(void **state)
{
	struct hl_lamp_pose p[2];
	double x[3], y[3], z[3], l[3];
	const double far[3] = { 100.0, 0.7, 0.65 - 1.0 };

	(void)state;
	default_poses(p);
	assert_float_equal(p[0].pos_m[1], 0.7, 1e-12);
	assert_float_equal(p[1].pos_m[1], -0.7, 1e-12);
	assert_float_equal(p[0].pos_m[2], 0.65, 1e-12);
	hl_lamp_basis(&p[0], x, y, z);
	/* The axis drops 1 m in 100 m; lamp x is the vehicle's right (-y). */
	assert_float_equal(z[2] / z[0], -0.01, 1e-12);
	assert_float_equal(x[1], -1.0, 1e-12);
	assert_true(y[2] > 0.99);
	hl_lamp_to_lamp_space(&p[0], far, l);
	assert_float_equal(l[0], 0.0, 1e-9);
	assert_float_equal(l[1], 0.0, 1e-9);
	/* A point to the vehicle's right is at lamp +x. */
	{
		const double right[3] = { 10.0, -5.0, 0.65 };

		hl_lamp_to_lamp_space(&p[0], right, l);
		assert_true(l[0] > 5.0);
	}
}

static void camera_ray_and_project_are_inverse(void **state)
{
	struct hl_camera cam = { .pos_m = { -1.8, 0.37, 1.2 },
				 .dir = { 1, 0.1, -0.05 },
				 .up = { 0, 0, 1 },
				 .fov_y_deg = 40.0,
				 .width = 64,
				 .height = 36 };
	double d[3], p[3], x, y;

	(void)state;
	hl_camera_ray(&cam, 10.25, 30.5, d);
	for (int i = 0; i < 3; i++)
		p[i] = cam.pos_m[i] + 7.0 * d[i];
	assert_int_equal(hl_camera_project(&cam, p, &x, &y), 0);
	assert_float_equal(x, 10.25, 1e-9);
	assert_float_equal(y, 30.5, 1e-9);
	for (int i = 0; i < 3; i++)
		p[i] = cam.pos_m[i] - d[i];
	assert_int_equal(hl_camera_project(&cam, p, &x, &y), -EDOM);
}

/* worldToCamera / worldToNDC as OpenEXR defines them (row vectors): NDC (0,0) top left. */
static void camera_exr_matrices_map_points_to_pixels(void **state)
{
	struct hl_camera cam = { .pos_m = { 1, 2, 3 },
				 .dir = { 1, -1, 0.2 },
				 .up = { 0, 0, 1 },
				 .fov_y_deg = 50.0,
				 .width = 80,
				 .height = 40 };
	float wc[16], wn[16];
	double d[3], p[4], c[4] = { 0 }, n[4] = { 0 };

	(void)state;
	hl_camera_world_to_camera(&cam, wc);
	hl_camera_world_to_ndc(&cam, wn);
	hl_camera_ray(&cam, 20.0, 30.0, d);
	for (int i = 0; i < 3; i++)
		p[i] = cam.pos_m[i] + 3.0 * d[i];
	p[3] = 1.0;
	for (int j = 0; j < 4; j++)
		for (int i = 0; i < 4; i++) {
			c[j] += p[i] * wc[i * 4 + j];
			n[j] += p[i] * wn[i * 4 + j];
		}
	/* Camera space: +z the viewing direction, distance along it 3 * |fwd component| = 3. */
	assert_float_equal(c[2], 3.0, 1e-5);
	assert_true(c[0] < 0.0); /* left half of the image */
	assert_true(c[1] < 0.0); /* lower half */
	assert_float_equal(n[0] / n[3], 20.0 / 80.0, 1e-5);
	assert_float_equal(n[1] / n[3], 30.0 / 40.0, 1e-5);
}

static void scene_sphere_is_centred_on_the_left_lamp(void **state)
{
	struct hl_lamp_pose p[2];
	struct hl_scene s;
	const double d[3] = { 0.3, -0.5, 0.2 };
	float pos[4], nrm[4];

	(void)state;
	default_poses(p);
	hl_scene_init(&s, HL_SCENE_SPHERE, p);
	assert_int_equal(hl_scene_cast(&s, p[0].pos_m, d, pos, nrm), HL_SURF_SPHERE);
	{
		const double dx = pos[0] - p[0].pos_m[0], dy = pos[1] - p[0].pos_m[1],
			     dz = pos[2] - p[0].pos_m[2];
		const double r = sqrt(dx * dx + dy * dy + dz * dz);

		assert_float_equal(r, 10.0, 1e-5);
		/* The normal points back at the lamp. */
		assert_float_equal(nrm[0], -dx / r, 1e-6);
		assert_float_equal(nrm[2], -dz / r, 1e-6);
	}
	assert_float_equal(pos[3], 0.5, 1e-6);
}

static void scene_wall_screen_at_its_distance(void **state)
{
	struct hl_lamp_pose p[2];
	struct hl_scene s;
	const double o[3] = { 0.0, 0.0, 1.0 }, ahead[3] = { 1.0, 0.02, 0.01 },
		     down[3] = { 1.0, 0.0, -0.2 };
	float pos[4], nrm[4];
	int id;

	(void)state;
	default_poses(p);
	hl_scene_init(&s, HL_SCENE_WALL, p);
	s.wall_distance_m = 10.0;
	id = hl_scene_cast(&s, o, ahead, pos, nrm);
	assert_true(id == HL_SURF_WALL || id == HL_SURF_WALL_LINE);
	assert_float_equal(pos[0], 10.0, 1e-5);
	assert_float_equal(nrm[0], -1.0, 0.0);
	assert_int_equal(hl_scene_cast(&s, o, down, pos, nrm), HL_SURF_ROAD);
	assert_float_equal(pos[0], 5.0, 1e-5);
	assert_float_equal(pos[2], 0.0, 0.0);
	assert_int_equal(hl_scene_from_name("wall"), HL_SCENE_WALL);
	assert_int_equal(hl_scene_from_name("moon"), -EINVAL);
}

static void scene_road_has_markings_and_posts(void **state)
{
	struct hl_lamp_pose p[2];
	struct hl_scene s;
	float pos[4], nrm[4];
	const double eye[3] = { 0.0, 0.0, 1.0 };
	/* Down onto the left edge line at x = 20 (y = 3.35), onto the lane (y = 1.7). */
	const double to_edge[3] = { 20.0, 3.35, -1.0 }, to_lane[3] = { 20.0, 1.7, -1.0 };
	/* A post at x = 30, y = -4.25, half a metre up. */
	const double to_post[3] = { 30.0, -4.25, -0.5 };
	/* Beyond the 140 m road: nothing. */
	const double to_far[3] = { 200.0, 0.0, -1.0 };

	(void)state;
	default_poses(p);
	hl_scene_init(&s, HL_SCENE_ROAD, p);
	assert_int_equal(hl_scene_cast(&s, eye, to_edge, pos, nrm), HL_SURF_MARKING);
	assert_int_equal(hl_scene_cast(&s, eye, to_lane, pos, nrm), HL_SURF_ROAD);
	assert_int_equal(hl_scene_cast(&s, eye, to_post, pos, nrm), HL_SURF_POST);
	assert_float_equal(nrm[0], -1.0, 0.0); /* the face towards the vehicle */
	assert_float_equal(pos[0], 30.0 - 0.06, 1e-4);
	assert_int_equal(hl_scene_cast(&s, eye, to_far, pos, nrm), HL_SURF_NONE);
	assert_float_equal(pos[3], 0.0, 0.0);
}

static void scene_render_checks_size_and_fills_albedo(void **state)
{
	struct hl_lamp_pose p[2];
	struct hl_scene s;
	struct hl_camera cam;
	struct hl_gbuffer *gb;
	int sky = 0, ground = 0;

	(void)state;
	default_poses(p);
	hl_scene_init(&s, HL_SCENE_ROAD, p);
	hl_scene_default_camera(&s, 32, 18, &cam);
	assert_int_equal(hl_gbuffer_new(32, 18, &gb), 0);
	assert_int_equal(hl_scene_render(&s, &cam, gb), 0);
	for (int i = 0; i < 32 * 18; i++) {
		assert_float_equal(gb->albedo[i], gb->pos[4 * i + 3], 0.0);
		sky += gb->nrm[4 * i + 3] == HL_SURF_NONE;
		ground += gb->nrm[4 * i + 3] != HL_SURF_NONE;
	}
	/* Top row: sky; bottom row: road. */
	assert_float_equal(gb->nrm[3], HL_SURF_NONE, 0.0);
	assert_float_equal(gb->nrm[4 * (17 * 32 + 16) + 3], HL_SURF_ROAD, 0.0);
	assert_true(sky > 50 && ground > 50);
	cam.width = 31;
	assert_int_equal(hl_scene_render(&s, &cam, gb), -EINVAL);
	hl_gbuffer_free(gb);
	hl_gbuffer_free(NULL);
	assert_int_equal(hl_gbuffer_new(0, 5, &gb), -EINVAL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(lamp_default_poses_are_left_right_and_one_percent_down),
		cmocka_unit_test(camera_ray_and_project_are_inverse),
		cmocka_unit_test(camera_exr_matrices_map_points_to_pixels),
		cmocka_unit_test(scene_sphere_is_centred_on_the_left_lamp),
		cmocka_unit_test(scene_wall_screen_at_its_distance),
		cmocka_unit_test(scene_road_has_markings_and_posts),
		cmocka_unit_test(scene_render_checks_size_and_fills_albedo),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
