/* SPDX-License-Identifier: MIT */
/*
 * The reference headlamp ECU's lighting functions (docs/ecu.md), as pure code: no CAN, no
 * clock of its own. The caller feeds the decoded inputs (can/inputs.h) with their receive times
 * and asks for each output cycle's source intensities at a time it chooses; `hdlamp ecu` does
 * the I/O around it.
 *
 * Each cycle, at now_ns:
 *   1. Fail-safe. The vehicle state and the camera objects are each valid while their newest
 *      accepted message is at most its timeout old (now - t_rx <= timeout) and fewer than
 *      e2e_max_errors of its messages in a row failed their E2E check. If either is not valid
 *      (never received, timed out, E2E failing), the lamps show the low beam, unturned: the
 *      fail-safe, with the reasons in hl_ecu_status.failsafe.
 *   2. The beam by the light switch: off -> every source 0; low -> low beam; high -> high beam,
 *      or the glare-free high beam with ADB enabled; auto -> low beam below auto_high_mps,
 *      above it the glare-free high beam with ADB enabled, else the high beam when there is no
 *      relevant object and the low beam when there is one.
 *   3. Bend light (ecu/bend.h) from speed and yaw rate, when enabled.
 *   4. Glare-free: per lamp and relevant object, the object's box from the camera is carried
 *      to the lamp's angles at its distance (ecu/parallax.h), widened by margin_deg on every
 *      side and in H also by atan(margin_m / distance), and every source whose window
 *      (ecu/windows.h) overlaps it is switched off (0).
 * A relevant object is one of class oncoming, preceding or pedestrian with confidence >=
 * min_confidence, a finite box with h_left <= h_right and v_bottom <= v_top, and a distance
 * > 0; others are counted in hl_ecu_status (ignored, invalid), never masked. Under the fault
 * ignore-objects every valid object is counted as ignored.
 *
 * Thread-safety: an hl_ecu belongs to one thread. Nothing allocates after hl_ecu_new().
 */
#ifndef HL_ECU_LIGHTING_H
#define HL_ECU_LIGHTING_H

#include <stdbool.h>
#include <stdint.h>

#include "can/inputs.h"
#include "ecu/bend.h"
#include "ecu/parallax.h"
#include "ecu/windows.h"
#include "lamp/lid.h"

#define HL_ECU_MAX_LAMPS 8

enum hl_ecu_mode {
	HL_ECU_OFF,
	HL_ECU_LOW,
	HL_ECU_HIGH,
	HL_ECU_GLAREFREE,
};

/* Why the fail-safe holds (bits of hl_ecu_status.failsafe). */
enum hl_ecu_failsafe {
	HL_ECU_FS_VEHICLE_MISSING = 1 << 0, /* never received, or older than its timeout */
	HL_ECU_FS_OBJECTS_MISSING = 1 << 1,
	HL_ECU_FS_VEHICLE_E2E = 1 << 2, /* e2e_max_errors failed in a row */
	HL_ECU_FS_OBJECTS_E2E = 1 << 3,
};

/* Misbehaviours switched in for tests of the verdicts (`hdlamp ecu --fault`). */
enum hl_ecu_fault {
	HL_ECU_FAULT_IGNORE_OBJECTS = 1 << 0, /* sees no objects: no masking, auto stays high */
	HL_ECU_FAULT_NO_FAILSAFE = 1 << 1, /* keeps the last inputs forever */
};

enum hl_ecu_input {
	HL_ECU_INPUT_VEHICLE,
	HL_ECU_INPUT_OBJECTS,
};

struct hl_ecu_config {
	struct hl_ecu_mount camera;
	double window_fraction; /* ecu/windows.h */
	double margin_deg; /* around every object's box, each side */
	/* also around it, each side in H, as a length at the object's distance: what a camera's
	 * box of the body leaves out (outside mirrors) and its lateral error */
	double margin_m;
	double min_confidence;
	double auto_high_mps; /* auto: high beam at or above this speed */
	int64_t vehicle_timeout_ns, objects_timeout_ns;
	int e2e_max_errors; /* consecutive E2E failures that invalidate an input at once */
	bool bend;
	struct hl_ecu_bend_config bend_config;
	unsigned faults; /* enum hl_ecu_fault bits */
};

struct hl_ecu_lamp {
	const struct hl_lid *lid; /* must outlive the ECU */
	struct hl_ecu_mount mount; /* vehicle frame */
	const float *low, *high; /* the beams, n_sources relative currents in [0, 1]; copied */
};

struct hl_ecu_status {
	enum hl_ecu_mode mode; /* HL_ECU_LOW during the fail-safe */
	unsigned failsafe; /* enum hl_ecu_failsafe bits, 0: inputs valid */
	double swivel_deg; /* bend, positive left */
	int objects; /* relevant objects this cycle */
	int ignored; /* valid objects of other classes, below min_confidence, or all valid ones
		      * under HL_ECU_FAULT_IGNORE_OBJECTS */
	int invalid; /* objects with a non-finite or inverted box or distance <= 0 */
	int masked[HL_ECU_MAX_LAMPS]; /* sources switched off for objects, per lamp */
};

/*
 * Camera behind the windscreen at (-1.8, 0, 1.3) m, level (hdlampd's restbus default); 5 %,
 * 0.5°, 0.5, 40 km/h, 60 ms (three 20 ms cycles) for both inputs, 3 E2E errors, bend on with
 * hl_ecu_bend_default().
 */
void hl_ecu_config_default(struct hl_ecu_config *ret);

struct hl_ecu;

/*
 * An ECU for n_lamps (1..HL_ECU_MAX_LAMPS) lamps. Computes every lamp's source windows from its
 * LID and high beam. 0, -EINVAL (a bad count, config value or beam value; *ret_what (may be
 * NULL) names it), -ENOMEM.
 */
int hl_ecu_new(const struct hl_ecu_config *c, const struct hl_ecu_lamp *lamps, int n_lamps,
	       struct hl_ecu **ret, const char **ret_what);
void hl_ecu_free(struct hl_ecu *e);

/* An accepted (E2E-checked) input, received at t_rx_ns (the clock of hl_ecu_step). */
void hl_ecu_vehicle(struct hl_ecu *e, const struct hl_vehicle_state *s, int64_t t_rx_ns);
void hl_ecu_objects(struct hl_ecu *e, const struct hl_camera_objects *o, int64_t t_rx_ns);
/* A message of the input that failed its E2E check (dropped by the caller). */
void hl_ecu_input_error(struct hl_ecu *e, enum hl_ecu_input in);

/* One output cycle at now_ns: fills every lamp's intensities (hl_ecu_output) and *ret. */
void hl_ecu_step(struct hl_ecu *e, int64_t now_ns, struct hl_ecu_status *ret);
/* Lamp l's intensities of the last step, n_sources values in [0, 1]; owned by e. */
const float *hl_ecu_output(const struct hl_ecu *e, int lamp);
/* Lamp l's source windows (n_sources); owned by e. */
const struct hl_ecu_window *hl_ecu_windows_of(const struct hl_ecu *e, int lamp);
const struct hl_ecu_rows *hl_ecu_rows_of(const struct hl_ecu *e, int lamp);

const char *hl_ecu_mode_name(enum hl_ecu_mode mode);
/*
 * The beam the lamps show in mode, as a lamp database's HdlBeamMode signal names it
 * (docs/dbc.md): "low" (also the fail-safe's), "high", "glarefree"; "unset" for off, which
 * shows no beam.
 */
const char *hl_ecu_beam_mode_name(enum hl_ecu_mode mode);

#endif
