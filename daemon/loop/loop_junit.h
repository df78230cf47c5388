/* SPDX-License-Identifier: MIT */
/*
 * A run's verdicts as JUnit XML (docs/sil.md, its paragraph "JUnit"), for a CI's test view:
 * one <testsuite> named after the scenario's file with a <testcase> per verdict set (failed when it failed on
 * a frame), per road user of the scenario (failed when its glare was over its limit in view
 * after the reaction time; without a camera, the strict rule of the run's verdict: on any frame),
 * one for the frames (failed when none was judged or one was not),
 * and, when the ECU failed, one for the ECU with its error. No time attributes: the file is the
 * same bytes for the same run.
 */
#ifndef HL_LOOP_JUNIT_H
#define HL_LOOP_JUNIT_H

#include "daemon/loop/loop_report.h"

/* ecu_error: NULL, or what ended the run. 0 or -errno. */
int hl_loop_junit_write(const struct hl_loop_report *r, const char *ecu_error, const char *path);

#endif
