/* SPDX-License-Identifier: MIT */
/*
 * hdlamp batch plan SPEC.json --out PLAN.jsonl: the matrix of a spec expanded into one line per
 * task (tools/batch.h; the spec's format in docs/scale.md, "The spec").
 */
#include <dirent.h>
#include <errno.h>
#include <getopt.h>
#include <jansson.h>
#include <libgen.h>
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "commands.h"
#include "base/file_replace.h"
#include "tools/batch.h"
#include "tools/batch_task.h"
#include "tools/suite_run.h"
#include "verdict/suite_plan.h"

#define PROG "hdlamp batch plan"

struct plan {
	const char *spec_path;
	char spec_dir[PATH_MAX];
	json_t *root;
	json_t *ecus, *faults, *presets; /* arrays of strings */
	json_t *root_scenarios, *root_drives; /* arrays of strings */
	char config[PATH_MAX]; /* absolute, or "" */
	json_t *sets; /* array of strings */
	FILE *out;
	unsigned n;
	/* the ids so far, to refuse a duplicate (two scenarios of the same name) */
	char **ids;
	unsigned n_ids, cap_ids;
};

static void usage(FILE *f)
{
	fputs("usage: hdlamp batch plan SPEC.json --out PLAN.jsonl\n"
	      "Expands the spec's matrix (docs/scale.md, \"The spec\") into one task per line:\n"
	      "every variant of each suite x (each ECU x each fault, and each preset), each\n"
	      "scenario x each ECU x each fault (hdlamp sil), each recorded drive of the drive\n"
	      "folders (LOG.log with its scenario LOG.json beside it, replayed by hdlampd).\n"
	      "Paths are resolved against the spec's folder and written absolute.\n"
	      "Exit: 0 written, 2 bad input (the file, the key and what was expected), 1 the plan\n"
	      "could not be written.\n",
	      f);
}

static int fail(const struct plan *p, const char *key, const char *what)
{
	fprintf(stderr, PROG ": %s: key '%s': %s\n", p->spec_path, key, what);
	return 2;
}

/* path resolved against the spec's folder into ret (absolute, not required to exist). */
static int resolve(const struct plan *p, const char *path, char *ret, size_t size)
{
	int n = path[0] == '/' ? snprintf(ret, size, "%s", path) :
				 snprintf(ret, size, "%s/%s", p->spec_dir, path);

	return n < 0 || (size_t)n >= size ? -ENAMETOOLONG : 0;
}

/* key: absent = def (a one-element array of def, or empty when def is NULL); else an array of
 * strings. */
static int strings(struct plan *p, const char *key, const char *def, json_t **ret)
{
	json_t *a = json_object_get(p->root, key);
	size_t i;
	json_t *v;

	if (!a) {
		*ret = json_array();
		if (def)
			json_array_append_new(*ret, json_string(def));
		return 0;
	}
	if (!json_is_array(a))
		return fail(p, key, "expected an array of strings");
	json_array_foreach(a, i, v)
	{
		if (!json_is_string(v)) {
			char k[64];

			snprintf(k, sizeof(k), "%s[%zu]", key, i);
			return fail(p, k, "expected a string");
		}
	}
	*ret = json_incref(a);
	return 0;
}

/* The task's id into id (HL_BATCH_ID_MAX): 0, or 2 (too long, told). */
static int make_id(const struct plan *p, char *id, const char *fmt, ...)
{
	va_list ap;
	int n;

	va_start(ap, fmt);
	n = vsnprintf(id, HL_BATCH_ID_MAX, fmt, ap);
	va_end(ap);
	if (n < 0 || n >= HL_BATCH_ID_MAX) {
		fprintf(stderr, PROG ": %s: a task's id '%.60s...' is longer than %d bytes\n",
			p->spec_path, id, HL_BATCH_ID_MAX - 1);
		return 2;
	}
	return 0;
}

static int add_id(struct plan *p, const char *id)
{
	for (unsigned i = 0; i < p->n_ids; i++)
		if (!strcmp(p->ids[i], id)) {
			fprintf(stderr,
				PROG ": %s: two tasks with the id '%s' (two scenarios or drives of "
				     "the same name, or an ECU, fault or preset listed twice)\n",
				p->spec_path, id);
			return 2;
		}
	if (p->n_ids == p->cap_ids) {
		unsigned cap = p->cap_ids ? 2 * p->cap_ids : 256;
		char **ids = realloc(p->ids, cap * sizeof(*ids));

		if (!ids)
			return 1;
		p->ids = ids;
		p->cap_ids = cap;
	}
	p->ids[p->n_ids] = strdup(id);
	return p->ids[p->n_ids++] ? 0 : 1;
}

