/* SPDX-License-Identifier: MIT */
/*
 * The Prometheus text writer: exact output, and a strict parser of the text format 0.0.4
 * (written here, as no client library is at hand) that accepts everything written, including
 * hostile label values, and rejects what breaks the format.
 */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "daemon/core/prom.h"

/* --- a strict parser --- */

#define MAX_FAMILIES 64
#define MAX_SERIES 512

struct family {
	char name[128];
	char type[16];
	bool help, samples_done;
};

struct bucket_run {
	char key[512]; /* histogram name + labels without le */
	double last_le;
	double last_count;
	bool open;
};

struct parser {
	struct family fam[MAX_FAMILIES];
	int n_fam;
	char series[MAX_SERIES][512];
	int n_series;
	int current; /* family whose samples are being read, -1 none */
	struct bucket_run run;
	double inf_count[MAX_SERIES]; /* per histogram label set: +Inf bucket, then _count */
	char inf_key[MAX_SERIES][512];
	int n_inf;
	char err[256];
	int line;
};

static bool name_ok(const char *s, size_t n, bool label)
{
	if (n == 0 || (s[0] >= '0' && s[0] <= '9'))
		return false;
	for (size_t i = 0; i < n; i++) {
		const char c = s[i];

		if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
		      c == '_' || (c == ':' && !label)))
			return false;
	}
	return true;
}

static int perr(struct parser *p, const char *fmt, ...)
{
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(p->err, sizeof(p->err), fmt, ap);
	va_end(ap);
	return -EBADMSG;
}

static bool parse_value(const char *s, size_t n, double *v)
{
	char buf[64], *end;

	if (n == 0 || n >= sizeof(buf))
		return false;
	memcpy(buf, s, n);
	buf[n] = '\0';
	if (strcmp(buf, "NaN") == 0) {
		*v = NAN;
		return true;
	}
	if (strcmp(buf, "+Inf") == 0 || strcmp(buf, "-Inf") == 0) {
		*v = buf[0] == '+' ? INFINITY : -INFINITY;
		return true;
	}
	/* strtod also takes "inf", "nan", hex: the format does not */
	for (size_t i = 0; i < n; i++)
		if (!strchr("0123456789+-.eE", buf[i]))
			return false;
	*v = strtod(buf, &end);
	return *end == '\0';
}

static struct family *find_family(struct parser *p, const char *name, size_t n)
{
	for (int i = 0; i < p->n_fam; i++)
		if (strlen(p->fam[i].name) == n && memcmp(p->fam[i].name, name, n) == 0)
			return &p->fam[i];
	return NULL;
}

static struct family *add_family(struct parser *p, const char *name, size_t n)
{
	struct family *f = find_family(p, name, n);

	if (f)
		return f;
	assert_true(p->n_fam < MAX_FAMILIES && n < sizeof(f->name));
	f = &p->fam[p->n_fam++];
	memset(f, 0, sizeof(*f));
	memcpy(f->name, name, n);
	return f;
}

/* The family of a sample name: itself, or for a histogram the name less its suffix. */
static struct family *family_of(struct parser *p, const char *name, size_t n, const char **suffix)
{
	static const char *const sfx[] = { "_bucket", "_sum", "_count" };
	struct family *f = find_family(p, name, n);

	*suffix = "";
	if (f && strcmp(f->type, "histogram") != 0)
		return f;
	for (int i = 0; i < 3; i++) {
		const size_t k = strlen(sfx[i]);

		if (n > k && memcmp(name + n - k, sfx[i], k) == 0) {
			f = find_family(p, name, n - k);
			if (f && strcmp(f->type, "histogram") == 0) {
				*suffix = sfx[i];
				return f;
			}
		}
	}
	return NULL;
}

