/* SPDX-License-Identifier: MIT */
/* The ADB lab's suite files (verdict/suite.h, docs/lab.md) read with jansson, checked key by key. */
#include "verdict/suite.h"

#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/json_check.h"
#include "base/share_dir.h"

#define FORMAT_VERSION 1
#define MAX_RANGE_M 1000.0
#define MAX_SPEED_MPH 200.0
#define MAX_LUX 1e6

static const char *const procedure_names[] = { "fmvss108-adb", "iihs", "r149-adb", NULL };
static const char *const road_names[] = { "straight", "left", "right", NULL };
static const char *const rounding_names[] = { "half-even", "half-up", NULL };
/* The stimulus vehicles' roles: hl_actor_role's first two, in its order. */
static const char *const role_names[] = { "oncoming", "preceding", NULL };
static const char *const scenario_role_names[] = { "oncoming", "preceding", "none", NULL };

static const struct hl_json_range r_range = { 0.0, MAX_RANGE_M, true, "m" };
static const struct hl_json_range r_lux = { 0.0, MAX_LUX, false, "lx" };
static const struct hl_json_range r_speed = { 0.0, MAX_SPEED_MPH, false, "mph" };
static const struct hl_json_range r_radius = { 10.0, 100000.0, false, "m" };
/* A point of a stimulus vehicle's body, as the scenarios' body frame allows (docs/scenarios.md). */
static const struct hl_json_range r_body[3] = { { -30.0, 20.0, false, "m" },
						{ -5.0, 5.0, false, "m" },
						{ 0.0, 5.0, false, "m" } };
static const struct hl_json_range r_normal[3] = { { -1000.0, 1000.0, false, "(direction)" },
						  { -1000.0, 1000.0, false, "(direction)" },
						  { -1000.0, 1000.0, false, "(direction)" } };

/*
 * obj.key as [lo, hi], both in r; lo <= hi, or lo < hi with strict. Absent: an error when
 * required, else ret untouched.
 */
static int get_pair(const struct hl_json_ctx *c, const char *path, const struct json_t *obj,
		    const char *key, bool required, const struct hl_json_range *r, bool strict,
		    double ret[2])
{
	const struct json_t *j = json_object_get(obj, key);
	char sub[HL_JSON_PATH_MAX], el[HL_JSON_PATH_MAX];
	double v[2];

	hl_json_join(sub, sizeof(sub), path, key);
	if (!j) {
		if (required)
			return hl_json_fail(c, sub, "missing: expected [lo, hi] in %s", r->unit);
		return 0;
	}
	if (!json_is_array(j) || json_array_size(j) != 2)
		return hl_json_fail(c, sub, "expected [lo, hi] in %s, found %s", r->unit,
				    json_is_array(j) ? "another number of elements" :
						       hl_json_type_name(j));
	for (int k = 0; k < 2; k++)
		if (hl_json_number(c, hl_json_index(el, sizeof(el), sub, k), json_array_get(j, k),
				   r, &v[k]) < 0)
			return -EBADMSG;
	if (strict ? !(v[0] < v[1]) : !(v[0] <= v[1]))
		return hl_json_fail(c, sub, "[%g, %g] %s: expected lo %s hi", v[0], v[1], r->unit,
				    strict ? "<" : "<=");
	ret[0] = v[0];
	ret[1] = v[1];
	return 0;
}

/* obj.key must be an array of at most max elements (min at least); its size in *ret_n. */
static int get_array(const struct hl_json_ctx *c, const char *path, const struct json_t *j, int min,
		     int max, const char *what, int *ret_n)
{
	if (!json_is_array(j))
		return hl_json_fail(c, path, "expected an array of %d to %d %s, found %s", min, max,
				    what, hl_json_type_name(j));
	if ((int)json_array_size(j) < min || json_array_size(j) > (size_t)max)
		return hl_json_fail(c, path, "%zu %s: expected %d to %d", json_array_size(j), what,
				    min, max);
	*ret_n = (int)json_array_size(j);
	return 0;
}

