/* SPDX-License-Identifier: MIT */
/*
 * A suite run's plan and its files (docs/lab.md "What a run writes"), shared by `hdlamp suite
 * run` (virtual time) and `hdlampd --suite` (real time): the variants selected, each with its
 * scenario file; the output directory's layout; the plots, report.json, junit.xml and
 * index.html written at the end.
 *
 * Thread-safety: plain functions on the caller's data.
 */
#ifndef HL_VERDICT_SUITE_PLAN_H
#define HL_VERDICT_SUITE_PLAN_H

#include <stdbool.h>
#include <stddef.h>

#include "verdict/suite.h"
#include "verdict/suite_result.h"

/*
 * r->v: every variant of s (samples points per range, >= 2) whose scenario id or own id is
 * only (NULL: all), with its id, scenario, road, speed, radius and measured range; r->suite = s.
 * The count (>= 1), -EINVAL (none matches only: msg says so), -ENOMEM.
 */
int hl_suite_plan(const struct hl_suite *s, const char *only, int samples,
		  struct hl_suite_result *r, char *msg, size_t msg_size);

/*
 * The output directory: DIR, DIR/scenarios, DIR/plots, and DIR/traces when traces (made when
 * missing). 0 or -errno (msg names the directory).
 */
int hl_suite_plan_dirs(const char *dir, bool traces, char *msg, size_t msg_size);

/*
 * Variant v's scenario generated (verdict/suite_scenario.h) and written to
 * DIR/scenarios/ID.json; its title (hl_suite_variant_title()), scenario_file and plot_file set; *ret_path the file's path.
 * 0, -EINVAL (the geometry cannot give the range), -errno (writing); msg says why.
 */
int hl_suite_plan_scenario(const struct hl_suite *s, struct hl_suite_variant *v, const char *dir,
			   char *ret_path, size_t path_size, char *msg, size_t msg_size);

/* DIR/plots/ID.svg of variant v. 0 or -errno. */
int hl_suite_plan_plot(const struct hl_suite_result *r, const struct hl_suite_variant *v,
		       const char *dir);

/*
 * DIR/report.json, DIR/junit.xml and DIR/index.html. 0, or the first -errno (msg names the
 * file); it goes on with the others after a failure.
 */
int hl_suite_plan_write(const struct hl_suite_result *r, const char *dir, char *msg,
			size_t msg_size);

#endif
