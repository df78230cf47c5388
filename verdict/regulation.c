/* SPDX-License-Identifier: MIT */
/* Regulation sets read from JSON with jansson (docs/regulations.md). */
#include <dirent.h>
#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "verdict/regulation.h"
#include "base/share_dir.h"

/* What the parser needs to say where a fault is. */
struct ctx {
	const char *name; /* the file */
	const char *text; /* its text, to find the line of a requirement */
	struct hl_regulation_error *err;
};

static int line_of(const struct ctx *c, const char *needle)
{
	const char *hit = c->text ? strstr(c->text, needle) : NULL;
	int line = 1;

	if (!hit)
		return 0;
	for (const char *p = c->text; p < hit; p++)
		line += *p == '\n';
	return line;
}

/* Line of requirement index i: the i-th '"id"' key after '"requirements"'. */
static int line_of_req(const struct ctx *c, int i)
{
	const char *p = c->text ? strstr(c->text, "\"requirements\"") : NULL;
	int line = 1;

	if (!p)
		return 0;
	for (int k = 0; k <= i; k++) {
		p = strstr(p + 1, "\"id\"");
		if (!p)
			return 0;
	}
	for (const char *q = c->text; q < p; q++)
		line += *q == '\n';
	return line;
}

__attribute__((format(printf, 3, 4))) static int fail(const struct ctx *c, int line,
						      const char *fmt, ...)
{
	va_list ap;
	char what[400];

	if (!c->err)
		return -EBADMSG;
	va_start(ap, fmt);
	vsnprintf(what, sizeof(what), fmt, ap);
	va_end(ap);
	c->err->line = line;
	c->err->column = 0;
	if (line > 0)
		snprintf(c->err->msg, sizeof(c->err->msg), "%s:%d: %s", c->name, line, what);
	else
		snprintf(c->err->msg, sizeof(c->err->msg), "%s: %s", c->name, what);
	return -EBADMSG;
}

int hl_regulation_angle(const char *s, char axis, double *ret_deg)
{
	char *end;
	double x;
	const char neg = axis == 'h' ? 'L' : 'D', pos = axis == 'h' ? 'R' : 'U';
	const char zero = axis == 'h' ? 'V' : 'H';

	if (!s || !*s)
		return -EINVAL;
	if (!s[1]) {
		if (s[0] == zero) {
			*ret_deg = 0.0;
			return 0;
		}
		if (s[0] == neg || s[0] == pos) {
			if (axis == 'h')
				*ret_deg = s[0] == neg ? HL_REG_OPEN_LEFT : HL_REG_OPEN_RIGHT;
			else
				*ret_deg = s[0] == neg ? HL_REG_OPEN_DOWN : HL_REG_OPEN_UP;
			return 0;
		}
	}
	errno = 0;
	x = strtod(s, &end);
	if (end == s || errno || !isfinite(x))
		return -EINVAL;
	if (!*end) {
		*ret_deg = x;
		return 0;
	}
	if (end[1] || x < 0.0 || (*end != neg && *end != pos))
		return -EINVAL;
	*ret_deg = *end == neg ? -x : x;
	return 0;
}

/* An [h, v] pair. */
static int get_point(const struct ctx *c, int line, const char *where, json_t *j, double ret[2])
{
	static const char axes[2] = { 'h', 'v' };

	if (!json_is_array(j) || json_array_size(j) != 2)
		return fail(c, line, "%s: expected [h, v] (e.g. [\"3.43L\", \"0.57U\"])", where);
	for (int k = 0; k < 2; k++) {
		json_t *e = json_array_get(j, k);

		if (json_is_number(e)) {
			ret[k] = json_number_value(e);
		} else if (!json_is_string(e) ||
			   hl_regulation_angle(json_string_value(e), axes[k], &ret[k]) < 0) {
			return fail(
				c, line,
				"%s: %s angle: expected a number or a string like \"%s\", found %s",
				where, k ? "vertical" : "horizontal", k ? "0.57U" : "3.43L",
				json_is_string(e) ? json_string_value(e) : "another type");
		}
		if (fabs(ret[k]) < 1e8 && fabs(ret[k]) > (k ? 90.0 : 180.0))
			return fail(c, line, "%s: %s angle %g is outside the sphere", where,
				    k ? "vertical" : "horizontal", ret[k]);
	}
	return 0;
}

