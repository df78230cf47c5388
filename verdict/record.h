/* SPDX-License-Identifier: MIT */
/*
 * A verdict set's record over a run, as a test engineer reads it
 * (docs/verdicts.md, "Now and so far"): the newest frame ("now": pass, FAIL, or not applicable when the set is outside its beam
 * mode) kept apart from the run so far (frames evaluated, failed and not applicable, the longest
 * failing stretch in seconds, the worst margin and where it was), and a strip with one cell per
 * frame: the last HL_RECORD_STRIP frames cell by cell, and the whole run as runs of equal cells
 * (state, deciding requirement and part).
 *
 * A failing stretch is a run of consecutive frames that failed; it lasts from its first frame to
 * the first frame that did not fail (passed, or was outside the set's mode), or to the newest
 * frame while it goes on. A frame's deciding requirement is the one with the smallest margin
 * (the first that failed worst, on a failing frame).
 *
 * The whole-run strip keeps at most the runs given to hl_record_new(); frames after the last
 * run that fits are counted (hl_record_summary's frames_unstripped), never silently left out.
 *
 * Thread-safety: one writer (the render thread); readers copy what they need under the same
 * lock as the writer (daemon/pipeline.c). Allocates only in hl_record_new().
 */
#ifndef HL_VERDICT_RECORD_H
#define HL_VERDICT_RECORD_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#define HL_RECORD_STRIP 3000 /* cells of the recent strip: 60 s at the ECU's 50 Hz */

enum hl_record_cell {
	HL_RECORD_PASS = 'p',
	HL_RECORD_FAIL = 'f',
	HL_RECORD_NA = 'n', /* outside the set's beam mode: not evaluated */
};

/* One frame as the record takes it. */
struct hl_record_frame {
	double t_s; /* the frame's time on the run's clock (s) */
	enum hl_record_cell cell;
	int req, part; /* the deciding requirement (index in the set) and part; -1 with NA */
	double margin; /* its margin (< 0: failed); ignored with NA and when NaN */
	int mode; /* the frame's beam mode (the mode signal's raw value), -1: none */
};

/* A run of equal cells in the whole-run strip. */
struct hl_record_run {
	double t0_s; /* its first frame's time */
	uint32_t frames;
	char cell; /* enum hl_record_cell */
	int16_t req; /* the deciding requirement on a failing run, -1 otherwise */
	int8_t part;
};

/* A cell of the recent strip. */
struct hl_record_cellinfo {
	char cell;
	int8_t part;
	int16_t req; /* on a failing cell: the requirement that failed worst; -1 otherwise */
	int16_t mode; /* the frame's beam mode, -1: none (values past 32767 as 32767) */
};

/* A beam mode's name for the JSON (NULL: written as its number). */
typedef const char *(*hl_record_mode_name_fn)(const void *ud, int mode);

struct hl_record_summary {
	uint64_t frames; /* every frame the set was asked about */
	uint64_t evaluated, failed, not_applicable;
	char now; /* the newest frame's cell, 0 before the first */
	int now_req, now_part; /* its deciding requirement, -1 with NA */
	double now_t_s;
	double longest_failing_s; /* 0 without a failing frame */
	double longest_failing_from_s; /* where the longest stretch began */
	int has_worst; /* a frame was evaluated */
	double worst_margin; /* the smallest margin of any evaluated frame */
	int worst_req, worst_part;
	double worst_t_s;
	uint64_t frames_unstripped; /* frames after the whole-run strip ran out of runs */
};

struct hl_record;

/* max_runs (>= 1): runs the whole-run strip keeps. 0, -EINVAL, -ENOMEM. */
int hl_record_new(size_t max_runs, struct hl_record **ret);
void hl_record_free(struct hl_record *r);
/* Forgets every frame (a reload of the sets, a new run). */
void hl_record_reset(struct hl_record *r);

/* Takes one frame. Allocates nothing. */
void hl_record_add(struct hl_record *r, const struct hl_record_frame *f);

void hl_record_summary(const struct hl_record *r, struct hl_record_summary *ret);
/* The last frames' cells, oldest first, at most max (HL_RECORD_STRIP hold all). Their number. */
size_t hl_record_strip(const struct hl_record *r, struct hl_record_cellinfo *buf, size_t max);
/* The whole run's runs, oldest first (valid until the next add or reset), and their number. */
size_t hl_record_runs(const struct hl_record *r, const struct hl_record_run **ret);

/*
 * The words (docs/verdicts.md): "pass", "FAIL", "not applicable" for a cell; the run so far:
 * "FAIL" when a frame failed, "pass" when frames were evaluated and none failed, "not
 * evaluated" when the set was never in its mode.
 */
const char *hl_record_cell_word(char cell);
const char *hl_record_so_far_word(const struct hl_record_summary *s);

/*
 * JSON members (no braces around) of a summary: "now":{...},"so_far":{...}; req_ids[i] names
 * requirement i, part_names[j] part j (both of the set).
 */
void hl_record_json_summary(const struct hl_record_summary *s, const char *const *req_ids,
			    const char *const *part_names, FILE *out);
/*
 * The recent strip as JSON members "cells":"pfn...","failing":[[first,count,"req","part"],...]
 * (runs of failing cells with the same deciding requirement, by index into cells),
 * "modes":[[first,count,"name"|value|null],...] (runs of frames in one beam mode; mode_name
 * (may be NULL) names them).
 */
void hl_record_json_strip(const struct hl_record_cellinfo *cells, size_t n,
			  const char *const *req_ids, const char *const *part_names,
			  hl_record_mode_name_fn mode_name, const void *ud, FILE *out);
/* The whole-run strip as a JSON array [[t0_s,frames,"p|f|n","req"|null,"part"|null],...]. */
void hl_record_json_runs(const struct hl_record_run *runs, size_t n, const char *const *req_ids,
			 const char *const *part_names, FILE *out);

#endif
