/* SPDX-License-Identifier: MIT */
/*
 * hdlamp suite run (docs/lab.md): every scenario variant of a suite, each with a held preset
 * (the lamps' distributions stepped through the scenario at the ECU's 50 Hz, no bus) or with an
 * ECU in the loop in virtual time (sil/sil.h: the reference ECU or an FMU, the restbus and the
 * virtual bus, the bus traced); measured by verdict/suite_measure.h, written into the output
 * directory: scenarios/ID.json, traces/ID.log, plots/ID.svg, report.json, junit.xml, index.html.
 */
#ifndef HL_TOOLS_SUITE_RUN_H
#define HL_TOOLS_SUITE_RUN_H

#include <stdio.h>

#include "daemon/core/config.h"
#include "sil/sil.h"
#include "verdict/suite.h"
#include "verdict/suite_result.h"

struct hl_suite_run_options {
	const struct hl_suite *suite;
	const struct hl_config *cfg; /* lamps, can.dbc, restbus.*, scene.glare_set, ... */
	const char *preset; /* a held preset (lamp/model.h name or file); NULL: the ECU */
	struct hl_sil_options sil; /* the ECU and its faults (ecu, ref, late_ms, ...) */
	const char *fault_text; /* the faults as given, for the report */
	const char *only; /* NULL, or a scenario's or a variant's id */
	int samples; /* points per speed and radius range, >= 2 */
	const char *out; /* the output directory (made if missing) */
	FILE *log;
};

/*
 * Runs and writes everything. Returns the exit code: 0 every test held, 3 one failed (or a bin
 * went unmeasured, or a run could not finish), 2 bad input (logged), 1 an output could not be
 * written.
 */
int hl_suite_run(const struct hl_suite_run_options *o);

/*
 * A suite by NAME (a shipped suite) or a .json path (tools/cmd_suite.c). 0, or 2 after telling
 * why on stderr ("PROG: ...").
 */
int hl_cli_suite_load(const char *prog, const char *arg, struct hl_suite **ret);

#endif
