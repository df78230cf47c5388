/* SPDX-License-Identifier: MIT */
#include "tools/benchmarks/bench_stats.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

double hl_bench_now_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

static int cmp_double(const void *a, const void *b)
{
	const double x = *(const double *)a, y = *(const double *)b;

	return (x > y) - (x < y);
}

struct stats hl_bench_summarise(double *t, int n)
{
	if (n <= 0)
		return (struct stats){ -1, -1, -1, 0 };
	qsort(t, n, sizeof(double), cmp_double);
	return (struct stats){ n % 2 ? t[n / 2] : (t[n / 2 - 1] + t[n / 2]) / 2, t[0], t[n - 1],
			       n };
}

FILE *hl_bench_open_json(const char *prog, const char *path)
{
	FILE *f;

	if (!path)
		return stdout;
	f = fopen(path, "we");
	if (!f)
		fprintf(stderr, "%s: '%s': %s\n", prog, path, strerror(errno));
	return f;
}