static int get_points(const struct ctx *c, int line, const char *where, json_t *j, int min_n,
		      struct hl_requirement *r)
{
	size_t n = json_is_array(j) ? json_array_size(j) : 0;
	char what[96];

	if (!json_is_array(j) || n < (size_t)min_n || n > HL_REG_MAX_VERTICES)
		return fail(c, line, "'%s' of '%s': expected an array of %d to %d [h, v] points",
			    where, r->id, min_n, HL_REG_MAX_VERTICES);
	for (size_t k = 0; k < n; k++) {
		snprintf(what, sizeof(what), "'%s' of '%s', point %zu", where, r->id, k + 1);
		if (get_point(c, line, what, json_array_get(j, k), r->pts[k]) < 0)
			return -EBADMSG;
	}
	r->n_pts = (int)n;
	return 0;
}

static int get_limit(const struct ctx *c, int line, const struct hl_regulation *reg,
		     struct hl_requirement *r, const char *key, json_t *j, struct hl_req_limit *ret)
{
	*ret = (struct hl_req_limit){ .of = -1 };
	if (!j)
		return 0;
	if (json_is_number(j)) {
		ret->cd = json_number_value(j);
		if (!isfinite(ret->cd) || ret->cd < 0.0)
			return fail(c, line, "'%s' of '%s': expected an intensity >= 0 cd", key,
				    r->id);
		ret->set = true;
		return 0;
	}
	if (json_is_object(j)) {
		json_t *of = json_object_get(j, "of"), *f = json_object_get(j, "factor");
		int idx;

		if (json_object_size(j) != 2 || !json_is_string(of) || !json_is_number(f))
			return fail(c, line,
				    "'%s' of '%s': expected {\"of\": ID, \"factor\": number}", key,
				    r->id);
		for (idx = 0; idx < reg->n_requirements; idx++)
			if (!strcmp(reg->req[idx].id, json_string_value(of)))
				break;
		if (idx == reg->n_requirements)
			return fail(c, line,
				    "'%s' of '%s': \"of\": \"%s\" names no earlier requirement",
				    key, r->id, json_string_value(of));
		ret->of = idx;
		ret->factor = json_number_value(f);
		if (!isfinite(ret->factor) || ret->factor <= 0.0)
			return fail(c, line, "'%s' of '%s': expected a factor > 0", key, r->id);
		ret->set = true;
		return 0;
	}
	return fail(c, line, "'%s' of '%s': expected a number (cd) or {\"of\": ID, \"factor\": x}",
		    key, r->id);
}

static int check_keys(const struct ctx *c, int line, const char *what, json_t *obj,
		      const char *const *allowed)
{
	const char *key;
	json_t *val;

	json_object_foreach(obj, key, val)
	{
		const char *const *a;

		for (a = allowed; *a; a++)
			if (!strcmp(*a, key))
				break;
		if (!*a)
			return fail(c, line, "%s: unknown key '%s'", what, key);
	}
	return 0;
}

static int copy_string(const struct ctx *c, int line, const char *what, json_t *obj,
		       const char *key, bool required, char *out, size_t size)
{
	json_t *j = json_object_get(obj, key);

	if (!j) {
		if (required)
			return fail(c, line, "%s: missing key '%s'", what, key);
		out[0] = '\0';
		return 0;
	}
	if (!json_is_string(j) || !json_string_length(j))
		return fail(c, line, "%s: '%s' expected a non-empty string", what, key);
	if (json_string_length(j) >= size)
		return fail(c, line, "%s: '%s' longer than %zu characters", what, key, size - 1);
	memcpy(out, json_string_value(j), json_string_length(j) + 1);
	return 0;
}

