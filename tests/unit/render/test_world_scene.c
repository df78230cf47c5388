/* SPDX-License-Identifier: MIT */
/*
 * render/world_scene.c (and hl_road_project() of world/road.c): road coordinates
 * against closed forms within 1 mm; a pixel's ray meets a road user's box where the test
 * intersects it; the standing ego on the shipped straight IIHS-like scenario sees road,
 * markings and shoulder where the test computes them; lamps face the right way and hide behind
 * bodies; nothing is allocated per frame.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "alloc_count.h"
#include "render/gbuffer_diff.h"
#include "world/scenario.h"
#include "world/road.h"
#include "render/scene.h"
#include "world/world.h"
#include "render/world_scene.h"

#define MM 1e-3

static struct hl_scenario *load(const char *text)
{
	struct hl_scenario *sc = NULL;
	struct hl_json_error err;
	char buf[1024];

	if (hl_scenario_parse(text, "world.json", &sc, &err) < 0)
		fail_msg("%s", hl_json_error_format(&err, buf, sizeof(buf)));
	return sc;
}

/* The shipped scenario NAME (scenarios/), and its driver's camera at w x h. */
static struct hl_scenario *shipped(const char *name, int w, int h, struct hl_camera *cam)
{
	struct hl_scenario *sc = NULL;
	struct hl_json_error err;
	char path[4096], buf[1024];

	snprintf(path, sizeof(path), "%s/scenarios/%s", getenv("HL_SOURCE_DIR"), name);
	if (hl_scenario_read(path, &sc, &err) < 0)
		fail_msg("%s", hl_json_error_format(&err, buf, sizeof(buf)));
	*cam = sc->ego.camera;
	cam->width = w;
	cam->height = h;
	return sc;
}

static void project_near(const struct hl_road *road, double x, double y, double s, double d)
{
	double gs, gd;

	hl_road_project(road, x, y, &gs, &gd);
	if (!(fabs(gs - s) <= MM && fabs(gd - d) <= MM))
		fail_msg("(%.4f, %.4f): got s %.6f d %.6f, want s %.6f d %.6f", x, y, gs, gd, s, d);
}

/* A 250 m arc from the origin along +x: (s, d) from the angle about the centre (0, ±250). */
static void road_project_250m_arc(void **state)
{
	(void)state;
	static const char *const turns[] = { "left", "right" };
	const double R = 250.0;
	char text[512];

	for (int k = 0; k < 2; k++) {
		const double sign = k ? -1.0 : 1.0;
		struct hl_scenario *sc;

		snprintf(text, sizeof(text),
			 "{\"version\": 1, \"duration_s\": 1, \"road\": {\"segments\": [{\"kind\": "
			 "\"arc\", \"length_m\": 400, \"radius_m\": 250, \"turn\": \"%s\"}]}}",
			 turns[k]);
		sc = load(text);
		for (double s = 0.0; s <= 400.0; s += 7.3)
			for (double d = -12.0; d <= 12.0; d += 2.4) {
				const double phi = s / R, r = R - sign * d;

				project_near(&sc->road, r * sin(phi), sign * (R - r * cos(phi)), s,
					     d);
			}
		/* And the other way round: the closed form of a point's (s, d). */
		for (double x = 5.0; x < 200.0; x += 13.0)
			for (double y = -8.0; y <= 8.0; y += 4.0) {
				const double cy = sign * R, vx = x, vy = y - cy;
				const double r = hypot(vx, vy);
				const double s = R * atan2(vx, -sign * vy);

				project_near(&sc->road, x, y, s, sign * (R - r));
			}
		hl_scenario_free(sc);
	}
}

/* 50 m straight, a 250 m left arc over 100 m, 80 m straight; and the run-on beyond the ends. */
static void road_project_straight_arc_straight(void **state)
{
	(void)state;
	static const char text[] =
		"{\"version\": 1, \"duration_s\": 1, \"road\": {\"segments\": ["
		"{\"kind\": \"straight\", \"length_m\": 50},"
		"{\"kind\": \"arc\", \"length_m\": 100, \"radius_m\": 250, \"turn\": \"left\"},"
		"{\"kind\": \"straight\", \"length_m\": 80}]}}";
	struct hl_scenario *sc = load(text);
	const double R = 250.0, th = 100.0 / R;
	const double ex = 50.0 + R * sin(th), ey = R - R * cos(th);

	for (double s = -30.0; s <= 290.0; s += 3.7)
		for (double d = -9.0; d <= 9.0; d += 1.5) {
			double x, y;

			if (s <= 50.0) {
				x = s;
				y = d;
			} else if (s <= 150.0) {
				const double phi = (s - 50.0) / R;

				x = 50.0 + (R - d) * sin(phi);
				y = R - (R - d) * cos(phi);
			} else {
				x = ex + (s - 150.0) * cos(th) - d * sin(th);
				y = ey + (s - 150.0) * sin(th) + d * cos(th);
			}
			project_near(&sc->road, x, y, s, d);
		}
	hl_scenario_free(sc);
}

