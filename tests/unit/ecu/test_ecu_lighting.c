/* SPDX-License-Identifier: MIT */
/*
 * The ECU's lighting functions (ecu/lighting.c) on both HD84 lamps and on a pixel lamp: beams by
 * the switch, auto high beam, the glare-free mask against windows and parallax computed here
 * (ecu_naive.h), the fail-safe's timing, E2E failures, the bend light and the faults.
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "ecu/beams.h"
#include "ecu/lighting.h"
#include "ecu_naive.h"
#include "lamp/model.h"

#define MS 1000000LL
#define T0 (1000 * MS)

struct fixture {
	struct hl_lid *lid[2];
	float low[2][HL_HD84_SOURCES], high[2][HL_HD84_SOURCES];
	struct hl_ecu_window win[2][HL_HD84_SOURCES]; /* naive */
	struct hl_ecu_lamp lamps[2];
};

static int setup(void **state)
{
	struct fixture *f = calloc(1, sizeof(*f));
	struct hl_preset *p;
	struct hl_lid *const none[2] = { NULL, NULL };

	if (!f || hl_preset_new(HL_HD84_SOURCES, &p) < 0)
		return -1;
	for (int s = 0; s < 2; s++) {
		if (hl_model_hd84(s, &f->lid[s]) < 0)
			return -1;
		/* the beams as the lamp layer's presets define them */
		hl_model_hd84_preset("low", none, p);
		hl_preset_intensities(p, s, f->low[s]);
		hl_model_hd84_preset("high", none, p);
		hl_preset_intensities(p, s, f->high[s]);
		if (naive_windows(f->lid[s], f->high[s], 0.05, f->win[s]) < 0)
			return -1;
		f->lamps[s] = (struct hl_ecu_lamp){
			.lid = f->lid[s],
			/* level lamps: the test's geometry is written for those */
			.mount = { .pos_m = { 0.0, s == 0 ? 0.7 : -0.7, 0.65 } },
			.low = f->low[s],
			.high = f->high[s],
		};
	}
	hl_preset_free(p);
	*state = f;
	return 0;
}

static int teardown(void **state)
{
	struct fixture *f = *state;

	hl_lid_free(f->lid[0]);
	hl_lid_free(f->lid[1]);
	free(f);
	return 0;
}

static struct hl_ecu *ecu_with(struct fixture *f, const struct hl_ecu_config *c)
{
	struct hl_ecu *e;
	const char *what = NULL;

	assert_int_equal(hl_ecu_new(c, f->lamps, 2, &e, &what), 0);
	assert_null(what);
	return e;
}

static struct hl_ecu *ecu_default(struct fixture *f)
{
	struct hl_ecu_config c;

	hl_ecu_config_default(&c);
	return ecu_with(f, &c);
}

static void feed(struct hl_ecu *e, enum hl_light_switch sw, bool adb, double speed_mps,
		 const struct hl_camera_objects *o, int64_t t_ns)
{
	const struct hl_vehicle_state v = { .speed_mps = speed_mps,
					    .light_switch = sw,
					    .adb_enable = adb };
	const struct hl_camera_objects none = { 0 };

	hl_ecu_vehicle(e, &v, t_ns);
	hl_ecu_objects(e, o ? o : &none, t_ns);
}

static void assert_beam(const struct hl_ecu *e, float beam[2][HL_HD84_SOURCES])
{
	for (int s = 0; s < 2; s++)
		assert_memory_equal(hl_ecu_output(e, s), beam[s], sizeof(float) * HL_HD84_SOURCES);
}

