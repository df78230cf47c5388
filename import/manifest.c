/* SPDX-License-Identifier: MIT */
#include "import/manifest.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "import/text.h"

struct source {
	char *file, *name;
	int format; /* enum hl_import_format, or -1: from the extension */
	int line; /* of the [source N] header; 0: not defined */
	int file_line;
};

struct hl_manifest {
	struct hl_lid_grid grid;
	int n_sources;
	struct source *sources;
};

int hl_import_format_from_name(const char *name)
{
	if (strcasecmp(name, "ies") == 0)
		return HL_IMPORT_IES;
	if (strcasecmp(name, "ldt") == 0)
		return HL_IMPORT_LDT;
	if (strcasecmp(name, "csv") == 0)
		return HL_IMPORT_CSV;
	return -EINVAL;
}

int hl_import_format_from_path(const char *path)
{
	const char *dot = strrchr(path, '.');

	if (!dot || strchr(dot, '/'))
		return -EINVAL;
	return hl_import_format_from_name(dot + 1);
}

void hl_manifest_free(struct hl_manifest *m)
{
	if (!m)
		return;
	for (int k = 0; k < m->n_sources; k++) {
		free(m->sources[k].file);
		free(m->sources[k].name);
	}
	free(m->sources);
	free(m);
}

static char *dup_n(const char *s, size_t n)
{
	char *d = malloc(n + 1);

	if (d) {
		memcpy(d, s, n);
		d[n] = '\0';
	}
	return d;
}

static size_t trim(const char **s, size_t n)
{
	while (n > 0 && (**s == ' ' || **s == '\t')) {
		(*s)++;
		n--;
	}
	while (n > 0 && ((*s)[n - 1] == ' ' || (*s)[n - 1] == '\t'))
		n--;
	return n;
}

static bool is(const char *s, size_t n, const char *word)
{
	return n == strlen(word) && memcmp(s, word, n) == 0;
}

/* Two numbers separated by a comma and/or blanks. */
static int pair(const char *s, size_t n, double *a, double *b)
{
	size_t i = 0, j;

	while (i < n && s[i] != ',' && s[i] != ' ' && s[i] != '\t')
		i++;
	if (hl_number_parse(s, i, a) < 0)
		return -EBADMSG;
	j = i;
	while (j < n && (s[j] == ' ' || s[j] == '\t'))
		j++;
	if (j < n && s[j] == ',')
		j++;
	while (j < n && (s[j] == ' ' || s[j] == '\t'))
		j++;
	return hl_number_parse(s + j, n - j, b);
}

static int samples(double first, double last, double step, int *ret)
{
	const double n = (last - first) / step;
	const long k = lround(n);

	if (!(last > first) || fabs(n - (double)k) > 1e-6 || k < 1 || k > 65535)
		return -EINVAL;
	*ret = (int)k + 1;
	return 0;
}

static int resolve(const char *base_dir, const char *s, size_t n, char **ret)
{
	char *p;

	if (n > 0 && s[0] == '/') {
		p = dup_n(s, n);
	} else if (base_dir && base_dir[0]) {
		size_t b = strlen(base_dir);

		p = malloc(b + 1 + n + 1);
		if (p) {
			memcpy(p, base_dir, b);
			p[b] = '/';
			memcpy(p + b + 1, s, n);
			p[b + 1 + n] = '\0';
		}
	} else {
		p = dup_n(s, n);
	}
	if (!p)
		return -ENOMEM;
	*ret = p;
	return 0;
}

int hl_manifest_parse(const char *buf, size_t len, const char *name, const char *base_dir,
		      struct hl_manifest **ret, struct hl_import_error *err)
{
	double h0 = -89.9, h1 = 89.9, v0 = -29.9, v1 = 19.9, step = 0.2;
	int grid_line = 0, h_line = 0, v_line = 0, step_line = 0, angles_line = 0;
	enum { NONE, GRID, SOURCE } section = NONE;
	struct hl_manifest *m;
	struct source *cur = NULL;
	struct hl_text t;
	const char *s;
	size_t n;
	int rc = 0, w, h;

