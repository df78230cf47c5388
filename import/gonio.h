/* SPDX-License-Identifier: MIT */
/*
 * A measured luminous intensity distribution in its own angles, as a goniophotometer (and the
 * IES, EULUMDAT and CSV files) give it: a table of candela values over "plane" angles and
 * "in-plane" angles, interpolated bilinearly in those angles and zero outside their coverage.
 *
 *   system  plane angle (LM-63 "horizontal")   in-plane angle (LM-63 "vertical")
 *   A       H, degrees, -180..180              V, degrees, -90..90
 *   B       H, degrees, -90..90                V, degrees, -180..180
 *   C       C, degrees, 0..360 (azimuth)       gamma, degrees, 0..180 (from the nadir)
 *
 * Directions: types A and B as docs/design.md §4 (lamp/angles.h), type C as import/typec.h.
 *
 * Type C tables are periodic in C when their planes span exactly 360 degrees (the symmetric
 * constructors below produce that); lookups then wrap. Otherwise, and for A and B, a lookup
 * outside the table's angles is 0: the distribution is not extended beyond what was measured.
 *
 * Thread-safety: built by one thread, then read-only; lookups may run in parallel.
 */
#ifndef HL_IMPORT_GONIO_H
#define HL_IMPORT_GONIO_H

enum hl_gonio_system {
	HL_GONIO_A,
	HL_GONIO_B,
	HL_GONIO_C,
};

/* How a type C table's planes stand for the full circle (LM-63 / EULUMDAT symmetries). */
enum hl_gonio_csym {
	HL_GONIO_CSYM_NONE, /* planes as given; if they start at 0 and end below 360, wrap */
	HL_GONIO_CSYM_ROTATIONAL, /* one plane stands for all */
	HL_GONIO_CSYM_QUADRANT, /* planes 0..90, mirrored about C0-C180 and C90-C270 */
	HL_GONIO_CSYM_C0_C180, /* planes 0..180, mirrored about the C0-C180 plane */
	HL_GONIO_CSYM_C90_C270, /* planes 90..270, mirrored about the C90-C270 plane */
};

struct hl_gonio;

/*
 * A table exactly as given: n_planes plane angles and n_in in-plane angles, both strictly
 * increasing and inside the system's ranges (above); values[i * n_in + j] in cd at
 * (planes[i], in[j]), finite and >= 0. Needs n_planes >= 2 and n_in >= 2.
 * Returns 0, -EINVAL (bad table), -ENOMEM.
 */
int hl_gonio_new(enum hl_gonio_system system, int n_planes, const double *planes, int n_in,
		 const double *in, const float *values, struct hl_gonio **ret);

/*
 * A type C table given with a symmetry, expanded to the full circle (planes over exactly 360
 * degrees). The planes must match the symmetry: ROTATIONAL one plane; QUADRANT 0..90;
 * C0_C180 0..180; C90_C270 90..270; NONE starts at 0 and ends above 180 (a table ending below
 * 360 is closed by repeating plane 0 at 360). 0, -EINVAL, -ENOMEM.
 */
int hl_gonio_new_c(enum hl_gonio_csym sym, int n_planes, const double *planes, int n_in,
		   const double *in, const float *values, struct hl_gonio **ret);

/*
 * A type A or B table laterally symmetric about H = 0: planes 0..H_last, mirrored to
 * -H_last..H_last (I(-H, V) = I(H, V)). 0, -EINVAL, -ENOMEM.
 */
int hl_gonio_new_lateral(enum hl_gonio_system system, int n_planes, const double *planes, int n_in,
			 const double *in, const float *values, struct hl_gonio **ret);

void hl_gonio_free(struct hl_gonio *g);

enum hl_gonio_system hl_gonio_system(const struct hl_gonio *g);
int hl_gonio_n_planes(const struct hl_gonio *g);
int hl_gonio_n_in(const struct hl_gonio *g);
/* Arrays owned by g, valid until hl_gonio_free. */
const double *hl_gonio_planes(const struct hl_gonio *g);
const double *hl_gonio_in(const struct hl_gonio *g);
const float *hl_gonio_values(const struct hl_gonio *g);
float hl_gonio_peak_cd(const struct hl_gonio *g);

/* Intensity in cd at (plane_deg, in_deg), bilinear in the table's angles, 0 outside. */
double hl_gonio_lookup(const struct hl_gonio *g, double plane_deg, double in_deg);
/* Intensity in cd towards lamp-space direction d (need not be unit length, not zero). */
double hl_gonio_lookup_dir(const struct hl_gonio *g, const double d[3]);

/* Angles of direction d in the given system, degrees (type C: C in [0, 360)). */
void hl_gonio_angles_from_dir(enum hl_gonio_system system, const double d[3], double *ret_plane_deg,
			      double *ret_in_deg);
/* Unit direction of (plane_deg, in_deg) in the given system. */
void hl_gonio_angles_to_dir(enum hl_gonio_system system, double plane_deg, double in_deg,
			    double ret_d[3]);

/* 'A', 'B', 'C'. */
char hl_gonio_system_letter(enum hl_gonio_system system);

#endif
