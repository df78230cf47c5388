/* SPDX-License-Identifier: MIT */
/*
 * hdlamp batch merge DIR [--plan PLAN] [--junit F] [--html F] [--json F]: every task of the plan
 * read from DIR/N/ one at a time (memory bounded, independent of the number of tasks) into one
 * JUnit, one dashboard page and one JSON summary. A task without a usable result — never run,
 * killed, crashed, half written, of another plan — is an error with its reason, never dropped.
 */
#include <errno.h>
#include <getopt.h>
#include <jansson.h>
#include <libxml/parser.h>
#include <libxml/tree.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "commands.h"
#include "base/file_replace.h"
#include "base/make_dirs.h"
#include "base/xml_write.h"
#include "tools/batch.h"
#include "tools/batch_task.h"

#define PROG "hdlamp batch merge"

/* Log-spaced bins of the tasks' latencies: 1 us .. 100 s, 400 a decade (0.58 % wide). */
#define LAT_LO_MS 1e-3
#define LAT_PER_DECADE 400
#define LAT_BINS (8 * LAT_PER_DECADE)

struct hist {
	unsigned long n, bin[LAT_BINS];
	double max;
};

struct merge {
	const char *dir, *plan;
	struct hl_batch_summary s;
	unsigned cap_suite, cap_scenario, cap_ecu, cap_preset;
	struct hist p50, p99;
	FILE *junit_body; /* the <testsuite>s, before the totals are known */
	FILE *errors; /* one JSON object per line: every error */
	unsigned cap_errors_list;
};

static void usage(FILE *f)
{
	fputs("usage: hdlamp batch merge DIR [--plan PLAN.jsonl] [--junit FILE] [--html FILE]\n"
	      "                          [--json FILE]\n"
	      "Reads every task of the plan (default DIR/plan.jsonl) from DIR/N/ and writes one\n"
	      "JUnit (a <testsuite> per task's suite, named after the task's id; a task without a\n"
	      "result is an <error> with its reason), a dashboard page (pass/fail by suite,\n"
	      "scenario, ECU and preset, the worst margins, the loop latency over the tasks, the\n"
	      "errors, links to each task's page) and a JSON summary. Memory does not grow with\n"
	      "the number of tasks.\n"
	      "Exit: 0 every task passed, 3 one failed or has no result, 2 bad input, 1 an output\n"
	      "could not be written.\n",
	      f);
}

static const char *str(json_t *o, const char *key)
{
	const char *v = json_string_value(json_object_get(o, key));

	return v ? v : "";
}

static void hist_add(struct hist *h, double ms)
{
	int b;

	if (!isfinite(ms) || ms < 0)
		return;
	b = ms <= LAT_LO_MS ? 0 : (int)floor(log10(ms / LAT_LO_MS) * LAT_PER_DECADE);
	h->bin[b < 0 ? 0 : b >= LAT_BINS ? LAT_BINS - 1 : b]++;
	h->n++;
	if (ms > h->max)
		h->max = ms;
}

/* The q-quantile (nearest rank) at its bin's geometric middle. */
static double hist_quantile(const struct hist *h, double q)
{
	unsigned long rank = (unsigned long)ceil(q * (double)h->n), seen = 0;

	if (rank < 1)
		rank = 1;
	for (int b = 0; b < LAT_BINS; b++) {
		seen += h->bin[b];
		if (seen >= rank)
			return fmin(h->max, LAT_LO_MS * pow(10, (b + 0.5) / LAT_PER_DECADE));
	}
	return h->max;
}