	hl_text_init(&t, buf, len, name, err);
	m = calloc(1, sizeof(*m));
	if (!m)
		return -ENOMEM;
	m->grid.angles = HL_ANGLES_A;
	for (;;) {
		const int line = t.line;
		const char *key, *val, *eq;
		size_t kn, vn;

		if (!hl_text_line(&t, &s, &n))
			break;
		n = trim(&s, n);
		if (n == 0 || s[0] == '#' || s[0] == ';')
			continue;
		if (s[0] == '[') {
			const char *in = s + 1;
			size_t in_n;
			long k;
			double kd;

			if (s[n - 1] != ']') {
				rc = hl_text_fail_at(&t, line, (int)n, -EBADMSG,
						     "expected ']' at the end of the section line");
				goto err;
			}
			in_n = trim(&in, n - 2);
			if (is(in, in_n, "grid")) {
				if (grid_line) {
					rc = hl_text_fail_at(&t, line, 1, -EBADMSG,
							     "[grid] again (first on line %d): "
							     "expected it at most once",
							     grid_line);
					goto err;
				}
				grid_line = line;
				section = GRID;
				continue;
			}
			if (in_n > 7 && memcmp(in, "source ", 7) == 0) {
				const char *num = in + 7;
				size_t num_n = trim(&num, in_n - 7);

				if (hl_number_parse(num, num_n, &kd) < 0 || kd != floor(kd) ||
				    kd < 1 || kd > HL_LID_MAX_SOURCES) {
					rc = hl_text_fail_at(&t, line, 2, -EBADMSG,
							     "expected [source N] with N from 1 "
							     "to %d",
							     HL_LID_MAX_SOURCES);
					goto err;
				}
				k = (long)kd;
				if (k > m->n_sources) {
					struct source *more =
						realloc(m->sources, sizeof(*more) * k);

					if (!more) {
						rc = -ENOMEM;
						goto err;
					}
					memset(more + m->n_sources, 0,
					       sizeof(*more) * (k - m->n_sources));
					m->sources = more;
					m->n_sources = (int)k;
				}
				cur = &m->sources[k - 1];
				if (cur->line) {
					rc = hl_text_fail_at(&t, line, 1, -EBADMSG,
							     "[source %ld] again (first on line "
							     "%d): expected each source once",
							     k, cur->line);
					goto err;
				}
				cur->line = line;
				cur->format = -1;
				section = SOURCE;
				continue;
			}
			rc = hl_text_fail_at(&t, line, 2, -EBADMSG,
					     "expected the section [grid] or [source N]");
			goto err;
		}
		eq = memchr(s, '=', n);
		if (!eq) {
			rc = hl_text_fail_at(&t, line, 1, -EBADMSG,
					     "expected 'key = value', a [section] or a comment");
			goto err;
		}
		key = s;
		kn = trim(&key, (size_t)(eq - s));
		val = eq + 1;
		vn = trim(&val, n - (size_t)(eq + 1 - s));
		if (section == NONE) {
			rc = hl_text_fail_at(&t, line, 1, -EBADMSG,
					     "expected a [grid] or [source N] section before "
					     "'key = value'");
			goto err;
		}
		if (vn == 0) {
			rc = hl_text_fail_at(&t, line, (int)(eq - s) + 2, -EBADMSG,
					     "expected a value after '='");
			goto err;
		}
		if (section == GRID) {
			int *seen;

			if (is(key, kn, "angles"))
				seen = &angles_line;
			else if (is(key, kn, "h"))
				seen = &h_line;
			else if (is(key, kn, "v"))
				seen = &v_line;
			else if (is(key, kn, "step"))
				seen = &step_line;
			else {
				rc = hl_text_fail_at(&t, line, 1, -EBADMSG,
						     "expected a [grid] key: angles, h, v or step");
				goto err;
			}
			if (*seen) {
				rc = hl_text_fail_at(&t, line, 1, -EBADMSG,
						     "'%.*s' again (first on line %d): expected "
						     "each key once",
						     (int)kn, key, *seen);
				goto err;
			}
			*seen = line;
			if (seen == &angles_line) {
				if (is(val, vn, "A"))
					m->grid.angles = HL_ANGLES_A;
				else if (is(val, vn, "B"))
					m->grid.angles = HL_ANGLES_B;
				else {
					rc = hl_text_fail_at(&t, line, (int)(val - s) + 1, -EBADMSG,
							     "expected angles A or B");
					goto err;
				}
			} else if (seen == &step_line) {
				if (hl_number_parse(val, vn, &step) < 0 || !(step >= 0.001) ||
				    step > 90.0) {
					rc = hl_text_fail_at(&t, line, (int)(val - s) + 1, -EBADMSG,
							     "expected a step in degrees, 0.001 "
							     "to 90");
					goto err;
				}
			} else {
				double *a = seen == &h_line ? &h0 : &v0;
				double *b = seen == &h_line ? &h1 : &v1;

				if (pair(val, vn, a, b) < 0) {
					rc = hl_text_fail_at(&t, line, (int)(val - s) + 1, -EBADMSG,
							     "expected two angles 'first, last' "
							     "in degrees");
					goto err;
				}
			}
			continue;
		}
		if (is(key, kn, "file")) {
			if (cur->file) {
				rc = hl_text_fail_at(&t, line, 1, -EBADMSG,
						     "'file' again (first on line %d): expected "
						     "one file per source",
						     cur->file_line);
				goto err;
			}
			cur->file_line = line;
			rc = resolve(base_dir, val, vn, &cur->file);
		} else if (is(key, kn, "name")) {
			if (cur->name) {
				rc = hl_text_fail_at(&t, line, 1, -EBADMSG,
						     "'name' again: expected one name per source");
				goto err;
			}
			cur->name = dup_n(val, vn);
			rc = cur->name ? 0 : -ENOMEM;
		} else if (is(key, kn, "format")) {
			char f[8];

			if (cur->format >= 0) {
				rc = hl_text_fail_at(&t, line, 1, -EBADMSG,
						     "'format' again: expected it once per source");
				goto err;
			}
			snprintf(f, sizeof(f), "%.*s", (int)(vn < 7 ? vn : 7), val);
			cur->format = vn < 7 ? hl_import_format_from_name(f) : -EINVAL;
			if (cur->format < 0) {
				rc = hl_text_fail_at(&t, line, (int)(val - s) + 1, -EBADMSG,
						     "expected format ies, ldt or csv");
				goto err;
			}
		} else {
			rc = hl_text_fail_at(&t, line, 1, -EBADMSG,
					     "expected a [source N] key: file, name or format");
			goto err;
		}
		if (rc < 0)
			goto err;
	}

