/* SPDX-License-Identifier: MIT */
#include "import/eulumdat.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "import/text.h"

#define MAX_C_PLANES 3600
#define MAX_GAMMA 18000
#define MAX_LAMP_SETS 1000

/* One field: the next line. */
static int field(struct hl_text *t, const char *what, const char **ret_s, size_t *ret_len,
		 int *ret_line)
{
	*ret_line = t->line;
	if (!hl_text_line(t, ret_s, ret_len))
		return hl_text_fail(t, -EBADMSG, "expected %s, found the end of the file", what);
	return 0;
}

static int field_number(struct hl_text *t, const char *what, double *ret)
{
	const char *s;
	size_t n;
	int line, rc = field(t, what, &s, &n, &line);
	size_t lead = 0;

	if (rc < 0)
		return rc;
	while (lead < n && (s[lead] == ' ' || s[lead] == '\t'))
		lead++;
	while (n > lead && (s[n - 1] == ' ' || s[n - 1] == '\t'))
		n--;
	if (hl_number_parse(s + lead, n - lead, ret) < 0)
		return hl_text_fail_at(t, line, (int)lead + 1, -EBADMSG,
				       "expected %s (one finite decimal number on the line)", what);
	return 0;
}

static int field_int(struct hl_text *t, const char *what, long min, long max, long *ret)
{
	double v;
	int rc = field_number(t, what, &v);

	if (rc < 0)
		return rc;
	if (v != floor(v) || v < (double)min || v > (double)max)
		return hl_text_fail_at(t, t->line - 1, 1, -EBADMSG,
				       "expected %s, an integer from %ld to %ld, found %g", what,
				       min, max, v);
	*ret = (long)v;
	return 0;
}

static int field_text(struct hl_text *t, const char *what)
{
	const char *s;
	size_t n;
	int line;

	return field(t, what, &s, &n, &line);
}

static int angles(struct hl_text *t, int n, double *a, const char *what, double lo, double hi)
{
	char name[64];
	int rc;

	for (int i = 0; i < n; i++) {
		snprintf(name, sizeof(name), "%s angle %d of %d", what, i + 1, n);
		if ((rc = field_number(t, name, &a[i])) < 0)
			return rc;
		if (a[i] < lo || a[i] > hi)
			return hl_text_fail_at(t, t->line - 1, 1, -EBADMSG,
					       "expected %s in %g..%g degrees, found %g", name, lo,
					       hi, a[i]);
		if (i > 0 && !(a[i] > a[i - 1]))
			return hl_text_fail_at(t, t->line - 1, 1, -EBADMSG,
					       "expected %s greater than the one before (%g), "
					       "found %g: angles must increase",
					       name, a[i - 1], a[i]);
	}
	return 0;
}

