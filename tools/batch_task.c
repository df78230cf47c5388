/* SPDX-License-Identifier: MIT */
/* One task of a batch plan: see tools/batch_task.h. */
#include "tools/batch_task.h"
#include "base/file_replace.h"

#include <errno.h>
#include <jansson.h>
#include <libxml/parser.h>
#include <libxml/tree.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

const char *hl_batch_status_name(enum hl_batch_status s)
{
	return s == HL_BATCH_PASSED ? "passed" : s == HL_BATCH_FAILED ? "failed" : "error";
}

/* Line k (0 = the header) of path into a malloc'd string; NULL at the end or on error. */
static char *read_line(FILE *f, unsigned k, int *ret_err)
{
	char *line = NULL;
	size_t cap = 0;
	ssize_t n = 0;

	for (unsigned i = 0; i <= k; i++) {
		n = getline(&line, &cap, f);
		if (n < 0) {
			*ret_err = ferror(f) ? -EIO : -ENOENT;
			free(line);
			return NULL;
		}
	}
	if (n > 0 && line[n - 1] == '\n')
		line[n - 1] = '\0';
	return line;
}

static const char *str(json_t *o, const char *key)
{
	const char *v = json_string_value(json_object_get(o, key));

	return v ? v : "";
}

int hl_batch_task_read(const char *plan, unsigned index, struct hl_batch_task *t, char *msg,
		       size_t msg_size)
{
	unsigned n;
	char *line;
	json_error_t jerr;
	json_t *j;
	const char *kind, *id;
	FILE *f;
	int rc = hl_batch_plan_count(plan, &n, msg, msg_size);

	*t = (struct hl_batch_task){ 0 };
	if (rc < 0)
		return rc;
	if (index >= n) {
		snprintf(msg, msg_size, "%s: task %u: the plan has %u tasks (0..%u)", plan, index,
			 n, n - 1);
		return -ERANGE;
	}
	f = fopen(plan, "r");
	if (!f) {
		snprintf(msg, msg_size, "%s: %s", plan, strerror(errno));
		return -errno;
	}
	line = read_line(f, index + 1, &rc);
	fclose(f);
	if (!line) {
		snprintf(msg, msg_size, "%s:%u: %s; expected task %u", plan, index + 2,
			 rc == -ENOENT ? "the file ends" : strerror(-rc), index);
		return rc;
	}
	j = json_loads(line, JSON_REJECT_DUPLICATES, &jerr);
	free(line);
	if (!j || !json_is_object(j)) {
		snprintf(msg, msg_size, "%s:%u:%d: %s; expected task %u as a JSON object", plan,
			 index + 2, j ? 1 : jerr.column, j ? "not an object" : jerr.text, index);
		json_decref(j);
		return -EINVAL;
	}
	kind = str(j, "kind");
	id = str(j, "id");
	if (json_integer_value(json_object_get(j, "index")) != (json_int_t)index || !id[0] ||
	    strlen(id) >= sizeof(t->id) ||
	    (strcmp(kind, "suite") && strcmp(kind, "sil") && strcmp(kind, "drive"))) {
		snprintf(msg, msg_size,
			 "%s:%u: expected task %u: \"index\": %u, an \"id\", \"kind\" suite, sil "
			 "or drive",
			 plan, index + 2, index, index);
		json_decref(j);
		return -EINVAL;
	}
	t->index = index;
	snprintf(t->id, sizeof(t->id), "%s", id);
	t->kind = !strcmp(kind, "suite") ? HL_BATCH_SUITE :
		  !strcmp(kind, "sil")	 ? HL_BATCH_SIL :
					   HL_BATCH_DRIVE;
	t->json = j;
	return 0;
}

void hl_batch_task_free(struct hl_batch_task *t)
{
	json_decref(t->json);
	t->json = NULL;
}

/* argv built in a string pool: one block, pointers first. */
struct args {
	char **v;
	int n, cap;
	char *pool;
	size_t used, size;
};

static void add(struct args *a, const char *s)
{
	size_t len = strlen(s) + 1;

	if (a->n + 1 >= a->cap || a->used + len > a->size) {
		a->n = -1;
		return;
	}
	memcpy(a->pool + a->used, s, len);
	a->v[a->n++] = a->pool + a->used;
	a->used += len;
}

static void add2(struct args *a, const char *opt, const char *v)
{
	if (a->n < 0)
		return;
	add(a, opt);
	if (a->n >= 0)
		add(a, v);
}

