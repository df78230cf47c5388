/* SPDX-License-Identifier: MIT */
/*
 * Software in the loop in virtual time (docs/sil.md): `hdlamp sil`. One discrete-event loop
 * over the libraries the daemon runs on — the restbus's deadlines (sil/restbus_node.h), the
 * virtual bus (can/vbus.h), the ECU's steps (sil/ecu_node.h), the cycle assembler, the lamps'
 * distributions, the verdict sets, the glare at the road users' eyes and the loop's judge — on
 * a clock of its own: as fast as the CPU allows, and reproducible to the bit (nothing in it
 * reads a wall clock, and the order of simultaneous events is fixed: the bus's deliveries,
 * then the restbus's deadlines, then the ECU's step and sends).
 *
 * A frame is judged when every lamp has a cycle newer than the last frame (or a lamp's new
 * cycle has waited a whole ECU period for the other), at the instant its later cycle ended
 * on the bus: the frame's scenario time, its t_lamp_done and its render end (the SIL frame
 * takes no time to render; docs/loop.md gives the derivation of the latencies).
 *
 * The report has the format of hdlampd --exit-at-end --report (daemon/loop/loop_report.h) with
 * "ecu" naming the ECU in the loop; nothing in it carries a wall-clock time.
 */
#ifndef HL_SIL_SIL_H
#define HL_SIL_SIL_H

#include <stdbool.h>
#include <stdio.h>

#include "daemon/core/config.h"
#include "ecu/lighting.h"

struct hl_lid;
struct hl_lid_grid;
struct hl_scenario;
struct hl_world_state;

/*
 * Called for every judged frame (the suites' photometers, docs/lab.md): the scenario, the world
 * at the frame's scenario time, and each lamp's distribution (cd) on its grid as the frame lit
 * it. On the loop's thread; what it is given lives until it returns.
 */
typedef void (*hl_sil_frame_fn)(void *ctx, const struct hl_scenario *sc,
				const struct hl_world_state *w,
				const struct hl_lid_grid *const grids[2],
				const float *const dist[2]);

struct hl_sil_options {
	const struct hl_config *cfg; /* cfg->scenario, lamps, dbc, restbus.*, verdict.*, loop.* */
	const char *ecu; /* "reference" or an FMU's path */
	struct hl_ecu_config ref; /* the reference ECU's options */
	bool ref_timeouts_set; /* false: the input timeouts from the database's cycle times */
	int late_ms;
	bool stuck_counter, bad_crc;
	const char *report; /* NULL: none */
	const char *junit; /* NULL: none */
	const char *trace; /* NULL: none; .log (candump -L) or .blf */
	const char
		*frames; /* NULL: none; an existing directory for the frames' PNGs (sil/frames.h) */
	uint32_t bitrate, data_bitrate; /* the virtual bus's; 0: 500 kbit/s, 2 Mbit/s */
	FILE *log;
	/* the lamps, borrowed (they must outlive the run; a suite loads them once for all its
	 * runs); NULL: cfg->lid_left/right or the HD84 model, loaded by the run */
	struct hl_lid *const *lids;
	hl_sil_frame_fn on_frame; /* NULL: none */
	void *on_frame_ctx;
	bool quiet; /* no speed and verdict lines on log (a suite logs its own) */
};

/*
 * Runs the scenario to its end. Returns the exit code: 0 the verdict held, 3 it failed, 2 a
 * configuration or input fault (logged, naming the file), 1 a run that could not go on (an
 * FMU's error or crash: the report is written with "end":"ecu_error").
 */
int hl_sil_run(const struct hl_sil_options *o);

#endif