/* Ego standing in lane 2 at s = 0; oncoming cars standing in lane 2 at s = 30 and 60. */
static const char two_cars[] = "{\"version\": 1, \"duration_s\": 10, \"road\": {\"segments\": ["
			       "{\"kind\": \"straight\", \"length_m\": 400}]},"
			       "\"ego\": {\"lane\": 2},"
			       "\"actors\": ["
			       "{\"id\": \"near\", \"kind\": \"car\", \"role\": \"oncoming\","
			       " \"path\": {\"lane\": 2, \"start_s_m\": 30, \"speed_mps\": 0}},"
			       "{\"id\": \"far\", \"kind\": \"car\", \"role\": \"oncoming\","
			       " \"path\": {\"lane\": 2, \"start_s_m\": 60, \"speed_mps\": 0}}]}";

static void ray_hits_actor_box(void **state)
{
	(void)state;
	struct hl_scenario *sc = load(two_cars);
	struct hl_world_scene *ws;
	struct hl_gbuffer *gb;
	struct hl_world_state st;
	struct hl_camera cam = sc->ego.camera;
	/* The near car's front face is the plane x = 30 (ego frame), |y| <= 0.9, z in 0..1.45. */
	const double target[3] = { 30.0, 0.3, 0.7 };
	double px, py, d[3], t, p[3];
	int col, row;
	size_t i;

	cam.width = 320;
	cam.height = 180;
	assert_int_equal(hl_world_scene_new(sc, &ws), 0);
	assert_int_equal(hl_gbuffer_new(320, 180, &gb), 0);
	hl_world_at(sc, 0.0, &st);
	assert_int_equal(hl_world_scene_render(ws, &st, &cam, gb), 0);
	assert_int_equal(hl_camera_project(&cam, target, &px, &py), 0);
	col = (int)floor(px);
	row = (int)floor(py);
	hl_camera_ray(&cam, col + 0.5, row + 0.5, d);
	t = (30.0 - cam.pos_m[0]) / d[0];
	for (int k = 0; k < 3; k++)
		p[k] = cam.pos_m[k] + t * d[k];
	assert_true(fabs(p[1]) < 0.9 && p[2] > 0.0 && p[2] < 1.45);
	i = (size_t)row * 320 + col;
	assert_int_equal((int)gb->nrm[4 * i + 3], HL_SURF_VEHICLE);
	for (int k = 0; k < 3; k++)
		assert_true(fabs(gb->pos[4 * i + k] - p[k]) <= MM);
	assert_float_equal(gb->nrm[4 * i + 0], -1.0, 1e-6);
	assert_float_equal(gb->nrm[4 * i + 1], 0.0, 1e-6);
	assert_float_equal(gb->nrm[4 * i + 2], 0.0, 1e-6);
	assert_float_equal(gb->albedo[i], 0.3, 1e-6);
	assert_float_equal(gb->pos[4 * i + 3], 0.3, 1e-6);
	assert_int_equal(hl_world_scene_objects_dropped(ws), 0);
	hl_gbuffer_free(gb);
	hl_world_scene_free(ws);
	hl_scenario_free(sc);
}

