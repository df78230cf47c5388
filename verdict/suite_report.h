/* SPDX-License-Identifier: MIT */
/*
 * A suite run's machine-readable results (docs/lab.md "What a run writes"): report.json — the suite, the
 * ECU or preset, the documented defaults used, and per variant its scenario, exit, every case
 * (bin, photometer, samples, the maximum as measured and as judged, the limit, the margin, where
 * the maximum occurred, the source) — and junit.xml: one <testsuite> per variant, one
 * <testcase> per case, <failure message="..."> with the measured value, the limit and the range
 * at which it occurred; a bin with a limit that was never reached is an <error>, and so is a run
 * that could not finish. The JUnit counts equal report.json's totals. Both written atomically
 * (base/file_replace.h). 0 or -errno.
 */
#ifndef HL_VERDICT_SUITE_REPORT_H
#define HL_VERDICT_SUITE_REPORT_H

#include "verdict/suite_result.h"

int hl_suite_report_write(const struct hl_suite_result *r, const char *path);
int hl_suite_junit_write(const struct hl_suite_result *r, const char *path);

#endif