	if (m->n_sources == 0) {
		rc = hl_text_fail(&t, -EBADMSG, "expected at least one [source N] section");
		goto err;
	}
	for (int k = 0; k < m->n_sources; k++) {
		struct source *src = &m->sources[k];

		if (!src->line) {
			rc = hl_text_fail(&t, -EBADMSG,
					  "expected sources 1..%d without gaps, [source %d] is "
					  "missing",
					  m->n_sources, k + 1);
			goto err;
		}
		if (!src->file || !src->name) {
			rc = hl_text_fail_at(&t, src->line, 1, -EBADMSG,
					     "expected 'file' and 'name' in [source %d]", k + 1);
			goto err;
		}
		if (src->format < 0) {
			src->format = hl_import_format_from_path(src->file);
			if (src->format < 0) {
				rc = hl_text_fail_at(&t, src->file_line, 1, -EBADMSG,
						     "cannot tell the format of '%s' from its "
						     "extension: expected .ies, .ldt or .csv, or "
						     "'format ='",
						     src->file);
				goto err;
			}
		}
	}
	if (samples(h0, h1, step, &w) < 0 || samples(v0, v1, step, &h) < 0) {
		rc = hl_text_fail_at(&t, grid_line ? grid_line : 1, 1, -EBADMSG,
				     "expected grid ranges h %g..%g and v %g..%g that are whole "
				     "numbers (1..65535) of steps of %g degrees",
				     h0, h1, v0, v1, step);
		goto err;
	}
	m->grid.width = w;
	m->grid.height = h;
	m->grid.h_first_deg = (float)h0;
	m->grid.h_last_deg = (float)h1;
	m->grid.v_first_deg = (float)v0;
	m->grid.v_last_deg = (float)v1;
	if (hl_lid_grid_check(&m->grid) < 0) {
		rc = hl_text_fail_at(&t, grid_line ? grid_line : 1, 1, -EBADMSG,
				     "expected a grid inside H -180..180 and V -90..90 degrees");
		goto err;
	}
	*ret = m;
	return 0;

err:
	hl_manifest_free(m);
	return rc;
}

int hl_manifest_read(const char *path, struct hl_manifest **ret, struct hl_import_error *err)
{
	const char *slash = strrchr(path, '/');
	char *buf, *dir = NULL;
	size_t len;
	int rc = hl_import_read_file(path, &buf, &len, err);

	if (rc < 0)
		return rc;
	if (slash) {
		dir = dup_n(path, slash == path ? 1 : (size_t)(slash - path));
		if (!dir) {
			free(buf);
			return -ENOMEM;
		}
	}
	rc = hl_manifest_parse(buf, len, path, dir, ret, err);
	free(dir);
	free(buf);
	return rc;
}

const struct hl_lid_grid *hl_manifest_grid(const struct hl_manifest *m)
{
	return &m->grid;
}

int hl_manifest_n_sources(const struct hl_manifest *m)
{
	return m->n_sources;
}

const char *hl_manifest_file(const struct hl_manifest *m, int k)
{
	return m->sources[k].file;
}

const char *hl_manifest_name(const struct hl_manifest *m, int k)
{
	return m->sources[k].name;
}

enum hl_import_format hl_manifest_format(const struct hl_manifest *m, int k)
{
	return (enum hl_import_format)m->sources[k].format;
}

int hl_manifest_line(const struct hl_manifest *m, int k)
{
	return m->sources[k].line;
}