static void emitters_face_and_hide(void **state)
{
	(void)state;
	struct hl_scenario *sc = load(two_cars);
	struct hl_world_scene *ws;
	struct hl_world_state st;
	struct hl_camera cam = sc->ego.camera;
	struct hl_world_emitter e[16];
	int n;

	cam.width = 320;
	cam.height = 180;
	assert_int_equal(hl_world_scene_new(sc, &ws), 0);
	hl_world_at(sc, 0.0, &st);
	n = hl_world_scene_emitters(ws, &st, &cam, e, 16);
	assert_int_equal(n, 8);
	for (int k = 0; k < n; k++) {
		/* Car 0: headlamps (0, 1) face the ego, tail lamps (2, 3) away; car 1 hidden. */
		const bool want = e[k].actor == 0 && e[k].lamp < 2;
		double w[3], p[3], x, y;

		assert_int_equal(e[k].actor, k / 4);
		assert_int_equal(e[k].lamp, k % 4);
		if (e[k].visible != want)
			fail_msg("actor %d lamp %d: visible %d, want %d", e[k].actor, e[k].lamp,
				 e[k].visible, want);
		hl_body_to_world(&st.actor[e[k].actor], sc->actor[e[k].actor].lamp[e[k].lamp].pos_m,
				 w);
		hl_world_to_ego(&st.ego, w, p);
		assert_int_equal(hl_camera_project(&cam, p, &x, &y), 0);
		assert_float_equal(e[k].x_px, x, 1e-6);
		assert_float_equal(e[k].y_px, y, 1e-6);
		{
			const double dx = p[0] - cam.pos_m[0], dy = p[1] - cam.pos_m[1];
			const double dz = p[2] - cam.pos_m[2];
			const double r2 = dx * dx + dy * dy + dz * dz;

			assert_float_equal(e[k].distance_m, sqrt(r2), 1e-9);
			assert_float_equal(e[k].illuminance_lx, want ? 350.0 / r2 : 0.0, 1e-12);
		}
	}
	/* Lamps off: nothing visible. */
	st.lamps_on = 0;
	n = hl_world_scene_emitters(ws, &st, &cam, e, 16);
	for (int k = 0; k < n; k++)
		assert_false(e[k].visible);
	hl_world_scene_free(ws);
	hl_scenario_free(sc);
}

/*
 * A car ahead in the ego's lane (seen from behind) with two lamps beside its body, where no
 * body hides them: the one shining forward (headlamp) is not seen, the one shining back (tail)
 * is.
 */
static void emitters_facing_without_occlusion(void **state)
{
	(void)state;
	static const char text[] =
		"{\"version\": 1, \"duration_s\": 10, \"road\": {\"segments\": ["
		"{\"kind\": \"straight\", \"length_m\": 400}]},"
		"\"actors\": [{\"id\": \"ahead\", \"kind\": \"car\", \"role\": \"preceding\","
		" \"path\": {\"lane\": 1, \"start_s_m\": 30, \"speed_mps\": 0},"
		" \"lamps\": [{\"kind\": \"headlamp\", \"pos_m\": [0, 1.5, 0.65], \"intensity_cd\": 100},"
		"  {\"kind\": \"tail\", \"pos_m\": [0, 1.5, 0.65], \"intensity_cd\": 100}]}]}";
	struct hl_scenario *sc = load(text);
	struct hl_world_scene *ws;
	struct hl_world_state st;
	struct hl_camera cam = sc->ego.camera;
	struct hl_world_emitter e[4];

	cam.width = 320;
	cam.height = 180;
	assert_int_equal(hl_world_scene_new(sc, &ws), 0);
	hl_world_at(sc, 0.0, &st);
	assert_int_equal(hl_world_scene_emitters(ws, &st, &cam, e, 4), 2);
	assert_false(e[0].visible);
	assert_true(e[1].visible);
	assert_float_equal(e[1].illuminance_lx, 100.0 / (e[1].distance_m * e[1].distance_m), 1e-12);
	hl_world_scene_free(ws);
	hl_scenario_free(sc);
}

/* The ground class of road coordinates on the default two-lane road, computed here. */
static int expected_ground(double s, double d, bool *ambiguous)
{
	const double ad = fabs(d);
	const double edge_lo = 3.5 - 0.15 - 0.075, edge_hi = 3.5 - 0.075;
	const double bounds[] = { 3.5, edge_lo, edge_hi, 0.06, -0.06, 40.0 };
	const double sm = s - 9.0 * floor(s / 9.0);

	*ambiguous = fabs(sm) < 1e-6 || fabs(sm - 3.0) < 1e-6 || fabs(sm - 9.0) < 1e-6;
	for (size_t i = 0; i < sizeof(bounds) / sizeof(bounds[0]); i++)
		*ambiguous = *ambiguous || fabs(ad - fabs(bounds[i])) < 1e-6;
	if (ad > 40.0)
		return HL_SURF_NONE;
	if (ad > 3.5)
		return HL_SURF_SHOULDER;
	if (ad >= edge_lo && ad <= edge_hi)
		return HL_SURF_MARKING;
	if (fabs(d) <= 0.06 && sm < 3.0)
		return HL_SURF_MARKING;
	return HL_SURF_ROAD;
}