/* The task's line: index, id, kind, then fields, then config and set. Steals fields. */
static int emit(struct plan *p, const char *id, const char *kind, json_t *fields)
{
	json_t *t = json_object();
	char *line;
	int rc = add_id(p, id);

	if (rc) {
		json_decref(fields);
		json_decref(t);
		return rc;
	}
	json_object_set_new(t, "index", json_integer(p->n));
	json_object_set_new(t, "id", json_string(id));
	json_object_set_new(t, "kind", json_string(kind));
	json_object_update(t, fields);
	json_decref(fields);
	json_object_set_new(t, "config", json_string(p->config));
	json_object_set(t, "set", p->sets);
	line = json_dumps(t, JSON_COMPACT | JSON_PRESERVE_ORDER | JSON_ENSURE_ASCII);
	json_decref(t);
	if (!line)
		return 1;
	fprintf(p->out, "%s\n", line);
	free(line);
	p->n++;
	return 0;
}

/* "reference", or the FMU's file name without .fmu */
static void ecu_label(const char *ecu, char *ret, size_t size)
{
	hl_batch_stem(ecu, ".fmu", ret, size);
}

static const char *fault_label(const char *f)
{
	return f[0] ? f : "none";
}

/* An ECU of the spec as the task names it: reference, or an absolute FMU path. */
static int ecu_path(struct plan *p, size_t i, char *ret, size_t size)
{
	const char *e = json_string_value(json_array_get(p->ecus, i));
	char key[64];

	if (!strcmp(e, "reference")) {
		snprintf(ret, size, "reference");
		return 0;
	}
	snprintf(key, sizeof(key), "ecus[%zu]", i);
	if (resolve(p, e, ret, size) < 0)
		return fail(p, key, "path too long");
	return 0;
}