static int parse_rounding(const struct hl_json_ctx *c, const struct json_t *j, struct hl_suite *s)
{
	static const char *const keys[] = { "decimals", "rule", "source", NULL };
	int rule = 0;

	if (hl_json_check_object(c, "rounding", j, keys) < 0 ||
	    hl_json_get_int(c, "rounding", j, "decimals", true, 0, 6, &s->decimals) < 0 ||
	    hl_json_get_enum(c, "rounding", j, "rule", true, rounding_names, &rule) < 0 ||
	    hl_json_get_string(c, "rounding", j, "source", true, s->rounding_source,
			       sizeof(s->rounding_source)) < 0)
		return -EBADMSG;
	s->rounding = (enum hl_suite_rounding)rule;
	s->has_rounding = true;
	return 0;
}

static int parse_bins(const struct hl_json_ctx *c, const struct json_t *j, struct hl_suite *s)
{
	static const char *const keys[] = { "role", "from_m", "to_m", "max_lx", "source", NULL };
	char p[HL_JSON_PATH_MAX], sub[HL_JSON_PATH_MAX];

	if (get_array(c, "bins", j, 1, HL_SUITE_MAX_BINS, "bins", &s->n_bins) < 0)
		return -EBADMSG;
	for (int i = 0; i < s->n_bins; i++) {
		const struct json_t *o = json_array_get(j, i), *lx;
		struct hl_suite_bin *b = &s->bin[i];
		int role = 0;

		hl_json_index(p, sizeof(p), "bins", i);
		if (hl_json_check_object(c, p, o, keys) < 0 ||
		    hl_json_get_enum(c, p, o, "role", true, role_names, &role) < 0 ||
		    hl_json_get_number(c, p, o, "from_m", true, &r_range, &b->from_m) < 0 ||
		    hl_json_get_number(c, p, o, "to_m", true, &r_range, &b->to_m) < 0)
			return -EBADMSG;
		b->role = (enum hl_actor_role)role;
		if (!(b->from_m < b->to_m))
			return hl_json_fail(c, hl_json_join(sub, sizeof(sub), p, "to_m"),
					    "the bin [%g, %g] m is empty: expected from_m < to_m",
					    b->from_m, b->to_m);
		lx = json_object_get(o, "max_lx");
		hl_json_join(sub, sizeof(sub), p, "max_lx");
		if (!lx)
			return hl_json_fail(c, sub,
					    "missing: expected a number in [0, %g] lx, or null (no "
					    "limit in this bin)",
					    MAX_LUX);
		if (json_is_null(lx))
			b->max_lx = NAN;
		else if (!json_is_number(lx))
			return hl_json_fail(c, sub,
					    "expected a number in [0, %g] lx or null, found %s",
					    MAX_LUX, hl_json_type_name(lx));
		else if (hl_json_number(c, sub, lx, &r_lux, &b->max_lx) < 0)
			return -EBADMSG;
		if (hl_json_get_string(c, p, o, "source", true, b->source, sizeof(b->source)) < 0)
			return -EBADMSG;
	}
	return 0;
}

static int parse_photometers(const struct hl_json_ctx *c, const struct json_t *j,
			     struct hl_suite *s)
{
	static const char *const keys[] = { "id", "role", "pos_m", "normal", "source", NULL };
	char p[HL_JSON_PATH_MAX], sub[HL_JSON_PATH_MAX];