static int parse_requirement(const struct ctx *c, struct hl_regulation *reg, int i, json_t *j)
{
	static const char *const keys[] = { "id",     "kind",	"at",	  "from",   "to", "polygon",
					    "points", "min_cd", "max_cd", "source", NULL };
	static const char *const kinds[] = { "point", "segment", "zone", "sum", "imax" };
	struct hl_requirement *r = &reg->req[reg->n_requirements];
	const int line = line_of_req(c, i);
	char what[64];
	json_t *kind;
	int k, rc;

	memset(r, 0, sizeof(*r));
	r->line = line;
	snprintf(what, sizeof(what), "requirement %d", i + 1);
	if (!json_is_object(j))
		return fail(c, line, "%s: expected an object", what);
	rc = copy_string(c, line, what, j, "id", true, r->id, sizeof(r->id));
	if (rc < 0)
		return rc;
	snprintf(what, sizeof(what), "requirement '%s'", r->id);
	if (check_keys(c, line, what, j, keys) < 0)
		return -EBADMSG;
	for (k = 0; k < reg->n_requirements; k++)
		if (!strcmp(reg->req[k].id, r->id))
			return fail(c, line, "%s: the id is used twice (first on line %d)", what,
				    reg->req[k].line);
	rc = copy_string(c, line, what, j, "source", true, r->source, sizeof(r->source));
	if (rc < 0)
		return rc;
	kind = json_object_get(j, "kind");
	for (k = 0; k < 5 && json_is_string(kind); k++)
		if (!strcmp(json_string_value(kind), kinds[k]))
			break;
	if (!json_is_string(kind) || k == 5)
		return fail(c, line, "%s: 'kind' expected point, segment, zone, sum or imax", what);
	r->kind = (enum hl_req_kind)k;
	{
		/* exactly the geometry keys of the kind */
		static const char *const geo[] = { "at", "from", "to", "polygon", "points" };
		static const unsigned need[] = { 1u << 0, 3u << 1, 1u << 3, 1u << 4, 0u };

		for (k = 0; k < 5; k++) {
			const bool has = json_object_get(j, geo[k]) != NULL;
			const bool want = need[r->kind] & (1u << k);

			if (has != want)
				return fail(c, line, "%s: a %s %s '%s'", what, kinds[r->kind],
					    want ? "needs" : "has no", geo[k]);
		}
	}
	switch (r->kind) {
	case HL_REQ_POINT:
		r->n_pts = 1;
		rc = get_point(c, line, what, json_object_get(j, "at"), r->pts[0]);
		break;
	case HL_REQ_SEGMENT:
		r->n_pts = 2;
		rc = get_point(c, line, what, json_object_get(j, "from"), r->pts[0]);
		if (rc >= 0)
			rc = get_point(c, line, what, json_object_get(j, "to"), r->pts[1]);
		if (rc >= 0 && r->pts[0][0] != r->pts[1][0] && r->pts[0][1] != r->pts[1][1])
			rc = fail(c, line,
				  "%s: a segment is horizontal (same v) or vertical (same h)",
				  what);
		if (rc >= 0 && r->pts[0][0] == r->pts[1][0] && r->pts[0][1] == r->pts[1][1])
			rc = fail(c, line, "%s: the segment's ends are the same point", what);
		break;
	case HL_REQ_ZONE:
		rc = get_points(c, line, "polygon", json_object_get(j, "polygon"), 3, r);
		break;
	case HL_REQ_SUM:
		rc = get_points(c, line, "points", json_object_get(j, "points"), 2, r);
		break;
	case HL_REQ_IMAX:
		break;
	}
	if (rc < 0)
		return rc;
	if (r->kind == HL_REQ_POINT || r->kind == HL_REQ_SUM)
		for (k = 0; k < r->n_pts; k++)
			if (fabs(r->pts[k][0]) > 1e8 || fabs(r->pts[k][1]) > 1e8)
				return fail(c, line, "%s: a %s cannot have an open end", what,
					    kinds[r->kind]);
	if (get_limit(c, line, reg, r, "min_cd", json_object_get(j, "min_cd"), &r->min) < 0 ||
	    get_limit(c, line, reg, r, "max_cd", json_object_get(j, "max_cd"), &r->max) < 0)
		return -EBADMSG;
	if (!r->min.set && !r->max.set)
		return fail(c, line, "%s: expected 'min_cd' or 'max_cd' (or both)", what);
	if (r->min.set && r->max.set && r->min.of < 0 && r->max.of < 0 && r->min.cd > r->max.cd)
		return fail(c, line, "%s: min_cd %g is above max_cd %g", what, r->min.cd,
			    r->max.cd);
	reg->n_requirements++;
	return 0;
}