int hl_batch_task_argv(const struct hl_batch_task *t, const char *self, const char *daemon,
		       const char *dir, char ***ret)
{
	json_t *j = t->json, *sets = json_object_get(t->json, "set"), *v;
	size_t size = 16384 + 2 * PATH_MAX, i;
	struct args a = { .cap = 64 + 2 * (int)json_array_size(sets) };
	char path[PATH_MAX + 32];
	void *block;

	for (i = 0; i < json_array_size(sets); i++)
		size += strlen(json_string_value(json_array_get(sets, i)) ?: "") + 8;
	block = malloc((size_t)a.cap * sizeof(char *) + size);
	if (!block)
		return -ENOMEM;
	a.v = block;
	a.pool = (char *)block + (size_t)a.cap * sizeof(char *);
	a.size = size;
	if (t->kind == HL_BATCH_SUITE) {
		add(&a, self);
		add(&a, "suite");
		add(&a, "run");
		add(&a, str(j, "suite"));
		add2(&a, "--only", str(j, "variant"));
		add2(&a, "--out", dir);
		if (str(j, "preset")[0])
			add2(&a, "--preset", str(j, "preset"));
		else
			add2(&a, "--ecu", str(j, "ecu"));
		if (str(j, "fault")[0])
			add2(&a, "--fault", str(j, "fault"));
		snprintf(path, sizeof(path), "%lld",
			 (long long)json_integer_value(json_object_get(j, "samples")));
		if (json_integer_value(json_object_get(j, "samples")) >= 2)
			add2(&a, "--samples", path);
	} else if (t->kind == HL_BATCH_SIL) {
		add(&a, self);
		add(&a, "sil");
		add(&a, str(j, "scenario"));
		add2(&a, "--ecu", str(j, "ecu"));
		if (str(j, "fault")[0])
			add2(&a, "--fault", str(j, "fault"));
		snprintf(path, sizeof(path), "%s/report.json", dir);
		add2(&a, "--report", path);
		snprintf(path, sizeof(path), "%s/junit.xml", dir);
		add2(&a, "--junit", path);
		snprintf(path, sizeof(path), "%s/trace.log", dir);
		add2(&a, "--trace", path);
	} else {
		add(&a, daemon);
		add2(&a, "--replay", str(j, "log"));
		add2(&a, "--scenario", str(j, "scenario"));
		add(&a, "--exit-at-end");
		snprintf(path, sizeof(path), "%s/report.json", dir);
		add2(&a, "--report", path);
		snprintf(path, sizeof(path), "%s/junit.xml", dir);
		add2(&a, "--junit", path);
		/* tasks side by side on one node: no listening sockets unless the spec sets them */
		add2(&a, "--set", "http.listen=");
		add2(&a, "--set", "stream.tcp=");
	}
	if (str(j, "config")[0])
		add2(&a, "--config", str(j, "config"));
	json_array_foreach(sets, i, v) add2(&a, "--set", json_string_value(v) ?: "");
	if (a.n < 0) {
		free(block);
		return -E2BIG;
	}
	a.v[a.n] = NULL;
	*ret = a.v;
	return 0;
}

/* The task's JUnit: tests, failures and errors counted from its <testcase>s. 0 or -errno (msg). */
static int junit_counts(const char *path, long *tests, long *failures, long *errors, char *msg,
			size_t msg_size)
{
	xmlDocPtr doc =
		xmlReadFile(path, NULL, XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING);
	const xmlError *e;

	*tests = *failures = *errors = 0;
	if (!doc) {
		e = xmlGetLastError();
		if (access(path, F_OK) < 0)
			snprintf(msg, msg_size, "no junit.xml");
		else
			snprintf(msg, msg_size, "junit.xml unreadable: line %d: %s",
				 e ? e->line : 0, e && e->message ? e->message : "not XML");
		return -EINVAL;
	}
	for (xmlNodePtr s = xmlDocGetRootElement(doc)->children; s; s = s->next) {
		if (s->type != XML_ELEMENT_NODE || xmlStrcmp(s->name, BAD_CAST "testsuite"))
			continue;
		for (xmlNodePtr c = s->children; c; c = c->next) {
			if (c->type != XML_ELEMENT_NODE || xmlStrcmp(c->name, BAD_CAST "testcase"))
				continue;
			++*tests;
			for (xmlNodePtr k = c->children; k; k = k->next) {
				if (k->type != XML_ELEMENT_NODE)
					continue;
				*failures += !xmlStrcmp(k->name, BAD_CAST "failure");
				*errors += !xmlStrcmp(k->name, BAD_CAST "error");
			}
		}
	}
	xmlFreeDoc(doc);
	return 0;
}