static int comment(struct parser *p, const char *s, size_t n)
{
	const char *name, *rest;
	struct family *f;
	size_t nn;

	if (n < 7 || (memcmp(s, "# HELP ", 7) != 0 && memcmp(s, "# TYPE ", 7) != 0))
		return 0; /* a plain comment */
	name = s + 7;
	rest = memchr(name, ' ', n - 7);
	if (!rest)
		return perr(p, "%.6s without text", s);
	nn = (size_t)(rest - name);
	if (!name_ok(name, nn, false))
		return perr(p, "bad metric name");
	f = add_family(p, name, nn);
	rest++;
	if (s[2] == 'H') {
		if (f->help)
			return perr(p, "second HELP for %s", f->name);
		f->help = true;
		for (const char *c = rest; c < s + n; c++)
			if (*c == '\\' && (c + 1 == s + n || (c[1] != '\\' && c[1] != 'n')))
				return perr(p, "bad escape in HELP");
			else if (*c == '\\')
				c++;
		return 0;
	}
	if (f->type[0])
		return perr(p, "second TYPE for %s", f->name);
	if (f->samples_done || (p->current >= 0 && &p->fam[p->current] == f))
		return perr(p, "TYPE after samples of %s", f->name);
	if ((size_t)(s + n - rest) >= sizeof(f->type))
		return perr(p, "bad type");
	memcpy(f->type, rest, (size_t)(s + n - rest));
	f->type[s + n - rest] = '\0';
	if (strcmp(f->type, "counter") && strcmp(f->type, "gauge") &&
	    strcmp(f->type, "histogram") && strcmp(f->type, "summary") &&
	    strcmp(f->type, "untyped"))
		return perr(p, "unknown type '%s'", f->type);
	return 0;
}