static int group_add(struct hl_batch_group **g, unsigned *n, unsigned *cap, const char *key,
		     int status)
{
	unsigned i;

	if (!key[0])
		return 0;
	for (i = 0; i < *n && strcmp((*g)[i].key, key); i++)
		;
	if (i == *n) {
		if (*n == *cap) {
			unsigned c = *cap ? 2 * *cap : 16;
			struct hl_batch_group *m = realloc(*g, c * sizeof(*m));

			if (!m)
				return -ENOMEM;
			*g = m;
			*cap = c;
		}
		(*g)[i] = (struct hl_batch_group){ 0 };
		snprintf((*g)[i].key, sizeof((*g)[i].key), "%s", key);
		(*n)++;
	}
	if (status == 0)
		(*g)[i].passed++;
	else if (status == 3)
		(*g)[i].failed++;
	else
		(*g)[i].errors++;
	return 0;
}

static int add_groups(struct merge *m, json_t *task, int status)
{
	struct hl_batch_summary *s = &m->s;
	const char *kind = str(task, "kind");
	char key[256], name[200];
	int rc = 0;

	if (!strcmp(kind, "suite")) {
		hl_batch_stem(str(task, "suite"), NULL, name, sizeof(name));
		rc = group_add(&s->by_suite, &s->n_suite, &m->cap_suite, name, status);
		snprintf(key, sizeof(key), "%s/%s", name, str(task, "variant"));
	} else {
		hl_batch_stem(str(task, !strcmp(kind, "drive") ? "log" : "scenario"), NULL, name,
			      sizeof(name));
		snprintf(key, sizeof(key), "%s %s", !strcmp(kind, "drive") ? "drive" : "sil", name);
	}
	if (!rc)
		rc = group_add(&s->by_scenario, &s->n_scenario, &m->cap_scenario, key, status);
	if (!strcmp(kind, "drive")) {
		snprintf(key, sizeof(key), "recorded");
	} else if (str(task, "ecu")[0]) {
		hl_batch_stem(str(task, "ecu"), NULL, name, sizeof(name));
		snprintf(key, sizeof(key), "%s%s%s", name, str(task, "fault")[0] ? " + " : "",
			 str(task, "fault"));
	} else {
		key[0] = '\0';
	}
	if (!rc)
		rc = group_add(&s->by_ecu, &s->n_ecu, &m->cap_ecu, key, status);
	if (!rc)
		rc = group_add(&s->by_preset, &s->n_preset, &m->cap_preset, str(task, "preset"),
			       status);
	return rc;
}

static void add_worst(struct merge *m, unsigned index, const char *id, json_t *worst)
{
	struct hl_batch_summary *s = &m->s;
	double margin = json_number_value(json_object_get(worst, "margin_lx"));
	unsigned k;

	if (!json_is_number(json_object_get(worst, "margin_lx")))
		return;
	for (k = s->n_worst; k > 0 && s->worst[k - 1].margin_lx > margin; k--)
		;
	if (k >= HL_BATCH_WORST_N)
		return;
	if (s->n_worst < HL_BATCH_WORST_N)
		s->n_worst++;
	memmove(&s->worst[k + 1], &s->worst[k], (s->n_worst - 1 - k) * sizeof(s->worst[0]));
	s->worst[k] = (struct hl_batch_worst){ .index = index, .margin_lx = margin };
	snprintf(s->worst[k].id, sizeof(s->worst[k].id), "%s", id);
	snprintf(s->worst[k].case_name, sizeof(s->worst[k].case_name), "%s", str(worst, "case"));
}

static void junit_error(struct merge *m, const char *id, const char *reason)
{
	FILE *f = m->junit_body;

	fputs("  <testsuite name=\"", f);
	hl_xml_write_text(f, id);
	fputs("\" tests=\"1\" failures=\"0\" errors=\"1\" skipped=\"0\">\n"
	      "    <testcase classname=\"",
	      f);
	hl_xml_write_text(f, id);
	fputs("\" name=\"task\">\n      <error message=\"", f);
	hl_xml_write_text(f, reason);
	fputs("\"/>\n    </testcase>\n  </testsuite>\n", f);
	m->s.tests++;
	m->s.test_errors++;
}