static void lighting_failsafe_low_before_any_input(void **state)
{
	struct fixture *f = *state;
	struct hl_ecu *e = ecu_default(f);
	struct hl_ecu_status st;

	hl_ecu_step(e, T0, &st);
	assert_int_equal(st.mode, HL_ECU_LOW);
	assert_int_equal(st.failsafe, HL_ECU_FS_VEHICLE_MISSING | HL_ECU_FS_OBJECTS_MISSING);
	assert_beam(e, f->low);
	assert_string_equal(hl_ecu_beam_mode_name(st.mode), "low"); /* the fail-safe shows it */
	/* only the vehicle: the camera is still missing */
	feed(e, HL_SWITCH_HIGH, false, 20, NULL, T0);
	hl_ecu_objects(e, &(struct hl_camera_objects){ 0 }, T0 - 61 * MS);
	hl_ecu_step(e, T0, &st);
	assert_int_equal(st.failsafe, HL_ECU_FS_OBJECTS_MISSING);
	assert_beam(e, f->low);
	hl_ecu_free(e);
}

static void lighting_switch_positions(void **state)
{
	struct fixture *f = *state;
	struct hl_ecu *e = ecu_default(f);
	struct hl_ecu_status st;

	feed(e, HL_SWITCH_LOW, false, 20, NULL, T0);
	hl_ecu_step(e, T0, &st);
	assert_int_equal(st.mode, HL_ECU_LOW);
	assert_int_equal(st.failsafe, 0);
	assert_beam(e, f->low);
	assert_string_equal(hl_ecu_beam_mode_name(st.mode), "low");
	feed(e, HL_SWITCH_HIGH, false, 20, NULL, T0);
	hl_ecu_step(e, T0, &st);
	assert_int_equal(st.mode, HL_ECU_HIGH);
	assert_beam(e, f->high);
	assert_string_equal(hl_ecu_beam_mode_name(st.mode), "high");
	/* ADB without objects: the whole high beam */
	feed(e, HL_SWITCH_HIGH, true, 20, NULL, T0);
	hl_ecu_step(e, T0, &st);
	assert_int_equal(st.mode, HL_ECU_GLAREFREE);
	assert_int_equal(st.masked[0] + st.masked[1], 0);
	assert_beam(e, f->high);
	assert_string_equal(hl_ecu_beam_mode_name(st.mode), "glarefree");
	feed(e, HL_SWITCH_OFF, false, 20, NULL, T0);
	hl_ecu_step(e, T0, &st);
	assert_int_equal(st.mode, HL_ECU_OFF);
	assert_string_equal(hl_ecu_beam_mode_name(st.mode), "unset"); /* dark: no beam said */
	for (int s = 0; s < 2; s++)
		for (int k = 0; k < HL_HD84_SOURCES; k++)
			assert_true(hl_ecu_output(e, s)[k] == 0.0f);
	hl_ecu_free(e);
}

static const struct hl_camera_object oncoming = {
	.id = 7,
	.cls = HL_OBJECT_ONCOMING,
	.h_left_deg = -5.0,
	.h_right_deg = -3.2,
	.v_bottom_deg = -1.2,
	.v_top_deg = 0.1,
	.distance_m = 60.0,
	.confidence = 0.9,
};