static int sample(struct parser *p, const char *s, size_t n)
{
	const char *c = s, *e = s + n, *suffix;
	char key[512], nole[512], le[256] = "";
	size_t kl = 0, nl = 0, name_len;
	struct family *f;
	double v;

	while (c < e && *c != '{' && *c != ' ')
		c++;
	name_len = (size_t)(c - s);
	if (!name_ok(s, name_len, false))
		return perr(p, "bad metric name");
	f = family_of(p, s, name_len, &suffix);
	if (!f || !f->type[0])
		return perr(p, "sample '%.*s' before its TYPE", (int)name_len, s);
	if (f->samples_done)
		return perr(p, "samples of %s not together", f->name);
	if (p->current >= 0 && &p->fam[p->current] != f)
		p->fam[p->current].samples_done = true;
	p->current = (int)(f - p->fam);
	kl = (size_t)snprintf(key, sizeof(key), "%.*s", (int)name_len, s);
	nl = (size_t)snprintf(nole, sizeof(nole), "%s", f->name);
	if (c < e && *c == '{') {
		c++;
		while (c < e && *c != '}') {
			const char *ln = c, *vs;
			char val[256];
			size_t vl = 0;

			while (c < e && *c != '=')
				c++;
			if (c == e || !name_ok(ln, (size_t)(c - ln), true))
				return perr(p, "bad label name");
			if (++c == e || *c != '"')
				return perr(p, "label value not quoted");
			vs = ++c;
			for (; c < e && *c != '"'; c++) {
				if (*c == '\\') {
					if (c + 1 == e ||
					    (c[1] != '\\' && c[1] != '"' && c[1] != 'n'))
						return perr(p, "bad escape in label value");
					c++;
				}
				if (*c == '\n')
					return perr(p, "raw newline in label value");
				if (vl < sizeof(val) - 1)
					val[vl++] = *c;
			}
			if (c == e)
				return perr(p, "unterminated label value");
			val[vl] = '\0';
			(void)vs;
			c++;
			if ((size_t)(c - ln) > 3 && memcmp(ln, "le=", 3) == 0)
				snprintf(le, sizeof(le), "%s", val);
			else
				nl += (size_t)snprintf(nole + nl, sizeof(nole) - nl, "|%.*s",
						       (int)(c - ln), ln);
			kl += (size_t)snprintf(key + kl, sizeof(key) - kl, "|%.*s", (int)(c - ln),
					       ln);
			if (c < e && *c == ',')
				c++;
			else if (c < e && *c != '}')
				return perr(p, "expected , or } after a label");
		}
		if (c == e)
			return perr(p, "unterminated label set");
		c++;
	}
	if (c == e || *c != ' ')
		return perr(p, "no value");
	c++;
	{
		const char *sp = memchr(c, ' ', (size_t)(e - c));
		const char *ve = sp ? sp : e;

		if (!parse_value(c, (size_t)(ve - c), &v))
			return perr(p, "bad value '%.*s'", (int)(ve - c), c);
		if (sp) {
			double ts;

			if (!parse_value(sp + 1, (size_t)(e - sp - 1), &ts) || ts != floor(ts))
				return perr(p, "bad timestamp");
		}
	}
	for (int i = 0; i < p->n_series; i++)
		if (strcmp(p->series[i], key) == 0)
			return perr(p, "duplicate series %s", key);
	assert_true(p->n_series < MAX_SERIES);
	snprintf(p->series[p->n_series++], sizeof(p->series[0]), "%s", key);
	if (strcmp(f->type, "counter") == 0 && !(v >= 0))
		return perr(p, "negative or NaN counter");
	if (strcmp(f->type, "histogram") != 0)
		return 0;
	if (strcmp(suffix, "_bucket") == 0) {
		double lev;

		if (!le[0] || !parse_value(le, strlen(le), &lev))
			return perr(p, "bucket without a valid le");
		if (p->run.open && strcmp(p->run.key, nole) == 0) {
			if (!(lev > p->run.last_le))
				return perr(p, "le not increasing");
			if (v < p->run.last_count)
				return perr(p, "buckets not cumulative");
		} else if (p->run.open) {
			return perr(p, "bucket run of %s ended before +Inf", p->run.key);
		}
		snprintf(p->run.key, sizeof(p->run.key), "%s", nole);
		p->run.last_le = lev;
		p->run.last_count = v;
		p->run.open = true;
		if (isinf(lev)) {
			p->run.open = false;
			snprintf(p->inf_key[p->n_inf], sizeof(p->inf_key[0]), "%s", nole);
			p->inf_count[p->n_inf++] = v;
		}
		return 0;
	}
	if (le[0])
		return perr(p, "le on %s", suffix);
	if (p->run.open)
		return perr(p, "bucket run of %s ended before +Inf", p->run.key);
	if (strcmp(suffix, "_count") == 0) {
		for (int i = 0; i < p->n_inf; i++)
			if (strcmp(p->inf_key[i], nole) == 0) {
				if (p->inf_count[i] != v)
					return perr(p, "_count %g != +Inf bucket %g", v,
						    p->inf_count[i]);
				return 0;
			}
		return perr(p, "_count without buckets");
	}
	if (strcmp(suffix, "_sum") != 0)
		return perr(p, "histogram sample without _bucket/_sum/_count");
	return 0;
}

/* 0, or -EBADMSG with p->line and p->err. */
static int parse(const char *text, struct parser *p)
{
	const char *s = text;
	int rc = 0;

	memset(p, 0, sizeof(*p));
	p->current = -1;
	while (*s && rc == 0) {
		const char *nl = strchr(s, '\n');
		size_t n;

		p->line++;
		if (!nl)
			return perr(p, "last line without newline");
		n = (size_t)(nl - s);
		if (n == 0)
			; /* empty lines are allowed */
		else if (s[0] == '#')
			rc = comment(p, s, n);
		else
			rc = sample(p, s, n);
		s = nl + 1;
	}
	if (rc == 0 && p->run.open)
		rc = perr(p, "bucket run of %s without +Inf", p->run.key);
	return rc;
}

static void assert_parses(const char *text)
{
	struct parser *p = malloc(sizeof(*p));

	assert_non_null(p);
	if (parse(text, p) != 0)
		fail_msg("line %d: %s\n%s", p->line, p->err, text);
	free(p);
}