static int add_error(struct merge *m, unsigned index, const char *id, const char *reason)
{
	struct hl_batch_summary *s = &m->s;
	json_t *e = json_pack("{s:i, s:s, s:s}", "index", (int)index, "id", id, "reason", reason);

	json_dumpf(e, m->errors, JSON_COMPACT | JSON_PRESERVE_ORDER);
	fputc('\n', m->errors);
	json_decref(e);
	junit_error(m, id, reason);
	s->errors++;
	if (s->n_errors_list < 100) {
		if (s->n_errors_list == m->cap_errors_list) {
			unsigned c = m->cap_errors_list ? 2 * m->cap_errors_list : 16;
			struct hl_batch_error *l = realloc(s->errors_list, c * sizeof(*l));

			if (!l)
				return -ENOMEM;
			s->errors_list = l;
			m->cap_errors_list = c;
		}
		s->errors_list[s->n_errors_list] = (struct hl_batch_error){ .index = index };
		snprintf(s->errors_list[s->n_errors_list].id, HL_BATCH_ID_MAX, "%s", id);
		snprintf(s->errors_list[s->n_errors_list].reason, sizeof(s->errors_list[0].reason),
			 "%s", reason);
		s->n_errors_list++;
	}
	return 0;
}

/* The task's JUnit copied into the merged one: each <testsuite> named after the task, each
 * <testcase>'s classname the task's id. 0, or -EINVAL with why. */
static int junit_copy(struct merge *m, const char *path, const char *id, char *why, size_t size)
{
	xmlDocPtr doc =
		xmlReadFile(path, NULL, XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING);
	xmlNodePtr root;
	xmlBufferPtr buf;

	if (!doc) {
		const xmlError *e = xmlGetLastError();

		if (access(path, F_OK) < 0)
			snprintf(why, size, "no junit.xml (the result says it ran)");
		else
			snprintf(why, size, "junit.xml unreadable: line %d: %s", e ? e->line : 0,
				 e && e->message ? e->message : "not XML");
		return -EINVAL;
	}
	root = xmlDocGetRootElement(doc);
	buf = xmlBufferCreate();
	for (xmlNodePtr s = root ? root->children : NULL; s && buf; s = s->next) {
		unsigned long tests = 0, failures = 0, errors = 0;
		xmlChar *orig;

		if (s->type != XML_ELEMENT_NODE || xmlStrcmp(s->name, BAD_CAST "testsuite"))
			continue;
		for (xmlNodePtr c = s->children; c; c = c->next) {
			if (c->type != XML_ELEMENT_NODE || xmlStrcmp(c->name, BAD_CAST "testcase"))
				continue;
			tests++;
			for (xmlNodePtr k = c->children; k; k = k->next) {
				failures += k->type == XML_ELEMENT_NODE &&
					    !xmlStrcmp(k->name, BAD_CAST "failure");
				errors += k->type == XML_ELEMENT_NODE &&
					  !xmlStrcmp(k->name, BAD_CAST "error");
			}
		}
		orig = xmlGetProp(s, BAD_CAST "name");
		fputs("  <testsuite name=\"", m->junit_body);
		hl_xml_write_text(m->junit_body, id);
		fprintf(m->junit_body,
			"\" tests=\"%lu\" failures=\"%lu\" errors=\"%lu\" skipped=\"0\">\n"
			"    <properties>\n      <property name=\"task_suite\" value=\"",
			tests, failures, errors);
		hl_xml_write_text(m->junit_body, orig ? (const char *)orig : "");
		fputs("\"/>\n    </properties>\n", m->junit_body);
		xmlFree(orig);
		for (xmlNodePtr c = s->children; c; c = c->next) {
			if (c->type != XML_ELEMENT_NODE || xmlStrcmp(c->name, BAD_CAST "testcase"))
				continue;
			xmlSetProp(c, BAD_CAST "classname", BAD_CAST id);
			xmlBufferEmpty(buf);
			xmlNodeDump(buf, doc, c, 2, 1);
			fprintf(m->junit_body, "    %s\n", (const char *)xmlBufferContent(buf));
		}
		fputs("  </testsuite>\n", m->junit_body);
		m->s.tests += tests;
		m->s.test_failures += failures;
		m->s.test_errors += errors;
	}
	xmlBufferFree(buf);
	xmlFreeDoc(doc);
	return 0;
}