static int parse_receiver(const struct ctx *c, struct hl_regulation *reg, json_t *j)
{
	static const char *const keys[] = { "shape", "size_deg", "source", NULL };
	const int line = line_of(c, "\"receiver\"");
	json_t *shape = json_object_get(j, "shape"), *size = json_object_get(j, "size_deg");

	if (!json_is_object(j))
		return fail(c, line, "'receiver': expected an object");
	if (check_keys(c, line, "'receiver'", j, keys) < 0)
		return -EBADMSG;
	if (!json_is_string(shape) || (strcmp(json_string_value(shape), "square") &&
				       strcmp(json_string_value(shape), "circle")))
		return fail(c, line, "'receiver': 'shape' expected \"square\" or \"circle\"");
	reg->receiver = strcmp(json_string_value(shape), "square") ? HL_RECEIVER_CIRCLE :
								     HL_RECEIVER_SQUARE;
	if (!json_is_number(size) || !(json_number_value(size) > 0.0) ||
	    json_number_value(size) > 5.0)
		return fail(c, line, "'receiver': 'size_deg' expected a number in (0, 5]");
	reg->receiver_deg = json_number_value(size);
	if (!json_is_string(json_object_get(j, "source")))
		return fail(c, line, "'receiver': missing 'source' (the citation)");
	return 0;
}

static int get_angle(const struct ctx *c, int line, json_t *obj, const char *key, char axis,
		     double *ret)
{
	json_t *j = json_object_get(obj, key);

	if (json_is_number(j)) {
		*ret = json_number_value(j);
		return 0;
	}
	if (!json_is_string(j) || hl_regulation_angle(json_string_value(j), axis, ret) < 0 ||
	    fabs(*ret) > 90.0)
		return fail(c, line, "'aim': '%s' expected an angle like \"%s\"", key,
			    axis == 'h' ? "2.5L" : "0.57D");
	return 0;
}

static int get_number(const struct ctx *c, int line, json_t *obj, const char *key, double lo,
		      double hi, double *ret)
{
	json_t *j = json_object_get(obj, key);

	if (!json_is_number(j) || !(json_number_value(j) >= lo) || json_number_value(j) > hi)
		return fail(c, line, "'aim': '%s' expected a number in [%g, %g]", key, lo, hi);
	*ret = json_number_value(j);
	return 0;
}

