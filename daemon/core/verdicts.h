/* SPDX-License-Identifier: MIT */
/*
 * The live verdicts (docs/live-verdicts.md, "Verdicts"): the configured regulation sets
 * (verdict.sets, verdict/regulation.h) checked on every rendered frame's combined distributions
 * with verdict/verdict.h, and the road KPIs (render/road_kpi.h) from the same distributions.
 *
 * hl_verdicts_new() loads every set from verdict.regulations, plans one evaluator per set on
 * the lamps' grid with the lamps' mounted aim (the pose as a shift: aim_v = pitch,
 * aim_h = -yaw) and fixes the layout of a frame's results: set i has parts (each lamp for an
 * each_lamp set, one "pair" part for a pair_half set), part j of set i has its
 * n_requirements results from hl_verdicts_part(i, j)->first on, in one flat array of
 * hl_verdicts_n_results() results that every pool frame holds (daemon/core/frame.h).
 *
 * Per frame (hl_verdicts_eval, hl_verdicts_road) the render thread fills a frame's results:
 * weighted sums only, no allocation, no logging. The readers (status, metrics, captures) take a
 * published frame from the pool and describe its results with the layout here.
 *
 * Thread-safety: new and free on the main thread; the object is read-only in between, and
 * eval and road run on the render thread while any thread writes JSON or metrics of a frame it
 * holds.
 */
#ifndef HL_DAEMON_CORE_VERDICTS_H
#define HL_DAEMON_CORE_VERDICTS_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "daemon/core/config.h"
#include "dbc/database.h"
#include "daemon/core/frame.h"
#include "daemon/core/prom.h"
#include "verdict/record.h"
#include "verdict/regulation.h"
#include "verdict/verdict.h"
#include "world/camera.h"
#include "render/road_kpi.h"

#define HL_VERDICTS_MAX_SETS HL_CONFIG_MAX_SETS /* bits of the frame header's set masks */
#define HL_VERDICTS_PAIR (-1) /* a part's lamp: half the sum of the pair */
#define HL_VERDICTS_MAX_MODES 64 /* named values of the HdlBeamMode signal */

/* Where part j of set i sits in a frame's results. */
struct hl_verdicts_part {
	int lamp; /* 0, 1, or HL_VERDICTS_PAIR */
	int first; /* index of its first result */
};

struct hl_verdicts;

/* The beam mode's source: a lamp's HdlBeamMode signal (can/assembler.h). */
struct hl_verdicts_mode_source {
	int lamp; /* whose cycles carry it, -1: no such signal */
	const struct hl_dbc_signal *signal; /* its VAL_ descriptions name the modes */
};

/*
 * Loads cfg's sets (cfg->verdict_sets from cfg->regulations) and plans them and the road KPIs
 * for the lamps: grids[l] and poses[l] of n_lamps (1 or 2) lamps called lamp_names[l]; copied.
 * mode (NULL or lamp -1: none; the signal must outlive the object) and cfg->verdict_modes
 * select the sets per beam mode. 0, -ENOENT (a set is missing), -EBADMSG (a set file is
 * malformed), -EINVAL (a pair_half set with one lamp, or lamps on different grids or aims;
 * verdict.modes without a mode signal, naming a mode the signal has no VAL_ for or a set that
 * is not in verdict.sets), -ENOMEM; err names the set, the file and the fault.
 */
int hl_verdicts_new(const struct hl_config *cfg, int n_lamps, const char *const *lamp_names,
		    const struct hl_lid_grid *const *grids, const struct hl_lamp_pose *poses,
		    const struct hl_verdicts_mode_source *mode, struct hl_verdicts **ret, char *err,
		    size_t err_size);
void hl_verdicts_free(struct hl_verdicts *v);

int hl_verdicts_n_sets(const struct hl_verdicts *v);
/* hl_req_result entries a frame holds for every set's parts. */
int hl_verdicts_n_results(const struct hl_verdicts *v);
const struct hl_regulation *hl_verdicts_set(const struct hl_verdicts *v, int set);
int hl_verdicts_n_parts(const struct hl_verdicts *v, int set);
const struct hl_verdicts_part *hl_verdicts_part(const struct hl_verdicts *v, int set, int part);
/* The part's name: the lamp's, or "pair". */
const char *hl_verdicts_part_name(const struct hl_verdicts *v, int set, int part);
/* The names a record's JSON uses (verdict/record.h): set's requirement ids (n_requirements) and
 * part names (n_parts). */