	if (get_array(c, "photometers", j, 0, HL_SUITE_MAX_PHOTOMETERS, "photometers",
		      &s->n_photometers) < 0)
		return -EBADMSG;
	for (int i = 0; i < s->n_photometers; i++) {
		const struct json_t *o = json_array_get(j, i);
		struct hl_suite_photometer *ph = &s->photometer[i];
		double len;
		int role = 0;

		hl_json_index(p, sizeof(p), "photometers", i);
		if (hl_json_check_object(c, p, o, keys) < 0 ||
		    hl_json_get_string(c, p, o, "id", true, ph->id, sizeof(ph->id)) < 0)
			return -EBADMSG;
		for (int k = 0; k < i; k++)
			if (!strcmp(s->photometer[k].id, ph->id))
				return hl_json_fail(
					c, hl_json_join(sub, sizeof(sub), p, "id"),
					"'%s' is the id of photometers[%d] already: expected a new "
					"one",
					ph->id, k);
		if (hl_json_get_enum(c, p, o, "role", true, role_names, &role) < 0 ||
		    hl_json_get_vec3(c, p, o, "pos_m", true, r_body, ph->pos_m) < 0 ||
		    hl_json_get_vec3(c, p, o, "normal", true, r_normal, ph->normal) < 0 ||
		    hl_json_get_string(c, p, o, "source", true, ph->source, sizeof(ph->source)) < 0)
			return -EBADMSG;
		ph->role = (enum hl_actor_role)role;
		len = sqrt(ph->normal[0] * ph->normal[0] + ph->normal[1] * ph->normal[1] +
			   ph->normal[2] * ph->normal[2]);
		if (!(len > 1e-9))
			return hl_json_fail(c, hl_json_join(sub, sizeof(sub), p, "normal"),
					    "[0, 0, 0] has no direction: expected a non-zero "
					    "vector (the side the photometer faces)");
		for (int k = 0; k < 3; k++)
			ph->normal[k] /= len;
	}
	return 0;
}

static int parse_scenario(const struct hl_json_ctx *c, const char *p, const struct json_t *o,
			  struct hl_suite *s, struct hl_suite_scenario *sc)
{
	static const char *const keys[] = { "id",	"title",   "role",   "road", "speed_mph",
					    "radius_m", "range_m", "source", NULL };
	char sub[HL_JSON_PATH_MAX];
	int role = 0, road = 0;

	if (hl_json_check_object(c, p, o, keys) < 0 ||
	    hl_json_get_string(c, p, o, "id", true, sc->id, sizeof(sc->id)) < 0)
		return -EBADMSG;
	for (int k = 0; k < s->n_scenarios; k++)
		if (!strcmp(s->scenario[k].id, sc->id))
			return hl_json_fail(
				c, hl_json_join(sub, sizeof(sub), p, "id"),
				"'%s' is the id of scenarios[%d] already: expected a new one",
				sc->id, k);
	if (hl_json_get_string(c, p, o, "title", true, sc->title, sizeof(sc->title)) < 0 ||
	    hl_json_get_enum(c, p, o, "role", true, scenario_role_names, &role) < 0 ||
	    hl_json_get_enum(c, p, o, "road", true, road_names, &road) < 0 ||
	    get_pair(c, p, o, "speed_mph", true, &r_speed, false, sc->speed_mph) < 0)
		return -EBADMSG;
	sc->has_role = role != 2;
	sc->role = sc->has_role ? (enum hl_actor_role)role : HL_ROLE_ONCOMING;
	sc->road = (enum hl_suite_road)road;
	if (sc->road == HL_SUITE_STRAIGHT) {
		if (json_object_get(o, "radius_m"))
			return hl_json_fail(c, hl_json_join(sub, sizeof(sub), p, "radius_m"),
					    "a straight road has no 'radius_m'");
	} else if (get_pair(c, p, o, "radius_m", true, &r_radius, false, sc->radius_m) < 0) {
		return -EBADMSG;
	}
	if (get_pair(c, p, o, "range_m", true, &r_range, true, sc->range_m) < 0 ||
	    hl_json_get_string(c, p, o, "source", true, sc->source, sizeof(sc->source)) < 0)
		return -EBADMSG;
	if (sc->has_role) {
		int n = 0;

		for (int k = 0; k < s->n_photometers; k++)
			n += s->photometer[k].role == sc->role;
		if (!n)
			return hl_json_fail(c, hl_json_join(sub, sizeof(sub), p, "role"),
					    "no photometer sits on a %s stimulus vehicle: expected "
					    "one in 'photometers'",
					    role_names[role]);
	}
	return 0;
}