static int parse_aim(const struct ctx *c, struct hl_regulation *reg, json_t *j)
{
	static const char *const keys[] = {
		"method", "scan_h", "cutoff_v", "linearity_h", "linearity_max_deg",
		"g_min",  "g_max",  "source",	NULL
	};
	const int line = line_of(c, "\"aim\"");
	json_t *method = json_object_get(j, "method"), *lin;

	reg->aim = HL_REG_AIM_NONE;
	if (!j)
		return 0;
	if (!json_is_object(j))
		return fail(c, line, "'aim': expected an object");
	if (check_keys(c, line, "'aim'", j, keys) < 0)
		return -EBADMSG;
	if (json_is_string(method) && !strcmp(json_string_value(method), "none"))
		return 0;
	if (!json_is_string(method) || strcmp(json_string_value(method), "cutoff"))
		return fail(c, line, "'aim': 'method' expected \"none\" or \"cutoff\"");
	reg->aim = HL_REG_AIM_CUTOFF;
	reg->aim_g_max = INFINITY; /* g_max is optional: FMVSS 108 sets only a minimum */
	lin = json_object_get(j, "linearity_h");
	if (get_angle(c, line, j, "scan_h", 'h', &reg->aim_scan_h_deg) < 0 ||
	    get_angle(c, line, j, "cutoff_v", 'v', &reg->aim_cutoff_v_deg) < 0)
		return -EBADMSG;
	if (!json_is_array(lin) || json_array_size(lin) != 2)
		return fail(c, line,
			    "'aim': 'linearity_h' expected two angles like [\"1.5L\", \"3.5L\"]");
	for (int k = 0; k < 2; k++) {
		json_t *e = json_array_get(lin, k);

		if (!json_is_string(e) ||
		    hl_regulation_angle(json_string_value(e), 'h', &reg->aim_linearity_h_deg[k]) <
			    0 ||
		    fabs(reg->aim_linearity_h_deg[k]) > 90.0)
			return fail(c, line,
				    "'aim': 'linearity_h' expected two angles like \"1.5L\"");
	}
	if (get_number(c, line, j, "linearity_max_deg", 0.0, 5.0, &reg->aim_linearity_max_deg) <
		    0 ||
	    get_number(c, line, j, "g_min", 0.0, 10.0, &reg->aim_g_min) < 0 ||
	    (json_object_get(j, "g_max") &&
	     get_number(c, line, j, "g_max", 0.0, 10.0, &reg->aim_g_max) < 0))
		return -EBADMSG;
	if (reg->aim_g_min > reg->aim_g_max)
		return fail(c, line, "'aim': g_min is above g_max");
	return 0;
}

int hl_regulation_parse(const char *text, const char *name, struct hl_regulation **ret,
			struct hl_regulation_error *err)
{
	static const char *const keys[] = { "id",     "title",	  "source", "applies_to",   "beam",
					    "angles", "receiver", "aim",    "requirements", NULL };
	const struct ctx c = { .name = name, .text = text, .err = err };
	struct hl_regulation *reg;
	json_error_t jerr;
	json_t *root, *j;
	int rc = -EBADMSG;