static void lighting_auto_high_beam(void **state)
{
	struct fixture *f = *state;
	struct hl_ecu *e = ecu_default(f);
	struct hl_ecu_status st;
	struct hl_camera_objects o = { .n = 1, .obj = { oncoming } };
	const double v_on = 40.0 / 3.6;

	feed(e, HL_SWITCH_AUTO, false, nextafter(v_on, 0), NULL, T0);
	hl_ecu_step(e, T0, &st);
	assert_int_equal(st.mode, HL_ECU_LOW);
	feed(e, HL_SWITCH_AUTO, false, v_on, NULL, T0);
	hl_ecu_step(e, T0, &st);
	assert_int_equal(st.mode, HL_ECU_HIGH);
	assert_beam(e, f->high);
	/* a relevant object: low beam without ADB, glare-free with it */
	feed(e, HL_SWITCH_AUTO, false, v_on, &o, T0);
	hl_ecu_step(e, T0, &st);
	assert_int_equal(st.mode, HL_ECU_LOW);
	assert_int_equal(st.objects, 1);
	assert_beam(e, f->low);
	feed(e, HL_SWITCH_AUTO, true, v_on, &o, T0);
	hl_ecu_step(e, T0, &st);
	assert_int_equal(st.mode, HL_ECU_GLAREFREE);
	assert_true(st.masked[0] > 0 && st.masked[1] > 0);
	/* objects that are not relevant keep the high beam, counted */
	o.n = 4;
	o.obj[0].cls = HL_OBJECT_OTHER;
	o.obj[1] = oncoming;
	o.obj[1].confidence = 0.49;
	o.obj[2] = oncoming;
	o.obj[2].h_left_deg = -2.0; /* left of right edge is not: inverted */
	o.obj[3] = oncoming;
	o.obj[3].distance_m = NAN;
	feed(e, HL_SWITCH_AUTO, false, v_on, &o, T0);
	hl_ecu_step(e, T0, &st);
	assert_int_equal(st.mode, HL_ECU_HIGH);
	assert_int_equal(st.objects, 0);
	assert_int_equal(st.ignored, 2);
	assert_int_equal(st.invalid, 2);
	/* a preceding car and a pedestrian are relevant */
	o.n = 1;
	o.obj[0] = oncoming;
	o.obj[0].cls = HL_OBJECT_PEDESTRIAN;
	feed(e, HL_SWITCH_AUTO, false, v_on, &o, T0);
	hl_ecu_step(e, T0, &st);
	assert_int_equal(st.mode, HL_ECU_LOW);
	o.obj[0].cls = HL_OBJECT_PRECEDING;
	feed(e, HL_SWITCH_AUTO, false, v_on, &o, T0);
	hl_ecu_step(e, T0, &st);
	assert_int_equal(st.mode, HL_ECU_LOW);
	hl_ecu_free(e);
}

/* The test's own mask: the nine points of the box, margin, windows from the dense grids. */
static void expected_mask(struct fixture *f, int s, const struct hl_camera_object *objs, int n,
			  double margin, double margin_m, const double cam[3], bool *off)
{
	for (int k = 0; k < HL_HD84_SOURCES; k++)
		off[k] = false;
	for (int i = 0; i < n; i++) {
		const struct hl_camera_object *o = &objs[i];
		double h0 = INFINITY, h1 = -INFINITY, v0 = INFINITY, v1 = -INFINITY;

		for (int a = 0; a < 3; a++) {
			for (int b = 0; b < 3; b++) {
				double h, v;

				naive_parallax(
					cam, 0.0,
					o->h_left_deg + a * (o->h_right_deg - o->h_left_deg) / 2,
					o->v_bottom_deg + b * (o->v_top_deg - o->v_bottom_deg) / 2,
					o->distance_m, f->lamps[s].mount.pos_m, 0.0, &h, &v);
				h0 = fmin(h0, h);
				h1 = fmax(h1, h);
				v0 = fmin(v0, v);
				v1 = fmax(v1, v);
			}
		}
		/* in H also the length margin at the object's distance */
		const double mh = margin + atan(margin_m / o->distance_m) * 180.0 / M_PI;

		h0 -= mh, h1 += mh, v0 -= margin, v1 += margin;
		for (int k = 0; k < HL_HD84_SOURCES; k++) {
			const struct hl_ecu_window *w = &f->win[s][k];

			if (!w->empty && w->h0_deg <= h1 && h0 <= w->h1_deg && w->v0_deg <= v1 &&
			    v0 <= w->v1_deg)
				off[k] = true;
		}
	}
}