static void straight_iihs_ground_and_markings(void **state)
{
	(void)state;
	struct hl_scenario *sc = NULL;
	struct hl_world_scene *ws;
	struct hl_gbuffer *gb;
	struct hl_world_state st;
	struct hl_camera cam;
	const int w = 640, h = 360;
	int counts[16] = { 0 }, checked = 0;

	sc = shipped("iihs-approach-straight.json", w, h, &cam);
	assert_int_equal(hl_world_scene_new(sc, &ws), 0);
	assert_int_equal(hl_gbuffer_new(w, h, &gb), 0);
	hl_world_at(sc, 0.0, &st);
	/* The ego stands at s = 50 in lane 1 (d = -1.75), heading along +x. */
	assert_float_equal(st.ego.s_m, 50.0, 1e-9);
	/* Two bands, as two threads would. */
	assert_int_equal(hl_world_scene_render_rows(ws, &st, &cam, gb, 0, 100), 0);
	assert_int_equal(hl_world_scene_render_rows(ws, &st, &cam, gb, 100, h - 100), 0);
	for (int row = 0; row < h; row++)
		for (int col = 0; col < w; col++) {
			const size_t i = (size_t)row * w + col;
			const int id = (int)gb->nrm[4 * i + 3];
			double d[3], t, x, y;
			bool amb;
			int want;

			hl_camera_ray(&cam, col + 0.5, row + 0.5, d);
			if (!(d[2] < 0.0)) {
				assert_int_equal(id, HL_SURF_NONE);
				continue;
			}
			t = -cam.pos_m[2] / d[2];
			x = cam.pos_m[0] + t * d[0];
			y = cam.pos_m[1] + t * d[1];
			want = expected_ground(50.0 + x, -1.75 + y, &amb);
			if (amb)
				continue;
			if (id == HL_SURF_POST || id == HL_SURF_VEHICLE) {
				/* In front of the ground. */
				assert_true(gb->pos[4 * i] < x);
				continue;
			}
			if (id != want)
				fail_msg("pixel (%d, %d): ground (%.3f, %.3f): id %d, want %d", col,
					 row, x, y, id, want);
			counts[id]++;
			checked++;
			if (want == HL_SURF_NONE)
				continue;
			assert_true(fabs(gb->pos[4 * i] - x) <= MM * fmax(1.0, t / 100));
			assert_true(fabs(gb->pos[4 * i + 1] - y) <= MM * fmax(1.0, t / 100));
			assert_true(gb->pos[4 * i + 2] == 0.0f);
			assert_true(gb->nrm[4 * i + 2] == 1.0f);
			assert_float_equal(gb->albedo[i],
					   want == HL_SURF_ROAD	   ? 0.12 :
					   want == HL_SURF_MARKING ? 0.6 :
								     0.07,
					   1e-6);
		}
	/* Not vacuous: every class seen in numbers. */
	assert_true(counts[HL_SURF_ROAD] > 10000);
	assert_true(counts[HL_SURF_MARKING] > 500);
	assert_true(counts[HL_SURF_SHOULDER] > 1000);
	assert_true(checked > w * h / 3);
	hl_gbuffer_free(gb);
	hl_world_scene_free(ws);
	hl_scenario_free(sc);
}

/*
 * The 250 m left curve (50 m straight, then the arc about (50, 250)) from the moving ego: every
 * ground pixel classed as the test computes from the ray's world point in closed form (runs of
 * one surface and the road's candidate parts are exact), at several instants.
 */