static int plan_suite(struct plan *p, json_t *entry, size_t si)
{
	char key[64], name[PATH_MAX], ecu[PATH_MAX], label[256], id[HL_BATCH_ID_MAX], msg[512];
	json_t *jname = json_object_get(entry, "suite"),
	       *jsamples = json_object_get(entry, "samples");
	json_t *jonly = json_object_get(entry, "only");
	struct hl_suite_result r = { 0 };
	struct hl_suite *s;
	int samples = 2, rc = 0, count;
	size_t k, e, f;
	json_t *v;

	snprintf(key, sizeof(key), "suites[%zu]", si);
	if (!json_is_object(entry) || !json_is_string(jname))
		return fail(p, key,
			    "expected {\"suite\": NAME or FILE, \"only\": [ID...], "
			    "\"samples\": N}");
	if (jsamples && (!json_is_integer(jsamples) || json_integer_value(jsamples) < 2 ||
			 json_integer_value(jsamples) > 100)) {
		snprintf(key, sizeof(key), "suites[%zu].samples", si);
		return fail(p, key, "expected an integer 2..100");
	}
	if (jonly && !json_is_array(jonly)) {
		snprintf(key, sizeof(key), "suites[%zu].only", si);
		return fail(p, key, "expected an array of scenario or variant ids");
	}
	if (jsamples)
		samples = (int)json_integer_value(jsamples);
	snprintf(name, sizeof(name), "%s", json_string_value(jname));
	if (strchr(name, '/') && resolve(p, json_string_value(jname), name, sizeof(name)) < 0)
		return fail(p, key, "path too long");
	{
		char prog[PATH_MAX + 128];

		snprintf(prog, sizeof(prog), PROG ": %s: key 'suites[%zu].suite'", p->spec_path,
			 si);
		if (hl_cli_suite_load(prog, name, &s))
			return 2;
	}
	count = hl_suite_plan(s, NULL, samples, &r, msg, sizeof(msg));
	if (count < 0) {
		fprintf(stderr, PROG ": %s: %s: %s\n", p->spec_path, key, msg);
		hl_suite_free(s);
		return 2;
	}
	/* every id of "only" must name something */
	json_array_foreach(jonly, k, v)
	{
		bool found = false;

		for (int i = 0; json_is_string(v) && i < count && !found; i++)
			found = !strcmp(r.v[i].id, json_string_value(v)) ||
				!strcmp(r.v[i].scenario_id, json_string_value(v));
		if (!found) {
			snprintf(key, sizeof(key), "suites[%zu].only[%zu]", si, k);
			rc = fail(p, key, "no scenario or variant of the suite has this id");
			goto out;
		}
	}
	for (int i = 0; i < count && rc == 0; i++) {
		bool selected = !jonly;

		json_array_foreach(jonly, k, v)
			selected = selected || !strcmp(r.v[i].id, json_string_value(v)) ||
				   !strcmp(r.v[i].scenario_id, json_string_value(v));
		if (!selected)
			continue;
		for (e = 0; e < json_array_size(p->ecus) && rc == 0; e++) {
			rc = ecu_path(p, e, ecu, sizeof(ecu));
			ecu_label(ecu, label, sizeof(label));
			for (f = 0; f < json_array_size(p->faults) && rc == 0; f++) {
				const char *fault = json_string_value(json_array_get(p->faults, f));

				rc = make_id(p, id, "suite/%s/%s/%s/%s", s->name, r.v[i].id, label,
					     fault_label(fault));
				if (!rc)
					rc = emit(p, id, "suite",
						  json_pack("{s:s, s:s, s:s, s:s, s:s, s:i}",
							    "suite", name, "variant", r.v[i].id,
							    "ecu", ecu, "fault", fault, "preset",
							    "", "samples", samples));
			}
		}
		json_array_foreach(p->presets, k, v)
		{
			if (rc)
				break;
			rc = make_id(p, id, "suite/%s/%s/preset/%s", s->name, r.v[i].id,
				     json_string_value(v));
			if (!rc)
				rc = emit(p, id, "suite",
					  json_pack("{s:s, s:s, s:s, s:s, s:s, s:i}", "suite", name,
						    "variant", r.v[i].id, "ecu", "", "fault", "",
						    "preset", json_string_value(v), "samples",
						    samples));
		}
	}
out:
	hl_suite_result_free(&r);
	hl_suite_free(s);
	return rc;
}

static int plan_scenario(struct plan *p, size_t i)
{
	const char *given = json_string_value(json_array_get(p->root_scenarios, i));
	char key[64], path[PATH_MAX], ecu[PATH_MAX], label[256], name[256], id[HL_BATCH_ID_MAX];
	struct stat st;
	int rc = 0;

	snprintf(key, sizeof(key), "scenarios[%zu]", i);
	if (resolve(p, given, path, sizeof(path)) < 0)
		return fail(p, key, "path too long");
	if (stat(path, &st) < 0 || !S_ISREG(st.st_mode)) {
		fprintf(stderr, PROG ": %s: key '%s': '%s': %s; expected a scenario file\n",
			p->spec_path, key, path,
			stat(path, &st) < 0 ? strerror(errno) : "not a file");
		return 2;
	}
	hl_batch_stem(path, ".json", name, sizeof(name));
	for (size_t e = 0; e < json_array_size(p->ecus) && rc == 0; e++) {
		rc = ecu_path(p, e, ecu, sizeof(ecu));
		ecu_label(ecu, label, sizeof(label));
		for (size_t f = 0; f < json_array_size(p->faults) && rc == 0; f++) {
			const char *fault = json_string_value(json_array_get(p->faults, f));

			rc = make_id(p, id, "sil/%s/%s/%s", name, label, fault_label(fault));
			if (!rc)
				rc = emit(p, id, "sil",
					  json_pack("{s:s, s:s, s:s}", "scenario", path, "ecu", ecu,
						    "fault", fault));
		}
	}
	return rc;
}

static int by_name(const void *a, const void *b)
{
	return strcmp(*(char *const *)a, *(char *const *)b);
}