static int parse_iihs(const struct hl_json_ctx *c, const struct json_t *j, struct hl_suite *s)
{
	static const char *const keys[] = { "visibility_lx", "visibility_height_m",
					    "glare_height_m", "source", NULL };
	static const struct hl_json_range r_lx = { 0.0, MAX_LUX, true, "lx" };
	static const struct hl_json_range r_height = { 0.0, 5.0, true, "m" };

	if (hl_json_check_object(c, "iihs", j, keys) < 0 ||
	    hl_json_get_number(c, "iihs", j, "visibility_lx", true, &r_lx, &s->visibility_lx) < 0 ||
	    hl_json_get_number(c, "iihs", j, "visibility_height_m", true, &r_height,
			       &s->visibility_height_m) < 0 ||
	    hl_json_get_number(c, "iihs", j, "glare_height_m", true, &r_height,
			       &s->glare_height_m) < 0 ||
	    hl_json_get_string(c, "iihs", j, "source", true, s->iihs_source,
			       sizeof(s->iihs_source)) < 0)
		return -EBADMSG;
	return 0;
}

static int parse_defaults(const struct hl_json_ctx *c, const struct json_t *j, struct hl_suite *s)
{
	static const char *const keys[] = { "what", "value", "why", NULL };
	char p[HL_JSON_PATH_MAX];

	if (get_array(c, "defaults", j, 0, HL_SUITE_MAX_DEFAULTS, "defaults", &s->n_defaults) < 0)
		return -EBADMSG;
	for (int i = 0; i < s->n_defaults; i++) {
		const struct json_t *o = json_array_get(j, i);
		struct hl_suite_default *d = &s->def[i];

		hl_json_index(p, sizeof(p), "defaults", i);
		if (hl_json_check_object(c, p, o, keys) < 0 ||
		    hl_json_get_string(c, p, o, "what", true, d->what, sizeof(d->what)) < 0 ||
		    hl_json_get_string(c, p, o, "value", true, d->value, sizeof(d->value)) < 0 ||
		    hl_json_get_string(c, p, o, "why", true, d->why, sizeof(d->why)) < 0)
			return -EBADMSG;
	}
	return 0;
}

/* A section only one procedure has: required there, refused elsewhere. */
static int check_section(const struct hl_json_ctx *c, const struct json_t *root, const char *key,
			 enum hl_suite_procedure owner, enum hl_suite_procedure p, const char *what)
{
	bool has = json_object_get(root, key) != NULL;

	if (p == owner && !has)
		return hl_json_fail(c, key, "missing: a %s suite has %s", procedure_names[owner],
				    what);
	if (p != owner && has)
		return hl_json_fail(c, key, "only a %s suite has '%s': this one is %s",
				    procedure_names[owner], key, procedure_names[p]);
	return 0;
}

/* The file's name without its folder and .json; "" when name does not end in .json. */
static void stem(const char *name, char *buf, size_t size)
{
	const char *base = strrchr(name, '/');
	size_t n;

	base = base ? base + 1 : name;
	n = strlen(base);
	buf[0] = '\0';
	if (n > 5 && !strcmp(base + n - 5, ".json") && n - 5 < size)
		snprintf(buf, size, "%.*s", (int)(n - 5), base);
}