/* Why task index has no result, from what its folder holds. */
static void no_result_reason(const char *tdir, unsigned index, char *why, size_t size)
{
	char path[PATH_MAX + 32];
	struct stat st;
	json_t *s;

	snprintf(path, sizeof(path), "%s/started.json", tdir);
	s = json_load_file(path, 0, NULL);
	if (s) {
		time_t t = (time_t)json_number_value(json_object_get(s, "started_unix"));
		char when[64];

		strftime(when, sizeof(when), "%Y-%m-%dT%H:%M:%SZ", gmtime(&t));
		snprintf(why, size,
			 "no result: started on %s at %s (pid %lld) and never finished: killed "
			 "(the scheduler's time limit, out of memory, scancel), or its node lost",
			 str(s, "host"), when,
			 (long long)json_integer_value(json_object_get(s, "pid")));
		json_decref(s);
	} else if (stat(tdir, &st) == 0) {
		snprintf(why, size,
			 "no result: its folder exists but the task never started "
			 "(no started.json)");
	} else {
		snprintf(why, size, "no result: the task never ran (no folder %u/)", index);
	}
}

static int merge_task(struct merge *m, unsigned index, json_t *task)
{
	char tdir[PATH_MAX], path[PATH_MAX + 32], why[1024];
	const char *id = str(task, "id");
	json_error_t jerr;
	json_t *r;
	int status;

	snprintf(tdir, sizeof(tdir), "%s/%u", m->dir, index);
	snprintf(path, sizeof(path), "%s/result.json", tdir);
	r = json_load_file(path, JSON_REJECT_DUPLICATES, &jerr);
	why[0] = '\0';
	if (!r) {
		if (access(path, F_OK) < 0)
			no_result_reason(tdir, index, why, sizeof(why));
		else
			snprintf(why, sizeof(why),
				 "result.json unreadable (half written?): line %d: %s", jerr.line,
				 jerr.text);
	} else if (strcmp(str(r, "id"), id) ||
		   json_integer_value(json_object_get(r, "index")) != index) {
		snprintf(why, sizeof(why),
			 "result.json is of another task ('%s'): the plan changed since it ran",
			 str(r, "id"));
	} else if (!strcmp(str(r, "status"), "error")) {
		snprintf(why, sizeof(why), "%s", str(r, "reason"));
	} else if (strcmp(str(r, "status"), "passed") && strcmp(str(r, "status"), "failed")) {
		snprintf(why, sizeof(why),
			 "result.json: status '%s': expected passed, failed or error",
			 str(r, "status"));
	} else {
		snprintf(path, sizeof(path), "%s/junit.xml", tdir);
		junit_copy(m, path, id, why, sizeof(why));
	}
	status = why[0] ? 1 : !strcmp(str(r, "status"), "passed") ? 0 : 3;
	if (status == 1) {
		if (add_error(m, index, id, why) < 0) {
			json_decref(r);
			return -ENOMEM;
		}
	} else {
		json_t *lat = json_object_get(r, "latency_ms");

		if (status == 0)
			m->s.passed++;
		else
			m->s.failed++;
		if (json_is_object(json_object_get(r, "worst")))
			add_worst(m, index, id, json_object_get(r, "worst"));
		if (json_is_object(lat) && json_integer_value(json_object_get(lat, "n")) > 0) {
			m->s.latency_tasks++;
			hist_add(&m->p50, json_number_value(json_object_get(lat, "p50")));
			hist_add(&m->p99, json_number_value(json_object_get(lat, "p99")));
			if (json_number_value(json_object_get(lat, "max")) > m->s.max_of_max)
				m->s.max_of_max = json_number_value(json_object_get(lat, "max"));
		}
	}
	json_decref(r);
	m->s.tasks++;
	return add_groups(m, task, status);
}