static void check_glarefree(struct fixture *f, const struct hl_camera_objects *o, double dist)
{
	struct hl_ecu *e = ecu_default(f);
	struct hl_ecu_config c;
	struct hl_ecu_status st;
	bool off[2][HL_HD84_SOURCES];

	hl_ecu_config_default(&c);
	feed(e, HL_SWITCH_HIGH, true, 25, o, T0);
	hl_ecu_step(e, T0, &st);
	assert_int_equal(st.mode, HL_ECU_GLAREFREE);
	for (int s = 0; s < 2; s++) {
		int n_off = 0, lit_off = 0;

		expected_mask(f, s, o->obj, o->n, c.margin_deg, c.margin_m, c.camera.pos_m, off[s]);
		for (int k = 0; k < HL_HD84_SOURCES; k++) {
			const float want = off[s][k] ? 0.0f : f->high[s][k];

			if (hl_ecu_output(e, s)[k] != want)
				fail_msg("%s lamp, source %d at %.0f m: %g, expected %g",
					 s ? "right" : "left", k + 1, dist, hl_ecu_output(e, s)[k],
					 want);
			n_off += off[s][k];
			lit_off += off[s][k] && f->high[s][k] > 0.0f;
		}
		/* something and not everything */
		assert_true(n_off > 0 && n_off < 40);
		assert_int_equal(st.masked[s], lit_off);
	}
	/* the lamps see the object from 1.4 m apart: their masks differ when it is near */
	if (dist < 20)
		assert_memory_not_equal(off[0], off[1], sizeof(off[0]));
	hl_ecu_free(e);
}

static void lighting_glarefree_masks_what_the_windows_say(void **state)
{
	struct fixture *f = *state;
	struct hl_camera_objects o = { .n = 1, .obj = { oncoming } };
	const double dists[3] = { 12.0, 60.0, 150.0 };

	for (int i = 0; i < 3; i++) {
		o.obj[0].distance_m = dists[i];
		check_glarefree(f, &o, dists[i]);
	}
	/* two objects: an oncoming car and a preceding one to the right */
	o.n = 2;
	o.obj[0].distance_m = 80.0;
	o.obj[1] = (struct hl_camera_object){ .id = 9,
					      .cls = HL_OBJECT_PRECEDING,
					      .h_left_deg = 1.0,
					      .h_right_deg = 2.6,
					      .v_bottom_deg = -1.4,
					      .v_top_deg = -0.2,
					      .distance_m = 45.0,
					      .confidence = 1.0 };
	check_glarefree(f, &o, 45.0);
	/* a car swept across the field at 0.13° steps: every edge of every window is met */
	o.n = 1;
	o.obj[0].distance_m = 60.0;
	for (double h = -12.0; h < 10.0; h += 0.13) {
		o.obj[0].h_left_deg = h;
		o.obj[0].h_right_deg = h + 1.1;
		check_glarefree(f, &o, 60.0);
	}
}

static void lighting_failsafe_timing(void **state)
{
	struct fixture *f = *state;
	struct hl_ecu *e = ecu_default(f);
	struct hl_ecu_status st;

	feed(e, HL_SWITCH_HIGH, false, 20, NULL, T0);
	hl_ecu_step(e, T0 + 60 * MS, &st); /* exactly the timeout: still valid */
	assert_int_equal(st.failsafe, 0);
	assert_int_equal(st.mode, HL_ECU_HIGH);
	hl_ecu_step(e, T0 + 60 * MS + 1, &st);
	assert_int_equal(st.failsafe, HL_ECU_FS_VEHICLE_MISSING | HL_ECU_FS_OBJECTS_MISSING);
	assert_int_equal(st.mode, HL_ECU_LOW);
	assert_beam(e, f->low);
	/* the camera alone keeps coming: the vehicle is missing */
	hl_ecu_objects(e, &(struct hl_camera_objects){ 0 }, T0 + 60 * MS);
	hl_ecu_step(e, T0 + 100 * MS, &st);
	assert_int_equal(st.failsafe, HL_ECU_FS_VEHICLE_MISSING);
	/* back: the inputs hold again */
	feed(e, HL_SWITCH_HIGH, false, 20, NULL, T0 + 100 * MS);
	hl_ecu_step(e, T0 + 100 * MS, &st);
	assert_int_equal(st.failsafe, 0);
	assert_beam(e, f->high);
	hl_ecu_free(e);
	/* a configured timeout */
	{
		struct hl_ecu_config c;

		hl_ecu_config_default(&c);
		c.objects_timeout_ns = 200 * MS;
		e = ecu_with(f, &c);
		feed(e, HL_SWITCH_HIGH, false, 20, NULL, T0);
		hl_ecu_vehicle(e, &(struct hl_vehicle_state){ .light_switch = HL_SWITCH_HIGH },
			       T0 + 150 * MS);
		hl_ecu_step(e, T0 + 200 * MS, &st);
		assert_int_equal(st.failsafe, 0);
		hl_ecu_step(e, T0 + 200 * MS + 1, &st);
		assert_int_equal(st.failsafe, HL_ECU_FS_OBJECTS_MISSING);
		hl_ecu_free(e);
	}
}