static void assert_rejected(const char *text, const char *why)
{
	struct parser *p = malloc(sizeof(*p));

	assert_non_null(p);
	assert_int_equal(parse(text, p), -EBADMSG);
	if (!strstr(p->err, why))
		fail_msg("rejected for '%s', expected '%s'", p->err, why);
	free(p);
}

/* --- tests --- */

static void prom_writes_the_exact_text(void **state)
{
	static const double bounds[] = { 1, 2.5, 10 };
	struct hl_prom_histogram h;
	struct hl_prom p;
	char buf[2048];

	(void)state;
	assert_int_equal(hl_prom_histogram_init(&h, bounds, 3), 0);
	hl_prom_histogram_observe(&h, 0.5);
	hl_prom_histogram_observe(&h, 1.0); /* on a bound: that bucket */
	hl_prom_histogram_observe(&h, 3.0);
	hl_prom_histogram_observe(&h, 99.0);
	hl_prom_init(&p, buf, sizeof(buf));
	hl_prom_family(&p, "hdlamp_cycles_total", HL_PROM_COUNTER, "Complete cycles.");
	hl_prom_counter(&p, "hdlamp_cycles_total", (const char *const[]){ "lamp", "left", NULL },
			18446744073709551615ull);
	hl_prom_counter(&p, "hdlamp_cycles_total", (const char *const[]){ "lamp", "right", NULL },
			7);
	hl_prom_family(&p, "hdlamp_render_seconds", HL_PROM_GAUGE, "Last render time, seconds.");
	hl_prom_gauge(&p, "hdlamp_render_seconds", NULL, 0.1);
	hl_prom_family(&p, "hdlamp_latency_ms", HL_PROM_HISTOGRAM, "CAN to frame.");
	hl_prom_histogram(&p, "hdlamp_latency_ms", NULL, &h);
	assert_int_equal(hl_prom_end(&p), (int)strlen(buf));
	assert_string_equal(buf, "# HELP hdlamp_cycles_total Complete cycles.\n"
				 "# TYPE hdlamp_cycles_total counter\n"
				 "hdlamp_cycles_total{lamp=\"left\"} 18446744073709551615\n"
				 "hdlamp_cycles_total{lamp=\"right\"} 7\n"
				 "# HELP hdlamp_render_seconds Last render time, seconds.\n"
				 "# TYPE hdlamp_render_seconds gauge\n"
				 "hdlamp_render_seconds 0.1\n"
				 "# HELP hdlamp_latency_ms CAN to frame.\n"
				 "# TYPE hdlamp_latency_ms histogram\n"
				 "hdlamp_latency_ms_bucket{le=\"1\"} 2\n"
				 "hdlamp_latency_ms_bucket{le=\"2.5\"} 2\n"
				 "hdlamp_latency_ms_bucket{le=\"10\"} 3\n"
				 "hdlamp_latency_ms_bucket{le=\"+Inf\"} 4\n"
				 "hdlamp_latency_ms_sum 103.5\n"
				 "hdlamp_latency_ms_count 4\n");
	assert_parses(buf);
}

static void prom_escapes_labels_and_help(void **state)
{
	struct hl_prom p;
	char buf[1024];

	(void)state;
	hl_prom_init(&p, buf, sizeof(buf));
	hl_prom_family(&p, "x_total", HL_PROM_COUNTER, "a \\ b\nc \"d\"");
	hl_prom_counter(&p, "x_total",
			(const char *const[]){ "lamp", "l\"e\\f\nt", "bus", "can0", NULL }, 1);
	assert_true(hl_prom_end(&p) > 0);
	assert_string_equal(buf, "# HELP x_total a \\\\ b\\nc \"d\"\n"
				 "# TYPE x_total counter\n"
				 "x_total{lamp=\"l\\\"e\\\\f\\nt\",bus=\"can0\"} 1\n");
	assert_parses(buf);
}

