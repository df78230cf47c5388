/* SPDX-License-Identifier: MIT */
#include "import/ies.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "import/text.h"

#define MAX_ANGLES 100000
#define MAX_VALUES (16L << 20) /* candela values per file */

static const char *const versions[] = {
	"IESNA91",
	"IESNA:LM-63-1995",
	"IESNA:LM-63-2002",
	"IES:LM-63-2019",
};

static bool starts_with(const char *s, size_t n, const char *prefix)
{
	size_t k = strlen(prefix);

	return n >= k && memcmp(s, prefix, k) == 0;
}

static size_t trim_right(const char *s, size_t n)
{
	while (n > 0 && (s[n - 1] == ' ' || s[n - 1] == '\t'))
		n--;
	return n;
}

/* The format line, the keyword block and TILT=NONE. */
static int parse_header(struct hl_text *t, struct hl_ies_info *info)
{
	const char *s;
	size_t n;
	int line;
	bool have_keyword = false;

	/* a UTF-8 byte order mark is not part of the format line */
	if (t->end - t->p >= 3 && memcmp(t->p, "\xef\xbb\xbf", 3) == 0)
		t->p += 3;
	line = t->line;
	if (!hl_text_line(t, &s, &n))
		return hl_text_fail(t, -EBADMSG,
				    "expected the LM-63 format line (e.g. IESNA:LM-63-2002), "
				    "found an empty file");
	n = trim_right(s, n);
	info->version[0] = '\0';
	for (size_t i = 0; i < sizeof(versions) / sizeof(versions[0]); i++)
		if (n == strlen(versions[i]) && memcmp(s, versions[i], n) == 0)
			snprintf(info->version, sizeof(info->version), "%s", versions[i]);
	if (!info->version[0])
		return hl_text_fail_at(t, line, 1, -EBADMSG,
				       "expected the LM-63 format line IESNA91, IESNA:LM-63-1995, "
				       "IESNA:LM-63-2002 or IES:LM-63-2019");

	for (;;) {
		line = t->line;
		if (!hl_text_line(t, &s, &n))
			return hl_text_fail(t, -EBADMSG,
					    "expected a TILT= line after the keywords, found the "
					    "end of the file");
		n = trim_right(s, n);
		if (starts_with(s, n, "TILT=")) {
			if (n == 9 && memcmp(s + 5, "NONE", 4) == 0)
				return 0;
			if (n == 12 && memcmp(s + 5, "INCLUDE", 7) == 0)
				return hl_text_fail_at(t, line, 6, -ENOTSUP,
						       "TILT=INCLUDE (a lamp-tilt table) is not "
						       "supported; expected TILT=NONE");
			return hl_text_fail_at(t, line, 6, -ENOTSUP,
					       "TILT=<file> (a lamp-tilt file) is not supported; "
					       "expected TILT=NONE");
		}
		if (n == 0)
			continue; /* blank lines between keywords are harmless */
		if (s[0] != '[' || !memchr(s, ']', n))
			return hl_text_fail_at(t, line, 1, -EBADMSG,
					       "expected a [KEYWORD] line or TILT=");
		if (starts_with(s, n, "[MORE]")) {
			if (!have_keyword)
				return hl_text_fail_at(t, line, 1, -EBADMSG,
						       "[MORE] continues nothing: expected a "
						       "[KEYWORD] line before it");
		} else {
			if (memchr(s, ']', n) == s + 1)
				return hl_text_fail_at(t, line, 2, -EBADMSG,
						       "expected a keyword between [ and ]");
			have_keyword = true;
		}
	}
}

/* A number token with its position, for messages about its value. */
struct pos {
	int line, col;
};

static int number_at(struct hl_text *t, const char *what, double *ret, struct pos *at)
{
	hl_text_skip_blanks(t, true, true);
	at->line = t->line;
	at->col = t->col;
	return hl_text_number(t, true, what, ret);
}

static int angles(struct hl_text *t, int n, double *a, const char *what, double lo, double hi,
		  struct pos *first, struct pos *last)
{
	char name[64];
	struct pos at = { 0, 0 };
	int rc;

	for (int i = 0; i < n; i++) {
		snprintf(name, sizeof(name), "%s angle %d of %d", what, i + 1, n);
		rc = number_at(t, name, &a[i], &at);
		if (rc < 0)
			return rc;
		if (i == 0)
			*first = at;
		if (a[i] < lo || a[i] > hi)
			return hl_text_fail_at(t, at.line, at.col, -EBADMSG,
					       "expected %s in %g..%g degrees, found %g", name, lo,
					       hi, a[i]);
		if (i > 0 && !(a[i] > a[i - 1]))
			return hl_text_fail_at(t, at.line, at.col, -EBADMSG,
					       "expected %s greater than the one before (%g), "
					       "found %g: angles must increase",
					       name, a[i - 1], a[i]);
	}
	*last = at;
	return 0;
}