static void lighting_e2e_failures_in_a_row(void **state)
{
	struct fixture *f = *state;
	struct hl_ecu *e = ecu_default(f);
	struct hl_ecu_status st;

	feed(e, HL_SWITCH_HIGH, false, 20, NULL, T0);
	hl_ecu_input_error(e, HL_ECU_INPUT_VEHICLE);
	hl_ecu_input_error(e, HL_ECU_INPUT_VEHICLE);
	hl_ecu_step(e, T0, &st);
	assert_int_equal(st.failsafe, 0);
	hl_ecu_input_error(e, HL_ECU_INPUT_VEHICLE);
	hl_ecu_step(e, T0, &st);
	assert_int_equal(st.failsafe, HL_ECU_FS_VEHICLE_E2E);
	assert_beam(e, f->low);
	/* a valid message ends the run */
	feed(e, HL_SWITCH_HIGH, false, 20, NULL, T0);
	hl_ecu_step(e, T0, &st);
	assert_int_equal(st.failsafe, 0);
	for (int i = 0; i < 3; i++)
		hl_ecu_input_error(e, HL_ECU_INPUT_OBJECTS);
	hl_ecu_step(e, T0, &st);
	assert_int_equal(st.failsafe, HL_ECU_FS_OBJECTS_E2E);
	hl_ecu_free(e);
}

static void lighting_faults(void **state)
{
	struct fixture *f = *state;
	struct hl_ecu_config c;
	struct hl_ecu *e;
	struct hl_ecu_status st;
	const struct hl_camera_objects o = { .n = 1, .obj = { oncoming } };

	hl_ecu_config_default(&c);
	c.faults = HL_ECU_FAULT_IGNORE_OBJECTS;
	e = ecu_with(f, &c);
	feed(e, HL_SWITCH_HIGH, true, 20, &o, T0);
	hl_ecu_step(e, T0, &st);
	assert_int_equal(st.mode, HL_ECU_GLAREFREE);
	assert_int_equal(st.masked[0] + st.masked[1], 0);
	assert_int_equal(st.objects, 0);
	assert_int_equal(st.ignored, 1); /* dropped by the fault, counted */
	assert_beam(e, f->high);
	feed(e, HL_SWITCH_AUTO, false, 20, &o, T0);
	hl_ecu_step(e, T0, &st);
	assert_int_equal(st.mode, HL_ECU_HIGH);
	hl_ecu_free(e);

	c.faults = HL_ECU_FAULT_NO_FAILSAFE;
	e = ecu_with(f, &c);
	hl_ecu_step(e, T0, &st); /* nothing received yet: still the fail-safe */
	assert_int_equal(st.mode, HL_ECU_LOW);
	feed(e, HL_SWITCH_HIGH, false, 20, NULL, T0);
	hl_ecu_step(e, T0 + 10000 * MS, &st);
	assert_int_equal(st.failsafe, 0);
	assert_int_equal(st.mode, HL_ECU_HIGH);
	hl_ecu_free(e);
}

