/* SPDX-License-Identifier: MIT */
/*
 * What a suite run found (docs/lab.md): per scenario variant, the judged cases (an FMVSS bin at
 * a photometer; an IIHS figure; an R149 table row), the illuminance series the plots draw, and,
 * for IIHS, the road edges and visibility points of the bird's-eye plot. Filled by the runner
 * (tools/cmd_suite.c), written as report.json (verdict/suite_report.c), junit.xml
 * (verdict/suite_junit.c), index.html (verdict/suite_html.c) and one SVG plot per variant
 * (verdict/suite_plot.c).
 *
 * Thread-safety: plain data, built by one thread.
 */
#ifndef HL_VERDICT_SUITE_RESULT_H
#define HL_VERDICT_SUITE_RESULT_H

#include <stdbool.h>
#include <stdio.h>

#include "verdict/suite.h"

#define HL_SUITE_MAX_SERIES 8

/* One test case: a bin at a photometer (FMVSS), a figure (IIHS), a row (R149). */
struct hl_suite_case {
	char name[128]; /* "oncoming 15.0-29.9 m, photometer driver" */
	char photometer[HL_SUITE_ID_MAX]; /* "" where none */
	double from_m, to_m; /* the bin as written; NAN when not a bin */
	const char *unit; /* "lx", "m", "cd" */
	int n_samples; /* frames in the bin; 0: the bin was never reached */
	double max_raw; /* the bin's maximum as measured; NAN without samples */
	double value; /* as judged: max_raw rounded by the suite's rule */
	double at_range_m, at_t_s; /* where the maximum occurred */
	double limit; /* NAN: reported only, not judged */
	bool limit_is_min; /* a lower bound (a distance that must be reached) */
	double margin; /* limit - value (or value - limit for a lower bound); NAN without limit */
	bool judged, pass; /* judged: a limit and at least one sample; pass is true when !judged */
	bool no_samples; /* judged as an error: the bin has a limit but was never reached */
	char source[HL_SUITE_TEXT_MAX]; /* the limit's source */
	int bin_index, photometer_index; /* the suite's bin[] and photometer[]; -1: none */
	double worst_margin; /* while judging: the smallest margin of any sample (R149) */
};

/* Illuminance against range at one photometer (or a figure against distance). */
struct hl_suite_series {
	char label[HL_SUITE_ID_MAX];
	enum hl_actor_role role;
	int n, cap;
	double *range_m, *lx, *t_s; /* malloc'd, n entries each */
};

/* The IIHS bird's-eye: both road edges ahead and where each drops below the visibility limit. */
struct hl_suite_birdseye {
	int n; /* points per edge */
	double (*left)[2], (*right)[2]; /* world x, y (malloc'd) */
	double ego[2], ego_heading_rad;
	double vis_m[2]; /* visibility distance along the left (0) and right (1) edge; NAN: never */
	double vis_at[2][2]; /* the points where it ends (world x, y) */
};

struct hl_suite_variant {
	char id[96]; /* "oncoming-left-25mph-85m" */
	char scenario_id[HL_SUITE_ID_MAX]; /* the suite's scenario it comes from */
	int scenario_index, variant_index; /* in suite->scenario[], in its variants */
	char title[HL_SUITE_TEXT_MAX];
	enum hl_suite_road road;
	double speed_mph, radius_m; /* radius 0 on a straight */
	double range_m[2];
	int n_cases;
	struct hl_suite_case *cases; /* malloc'd */
	int n_series;
	struct hl_suite_series series[HL_SUITE_MAX_SERIES];
	bool has_birdseye;
	struct hl_suite_birdseye birdseye;
	char scenario_file[128]; /* relative to the output directory */
	char trace_file[128]; /* "" without a bus (a held preset) */
	char plot_file[128]; /* "NAME.svg" */
	char error[512]; /* "" or why the run could not finish (the ECU failed) */
	int exit_code; /* the run's: 0, 1 (the ECU failed), 2 */
	int n_frames;
};

struct hl_suite_result {
	const struct hl_suite *suite;
	char ecu[256]; /* "reference", an FMU's path, "can:IFACE", or "" with a held preset */
	char preset[64]; /* "" with an ECU */
	char fault[128]; /* "" or the ECU fault */
	int n_variants;
	struct hl_suite_variant *v; /* malloc'd */
};

/* Totals over every case (judged cases only count as passed/failed). */
struct hl_suite_totals {
	int cases, judged, failed, no_samples, errors; /* errors: variants that did not finish */
};
void hl_suite_result_totals(const struct hl_suite_result *r, struct hl_suite_totals *ret);
/* The same for one variant (errors: 1 when it did not finish). */
void hl_suite_variant_totals(const struct hl_suite_variant *v, struct hl_suite_totals *ret);
/* True when every judged case passed, no bin with a limit went unreached and every run finished. */
bool hl_suite_result_passed(const struct hl_suite_result *r);
void hl_suite_result_free(struct hl_suite_result *r); /* frees what is malloc'd inside, not r */

/*
 * Adds a sample to a series (grows it). 0 or -ENOMEM.
 */
int hl_suite_series_add(struct hl_suite_series *s, double range_m, double lx, double t_s);

/*
 * The plot of one variant as a standalone SVG document (verdict/suite_plot.c): illuminance
 * against range for each series on a log axis, each photometer's limit as a step line over the
 * bins, the stretches over the limit marked; or, with has_birdseye, the road edges seen from
 * above with the visibility distances labelled. Writes to f. 0 or -EIO.
 */
int hl_suite_plot_svg(const struct hl_suite_result *r, const struct hl_suite_variant *v, FILE *f);

/*
 * index.html (verdict/suite_html.c): one self-contained page — the suite, the ECU or preset,
 * the totals, the documented defaults, per variant a table of its cases (value, limit, margin,
 * range, source; failures marked) with its plot inline (the SVG embedded, nothing fetched),
 * and links to each variant's trace and scenario file. Written atomically
 * (base/file_replace.h). 0 or -errno.
 */
int hl_suite_html_write(const struct hl_suite_result *r, const char *path);

#endif
