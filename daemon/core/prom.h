/* SPDX-License-Identifier: MIT */
/*
 * Prometheus text exposition format 0.0.4, written into a caller's buffer (for the /metrics
 * callback of daemon/out/http.h): a family is its "# HELP" and "# TYPE" lines followed by its
 * samples; label values and help text are escaped as the format says (\\, \", \n in label
 * values; \\ and \n in help). Histograms are written as cumulative _bucket{le="..."} lines up
 * to le="+Inf", then _sum and _count.
 *
 *   struct hl_prom p;
 *   hl_prom_init(&p, buf, size);
 *   hl_prom_family(&p, "hdlamp_cycles_total", HL_PROM_COUNTER, "Complete CAN cycles.");
 *   hl_prom_counter(&p, "hdlamp_cycles_total", (const char *[]){ "lamp", "left", NULL }, n);
 *   return hl_prom_end(&p);  (the length, or -ENOBUFS)
 *
 * Metric and label names are the program's own: an invalid one is a programming error
 * (assert). Thread-safety: a struct hl_prom is used by one thread; a histogram is observed
 * by one thread and written out by whoever holds it still (copy it under the owner's lock).
 */
#ifndef HL_DAEMON_CORE_PROM_H
#define HL_DAEMON_CORE_PROM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

enum hl_prom_type {
	HL_PROM_COUNTER,
	HL_PROM_GAUGE,
	HL_PROM_HISTOGRAM,
};

struct hl_prom {
	char *buf;
	size_t size, len;
	bool overflow;
};

#define HL_PROM_MAX_BUCKETS 24

struct hl_prom_histogram {
	int n_bounds;
	double bounds[HL_PROM_MAX_BUCKETS]; /* upper bounds, increasing; +Inf is implied */
	uint64_t counts[HL_PROM_MAX_BUCKETS + 1]; /* per bucket (not cumulative); last: > all */
	uint64_t count;
	double sum;
};

void hl_prom_init(struct hl_prom *p, char *buf, size_t size);
/* # HELP and # TYPE of a family; write each family once, before its samples. */
void hl_prom_family(struct hl_prom *p, const char *name, enum hl_prom_type type, const char *help);
/*
 * One sample. labels: NULL, or name/value pairs ending with NULL ({ "lamp", "left", NULL }).
 * Values: integers exactly; doubles shortest round-trip, NaN, +Inf, -Inf.
 */
void hl_prom_counter(struct hl_prom *p, const char *name, const char *const *labels,
		     uint64_t value);
void hl_prom_gauge(struct hl_prom *p, const char *name, const char *const *labels, double value);
/* name_bucket (cumulative, with le), name_sum, name_count; labels as above, without "le". */
void hl_prom_histogram(struct hl_prom *p, const char *name, const char *const *labels,
		       const struct hl_prom_histogram *h);
/* The text's length (NUL-terminated in buf), or -ENOBUFS when it did not fit. */
int hl_prom_end(struct hl_prom *p);

/* Bounds must be finite and strictly increasing, 1..HL_PROM_MAX_BUCKETS. 0 or -EINVAL. */
int hl_prom_histogram_init(struct hl_prom_histogram *h, const double *bounds, int n);
/* Counts v in the first bucket whose bound is >= v. Allocates nothing; no locks. */
void hl_prom_histogram_observe(struct hl_prom_histogram *h, double v);

#endif