static void copy_stream(FILE *from, FILE *to)
{
	char buf[65536];
	size_t n;

	rewind(from);
	while ((n = fread(buf, 1, sizeof(buf), from)) > 0)
		fwrite(buf, 1, n, to);
}

static void write_junit(void *ctx, FILE *f)
{
	struct merge *m = ctx;

	fprintf(f,
		"<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
		"<testsuites name=\"hdlamp batch\" tests=\"%lu\" failures=\"%lu\" errors=\"%lu\">\n",
		m->s.tests, m->s.test_failures, m->s.test_errors);
	copy_stream(m->junit_body, f);
	fputs("</testsuites>\n", f);
}

static json_t *groups_json(const struct hl_batch_group *g, unsigned n)
{
	json_t *a = json_array();

	for (unsigned i = 0; i < n; i++)
		json_array_append_new(a, json_pack("{s:s, s:i, s:i, s:i}", "key", g[i].key,
						   "passed", g[i].passed, "failed", g[i].failed,
						   "errors", g[i].errors));
	return a;
}

static void write_json(void *ctx, FILE *f)
{
	struct merge *m = ctx;
	const struct hl_batch_summary *s = &m->s;
	json_t *j = json_pack("{s:s, s:i, s:s, s:s}", "summary", "hdlamp batch merge", "version", 1,
			      "plan", m->plan, "verdict",
			      s->tasks && s->passed == s->tasks ? "passed" : "failed");
	json_t *w = json_array();
	char *text, *cut;
	char line[8192];

	json_object_set_new(j, "tasks", json_integer(s->tasks));
	json_object_set_new(j, "passed", json_integer(s->passed));
	json_object_set_new(j, "failed", json_integer(s->failed));
	json_object_set_new(j, "errors", json_integer(s->errors));
	json_object_set_new(j, "tests", json_integer((json_int_t)s->tests));
	json_object_set_new(j, "test_failures", json_integer((json_int_t)s->test_failures));
	json_object_set_new(j, "test_errors", json_integer((json_int_t)s->test_errors));
	json_object_set_new(j, "by_suite", groups_json(s->by_suite, s->n_suite));
	json_object_set_new(j, "by_scenario", groups_json(s->by_scenario, s->n_scenario));
	json_object_set_new(j, "by_ecu", groups_json(s->by_ecu, s->n_ecu));
	json_object_set_new(j, "by_preset", groups_json(s->by_preset, s->n_preset));
	for (unsigned i = 0; i < s->n_worst; i++)
		json_array_append_new(w,
				      json_pack("{s:i, s:s, s:s, s:f}", "index", s->worst[i].index,
						"id", s->worst[i].id, "case", s->worst[i].case_name,
						"margin_lx", s->worst[i].margin_lx));
	json_object_set_new(j, "worst", w);
	json_object_set_new(j, "latency_ms",
			    s->latency_tasks ?
				    json_pack("{s:i, s:f, s:f, s:f, s:f}", "tasks",
					      s->latency_tasks, "p50_of_p50", s->p50_of_p50,
					      "p50_of_p99", s->p50_of_p99, "p99_of_p99",
					      s->p99_of_p99, "max_of_max", s->max_of_max) :
				    json_null());
	json_object_set_new(j, "errors_list", json_array());
	/* every error, streamed from the errors file into the array's place */
	text = json_dumps(j, JSON_INDENT(1) | JSON_PRESERVE_ORDER);
	json_decref(j);
	if (!text)
		return;
	cut = strstr(text, "\"errors_list\": []");
	if (!cut) {
		fputs(text, f);
		free(text);
		return;
	}
	fwrite(text, 1, (size_t)(cut - text), f);
	fputs("\"errors_list\": [", f);
	rewind(m->errors);
	for (bool first = true; fgets(line, sizeof(line), m->errors); first = false) {
		line[strcspn(line, "\n")] = '\0';
		fprintf(f, "%s\n  %s", first ? "" : ",", line);
	}
	fputs("]", f);
	fputs(cut + strlen("\"errors_list\": []"), f);
	fputc('\n', f);
	free(text);
}