static int parse_root(const struct hl_json_ctx *c, const struct json_t *root, struct hl_suite *s)
{
	static const char *const keys[] = { "version",	 "name",     "title",	  "procedure",
					    "source",	 "rounding", "bins",	  "photometers",
					    "scenarios", "iihs",     "glare_set", "defaults",
					    NULL };
	const struct json_t *o;
	char p[HL_JSON_PATH_MAX], want[HL_SUITE_ID_MAX + 8];
	int version = 0, procedure = 0, n = 0;

	if (hl_json_check_object(c, "", root, keys) < 0 ||
	    hl_json_get_int(c, "", root, "version", true, FORMAT_VERSION, FORMAT_VERSION,
			    &version) < 0 ||
	    hl_json_get_string(c, "", root, "name", true, s->name, sizeof(s->name)) < 0)
		return -EBADMSG;
	stem(c->name, want, sizeof(want));
	if (want[0] && strcmp(want, s->name))
		return hl_json_fail(c, "name", "'%s': expected the file's name without .json, '%s'",
				    s->name, want);
	if (hl_json_get_string(c, "", root, "title", true, s->title, sizeof(s->title)) < 0 ||
	    hl_json_get_enum(c, "", root, "procedure", true, procedure_names, &procedure) < 0 ||
	    hl_json_get_string(c, "", root, "source", true, s->source, sizeof(s->source)) < 0)
		return -EBADMSG;
	s->procedure = (enum hl_suite_procedure)procedure;
	if (check_section(c, root, "bins", HL_SUITE_FMVSS108_ADB, s->procedure,
			  "bins: its limit table, one row per range bin") < 0 ||
	    check_section(c, root, "iihs", HL_SUITE_IIHS, s->procedure,
			  "an 'iihs' section: its thresholds and heights") < 0 ||
	    check_section(c, root, "glare_set", HL_SUITE_R149_ADB, s->procedure,
			  "a glare_set: the regulation set it judges") < 0)
		return -EBADMSG;
	o = json_object_get(root, "rounding");
	if (o && parse_rounding(c, o, s) < 0)
		return -EBADMSG;
	o = json_object_get(root, "bins");
	if (o && parse_bins(c, o, s) < 0)
		return -EBADMSG;
	o = json_object_get(root, "photometers");
	if (o && parse_photometers(c, o, s) < 0)
		return -EBADMSG;
	o = json_object_get(root, "scenarios");
	if (!o)
		return hl_json_fail(c, "scenarios",
				    "missing: expected an array of 1 to %d scenarios",
				    HL_SUITE_MAX_SCENARIOS);
	if (get_array(c, "scenarios", o, 1, HL_SUITE_MAX_SCENARIOS, "scenarios", &n) < 0)
		return -EBADMSG;
	for (int i = 0; i < n; i++) {
		if (parse_scenario(c, hl_json_index(p, sizeof(p), "scenarios", i),
				   json_array_get(o, i), s, &s->scenario[i]) < 0)
			return -EBADMSG;
		s->n_scenarios++;
	}
	o = json_object_get(root, "iihs");
	if (o && parse_iihs(c, o, s) < 0)
		return -EBADMSG;
	if (hl_json_get_string(c, "", root, "glare_set", false, s->glare_set,
			       sizeof(s->glare_set)) < 0)
		return -EBADMSG;
	o = json_object_get(root, "defaults");
	if (o && parse_defaults(c, o, s) < 0)
		return -EBADMSG;
	return 0;
}

/* parse_root for hl_json_parse_struct() */
static int parse_any(struct hl_json_ctx *c, json_t *root, void *out)
{
	return parse_root(c, root, out);
}

int hl_suite_parse(const char *text, const char *name, struct hl_suite **ret,
		   struct hl_json_error *err)
{
	return hl_json_parse_struct(text, name, sizeof(**ret), parse_any, (void **)ret, err);
}

int hl_suite_read(const char *path, struct hl_suite **ret, struct hl_json_error *err)
{
	return hl_json_read_struct(path, sizeof(**ret), parse_any, (void **)ret, err);
}

void hl_suite_free(struct hl_suite *s)
{
	free(s);
}

int hl_suite_default_dir(char *buf, size_t size)
{
	return hl_share_dir("suites", buf, size);
}

const char *hl_suite_procedure_name(enum hl_suite_procedure p)
{
	return (unsigned)p < 3 ? procedure_names[p] : "?";
}

const char *hl_suite_road_name(enum hl_suite_road r)
{
	return (unsigned)r < 3 ? road_names[r] : "?";
}