/* Row 3 (LEDs 57..84) turned by the swivel the law gives, from the dense windows' centres. */
static void lighting_bend_turns_the_rows(void **state)
{
	struct fixture *f = *state;
	struct hl_ecu *e = ecu_default(f);
	struct hl_ecu_status st;
	const struct hl_vehicle_state v = { .speed_mps = 20.0,
					    .yaw_rate_rad_s = 0.1,
					    .light_switch = HL_SWITCH_HIGH };
	const double sw = asin(40.0 / 400.0) * 180 / M_PI;

	hl_ecu_vehicle(e, &v, T0);
	hl_ecu_objects(e, &(struct hl_camera_objects){ 0 }, T0);
	hl_ecu_step(e, T0, &st);
	assert_float_equal(st.swivel_deg, sw, 1e-12);
	for (int s = 0; s < 2; s++) {
		const float *out = hl_ecu_output(e, s);
		const struct hl_ecu_window *w = f->win[s];

		for (int j = 0; j < HL_HD84_ROW_LEDS; j++) {
			const int k = 2 * HL_HD84_ROW_LEDS + j;
			const double q = (w[k].h0_deg + w[k].h1_deg) / 2 + sw;
			double want = f->high[s][3 * HL_HD84_ROW_LEDS - 1];

			for (int i = 2 * HL_HD84_ROW_LEDS; i < 3 * HL_HD84_ROW_LEDS; i++) {
				const double c = (w[i].h0_deg + w[i].h1_deg) / 2;
				const double c1 = (w[i + 1].h0_deg + w[i + 1].h1_deg) / 2;

				if (i == 2 * HL_HD84_ROW_LEDS && q <= c) {
					want = f->high[s][i];
					break;
				}
				if (i + 1 < 3 * HL_HD84_ROW_LEDS && q > c && q <= c1) {
					want = f->high[s][i] +
					       (q - c) / (c1 - c) *
						       (f->high[s][i + 1] - f->high[s][i]);
					break;
				}
			}
			assert_float_equal(out[k], want, 1e-6);
		}
		/* the left curve lights bend_left at swivel / 15°, leaves bend_right off */
		assert_float_equal(out[HL_HD84_BEND_LEFT - 1], sw / 15.0, 1e-6);
		assert_true(out[HL_HD84_BEND_RIGHT - 1] == 0.0f);
	}
	/* the fail-safe is the plain low beam: unturned */
	hl_ecu_step(e, T0 + 61 * MS, &st);
	assert_true(st.swivel_deg == 0.0);
	assert_beam(e, f->low);
	hl_ecu_free(e);
}

static void lighting_bad_config(void **state)
{
	struct fixture *f = *state;
	struct hl_ecu_config c;
	struct hl_ecu *e = NULL;
	const char *what = NULL;
	float bad[HL_HD84_SOURCES];
	struct hl_ecu_lamp lamps[2];

	hl_ecu_config_default(&c);
	c.window_fraction = 1.0;
	assert_int_equal(hl_ecu_new(&c, f->lamps, 2, &e, &what), -EINVAL);
	assert_string_equal(what, "window fraction: expected a number in (0, 1)");
	hl_ecu_config_default(&c);
	c.objects_timeout_ns = 0;
	assert_int_equal(hl_ecu_new(&c, f->lamps, 2, &e, &what), -EINVAL);
	assert_string_equal(what, "timeout: expected a positive time");
	hl_ecu_config_default(&c);
	assert_int_equal(hl_ecu_new(&c, f->lamps, 0, &e, &what), -EINVAL);
	assert_string_equal(what, "lamps: expected 1 to 8");
	memcpy(bad, f->high[0], sizeof(bad));
	bad[3] = 1.01f;
	memcpy(lamps, f->lamps, sizeof(lamps));
	lamps[1].high = bad;
	assert_int_equal(hl_ecu_new(&c, lamps, 2, &e, &what), -EINVAL);
	assert_string_equal(what, "beam: expected relative currents in [0, 1]");
	assert_null(e);
}