static int parse(struct hl_text *t, struct hl_eulumdat_info *info, struct hl_gonio **ret)
{
	static const char *const dims[] = {
		"the luminaire length or diameter (mm)",
		"the luminaire width (mm)",
		"the luminaire height (mm)",
		"the luminous area length or diameter (mm)",
		"the luminous area width (mm)",
		"the luminous area height at C0 (mm)",
		"the luminous area height at C90 (mm)",
		"the luminous area height at C180 (mm)",
		"the luminous area height at C270 (mm)",
		"the downward flux fraction (%)",
		"the light output ratio (%)",
	};
	double v, *c = NULL, *g = NULL;
	/* set by field_int() before use; initialised for GCC, which cannot see that in Release */
	long ityp = 0, isym = 0, mc = 0, ng = 0, sets = 0, lamps = 0;
	float *values = NULL;
	int rc, first_plane = 0, c_line, n_planes;
	size_t n_values;
	enum hl_gonio_csym sym;

	if ((rc = field_text(t, "the company identification line")) < 0)
		return rc;
	if ((rc = field_int(t, "the type indicator Ityp", 0, 3, &ityp)) < 0)
		return rc;
	if ((rc = field_int(t, "the symmetry indicator Isym", 0, 4, &isym)) < 0)
		return rc;
	if ((rc = field_int(t, "the number of C planes Mc", 1, MAX_C_PLANES, &mc)) < 0)
		return rc;
	if ((isym == 2 || isym == 3) && mc % 2 != 0)
		return hl_text_fail_at(t, t->line - 1, 1, -EBADMSG,
				       "expected an even number of C planes Mc for symmetry "
				       "indicator %ld, found %ld",
				       isym, mc);
	if (isym == 4 && mc % 4 != 0)
		return hl_text_fail_at(t, t->line - 1, 1, -EBADMSG,
				       "expected a number of C planes Mc divisible by 4 for "
				       "symmetry indicator 4, found %ld",
				       mc);
	if ((rc = field_number(t, "the distance between C planes Dc", &v)) < 0)
		return rc;
	if ((rc = field_int(t, "the number of intensities per C plane Ng", 2, MAX_GAMMA, &ng)) < 0)
		return rc;
	if ((rc = field_number(t, "the distance between gamma angles Dg", &v)) < 0)
		return rc;
	if ((rc = field_text(t, "the measurement report number")) < 0 ||
	    (rc = field_text(t, "the luminaire name")) < 0 ||
	    (rc = field_text(t, "the luminaire number")) < 0 ||
	    (rc = field_text(t, "the file name")) < 0 ||
	    (rc = field_text(t, "the date and user")) < 0)
		return rc;
	for (size_t i = 0; i < sizeof(dims) / sizeof(dims[0]); i++)
		if ((rc = field_number(t, dims[i], &v)) < 0)
			return rc;
	if ((rc = field_number(t, "the conversion factor for intensities",
			       &info->conversion_factor)) < 0)
		return rc;
	if (!(info->conversion_factor > 0.0))
		return hl_text_fail_at(t, t->line - 1, 1, -EBADMSG,
				       "expected a conversion factor > 0, found %g",
				       info->conversion_factor);
	if ((rc = field_number(t, "the measurement tilt (degrees)", &v)) < 0)
		return rc;
	if ((rc = field_int(t, "the number of standard sets of lamps", 1, MAX_LAMP_SETS, &sets)) <
	    0)
		return rc;
	info->n_lamp_sets = (int)sets;
	for (long i = 0; i < sets; i++)
		if ((rc = field_int(t, "the number of lamps of a set (negative: absolute)", -100000,
				    100000, &lamps)) < 0)
			return rc;
	for (long i = 0; i < sets; i++)
		if ((rc = field_text(t, "the type of lamps of a set")) < 0)
			return rc;
	info->lamp_flux_lm = 0.0;
	for (long i = 0; i < sets; i++) {
		if ((rc = field_number(t, "the total luminous flux of a lamp set (lm)", &v)) < 0)
			return rc;
		if (!(v > 0.0))
			return hl_text_fail_at(t, t->line - 1, 1, -EBADMSG,
					       "expected a lamp flux > 0 lm, found %g", v);
		info->lamp_flux_lm += v;
	}
	for (long i = 0; i < sets; i++)
		if ((rc = field_text(t, "the colour temperature of a lamp set")) < 0)
			return rc;
	for (long i = 0; i < sets; i++)
		if ((rc = field_text(t, "the colour rendering index of a lamp set")) < 0)
			return rc;
	for (long i = 0; i < sets; i++)
		if ((rc = field_number(t, "the wattage of a lamp set including ballast (W)", &v)) <
		    0)
			return rc;
	for (int i = 0; i < 10; i++)
		if ((rc = field_number(t, "a direct ratio", &v)) < 0)
			return rc;

	switch (isym) {
	case 0:
		n_planes = (int)mc;
		sym = HL_GONIO_CSYM_NONE;
		break;
	case 1:
		n_planes = 1;
		sym = HL_GONIO_CSYM_ROTATIONAL;
		break;
	case 2:
		n_planes = (int)mc / 2 + 1;
		sym = HL_GONIO_CSYM_C0_C180;
		break;
	case 3:
		n_planes = (int)mc / 2 + 1;
		first_plane = (int)mc / 4;
		sym = HL_GONIO_CSYM_C90_C270;
		break;
	default:
		n_planes = (int)mc / 4 + 1;
		sym = HL_GONIO_CSYM_QUADRANT;
		break;
	}
	info->type_indicator = (int)ityp;
	info->symmetry = (int)isym;
	info->n_c_planes = (int)mc;
	info->n_gamma = (int)ng;
	info->n_planes_stored = n_planes;
	info->scale = info->lamp_flux_lm / 1000.0 * info->conversion_factor;

	n_values = (size_t)n_planes * (size_t)ng;
	/* one value per line, at least two bytes each: refuse a large table that cannot be there */
	if (n_values > 65536 &&
	    (size_t)(t->end - t->p) / 2 + 1 < n_values + (size_t)mc + (size_t)ng)
		return hl_text_fail(t, -EBADMSG,
				    "the file is too short for the %ld C angles, %ld gamma angles "
				    "and %zu intensities its header announces (truncated?)",
				    mc, ng, n_values);
	c = malloc(sizeof(double) * mc);
	g = malloc(sizeof(double) * ng);
	values = malloc(sizeof(float) * n_values);
	if (!c || !g || !values) {
		rc = -ENOMEM;
		goto out;
	}
	c_line = t->line;
	if ((rc = angles(t, (int)mc, c, "C", 0.0, 360.0)) < 0)
		goto out;
	if ((rc = angles(t, (int)ng, g, "gamma", 0.0, 180.0)) < 0)
		goto out;
	for (size_t k = 0; k < n_values; k++) {
		const int i = (int)(k / ng), j = (int)(k % ng);

		if ((rc = field_number(t, "an intensity (cd/klm)", &v)) < 0) {
			if (t->err) {
				size_t l = strlen(t->err->msg);

				snprintf(t->err->msg + l, sizeof(t->err->msg) - l,
					 " (value %zu of %zu: C %g, gamma %g)", k + 1, n_values,
					 c[(first_plane + i) % mc], g[j]);
			}
			goto out;
		}
		if (v < 0.0) {
			rc = hl_text_fail_at(
				t, t->line - 1, 1, -EBADMSG,
				"expected an intensity >= 0 at C %g, gamma %g, found %g",
				c[(first_plane + i) % mc], g[j], v);
			goto out;
		}
		v *= info->scale;
		if (!(v <= 3.0e38)) {
			rc = hl_text_fail_at(t, t->line - 1, 1, -EBADMSG,
					     "the intensity at C %g, gamma %g times the lamp flux "
					     "is out of range",
					     c[(first_plane + i) % mc], g[j]);
			goto out;
		}
		values[k] = (float)v;
	}
	for (;;) {
		const char *s;
		size_t n;
		int line = t->line;

		if (!hl_text_line(t, &s, &n))
			break;
		while (n > 0 && (s[n - 1] == ' ' || s[n - 1] == '\t' || s[n - 1] == 0x1a))
			n--;
		if (n > 0) {
			rc = hl_text_fail_at(t, line, 1, -EBADMSG,
					     "expected the end of the file after the %zu "
					     "intensities",
					     n_values);
			goto out;
		}
	}

	/* the stored planes must be the ones the symmetry names */
	{
		static const double want[5][2] = {
			{ 0, 0 }, { 0, 0 }, { 0, 180 }, { 90, 270 }, { 0, 90 }
		};
		const double lo = c[first_plane];
		const double hi = c[first_plane + n_planes - 1];

		if (isym == 0 && (c[0] != 0.0 || !(c[mc - 1] > 180.0) || mc < 2)) {
			rc = hl_text_fail_at(t, c_line, 1, -EBADMSG,
					     "expected C angles from 0 to above 180 for symmetry "
					     "indicator 0, found %g..%g",
					     c[0], c[mc - 1]);
			goto out;
		}
		if (isym >= 2 && (lo != want[isym][0] || hi != want[isym][1])) {
			rc = hl_text_fail_at(t, c_line, 1, -EBADMSG,
					     "expected the stored C planes %g..%g for symmetry "
					     "indicator %ld, the C angles give %g..%g",
					     want[isym][0], want[isym][1], isym, lo, hi);
			goto out;
		}
	}
	rc = hl_gonio_new_c(sym, n_planes, c + first_plane, (int)ng, g, values, ret);
	if (rc == -EINVAL)
		rc = hl_text_fail_at(t, c_line, 1, -EBADMSG, "inconsistent angle table");
out:
	free(c);
	free(g);
	free(values);
	return rc;
}

int hl_eulumdat_parse(const char *buf, size_t len, const char *name, struct hl_gonio **ret,
		      struct hl_eulumdat_info *ret_info, struct hl_import_error *err)
{
	struct hl_eulumdat_info info;
	struct hl_text t;
	int rc;

	memset(&info, 0, sizeof(info));
	hl_text_init(&t, buf, len, name, err);
	rc = parse(&t, &info, ret);
	if (rc == 0 && ret_info)
		*ret_info = info;
	return rc;
}

int hl_eulumdat_read(const char *path, struct hl_gonio **ret, struct hl_eulumdat_info *ret_info,
		     struct hl_import_error *err)
{
	char *buf;
	size_t len;
	int rc = hl_import_read_file(path, &buf, &len, err);

	if (rc < 0)
		return rc;
	rc = hl_eulumdat_parse(buf, len, path, ret, ret_info, err);
	free(buf);
	return rc;
}