static void prom_values_round_trip(void **state)
{
	static const double values[] = { 0.0, -0.0, 1e-300, 123456789.125, 1.0 / 3.0, -2.5e17 };
	struct hl_prom p;
	char buf[4096], line[128];

	(void)state;
	hl_prom_init(&p, buf, sizeof(buf));
	hl_prom_family(&p, "g", HL_PROM_GAUGE, "values");
	for (size_t i = 0; i < sizeof(values) / sizeof(values[0]); i++) {
		snprintf(line, sizeof(line), "%zu", i);
		hl_prom_gauge(&p, "g", (const char *const[]){ "i", line, NULL }, values[i]);
	}
	hl_prom_gauge(&p, "g", (const char *const[]){ "i", "nan", NULL }, NAN);
	hl_prom_gauge(&p, "g", (const char *const[]){ "i", "inf", NULL }, INFINITY);
	hl_prom_gauge(&p, "g", (const char *const[]){ "i", "-inf", NULL }, -INFINITY);
	assert_true(hl_prom_end(&p) > 0);
	assert_parses(buf);
	for (size_t i = 0; i < sizeof(values) / sizeof(values[0]); i++) {
		const char *s;

		snprintf(line, sizeof(line), "g{i=\"%zu\"} ", i);
		s = strstr(buf, line);
		assert_non_null(s);
		assert_true(strtod(s + strlen(line), NULL) == values[i]);
	}
	assert_non_null(strstr(buf, "g{i=\"nan\"} NaN\n"));
	assert_non_null(strstr(buf, "g{i=\"inf\"} +Inf\n"));
	assert_non_null(strstr(buf, "g{i=\"-inf\"} -Inf\n"));
	assert_non_null(strstr(buf, "g{i=\"4\"} 0.3333333333333333\n"));
}

static void prom_daemon_like_metrics_parse(void **state)
{
	static const double bounds[] = { 0.5, 1, 2, 5, 10, 20, 50, 100 };
	static const char *const lamps[] = { "left", "right \"B\"" };
	struct hl_prom_histogram h[2];
	struct hl_prom p;
	static char buf[16384];

	(void)state;
	for (int l = 0; l < 2; l++) {
		assert_int_equal(hl_prom_histogram_init(&h[l], bounds, 8), 0);
		for (int i = 0; i < 1000; i++)
			hl_prom_histogram_observe(&h[l], (double)((i * 37 + l) % 150) / 1.7);
	}
	hl_prom_init(&p, buf, sizeof(buf));
	hl_prom_family(&p, "hdlamp_cycles_total", HL_PROM_COUNTER, "Cycles per lamp.");
	for (int l = 0; l < 2; l++)
		hl_prom_counter(&p, "hdlamp_cycles_total",
				(const char *const[]){ "lamp", lamps[l], NULL }, 100u + l);
	hl_prom_family(&p, "hdlamp_lamp_stale", HL_PROM_GAUGE, "1 while a lamp is stale.");
	for (int l = 0; l < 2; l++)
		hl_prom_gauge(&p, "hdlamp_lamp_stale",
			      (const char *const[]){ "lamp", lamps[l], NULL }, l);
	hl_prom_family(&p, "hdlamp_can_to_frame_ms", HL_PROM_HISTOGRAM, "Latency.");
	for (int l = 0; l < 2; l++)
		hl_prom_histogram(&p, "hdlamp_can_to_frame_ms",
				  (const char *const[]){ "lamp", lamps[l], NULL }, &h[l]);
	assert_true(hl_prom_end(&p) > 0);
	assert_parses(buf);
	assert_int_equal(h[0].count, 1000);
	assert_non_null(
		strstr(buf, "hdlamp_can_to_frame_ms_bucket{lamp=\"left\",le=\"+Inf\"} 1000\n"));
}