void hl_verdicts_names(const struct hl_verdicts *v, int set, const char **ret_req_ids,
		       const char **ret_part_names);
/* The lamp whose cycles carry the beam mode, -1 for none. */
int hl_verdicts_mode_lamp(const struct hl_verdicts *v);
/*
 * The sets evaluated in beam mode mode (a raw value of the mode signal; -1: unknown, no signal
 * or no cycle yet): every set without a mode signal or when unknown. With verdict.modes, the
 * sets it names for the mode's VAL_ name (none for a mode or value it does not name). Without
 * verdict.modes, by the sets' beams (hl_regulation.beam): a mode named low or passing has the
 * passing sets, high or driving the driving sets, glarefree or adb the ADB sets (any case),
 * each with the sets that have no beam; any other name ("unset") or a value without a name has
 * every set.
 */
uint32_t hl_verdicts_active(const struct hl_verdicts *v, int64_t mode);
/* Whether the sets follow the beam mode; false: every set on every frame (no mode signal). */
bool hl_verdicts_mode_aware(const struct hl_verdicts *v);
/* The set's beam as its file writes it ("passing", "driving", "adb"), NULL for none. */
const char *hl_verdicts_set_beam(const struct hl_verdicts *v, int set);
/* The mode's VAL_ name, or NULL (unknown, or a value without a description). */
const char *hl_verdicts_mode_name(const struct hl_verdicts *v, int64_t mode);
/* The road KPIs' levels and widths (what the header's floats are of). */
const struct hl_road_kpi_options *hl_verdicts_road_options(const struct hl_verdicts *v);

/*
 * Render thread: evaluates the sets whose bit is in active on the lamps' distributions
 * dist[l] (grid layout, cd), writing their parts' results into results
 * (hl_verdicts_n_results() entries; inactive sets' entries are left alone). Returns the mask
 * of sets that failed (some part did not pass). Allocates nothing.
 */
uint32_t hl_verdicts_eval(const struct hl_verdicts *v, uint32_t active, const float *const *dist,
			  struct hl_req_result *results);
/*
 * The same with each lamp's peak (n_lamps entries, from hl_verdict_copy_peak() as the frame's
 * distributions were copied) given, so that no set scans a whole grid for its Imax; NULL:
 * computed where needed.
 */
uint32_t hl_verdicts_eval_peaks(const struct hl_verdicts *v, uint32_t active,
				const float *const *dist, const struct hl_verdict_peak *lamp_peaks,
				struct hl_req_result *results);
/* Render thread: the road KPIs of the distributions. Allocates nothing. */
void hl_verdicts_road(const struct hl_verdicts *v, const float *const *dist,
		      struct hl_road_kpi *ret);
/* The header's road floats as the KPIs (and back). */
void hl_verdicts_road_to_header(const struct hl_road_kpi *k, struct hl_frame_header *h);

/*
 * Writes a frame's verdicts as JSON members (no braces around):
 * "verdicts":{"traffic":...,"frame":...,"mode":...,"mode_aware":...,"modes_configured":...,
 * "sets":[...]},"road":{...}. Each set ("id", "title", "applies", "beam", "evaluated": on the
 * newest frame, "results") with, from so_far (NULL: left out; n_sets entries, the records of
 * daemon/core/verdict_records.h copied by the caller), "now", "so_far", "strip" and the counts
 * "frames" (evaluated) and "failed_frames". Any thread, on a frame it holds.
 */
struct hl_verdicts_so_far {
	struct hl_record_summary sum;
	const struct hl_record_cellinfo *strip;
	size_t n_strip;
};
void hl_verdicts_json(const struct hl_verdicts *v, const struct hl_frame *f,
		      const struct hl_verdicts_so_far *so_far, FILE *out);
/*
 * The metric families of a frame's verdicts and road KPIs (f NULL: no frame yet, the counters
 * only): hdlamp_verdict_pass, hdlamp_requirement_margin, hdlamp_verdict_failed_frames_total,
 * hdlamp_verdict_frames_total, hdlamp_road_range_meters, hdlamp_road_width_meters.
 */
void hl_verdicts_metrics(const struct hl_verdicts *v, const struct hl_frame *f,
			 const uint64_t *frames, const uint64_t *failed_frames, struct hl_prom *p);

#endif