static void curve_ground_matches_closed_form(void **state)
{
	(void)state;
	struct hl_scenario *sc = NULL;
	struct hl_world_scene *ws;
	struct hl_gbuffer *gb;
	struct hl_world_state st;
	struct hl_camera cam;
	const int w = 640, h = 360;
	int counts[16] = { 0 }, checked = 0;

	sc = shipped("iihs-approach-curve-250m-left.json", w, h, &cam);
	assert_int_equal(hl_world_scene_new(sc, &ws), 0);
	assert_int_equal(hl_gbuffer_new(w, h, &gb), 0);
	for (double t = 0.0; t < 6.0; t += 1.9) {
		hl_world_at(sc, t, &st);
		assert_int_equal(hl_world_scene_render(ws, &st, &cam, gb), 0);
		for (int row = 0; row < h; row++)
			for (int col = 0; col < w; col++) {
				const size_t i = (size_t)row * w + col;
				const int id = (int)gb->nrm[4 * i + 3];
				const double hc = cos(st.ego.heading_rad),
					     hs = sin(st.ego.heading_rad);
				double d[3], tt, x, y, wx, wy, s_road, d_road, phi, r, d_str;
				bool amb;
				int want;

				hl_camera_ray(&cam, col + 0.5, row + 0.5, d);
				if (!(d[2] < 0.0) || id == HL_SURF_POST || id == HL_SURF_VEHICLE)
					continue;
				tt = -cam.pos_m[2] / d[2];
				x = cam.pos_m[0] + tt * d[0];
				y = cam.pos_m[1] + tt * d[1];
				wx = st.ego.pos_m[0] + x * hc - y * hs;
				wy = st.ego.pos_m[1] + x * hs + y * hc;
				/* the straight up to x = 50, the arc beyond (nearest part, closed form) */
				phi = atan2(wx - 50.0, 250.0 - wy);
				r = hypot(wx - 50.0, wy - 250.0);
				d_str = wx <= 50.0 ? fabs(wy) : hypot(wx - 50.0, wy);
				if (wx <= 50.0) {
					s_road = wx;
					d_road = wy;
				} else {
					s_road = 50.0 + 250.0 * phi;
					d_road = 250.0 - r;
				}
				/* near the junction, the arc's far end or a tie: not judged */
				if (fabs(wx - 50.0) < 0.5 || phi > 1.5 ||
				    (wx > 50.0 && fabs(d_str - fabs(d_road)) < 1e-3))
					continue;
				want = expected_ground(s_road, d_road, &amb);
				if (amb)
					continue;
				if (id != want)
					fail_msg(
						"t %.1f pixel (%d, %d): ground (%.3f, %.3f) s %.3f d "
						"%.3f: id %d, want %d",
						t, col, row, wx, wy, s_road, d_road, id, want);
				counts[id]++;
				checked++;
			}
	}
	/* Not vacuous: every class seen in numbers, most pixels judged. */
	assert_true(counts[HL_SURF_ROAD] > 30000);
	assert_true(counts[HL_SURF_MARKING] > 1500);
	assert_true(counts[HL_SURF_SHOULDER] > 3000);
	assert_true(checked > w * h);
	hl_gbuffer_free(gb);
	hl_world_scene_free(ws);
	hl_scenario_free(sc);
}

/* Also: hl_world_emitters_boxes() holds every pixel the lamps were drawn into. */
static void no_allocation_per_frame(void **state)
{
	(void)state;
	struct hl_scenario *sc = NULL;
	struct hl_world_scene *ws;
	struct hl_gbuffer *gb;
	struct hl_world_state st;
	struct hl_camera cam;
	struct hl_world_emitter e[32];
	int boxes[32][4];
	long drawn = 0;
	uint8_t *rgb = calloc(3 * 160 * 90, 1);

	sc = shipped("iihs-approach-curve-250m-left.json", 160, 90, &cam);
	assert_non_null(rgb);
	assert_int_equal(hl_world_scene_new(sc, &ws), 0);
	assert_int_equal(hl_gbuffer_new(160, 90, &gb), 0);
	allocs = 0;
	for (double t = 0.0; t < 6.0; t += 0.5) {
		int n, nb;

		hl_world_at(sc, t, &st);
		assert_int_equal(hl_world_scene_render_rows(ws, &st, &cam, gb, 0, 45), 0);
		assert_int_equal(hl_world_scene_render_rows(ws, &st, &cam, gb, 45, 45), 0);
		n = hl_world_scene_emitters(ws, &st, &cam, e, 32);
		/* on a black buffer: every pixel drawn lies in a box the boxes call names */
		memset(rgb, 0, 160 * 90 * 3);
		hl_world_emitters_draw(&cam, e, n, 0.0, rgb);
		nb = hl_world_emitters_boxes(&cam, e, n, 0.0, boxes, 32);
		for (int y = 0; y < 90; y++)
			for (int x = 0; x < 160; x++) {
				const uint8_t *px = rgb + 3 * (y * 160 + x);
				bool in = false;

				for (int k = 0; k < nb; k++)
					in |= x >= boxes[k][0] && x <= boxes[k][2] &&
					      y >= boxes[k][1] && y <= boxes[k][3];
				if ((px[0] | px[1] | px[2]) && !in)
					fail_msg("t %.1f: pixel %d,%d drawn outside every box", t,
						 x, y);
				drawn += (px[0] | px[1] | px[2]) != 0;
			}
	}
	assert_true(drawn > 0); /* the car's lamps were drawn at some time */
	if (HL_COUNT_ALLOCS)
		assert_int_equal(allocs, 0);
	allocs = -1;
	assert_int_equal(hl_world_scene_render_rows(ws, &st, &cam, gb, 80, 11), -EINVAL);
	free(rgb);
	hl_gbuffer_free(gb);
	hl_world_scene_free(ws);
	hl_scenario_free(sc);
}