/* s as a URL path: every byte but A-Z a-z 0-9 - . _ ~ / : percent-encoded (RFC 3986, 2.1). */
static void url_encode(const char *s, char *ret, size_t size)
{
	size_t used = 0;

	for (; *s && used + 4 < size; s++) {
		unsigned char c = (unsigned char)*s;

		if ((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
		    strchr("-._~/:", c))
			ret[used++] = (char)c;
		else
			used += (size_t)snprintf(ret + used, size - used, "%%%02X", c);
	}
	ret[used] = '\0';
}

/* The page's folder made; its links to the tasks relative to it. */
static int html_out(struct merge *m, const char *path)
{
	char dir[PATH_MAX], rdir[PATH_MAX], rtasks[PATH_MAX], prefix[PATH_MAX * 2];
	char url[PATH_MAX * 6];
	const char *slash = strrchr(path, '/');
	int rc;

	snprintf(dir, sizeof(dir), "%.*s", slash ? (int)(slash - path) : 1, slash ? path : ".");
	if (!dir[0])
		snprintf(dir, sizeof(dir), "/");
	rc = hl_make_dirs(dir);
	if (rc < 0)
		return rc;
	if (!realpath(dir, rdir) || !realpath(m->dir, rtasks))
		return -errno;
	/* a relative link when the tasks lie below or beside the page's folder, else file:// */
	{
		size_t n = strlen(rdir);
		const char *up = "";
		char parent[PATH_MAX];

		if (!strncmp(rtasks, rdir, n) && (rtasks[n] == '/' || !rtasks[n])) {
			snprintf(prefix, sizeof(prefix), "%s%s", rtasks[n] ? rtasks + n + 1 : "",
				 rtasks[n] ? "/" : "");
		} else {
			snprintf(parent, sizeof(parent), "%s", rdir);
			char *p = strrchr(parent, '/');

			if (p)
				*p = '\0';
			n = strlen(parent);
			up = "../";
			if (n && !strncmp(rtasks, parent, n) && rtasks[n] == '/')
				snprintf(prefix, sizeof(prefix), "%s%s/", up, rtasks + n + 1);
			else if (!n || !strcmp(rtasks, parent))
				snprintf(prefix, sizeof(prefix), "%s", up);
			else
				snprintf(prefix, sizeof(prefix), "file://%s/", rtasks);
		}
	}
	url_encode(prefix, url, sizeof(url));
	return hl_batch_html_write(&m->s, url, path);
}

static int parent_dirs(const char *path)
{
	char dir[PATH_MAX];
	const char *slash = strrchr(path, '/');

	if (!slash || slash == path)
		return 0;
	snprintf(dir, sizeof(dir), "%.*s", (int)(slash - path), path);
	return hl_make_dirs(dir);
}

int hl_batch_merge_cmd(int argc, char **argv)
{
	static const struct option opts[] = {
		{ "plan", required_argument, NULL, 'p' }, { "junit", required_argument, NULL, 'j' },
		{ "html", required_argument, NULL, 'w' }, { "json", required_argument, NULL, 'J' },
		{ "help", no_argument, NULL, 'h' },	  { NULL, 0, NULL, 0 },
	};
	const char *junit = NULL, *html = NULL, *jsonp = NULL;
	char plan[PATH_MAX + 32], msg[1024];
	struct merge m = { 0 };
	char *line = NULL;
	size_t cap = 0;
	unsigned n;
	FILE *f = NULL;
	int c, rc = 0;

	plan[0] = '\0';
	optind = 1;
	while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
		switch (c) {
		case 'p':
			snprintf(plan, sizeof(plan), "%s", optarg);
			break;
		case 'j':
			junit = optarg;
			break;
		case 'w':
			html = optarg;
			break;
		case 'J':
			jsonp = optarg;
			break;
		case 'h':
			usage(stdout);
			return 0;
		default:
			usage(stderr);
			return 2;
		}
	}
	if (optind != argc - 1) {
		usage(stderr);
		return 2;
	}
	m.dir = argv[optind];
	if (!plan[0])
		snprintf(plan, sizeof(plan), "%s/plan.jsonl", m.dir);
	m.plan = plan;
	rc = hl_batch_plan_count(plan, &n, msg, sizeof(msg));
	if (rc < 0) {
		fprintf(stderr, PROG ": %s\n", msg);
		return 2;
	}
	f = fopen(plan, "r");
	m.junit_body = tmpfile();
	m.errors = tmpfile();
	if (!f || !m.junit_body || !m.errors) {
		fprintf(stderr, PROG ": %s\n", strerror(errno));
		rc = 1;
		goto out;
	}
	getline(&line, &cap, f); /* the header, read by hl_batch_plan_count */
	for (unsigned i = 0; i < n && rc == 0; i++) {
		json_error_t jerr;
		json_t *task = getline(&line, &cap, f) >= 0 ?
				       json_loads(line, JSON_REJECT_DUPLICATES, &jerr) :
				       NULL;

		if (!task || json_integer_value(json_object_get(task, "index")) != i) {
			fprintf(stderr,
				PROG ": %s:%u: expected task %u (a JSON line with \"index\": %u)\n",
				plan, i + 2, i, i);
			json_decref(task);
			rc = 2;
			break;
		}
		if (merge_task(&m, i, task) < 0)
			rc = 1;
		json_decref(task);
	}
	if (rc)
		goto out;
	m.s.p50_of_p50 = hist_quantile(&m.p50, 0.5);
	m.s.p50_of_p99 = hist_quantile(&m.p99, 0.5);
	m.s.p99_of_p99 = hist_quantile(&m.p99, 0.99);
	if (fflush(m.junit_body) || fflush(m.errors)) {
		fprintf(stderr, PROG ": a temporary file: %s\n", strerror(errno));
		rc = 1;
		goto out;
	}
	if (junit &&
	    (parent_dirs(junit) < 0 || (rc = hl_file_replace(junit, write_junit, &m)) < 0)) {
		fprintf(stderr, PROG ": --junit '%s': %s\n", junit, strerror(rc < 0 ? -rc : errno));
		rc = 1;
		goto out;
	}
	if (jsonp &&
	    (parent_dirs(jsonp) < 0 || (rc = hl_file_replace(jsonp, write_json, &m)) < 0)) {
		fprintf(stderr, PROG ": --json '%s': %s\n", jsonp, strerror(rc < 0 ? -rc : errno));
		rc = 1;
		goto out;
	}
	if (html && (rc = html_out(&m, html)) < 0) {
		fprintf(stderr, PROG ": --html '%s': %s\n", html, strerror(-rc));
		rc = 1;
		goto out;
	}
	fprintf(stderr,
		PROG ": %u tasks: %u passed, %u failed, %u errors; %lu tests, %lu failures, %lu "
		     "errors: %s\n",
		m.s.tasks, m.s.passed, m.s.failed, m.s.errors, m.s.tests, m.s.test_failures,
		m.s.test_errors, m.s.tasks && m.s.passed == m.s.tasks ? "PASSED" : "FAILED");
	for (unsigned i = 0; i < m.s.n_errors_list && i < 10; i++)
		fprintf(stderr, PROG ": task %u (%s): %s\n", m.s.errors_list[i].index,
			m.s.errors_list[i].id, m.s.errors_list[i].reason);
	rc = m.s.tasks && m.s.passed == m.s.tasks ? 0 : 3;
out:
	free(line);
	if (f)
		fclose(f);
	if (m.junit_body)
		fclose(m.junit_body);
	if (m.errors)
		fclose(m.errors);
	free(m.s.by_suite);
	free(m.s.by_scenario);
	free(m.s.by_ecu);
	free(m.s.by_preset);
	free(m.s.errors_list);
	return rc;
}
