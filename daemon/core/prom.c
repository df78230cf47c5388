/* SPDX-License-Identifier: MIT */
#include "daemon/core/prom.h"

#include <assert.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void hl_prom_init(struct hl_prom *p, char *buf, size_t size)
{
	*p = (struct hl_prom){ .buf = buf, .size = size };
	if (size)
		buf[0] = '\0';
}

static void put(struct hl_prom *p, const char *s, size_t n)
{
	if (p->overflow || p->len + n + 1 > p->size) {
		p->overflow = true;
		return;
	}
	memcpy(p->buf + p->len, s, n);
	p->len += n;
	p->buf[p->len] = '\0';
}

static void puts_(struct hl_prom *p, const char *s)
{
	put(p, s, strlen(s));
}

__attribute__((format(printf, 2, 3))) static void putf(struct hl_prom *p, const char *fmt, ...)
{
	char tmp[64];
	va_list ap;
	int n;

	va_start(ap, fmt);
	n = vsnprintf(tmp, sizeof(tmp), fmt, ap);
	va_end(ap);
	assert(n >= 0 && (size_t)n < sizeof(tmp));
	put(p, tmp, (size_t)n);
}

/* [a-zA-Z_:][a-zA-Z0-9_:]*; label names without ':'. */
__attribute__((unused)) static bool valid_name(const char *s, bool label)
{
	if (!*s || (*s >= '0' && *s <= '9'))
		return false;
	for (; *s; s++) {
		const char c = *s;

		if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
		      c == '_' || (c == ':' && !label)))
			return false;
	}
	return true;
}

/* Help text escapes \ and newline; label values also ". */
static void escaped(struct hl_prom *p, const char *s, bool label)
{
	for (; *s; s++) {
		if (*s == '\\')
			puts_(p, "\\\\");
		else if (*s == '\n')
			puts_(p, "\\n");
		else if (*s == '"' && label)
			puts_(p, "\\\"");
		else
			put(p, s, 1);
	}
}

void hl_prom_family(struct hl_prom *p, const char *name, enum hl_prom_type type, const char *help)
{
	static const char *const types[] = { "counter", "gauge", "histogram" };

	assert(valid_name(name, false));
	puts_(p, "# HELP ");
	puts_(p, name);
	puts_(p, " ");
	escaped(p, help, false);
	puts_(p, "\n# TYPE ");
	puts_(p, name);
	puts_(p, " ");
	puts_(p, types[type]);
	puts_(p, "\n");
}

/* name{a="x",b="y"[,le="..."]} */
static void series(struct hl_prom *p, const char *name, const char *suffix,
		   const char *const *labels, const char *le)
{
	bool any = false;

	assert(valid_name(name, false));
	puts_(p, name);
	puts_(p, suffix);
	for (int i = 0; labels && labels[i]; i += 2) {
		assert(labels[i + 1] && valid_name(labels[i], true) && strcmp(labels[i], "le"));
		puts_(p, any ? "," : "{");
		puts_(p, labels[i]);
		puts_(p, "=\"");
		escaped(p, labels[i + 1], true);
		puts_(p, "\"");
		any = true;
	}
	if (le) {
		puts_(p, any ? "," : "{");
		puts_(p, "le=\"");
		puts_(p, le);
		puts_(p, "\"");
		any = true;
	}
	if (any)
		puts_(p, "}");
	puts_(p, " ");
}

/* Shortest text that reads back as the same double. */
static void format_double(double v, char *out, size_t size)
{
	if (isnan(v)) {
		snprintf(out, size, "NaN");
		return;
	}
	if (isinf(v)) {
		snprintf(out, size, v > 0 ? "+Inf" : "-Inf");
		return;
	}
	/* Whole numbers as such ("10", not "1e+01"): bucket bounds read better. */
	if (v == floor(v) && fabs(v) < 1e15) {
		snprintf(out, size, "%.0f", v);
		return;
	}
	for (int prec = 1; prec <= 17; prec++) {
		snprintf(out, size, "%.*g", prec, v);
		if (strtod(out, NULL) == v)
			return;
	}
}

void hl_prom_counter(struct hl_prom *p, const char *name, const char *const *labels, uint64_t value)
{
	series(p, name, "", labels, NULL);
	putf(p, "%llu\n", (unsigned long long)value);
}

void hl_prom_gauge(struct hl_prom *p, const char *name, const char *const *labels, double value)
{
	char v[32];

	format_double(value, v, sizeof(v));
	series(p, name, "", labels, NULL);
	puts_(p, v);
	puts_(p, "\n");
}

void hl_prom_histogram(struct hl_prom *p, const char *name, const char *const *labels,
		       const struct hl_prom_histogram *h)
{
	uint64_t cum = 0;
	char le[32];

	for (int b = 0; b <= h->n_bounds; b++) {
		cum += h->counts[b];
		if (b < h->n_bounds)
			format_double(h->bounds[b], le, sizeof(le));
		else
			snprintf(le, sizeof(le), "+Inf");
		series(p, name, "_bucket", labels, le);
		putf(p, "%llu\n", (unsigned long long)cum);
	}
	format_double(h->sum, le, sizeof(le));
	series(p, name, "_sum", labels, NULL);
	puts_(p, le);
	puts_(p, "\n");
	series(p, name, "_count", labels, NULL);
	putf(p, "%llu\n", (unsigned long long)h->count);
}

int hl_prom_end(struct hl_prom *p)
{
	if (p->overflow)
		return -ENOBUFS;
	return (int)p->len;
}

int hl_prom_histogram_init(struct hl_prom_histogram *h, const double *bounds, int n)
{
	if (n < 1 || n > HL_PROM_MAX_BUCKETS)
		return -EINVAL;
	for (int i = 0; i < n; i++)
		if (!isfinite(bounds[i]) || (i && !(bounds[i] > bounds[i - 1])))
			return -EINVAL;
	memset(h, 0, sizeof(*h));
	h->n_bounds = n;
	memcpy(h->bounds, bounds, sizeof(double) * (size_t)n);
	return 0;
}

void hl_prom_histogram_observe(struct hl_prom_histogram *h, double v)
{
	int b = 0;

	while (b < h->n_bounds && !(v <= h->bounds[b]))
		b++;
	h->counts[b]++;
	h->count++;
	h->sum += v;
}