	if (err)
		memset(err, 0, sizeof(*err));
	root = json_loads(text, JSON_REJECT_DUPLICATES, &jerr);
	if (!root) {
		if (err) {
			err->line = jerr.line;
			err->column = jerr.column;
			snprintf(err->msg, sizeof(err->msg), "%s:%d:%d: %s", name, jerr.line,
				 jerr.column, jerr.text);
		}
		return -EBADMSG;
	}
	reg = calloc(1, sizeof(*reg));
	if (!reg) {
		json_decref(root);
		return -ENOMEM;
	}
	if (!json_is_object(root)) {
		fail(&c, 1, "expected a JSON object at the top");
		goto err_free;
	}
	if (check_keys(&c, 0, "the set", root, keys) < 0 ||
	    copy_string(&c, line_of(&c, "\"id\""), "the set", root, "id", true, reg->id,
			sizeof(reg->id)) < 0 ||
	    copy_string(&c, line_of(&c, "\"title\""), "the set", root, "title", true, reg->title,
			sizeof(reg->title)) < 0 ||
	    copy_string(&c, line_of(&c, "\"source\""), "the set", root, "source", true, reg->source,
			sizeof(reg->source)) < 0)
		goto err_free;
	j = json_object_get(root, "applies_to");
	if (json_is_string(j) && !strcmp(json_string_value(j), "each_lamp")) {
		reg->applies = HL_REG_EACH_LAMP;
	} else if (json_is_string(j) && !strcmp(json_string_value(j), "pair_half")) {
		reg->applies = HL_REG_PAIR_HALF;
	} else {
		fail(&c, line_of(&c, "\"applies_to\""),
		     "'applies_to': expected \"each_lamp\" or \"pair_half\"");
		goto err_free;
	}
	j = json_object_get(root, "beam");
	reg->beam = HL_REG_BEAM_NONE;
	for (int b = HL_REG_BEAM_PASSING; j && b <= HL_REG_BEAM_ADB; b++)
		if (json_is_string(j) && !strcmp(json_string_value(j), hl_reg_beam_name(b)))
			reg->beam = (enum hl_reg_beam)b;
	if (j && reg->beam == HL_REG_BEAM_NONE) {
		fail(&c, line_of(&c, "\"beam\""),
		     "'beam': expected \"passing\", \"driving\" or \"adb\" (or no 'beam': every "
		     "mode)");
		goto err_free;
	}
	j = json_object_get(root, "angles");
	if (json_is_string(j) &&
	    (!strcmp(json_string_value(j), "A") || !strcmp(json_string_value(j), "B"))) {
		reg->angles = json_string_value(j)[0] == 'A' ? HL_ANGLES_A : HL_ANGLES_B;
	} else {
		fail(&c, line_of(&c, "\"angles\""), "'angles': expected \"A\" or \"B\"");
		goto err_free;
	}
	if (!json_object_get(root, "receiver")) {
		fail(&c, 0, "missing key 'receiver'");
		goto err_free;
	}
	if (parse_receiver(&c, reg, json_object_get(root, "receiver")) < 0 ||
	    parse_aim(&c, reg, json_object_get(root, "aim")) < 0)
		goto err_free;
	j = json_object_get(root, "requirements");
	if (!json_is_array(j) || !json_array_size(j) ||
	    json_array_size(j) > HL_REG_MAX_REQUIREMENTS) {
		fail(&c, line_of(&c, "\"requirements\""),
		     "'requirements': expected an array of 1 to %d requirements",
		     HL_REG_MAX_REQUIREMENTS);
		goto err_free;
	}
	for (size_t i = 0; i < json_array_size(j); i++)
		if (parse_requirement(&c, reg, (int)i, json_array_get(j, i)) < 0)
			goto err_free;
	json_decref(root);
	*ret = reg;
	return 0;

err_free:
	json_decref(root);
	free(reg);
	return rc;
}

int hl_regulation_read(const char *path, struct hl_regulation **ret,
		       struct hl_regulation_error *err)
{
	FILE *f = fopen(path, "re");
	char *text = NULL;
	size_t size = 0, len = 0;
	int rc;

	if (err)
		memset(err, 0, sizeof(*err));
	if (!f) {
		rc = -errno;
		if (err)
			snprintf(err->msg, sizeof(err->msg), "%s: cannot open: %s", path,
				 strerror(-rc));
		return rc;
	}
	for (;;) {
		if (len + 4096 + 1 > size) {
			char *t = realloc(text, size + 65536);

			if (!t) {
				free(text);
				fclose(f);
				return -ENOMEM;
			}
			text = t;
			size += 65536;
		}
		const size_t n = fread(text + len, 1, size - len - 1, f);

		len += n;
		if (n == 0)
			break;
	}
	rc = ferror(f) ? -EIO : 0;
	fclose(f);
	if (rc < 0) {
		if (err)
			snprintf(err->msg, sizeof(err->msg), "%s: read error", path);
		free(text);
		return rc;
	}
	text[len] = '\0';
	if (strlen(text) != len) {
		if (err)
			snprintf(err->msg, sizeof(err->msg),
				 "%s: expected JSON text, found a NUL byte", path);
		free(text);
		return -EBADMSG;
	}
	rc = hl_regulation_parse(text, path, ret, err);
	free(text);
	return rc;
}