/* A drive folder: every NAME.log (sorted), each with NAME.json beside it. */
static int plan_drives(struct plan *p, size_t i)
{
	const char *given = json_string_value(json_array_get(p->root_drives, i));
	char key[64], dir[PATH_MAX], log[PATH_MAX + 256], scn[PATH_MAX + 256], name[256];
	char id[HL_BATCH_ID_MAX];
	char **names = NULL;
	size_t n = 0, cap = 0;
	struct dirent *de;
	struct stat st;
	DIR *d;
	int rc = 0;

	snprintf(key, sizeof(key), "drives[%zu]", i);
	if (resolve(p, given, dir, sizeof(dir)) < 0)
		return fail(p, key, "path too long");
	d = opendir(dir);
	if (!d) {
		fprintf(stderr, PROG ": %s: key '%s': '%s': %s; expected a folder of drives\n",
			p->spec_path, key, dir, strerror(errno));
		return 2;
	}
	while ((de = readdir(d))) {
		size_t len = strlen(de->d_name);

		if (len <= 4 || strcmp(de->d_name + len - 4, ".log"))
			continue;
		if (n == cap) {
			char **m = realloc(names, (cap = cap ? 2 * cap : 64) * sizeof(*m));

			if (!m) {
				rc = 1;
				break;
			}
			names = m;
		}
		names[n] = strdup(de->d_name);
		if (!names[n++]) {
			rc = 1;
			break;
		}
	}
	closedir(d);
	if (rc == 0 && n == 0) {
		fprintf(stderr, PROG ": %s: key '%s': '%s' holds no drive (NAME.log)\n",
			p->spec_path, key, dir);
		rc = 2;
	}
	if (n > 1)
		qsort(names, n, sizeof(*names), by_name);
	for (size_t k = 0; k < n && rc == 0; k++) {
		hl_batch_stem(names[k], ".log", name, sizeof(name));
		if (snprintf(log, sizeof(log), "%s/%s", dir, names[k]) >= (int)sizeof(log) ||
		    snprintf(scn, sizeof(scn), "%s/%s.json", dir, name) >= (int)sizeof(scn)) {
			rc = fail(p, key, "a drive's path is too long");
			break;
		}
		if (stat(scn, &st) < 0) {
			fprintf(stderr,
				PROG
				": %s: key '%s': drive '%s' has no scenario '%s' beside it (%s); "
				"a drive is NAME.log with its NAME.json\n",
				p->spec_path, key, log, scn, strerror(errno));
			rc = 2;
			break;
		}
		rc = make_id(p, id, "drive/%s", name);
		if (!rc)
			rc = emit(p, id, "drive",
				  json_pack("{s:s, s:s}", "log", log, "scenario", scn));
	}
	for (size_t k = 0; k < n; k++)
		free(names[k]);
	free(names);
	return rc;
}

struct header {
	const struct plan *p;
	const char *body;
	size_t body_size;
};

static void write_plan(void *ctx, FILE *f)
{
	const struct header *h = ctx;
	json_t *head = json_pack("{s:s, s:i, s:i, s:s}", "plan", "hdlamp batch plan", "version", 1,
				 "tasks", (json_int_t)h->p->n, "spec", h->p->spec_path);
	char *line = json_dumps(head, JSON_COMPACT | JSON_PRESERVE_ORDER | JSON_ENSURE_ASCII);

	fprintf(f, "%s\n", line ? line : "");
	fwrite(h->body, 1, h->body_size, f);
	free(line);
	json_decref(head);
}

static const char *const spec_keys[] = { "spec",      "version", "config", "set",    "suites",
					 "scenarios", "drives",	 "ecus",   "faults", "presets" };

static int check_keys(struct plan *p)
{
	const char *key;
	json_t *v, *j;

	json_object_foreach(p->root, key, v)
	{
		bool known = false;

		for (size_t i = 0; i < sizeof(spec_keys) / sizeof(*spec_keys); i++)
			known = known || !strcmp(key, spec_keys[i]);
		if (!known)
			return fail(p, key,
				    "unknown key (expected spec, version, config, set, "
				    "suites, scenarios, drives, ecus, faults, presets)");
	}
	j = json_object_get(p->root, "spec");
	if (!json_is_string(j) || strcmp(json_string_value(j), "hdlamp batch"))
		return fail(p, "spec", "expected \"hdlamp batch\"");
	j = json_object_get(p->root, "version");
	if (!json_is_integer(j) || json_integer_value(j) != 1)
		return fail(p, "version", "expected 1");
	j = json_object_get(p->root, "config");
	if (j && !json_is_string(j))
		return fail(p, "config", "expected a path to an hdlampd configuration file");
	if (j && resolve(p, json_string_value(j), p->config, sizeof(p->config)) < 0)
		return fail(p, "config", "path too long");
	if (p->config[0] && access(p->config, R_OK) < 0) {
		fprintf(stderr, PROG ": %s: key 'config': '%s': %s\n", p->spec_path, p->config,
			strerror(errno));
		return 2;
	}
	j = json_object_get(p->root, "suites");
	if (j && !json_is_array(j))
		return fail(p, "suites", "expected an array of {\"suite\": NAME, ...}");
	return 0;
}