/* The last non-empty line of the task's log (what a failing command said last). */
static void last_line(const char *log, char *ret, size_t size)
{
	char buf[4096];
	FILE *f = fopen(log, "r");

	ret[0] = '\0';
	if (!f)
		return;
	while (fgets(buf, sizeof(buf), f)) {
		size_t n = strlen(buf);

		while (n && (buf[n - 1] == '\n' || buf[n - 1] == '\r' || buf[n - 1] == ' '))
			buf[--n] = '\0';
		if (n)
			snprintf(ret, size, "%s", buf);
	}
	fclose(f);
}

/* The smallest margin of a suite's lx cases, and the loop's frame latency of a run's report. */
static void from_report(const struct hl_batch_task *t, const char *dir, json_t *res)
{
	char path[PATH_MAX + 32];
	json_t *r, *v, *c, *worst = NULL;
	size_t i, k;

	snprintf(path, sizeof(path), "%s/report.json", dir);
	r = json_load_file(path, 0, NULL);
	if (!r)
		return;
	if (t->kind == HL_BATCH_SUITE) {
		double best = 0;

		json_array_foreach(json_object_get(r, "variants"), i, v)
			json_array_foreach(json_object_get(v, "cases"), k, c)
		{
			json_t *m = json_object_get(c, "margin");

			if (!json_is_number(m) || strcmp(str(c, "unit"), "lx"))
				continue;
			if (!worst || json_number_value(m) < best) {
				best = json_number_value(m);
				json_decref(worst);
				worst = json_pack("{s:s, s:f}", "case", str(c, "name"), "margin_lx",
						  best);
			}
		}
	} else {
		json_t *fr = json_object_get(
			json_object_get(json_object_get(r, "loop"), "latency_ms"), "frame");

		if (json_integer_value(json_object_get(fr, "n")) > 0)
			json_object_set(res, "latency_ms", fr);
	}
	if (worst)
		json_object_set_new(res, "worst", worst);
	json_decref(r);
}

static void write_json(void *ctx, FILE *f)
{
	json_dumpf(ctx, f, JSON_INDENT(1) | JSON_PRESERVE_ORDER);
	fputc('\n', f);
}

int hl_batch_result_write(const struct hl_batch_task *t, const char *dir,
			  struct hl_batch_outcome *oc, char *msg, size_t msg_size)
{
	char path[PATH_MAX + 32], host[256] = "", why[448] = "";
	long tests = 0, failures = 0, errors = 0;
	json_t *j = t->json, *res;
	int rc;

	gethostname(host, sizeof(host) - 1);
	snprintf(path, sizeof(path), "%s/junit.xml", dir);
	if (oc->ran && !oc->signal && (oc->exit == 0 || oc->exit == 3) &&
	    junit_counts(path, &tests, &failures, &errors, why, sizeof(why)) < 0) {
		/* a verdict without its JUnit is not a result */
		snprintf(oc->reason, sizeof(oc->reason), "exit %d but %s", oc->exit, why);
		oc->exit = 1;
	}
	if (!oc->ran || oc->reason[0]) {
		oc->status = HL_BATCH_ERROR;
	} else if (oc->stop_signal) {
		oc->status = HL_BATCH_ERROR;
		snprintf(
			oc->reason, sizeof(oc->reason),
			"stopped by SIG%s (scancel, the scheduler's time limit or a node shutdown)",
			sigabbrev_np(oc->stop_signal) ?: "?");
		oc->exit = 1;
	} else if (oc->signal) {
		oc->status = HL_BATCH_ERROR;
		snprintf(oc->reason, sizeof(oc->reason), "crashed: signal %d (%s)%s", oc->signal,
			 strsignal(oc->signal),
			 oc->signal == SIGKILL ? ": killed (out of memory, or a time limit)" : "");
	} else if (oc->exit == 0 || oc->exit == 3) {
		oc->status = oc->exit == 0 ? HL_BATCH_PASSED : HL_BATCH_FAILED;
	} else {
		oc->status = HL_BATCH_ERROR;
		snprintf(path, sizeof(path), "%s/log.txt", dir);
		last_line(path, why, sizeof(why));
		snprintf(oc->reason, sizeof(oc->reason), "exit %d%s: %s", oc->exit,
			 oc->exit == 2 ? " (bad input)" : "", why[0] ? why : "(no message)");
	}
	res = json_pack("{s:s, s:i, s:i, s:s, s:s}", "result", "hdlamp batch task", "version", 1,
			"index", (int)t->index, "id", t->id, "kind",
			t->kind == HL_BATCH_SUITE ? "suite" :
			t->kind == HL_BATCH_SIL	  ? "sil" :
						    "drive");
	json_object_set_new(res, "suite", json_string(str(j, "suite")));
	json_object_set_new(res, "variant", json_string(str(j, "variant")));
	json_object_set_new(res, "scenario", json_string(str(j, "scenario")));
	json_object_set_new(res, "log", json_string(str(j, "log")));
	json_object_set_new(res, "ecu", json_string(str(j, "ecu")));
	json_object_set_new(res, "fault", json_string(str(j, "fault")));
	json_object_set_new(res, "preset", json_string(str(j, "preset")));
	json_object_set_new(res, "status", json_string(hl_batch_status_name(oc->status)));
	json_object_set_new(res, "exit", json_integer(oc->exit));
	json_object_set_new(res, "signal", json_integer(oc->signal));
	json_object_set_new(res, "reason", json_string(oc->reason));
	json_object_set_new(res, "host", json_string(host));
	json_object_set_new(res, "started_unix", json_real(oc->started_unix));
	json_object_set_new(res, "duration_s", json_real(oc->duration_s));
	json_object_set_new(res, "tests", json_integer(tests));
	json_object_set_new(res, "failures", json_integer(failures));
	json_object_set_new(res, "errors", json_integer(errors));
	json_object_set_new(res, "worst", json_null());
	json_object_set_new(res, "latency_ms", json_null());
	if (oc->status != HL_BATCH_ERROR)
		from_report(t, dir, res);
	snprintf(path, sizeof(path), "%s/result.json", dir);
	rc = hl_file_replace(path, write_json, res);
	json_decref(res);
	if (rc < 0)
		snprintf(msg, msg_size, "'%s': %s", path, strerror(-rc));
	return rc;
}