/* Another model: a pixel lamp with the default beams of ecu/beams.h. */
static void lighting_pixel_lamp(void **state)
{
	(void)state;
	enum { N = 120 };
	struct hl_lid *lid;
	float low[N], high[N];
	struct hl_ecu_window w[N];
	struct hl_ecu_config c;
	struct hl_ecu *e;
	struct hl_ecu_status st;
	const struct hl_camera_objects o = { .n = 1, .obj = { oncoming } };
	struct hl_ecu_lamp lamp = { .mount = { .pos_m = { 0, 0.7, 0.65 } } };
	int n_low = 0, n_off = 0;

	assert_int_equal(hl_model_pixel(N, &lid), 0);
	assert_false(hl_ecu_beams_is_hd84(lid));
	assert_int_equal(hl_ecu_beams_default(lid, HL_SIDE_LEFT, 0.05, low, high), 0);
	assert_int_equal(naive_windows(lid, high, 0.05, w), 0);
	for (int k = 0; k < N; k++) {
		assert_true(high[k] == 1.0f);
		assert_true(low[k] == (w[k].v1_deg <= 0.0 ? 1.0f : 0.0f));
		n_low += low[k] > 0;
	}
	assert_true(n_low > 0 && n_low < N);
	lamp.lid = lid;
	lamp.low = low;
	lamp.high = high;
	hl_ecu_config_default(&c);
	c.bend = false;
	assert_int_equal(hl_ecu_new(&c, &lamp, 1, &e, NULL), 0);
	feed(e, HL_SWITCH_HIGH, true, 20, &o, T0);
	hl_ecu_step(e, T0, &st);
	for (int k = 0; k < N; k++) {
		double h0 = INFINITY, h1 = -INFINITY, v0 = INFINITY, v1 = -INFINITY;
		bool off;

		for (int a = 0; a < 3; a++) {
			for (int b = 0; b < 3; b++) {
				double h, v;

				naive_parallax(c.camera.pos_m, 0.0, -5.0 + a * 0.9, -1.2 + b * 0.65,
					       60.0, lamp.mount.pos_m, 0.0, &h, &v);
				h0 = fmin(h0, h), h1 = fmax(h1, h), v0 = fmin(v0, v),
				v1 = fmax(v1, v);
			}
		}
		/* 0.5 deg on every side, and 0.2 m at the 60 m of the object in H */
		const double mh = 0.5 + atan(0.2 / 60.0) * 180.0 / M_PI;

		off = !w[k].empty && w[k].h0_deg <= h1 + mh && h0 - mh <= w[k].h1_deg &&
		      w[k].v0_deg <= v1 + 0.5 && v0 - 0.5 <= w[k].v1_deg;
		n_off += off;
		assert_true(hl_ecu_output(e, 0)[k] == (off ? 0.0f : 1.0f));
	}
	assert_int_equal(st.masked[0], n_off);
	assert_true(n_off > 0);
	hl_ecu_free(e);
	hl_lid_free(lid);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(lighting_failsafe_low_before_any_input),
		cmocka_unit_test(lighting_switch_positions),
		cmocka_unit_test(lighting_auto_high_beam),
		cmocka_unit_test(lighting_glarefree_masks_what_the_windows_say),
		cmocka_unit_test(lighting_failsafe_timing),
		cmocka_unit_test(lighting_e2e_failures_in_a_row),
		cmocka_unit_test(lighting_faults),
		cmocka_unit_test(lighting_bend_turns_the_rows),
		cmocka_unit_test(lighting_bad_config),
		cmocka_unit_test(lighting_pixel_lamp),
	};

	return cmocka_run_group_tests(tests, setup, teardown);
}