static int plan_all(struct plan *p)
{
	json_t *suites = json_object_get(p->root, "suites"), *v;
	size_t i;
	int rc;

	rc = check_keys(p);
	if (!rc)
		rc = strings(p, "set", NULL, &p->sets);
	if (!rc)
		rc = strings(p, "ecus", "reference", &p->ecus);
	if (!rc)
		rc = strings(p, "faults", "", &p->faults);
	if (!rc)
		rc = strings(p, "presets", NULL, &p->presets);
	if (!rc)
		rc = strings(p, "scenarios", NULL, &p->root_scenarios);
	if (!rc)
		rc = strings(p, "drives", NULL, &p->root_drives);
	if (!rc && json_array_size(p->ecus) == 0 && json_array_size(p->presets) == 0)
		rc = fail(p, "ecus", "empty, and no presets: nothing would run");
	json_array_foreach(suites, i, v)
	{
		if (rc)
			break;
		rc = plan_suite(p, v, i);
	}
	for (i = 0; !rc && i < json_array_size(p->root_scenarios); i++)
		rc = plan_scenario(p, i);
	for (i = 0; !rc && i < json_array_size(p->root_drives); i++)
		rc = plan_drives(p, i);
	if (!rc && p->n == 0)
		rc = fail(p, "suites", "the spec names no suite, scenario or drive: no task");
	return rc;
}

int hl_batch_plan_cmd(int argc, char **argv)
{
	static const struct option opts[] = {
		{ "out", required_argument, NULL, 'o' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	struct plan p = { 0 };
	char *body = NULL, abs_spec[PATH_MAX], dir[PATH_MAX];
	const char *out = NULL;
	size_t body_size = 0;
	json_error_t jerr;
	int c, rc;

	optind = 1;
	while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
		if (c == 'o') {
			out = optarg;
		} else if (c == 'h') {
			usage(stdout);
			return 0;
		} else {
			usage(stderr);
			return 2;
		}
	}
	if (optind != argc - 1 || !out) {
		usage(stderr);
		return 2;
	}
	if (!realpath(argv[optind], abs_spec)) {
		fprintf(stderr, PROG ": '%s': %s; expected a batch spec (JSON)\n", argv[optind],
			strerror(errno));
		return 2;
	}
	p.spec_path = abs_spec;
	snprintf(dir, sizeof(dir), "%s", abs_spec);
	snprintf(p.spec_dir, sizeof(p.spec_dir), "%s", dirname(dir));
	p.root = json_load_file(abs_spec, JSON_REJECT_DUPLICATES, &jerr);
	if (!p.root || !json_is_object(p.root)) {
		fprintf(stderr, PROG ": %s:%d:%d: %s; expected a JSON object (docs/scale.md)\n",
			abs_spec, p.root ? 1 : jerr.line, p.root ? 1 : jerr.column,
			p.root ? "not an object" : jerr.text);
		json_decref(p.root);
		return 2;
	}
	p.out = open_memstream(&body, &body_size);
	rc = p.out ? plan_all(&p) : 1;
	if (p.out && fclose(p.out))
		rc = rc ? rc : 1;
	if (rc == 0) {
		struct header h = { &p, body, body_size };
		int wr = hl_file_replace(out, write_plan, &h);

		if (wr < 0) {
			fprintf(stderr, PROG ": --out '%s': %s\n", out, strerror(-wr));
			rc = 1;
		} else {
			fprintf(stderr, PROG ": %u tasks in %s\n", p.n, out);
		}
	}
	free(body);
	for (unsigned i = 0; i < p.n_ids; i++)
		free(p.ids[i]);
	free(p.ids);
	json_decref(p.ecus);
	json_decref(p.faults);
	json_decref(p.presets);
	json_decref(p.sets);
	json_decref(p.root_scenarios);
	json_decref(p.root_drives);
	json_decref(p.root);
	return rc;
}