static void prom_parser_rejects_broken_text(void **state)
{
	(void)state;
	assert_rejected("x 1\n", "before its TYPE");
	assert_rejected("# TYPE x counter\nx 1", "without newline");
	assert_rejected("# TYPE x counter\nx{a=\"b\\q\"} 1\n", "bad escape");
	assert_rejected("# TYPE x counter\nx{a=b} 1\n", "not quoted");
	assert_rejected("# TYPE x counter\nx{a=\"b\" 1\n", "expected , or }");
	assert_rejected("# TYPE x counter\nx{a=\"b\"} one\n", "bad value");
	assert_rejected("# TYPE x counter\nx -1\n", "negative");
	assert_rejected("# TYPE x counter\nx 1\nx 2\n", "duplicate series");
	assert_rejected("# TYPE x counter\n# TYPE y gauge\nx 1\ny 1\nx{a=\"1\"} 1\n",
			"not together");
	assert_rejected("# TYPE x gauge\n# TYPE x gauge\n", "second TYPE");
	assert_rejected("# TYPE x wibble\n", "unknown type");
	assert_rejected("# TYPE 1x gauge\n", "bad metric name");
	assert_rejected("# TYPE h histogram\nh_bucket{le=\"1\"} 2\nh_bucket{le=\"2\"} 1\n"
			"h_bucket{le=\"+Inf\"} 2\nh_sum 1\nh_count 2\n",
			"not cumulative");
	assert_rejected("# TYPE h histogram\nh_bucket{le=\"2\"} 1\nh_bucket{le=\"1\"} 1\n",
			"le not increasing");
	assert_rejected("# TYPE h histogram\nh_bucket{le=\"1\"} 1\nh_sum 1\n", "before +Inf");
	assert_rejected("# TYPE h histogram\nh_bucket{le=\"+Inf\"} 2\nh_sum 1\nh_count 3\n",
			"_count 3 != +Inf bucket 2");
	assert_rejected("# TYPE h histogram\nh_bucket 1\n", "without a valid le");
	assert_parses("# a comment\n\n# TYPE x untyped\nx{a=\"1\",} 1 1700000000000\n");
}

static void prom_reports_a_full_buffer(void **state)
{
	struct hl_prom p;
	char buf[40];

	(void)state;
	hl_prom_init(&p, buf, sizeof(buf));
	hl_prom_family(&p, "a_long_metric_name_total", HL_PROM_COUNTER, "does not fit");
	hl_prom_counter(&p, "a_long_metric_name_total", NULL, 1);
	assert_int_equal(hl_prom_end(&p), -ENOBUFS);
	assert_true(strlen(buf) < sizeof(buf)); /* still a terminated string */
}

static void prom_histogram_bounds_are_checked(void **state)
{
	static const double down[] = { 2, 1 }, same[] = { 1, 1 }, inf[] = { 1, INFINITY };
	double many[HL_PROM_MAX_BUCKETS + 1];
	struct hl_prom_histogram h;

	(void)state;
	for (int i = 0; i <= HL_PROM_MAX_BUCKETS; i++)
		many[i] = i;
	assert_int_equal(hl_prom_histogram_init(&h, down, 2), -EINVAL);
	assert_int_equal(hl_prom_histogram_init(&h, same, 2), -EINVAL);
	assert_int_equal(hl_prom_histogram_init(&h, inf, 2), -EINVAL);
	assert_int_equal(hl_prom_histogram_init(&h, many, 0), -EINVAL);
	assert_int_equal(hl_prom_histogram_init(&h, many, HL_PROM_MAX_BUCKETS + 1), -EINVAL);
	assert_int_equal(hl_prom_histogram_init(&h, many, HL_PROM_MAX_BUCKETS), 0);
	hl_prom_histogram_observe(&h, 1e9);
	hl_prom_histogram_observe(&h, -5);
	assert_int_equal(h.counts[HL_PROM_MAX_BUCKETS], 1);
	assert_int_equal(h.counts[0], 1);
	assert_int_equal(h.count, 2);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(prom_writes_the_exact_text),
		cmocka_unit_test(prom_escapes_labels_and_help),
		cmocka_unit_test(prom_values_round_trip),
		cmocka_unit_test(prom_daemon_like_metrics_parse),
		cmocka_unit_test(prom_parser_rejects_broken_text),
		cmocka_unit_test(prom_reports_a_full_buffer),
		cmocka_unit_test(prom_histogram_bounds_are_checked),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