static int parse_body(struct hl_text *t, struct hl_ies_info *info, struct hl_gonio **ret)
{
	struct pos at, counts, v_first, v_last, h_first, h_last;
	double v, dims[3], *vert = NULL, *hori = NULL;
	long n_lamps, n_v, n_h, type, units;
	float *values = NULL;
	enum hl_gonio_system system;
	size_t n_values;
	int rc;

	if ((rc = hl_text_int(t, true, "the number of lamps", 1, 1000000, &n_lamps)) < 0)
		return rc;
	if ((rc = number_at(t, "the lumens per lamp", &info->lumens_per_lamp, &at)) < 0)
		return rc;
	if (info->lumens_per_lamp != -1.0 && !(info->lumens_per_lamp > 0.0))
		return hl_text_fail_at(t, at.line, at.col, -EBADMSG,
				       "expected the lumens per lamp, > 0 or -1 (absolute "
				       "photometry), found %g",
				       info->lumens_per_lamp);
	if ((rc = number_at(t, "the candela multiplier", &info->candela_multiplier, &at)) < 0)
		return rc;
	if (!(info->candela_multiplier > 0.0))
		return hl_text_fail_at(t, at.line, at.col, -EBADMSG,
				       "expected a candela multiplier > 0, found %g",
				       info->candela_multiplier);
	if ((rc = hl_text_int(t, true, "the number of vertical angles", 2, MAX_ANGLES, &n_v)) < 0)
		return rc;
	hl_text_skip_blanks(t, true, true);
	at = (struct pos){ t->line, t->col };
	counts = at;
	if ((rc = hl_text_int(t, true, "the number of horizontal angles", 1, MAX_ANGLES, &n_h)) < 0)
		return rc;
	if (n_v * n_h > MAX_VALUES)
		return hl_text_fail_at(t, at.line, at.col, -EBADMSG,
				       "expected at most %ld candela values, the counts announce "
				       "%ld x %ld",
				       MAX_VALUES, n_h, n_v);
	if ((rc = hl_text_int(t, true, "the photometric type (1 = C, 2 = B, 3 = A)", 1, 3, &type)) <
	    0)
		return rc;
	if ((rc = hl_text_int(t, true, "the units type (1 = feet, 2 = metres)", 1, 2, &units)) < 0)
		return rc;
	for (int i = 0; i < 3; i++) {
		static const char *const what[] = { "the luminous width", "the luminous length",
						    "the luminous height" };

		if ((rc = hl_text_number(t, true, what[i], &dims[i])) < 0)
			return rc;
	}
	if ((rc = number_at(t, "the ballast factor", &info->ballast_factor, &at)) < 0)
		return rc;
	if (!(info->ballast_factor > 0.0))
		return hl_text_fail_at(t, at.line, at.col, -EBADMSG,
				       "expected a ballast factor > 0, found %g",
				       info->ballast_factor);
	if ((rc = number_at(t, "the ballast-lamp photometric factor (future use in 2019)",
			    &info->ballast_lamp_factor, &at)) < 0)
		return rc;
	if (!(info->ballast_lamp_factor > 0.0))
		return hl_text_fail_at(t, at.line, at.col, -EBADMSG,
				       "expected a ballast-lamp photometric factor > 0, found %g",
				       info->ballast_lamp_factor);
	if ((rc = hl_text_number(t, true, "the input watts", &v)) < 0)
		return rc;

	info->n_lamps = (int)n_lamps;
	info->n_vertical = (int)n_v;
	info->n_horizontal = (int)n_h;
	info->photometric_type = (int)type;
	system = type == 1 ? HL_GONIO_C : type == 2 ? HL_GONIO_B : HL_GONIO_A;
	info->scale = info->candela_multiplier * info->ballast_factor;
	if (strcmp(info->version, "IES:LM-63-2019") != 0)
		info->scale *= info->ballast_lamp_factor;

	/*
	 * Each number takes at least one character and one separator: refuse a large table that
	 * cannot be there before allocating it (small ones fail where the data ends).
	 */
	n_values = (size_t)n_v * (size_t)n_h;
	if (n_values > 65536 &&
	    (size_t)(t->end - t->p) / 2 + 1 < n_values + (size_t)n_v + (size_t)n_h)
		return hl_text_fail_at(t, counts.line, counts.col, -EBADMSG,
				       "the file is too short for the %ld + %ld angles and %ld x "
				       "%ld candela values its header announces (truncated?)",
				       n_v, n_h, n_h, n_v);
	vert = malloc(sizeof(double) * n_v);
	hori = malloc(sizeof(double) * n_h);
	values = malloc(sizeof(float) * n_values);
	if (!vert || !hori || !values) {
		rc = -ENOMEM;
		goto out;
	}
	if (system == HL_GONIO_C)
		rc = angles(t, n_v, vert, "vertical", 0.0, 180.0, &v_first, &v_last);
	else if (system == HL_GONIO_B)
		rc = angles(t, n_v, vert, "vertical", -180.0, 180.0, &v_first, &v_last);
	else
		rc = angles(t, n_v, vert, "vertical", -90.0, 90.0, &v_first, &v_last);
	if (rc < 0)
		goto out;
	if (system == HL_GONIO_C)
		rc = angles(t, n_h, hori, "horizontal", 0.0, 360.0, &h_first, &h_last);
	else if (system == HL_GONIO_B)
		rc = angles(t, n_h, hori, "horizontal", -90.0, 90.0, &h_first, &h_last);
	else
		rc = angles(t, n_h, hori, "horizontal", -180.0, 180.0, &h_first, &h_last);
	if (rc < 0)
		goto out;

	for (long i = 0; i < n_h; i++) {
		for (long j = 0; j < n_v; j++) {
			double cd;

			if ((rc = number_at(t, "a candela value", &cd, &at)) < 0) {
				if (t->err) {
					size_t k = strlen(t->err->msg);

					snprintf(t->err->msg + k, sizeof(t->err->msg) - k,
						 " (value %ld of %zu: horizontal %g, vertical %g)",
						 i * n_v + j + 1, n_values, hori[i], vert[j]);
				}
				goto out;
			}
			if (cd < 0.0) {
				rc = hl_text_fail_at(t, at.line, at.col, -EBADMSG,
						     "expected a candela value >= 0 at horizontal "
						     "%g, vertical %g, found %g",
						     hori[i], vert[j], cd);
				goto out;
			}
			cd *= info->scale;
			if (!(cd <= 3.0e38)) {
				rc = hl_text_fail_at(t, at.line, at.col, -EBADMSG,
						     "the candela value at horizontal %g, vertical "
						     "%g times the multipliers is out of range",
						     hori[i], vert[j]);
				goto out;
			}
			values[i * n_v + j] = (float)cd;
		}
	}
	hl_text_skip_blanks(t, true, true);
	if (t->p < t->end && *t->p == 0x1a) /* DOS end-of-file mark */
		hl_text_advance(t);
	hl_text_skip_blanks(t, true, true);
	if (!hl_text_eof(t)) {
		rc = hl_text_fail(t, -EBADMSG,
				  "expected the end of the file after the %zu candela values",
				  n_values);
		goto out;
	}

	if (system == HL_GONIO_C) {
		const double first = hori[0], last = hori[n_h - 1];
		enum hl_gonio_csym sym;

		if (n_h == 1 && first == 0.0)
			sym = HL_GONIO_CSYM_ROTATIONAL;
		else if (first == 0.0 && last == 90.0)
			sym = HL_GONIO_CSYM_QUADRANT;
		else if (first == 0.0 && last == 180.0)
			sym = HL_GONIO_CSYM_C0_C180;
		else if (first == 90.0 && last == 270.0)
			sym = HL_GONIO_CSYM_C90_C270;
		else if (first == 0.0 && last > 180.0)
			sym = HL_GONIO_CSYM_NONE;
		else {
			rc = hl_text_fail_at(t, h_first.line, h_first.col, -EBADMSG,
					     "expected type C horizontal angles 0 (rotational), "
					     "0..90, 0..180, 90..270 or 0..360, found %g..%g",
					     first, last);
			goto out;
		}
		rc = hl_gonio_new_c(sym, (int)n_h, hori, (int)n_v, vert, values, ret);
	} else if (n_h < 2) {
		rc = hl_text_fail_at(t, h_first.line, h_first.col, -EBADMSG,
				     "expected at least 2 horizontal angles for type %c",
				     hl_gonio_system_letter(system));
	} else if (hori[0] == 0.0) {
		rc = hl_gonio_new_lateral(system, (int)n_h, hori, (int)n_v, vert, values, ret);
	} else {
		rc = hl_gonio_new(system, (int)n_h, hori, (int)n_v, vert, values, ret);
	}
	if (rc == -EINVAL) /* every table fault is reported above; keep the contract anyway */
		rc = hl_text_fail_at(t, h_first.line, h_first.col, -EBADMSG,
				     "inconsistent angle table");
out:
	free(vert);
	free(hori);
	free(values);
	return rc;
}

int hl_ies_parse(const char *buf, size_t len, const char *name, struct hl_gonio **ret,
		 struct hl_ies_info *ret_info, struct hl_import_error *err)
{
	struct hl_ies_info info;
	struct hl_text t;
	int rc;

	memset(&info, 0, sizeof(info));
	hl_text_init(&t, buf, len, name, err);
	rc = parse_header(&t, &info);
	if (rc == 0)
		rc = parse_body(&t, &info, ret);
	if (rc == 0 && ret_info)
		*ret_info = info;
	return rc;
}

int hl_ies_read(const char *path, struct hl_gonio **ret, struct hl_ies_info *ret_info,
		struct hl_import_error *err)
{
	char *buf;
	size_t len;
	int rc = hl_import_read_file(path, &buf, &len, err);

	if (rc < 0)
		return rc;
	rc = hl_ies_parse(buf, len, path, ret, ret_info, err);
	free(buf);
	return rc;
}