void hl_regulation_free(struct hl_regulation *reg)
{
	free(reg);
}

static bool valid_id(const char *id)
{
	if (!*id || strlen(id) >= HL_REG_ID_MAX)
		return false;
	for (const char *p = id; *p; p++)
		if (!((*p >= 'a' && *p <= 'z') || (*p >= '0' && *p <= '9') || *p == '-' ||
		      *p == '_' || *p == '.'))
			return false;
	return id[0] != '.';
}

int hl_regulation_load(const char *dir, const char *id, struct hl_regulation **ret,
		       struct hl_regulation_error *err)
{
	char path[4096];
	struct hl_regulation *reg;
	int rc;

	if (err)
		memset(err, 0, sizeof(*err));
	if (!valid_id(id)) {
		if (err)
			snprintf(err->msg, sizeof(err->msg),
				 "'%s': expected a set id (lower-case letters, digits, '-')", id);
		return -EINVAL;
	}
	snprintf(path, sizeof(path), "%s/%s.json", dir, id);
	rc = hl_regulation_read(path, &reg, err);
	if (rc == -ENOENT && err)
		snprintf(err->msg, sizeof(err->msg), "no regulation set '%s' in %.400s", id, dir);
	if (rc < 0)
		return rc;
	if (strcmp(reg->id, id)) {
		if (err)
			snprintf(err->msg, sizeof(err->msg),
				 "%.300s: 'id' is '%s', expected '%s' (the file name)", path,
				 reg->id, id);
		hl_regulation_free(reg);
		return -EBADMSG;
	}
	*ret = reg;
	return 0;
}

int hl_regulation_default_dir(char *buf, size_t size)
{
	return hl_share_dir("regulations", buf, size);
}

static int cmp_str(const void *a, const void *b)
{
	return strcmp(*(char *const *)a, *(char *const *)b);
}

int hl_regulation_list(const char *dir, char ***ret)
{
	DIR *d = opendir(dir);
	struct dirent *e;
	char **ids = NULL;
	size_t n = 0;

	if (!d)
		return -errno;
	while ((e = readdir(d))) {
		const size_t len = strlen(e->d_name);
		char **t;

		if (len < 6 || strcmp(e->d_name + len - 5, ".json") || e->d_name[0] == '.')
			continue;
		t = realloc(ids, (n + 2) * sizeof(*ids));
		if (!t)
			goto err_nomem;
		ids = t;
		ids[n] = strndup(e->d_name, len - 5);
		if (!ids[n])
			goto err_nomem;
		ids[++n] = NULL;
	}
	closedir(d);
	if (!ids) {
		ids = calloc(1, sizeof(*ids));
		if (!ids)
			return -ENOMEM;
	}
	qsort(ids, n, sizeof(*ids), cmp_str);
	*ret = ids;
	return 0;

err_nomem:
	closedir(d);
	if (ids)
		ids[n] = NULL;
	hl_regulation_list_free(ids);
	return -ENOMEM;
}

void hl_regulation_list_free(char **ids)
{
	if (!ids)
		return;
	for (char **p = ids; *p; p++)
		free(*p);
	free(ids);
}

int hl_regulation_find(const struct hl_regulation *reg, const char *id)
{
	for (int k = 0; k < reg->n_requirements; k++)
		if (!strcmp(reg->req[k].id, id))
			return k;
	return -ENOENT;
}

const char *hl_req_kind_name(enum hl_req_kind kind)
{
	static const char *const names[] = { "point", "segment", "zone", "sum", "imax" };

	return (unsigned)kind < 5 ? names[kind] : "?";
}

const char *hl_reg_beam_name(enum hl_reg_beam beam)
{
	static const char *const names[] = { NULL, "passing", "driving", "adb" };

	return (unsigned)beam < sizeof(names) / sizeof(names[0]) ? names[beam] : NULL;
}