bool hl_batch_task_finished(const char *dir, unsigned index, const char *id)
{
	char path[PATH_MAX + 32];
	json_t *r, *e;
	bool done;

	snprintf(path, sizeof(path), "%s/%u/result.json", dir, index);
	r = json_load_file(path, 0, NULL);
	if (!r)
		return false;
	e = json_object_get(r, "exit");
	done = json_is_integer(e) &&
	       (json_integer_value(e) == 0 || json_integer_value(e) == 2 ||
		json_integer_value(e) == 3) &&
	       json_integer_value(json_object_get(r, "index")) == index &&
	       (!id || !strcmp(str(r, "id"), id));
	json_decref(r);
	return done;
}

int hl_batch_unfinished_list(const char *plan, const char *dir, char *buf, size_t buf_size,
			     char *msg, size_t msg_size)
{
	unsigned n, count = 0;
	size_t used = 0;
	long start = -1;
	int rc = hl_batch_plan_count(plan, &n, msg, msg_size);
	FILE *f;
	char *line = NULL;
	size_t cap = 0;

	if (rc < 0)
		return rc;
	f = fopen(plan, "r");
	if (!f) {
		snprintf(msg, msg_size, "%s: %s", plan, strerror(errno));
		return -errno;
	}
	buf[0] = '\0';
	if (getline(&line, &cap, f) < 0) /* the header */
		n = 0;
	for (unsigned i = 0; i <= n; i++) {
		bool to_run = false;

		if (i < n) {
			json_t *j = getline(&line, &cap, f) >= 0 ? json_loads(line, 0, NULL) : NULL;

			to_run = !hl_batch_task_finished(dir, i, j ? str(j, "id") : "");
			json_decref(j);
		}
		if (to_run && start < 0)
			start = i;
		if (!to_run && start >= 0) {
			int w = (unsigned)start == i - 1 ?
					snprintf(buf + used, buf_size - used, "%s%ld",
						 used ? "," : "", start) :
					snprintf(buf + used, buf_size - used, "%s%ld-%u",
						 used ? "," : "", start, i - 1);

			if (w < 0 || (size_t)w >= buf_size - used) {
				snprintf(msg, msg_size, "the list of unfinished tasks is too long");
				free(line);
				fclose(f);
				return -E2BIG;
			}
			used += (size_t)w;
			count += i - (unsigned)start;
			start = -1;
		}
	}
	free(line);
	fclose(f);
	return (int)count;
}

void hl_batch_stem(const char *path, const char *ext, char *ret, size_t size)
{
	const char *b = strrchr(path, '/');
	size_t n;
	char *dot;

	b = b ? b + 1 : path;
	n = strnlen(b, size - 1);
	memcpy(ret, b, n);
	ret[n] = '\0';
	if (!ext) {
		dot = strrchr(ret, '.');
		if (dot && dot != ret)
			*dot = '\0';
	} else if (n > strlen(ext) && !strcmp(ret + n - strlen(ext), ext)) {
		ret[n - strlen(ext)] = '\0';
	}
}
