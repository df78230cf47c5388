/* SPDX-License-Identifier: MIT */
/*
 * The bend light (docs/ecu.md, "Bend light"): the beam turns toward the curve the car drives.
 *
 * The law. Driving at speed v with yaw rate w, the car follows a circle of radius R = v / |w|.
 * The beam aims at a preview point on that circle, d = clamp(v * preview_s, min_m, max_m) ahead
 * along the chord; a chord of length d on a circle of radius R leaves the tangent at
 * asin(d / 2R), so the swivel is
 *
 *     swivel = sign(w) * min(max_deg, asin(min(1, d * |w| / (2 v))))      (positive left)
 *
 * and 0 below min_speed_mps (parking and turning are the cornering light's job).
 *
 * Turning a matrix beam. The matrix has no motor: the pattern moves across the sources. Rows
 * are found from the source windows (ecu/windows.h): at least 3 sources whose windows have the
 * same V extent within 0.5° and H widths within a factor 1.5 of the row's first source; in a
 * row, sorted by the H centre of their windows, source k takes the value the unturned pattern
 * has at c_k + swivel (linear between the neighbouring centres, the end value beyond the row's
 * ends), which moves the pattern by the swivel toward the curve (H is positive right, a left
 * swivel moves light to negative H). Sources in no row keep their value; a source named
 * "bend_left" ("bend_right") is lit in a left (right) curve at |swivel| / max_deg, if that is
 * more than its value.
 *
 * Thread-safety: rows are built once and then read-only; the functions allocate nothing after
 * hl_ecu_rows_new().
 */
#ifndef HL_ECU_BEND_H
#define HL_ECU_BEND_H

#include "ecu/windows.h"
#include "lamp/lid.h"

struct hl_ecu_bend_config {
	double preview_s; /* time to the preview point */
	double preview_min_m, preview_max_m;
	double max_deg; /* largest swivel */
	double min_speed_mps; /* no swivel below */
};

/* The defaults: 2 s, 10..60 m, 15°, 10 km/h. */
void hl_ecu_bend_default(struct hl_ecu_bend_config *ret);

/* The swivel in degrees (positive left) by the law above. */
double hl_ecu_bend_swivel_deg(const struct hl_ecu_bend_config *c, double speed_mps,
			      double yaw_rate_rad_s);

struct hl_ecu_rows;

/* The rows of a lamp's sources from their windows (n of them, from hl_ecu_windows). names (n
 * entries, NULL allowed) find the bend sources. 0, -ENOMEM. */
int hl_ecu_rows_new(const struct hl_ecu_window *w, const char *const *names, int n,
		    struct hl_ecu_rows **ret);
void hl_ecu_rows_free(struct hl_ecu_rows *r);

int hl_ecu_rows_count(const struct hl_ecu_rows *r);
/* Row i's sources (0-based), by increasing H centre, and their number in *ret_n; owned by r. */
const int *hl_ecu_rows_row(const struct hl_ecu_rows *r, int i, int *ret_n);

/* out = in turned by swivel_deg (n values, in != out). max_deg scales the bend sources. */
void hl_ecu_rows_turn(const struct hl_ecu_rows *r, const float *in, double swivel_deg,
		      double max_deg, float *out);

#endif
