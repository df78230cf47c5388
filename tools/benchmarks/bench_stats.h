/* SPDX-License-Identifier: MIT */
/* What the benchmark programs share: a monotonic clock and the median/min/max of timings. */
#ifndef HL_TOOLS_BENCH_STATS_H
#define HL_TOOLS_BENCH_STATS_H

#include <stdio.h>

struct stats {
	double median, min, max;
	int n;
};

/* CLOCK_MONOTONIC in milliseconds. */
double hl_bench_now_ms(void);
/* Sorts t (n timings) and summarises them; n <= 0 gives { -1, -1, -1, 0 }. */
struct stats hl_bench_summarise(double *t, int n);
/* Where the JSON goes: path opened for writing, or stdout when NULL; NULL after telling why. */
FILE *hl_bench_open_json(const char *prog, const char *path);

#endif