/*
 * A raster's frames (hl_world_raster_pixels, ranges cast out of order as the renderer's
 * threads take them) equal full renders bit for bit at every instant, jumps back included, and
 * its changed flags are exactly render/gbuffer_diff's between consecutive frames.
 */
static void raster_frames_equal_full_renders(void **state)
{
	(void)state;
	static const double times[] = { 0.0, 0.02, 0.04, 1.5, 1.52, 3.0, 0.04, 5.9, 6.5 };
	const int w = 320, h = 180;
	const size_t n = (size_t)w * h, band = 7001; /* not a row's multiple */
	struct hl_scenario *sc = NULL;
	struct hl_world_scene *ws;
	struct hl_world_raster *raster;
	struct hl_gbuffer *gb, *ref;
	struct hl_gbuffer_diff *diff;
	struct hl_world_state st;
	struct hl_camera cam;
	uint8_t *changed = malloc(n);
	size_t total_changed = 0;

	sc = shipped("demo-drive.json", w, h, &cam);
	assert_non_null(changed);
	assert_int_equal(hl_world_scene_new(sc, &ws), 0);
	assert_int_equal(hl_gbuffer_new(w, h, &gb), 0);
	assert_int_equal(hl_gbuffer_new(w, h, &ref), 0);
	assert_int_equal(hl_world_raster_new(ws, &cam, gb, &raster), 0);
	assert_ptr_equal(hl_world_raster_gbuffer(raster), gb);
	for (size_t k = 0; k < sizeof(times) / sizeof(times[0]); k++) {
		size_t n_diff;

		hl_world_at(sc, times[k], &st);
		assert_int_equal(hl_world_scene_render(ws, &st, &cam, ref), 0);
		if (k == 0)
			assert_int_equal(hl_gbuffer_diff_new(w, h, NULL, &diff), 0);
		n_diff = hl_gbuffer_diff_band(diff, ref, 0, n, k == 0);
		memset(changed, 0xee, n);
		/* the bands from the last to the first */
		for (size_t first = (n - 1) / band * band;; first -= band) {
			const size_t count = n - first < band ? n - first : band;

			assert_int_equal(hl_world_raster_pixels(raster, &st, first, count, changed),
					 0);
			if (first == 0)
				break;
		}
		if (memcmp(gb->pos, ref->pos, sizeof(float) * 4 * n) != 0 ||
		    memcmp(gb->nrm, ref->nrm, sizeof(float) * 4 * n) != 0 ||
		    memcmp(gb->albedo, ref->albedo, sizeof(float) * n) != 0)
			fail_msg("t %.2f: the raster's G-buffer differs from a full render",
				 times[k]);
		if (k > 0) {
			if (memcmp(changed, hl_gbuffer_diff_flags(diff), n) != 0)
				fail_msg("t %.2f: changed flags differ from gbuffer_diff's",
					 times[k]);
			total_changed += n_diff;
		}
	}
	/* Not vacuous: things moved, and most of the ground did not. */
	assert_true(total_changed > 100);
	assert_true(total_changed < n * (sizeof(times) / sizeof(times[0])) / 2);
	assert_int_equal(hl_world_raster_pixels(raster, &st, n - 10, 11, changed), -EINVAL);
	hl_gbuffer_diff_free(diff);
	hl_world_raster_free(raster);
	hl_gbuffer_free(gb);
	hl_gbuffer_free(ref);
	hl_world_scene_free(ws);
	hl_scenario_free(sc);
	free(changed);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(road_project_250m_arc),
		cmocka_unit_test(road_project_straight_arc_straight),
		cmocka_unit_test(ray_hits_actor_box),
		cmocka_unit_test(emitters_face_and_hide),
		cmocka_unit_test(emitters_facing_without_occlusion),
		cmocka_unit_test(straight_iihs_ground_and_markings),
		cmocka_unit_test(curve_ground_matches_closed_form),
		cmocka_unit_test(no_allocation_per_frame),
		cmocka_unit_test(raster_frames_equal_full_renders),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
