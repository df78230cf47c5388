/* SPDX-License-Identifier: MIT */
#include "import/csv.h"

#include <errno.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "import/text.h"

#define MAX_ANGLES 100000
#define MAX_VALUES (16L << 20)

/* One cell of a line: [s, s + n) trimmed, starting at column col (1-based). */
struct cell {
	const char *s;
	size_t n;
	int col;
};

/* Splits off the next cell of the line [*p, end); false when the line is used up. */
static bool next_cell(const char *line, const char **p, const char *end, bool *more, struct cell *c)
{
	const char *q = *p, *e;

	if (!*more)
		return false;
	while (q < end && (*q == ' ' || *q == '\t'))
		q++;
	e = q;
	while (e < end && *e != ',')
		e++;
	c->s = q;
	c->col = (int)(q - line) + 1;
	c->n = (size_t)(e - q);
	while (c->n > 0 && (c->s[c->n - 1] == ' ' || c->s[c->n - 1] == '\t'))
		c->n--;
	*more = e < end; /* a comma follows */
	*p = e < end ? e + 1 : e;
	return true;
}

static bool skippable(const char *s, size_t n)
{
	size_t i = 0;

	while (i < n && (s[i] == ' ' || s[i] == '\t'))
		i++;
	return i == n || s[i] == '#';
}

static int check_angle(struct hl_text *t, int line, int col, const char *what, double a, double lo,
		       double hi, const double *prev, int *dir)
{
	if (a < lo || a > hi)
		return hl_text_fail_at(t, line, col, -EBADMSG,
				       "expected the %s angle in %g..%g degrees, found %g", what,
				       lo, hi, a);
	if (prev) {
		int d = a > *prev ? 1 : a < *prev ? -1 : 0;

		if (d == 0 || (*dir != 0 && d != *dir))
			return hl_text_fail_at(t, line, col, -EBADMSG,
					       "expected %s angles that strictly %s, found %g "
					       "after %g",
					       what,
					       *dir > 0 ? "increase" :
					       *dir < 0 ? "decrease" :
							  "increase or decrease",
					       a, *prev);
		*dir = d;
	}
	return 0;
}

static int parse(struct hl_text *t, struct hl_gonio **ret)
{
	enum hl_gonio_system system;
	double p_lo, p_hi, i_lo, i_hi;
	double *cols = NULL, *rows = NULL, *planes = NULL, *in = NULL;
	float *vals = NULL, *table = NULL;
	int n_cols = 0, n_rows = 0, cap_rows = 0, col_dir = 0, row_dir = 0, rc = 0;
	int header_line = 0;
	const char *s;
	size_t n;

	/* header */
	for (;;) {
		header_line = t->line;
		if (!hl_text_line(t, &s, &n))
			return hl_text_fail(t, -EBADMSG,
					    "expected the header line (A, B or C, then the column "
					    "angles), found the end of the file");
		if (!skippable(s, n))
			break;
	}
	{
		const char *p = s, *end = s + n;
		bool more = true;
		struct cell c;
		int cap = 64;

		next_cell(s, &p, end, &more, &c);
		if (c.n != 1 || (c.s[0] != 'A' && c.s[0] != 'B' && c.s[0] != 'C'))
			return hl_text_fail_at(t, header_line, c.col, -EBADMSG,
					       "expected the angle system A, B or C in the first "
					       "cell of the header");
		system = c.s[0] == 'A' ? HL_GONIO_A : c.s[0] == 'B' ? HL_GONIO_B : HL_GONIO_C;
		{
			static const double r[3][4] = {
				[HL_GONIO_A] = { -180, 180, -90, 90 },
				[HL_GONIO_B] = { -90, 90, -180, 180 },
				[HL_GONIO_C] = { 0, 360, 0, 180 },
			};

			p_lo = r[system][0];
			p_hi = r[system][1];
			i_lo = r[system][2];
			i_hi = r[system][3];
		}
		cols = malloc(sizeof(double) * cap);
		if (!cols)
			return -ENOMEM;
		while (next_cell(s, &p, end, &more, &c)) {
			double a;

			if (n_cols == MAX_ANGLES) {
				rc = hl_text_fail_at(t, header_line, c.col, -EBADMSG,
						     "expected at most %d columns", MAX_ANGLES);
				goto out;
			}
			if (hl_number_parse(c.s, c.n, &a) < 0) {
				rc = hl_text_fail_at(t, header_line, c.col, -EBADMSG,
						     "expected column angle %d (a finite decimal "
						     "number)",
						     n_cols + 1);
				goto out;
			}
			rc = check_angle(t, header_line, c.col,
					 system == HL_GONIO_C ? "C (column)" : "H (column)", a,
					 p_lo, p_hi, n_cols ? &cols[n_cols - 1] : NULL, &col_dir);
			if (rc < 0)
				goto out;
			if (n_cols == cap) {
				double *bigger = realloc(cols, sizeof(double) * cap * 2);

				if (!bigger) {
					rc = -ENOMEM;
					goto out;
				}
				cols = bigger;
				cap *= 2;
			}
			cols[n_cols++] = a;
		}
		if (n_cols < 2) {
			rc = hl_text_fail_at(t, header_line, (int)n + 1, -EBADMSG,
					     "expected at least 2 column angles in the header");
			goto out;
		}
	}

	/* rows */
	for (;;) {
		const int line = t->line;
		const char *p, *end;
		bool more = true;
		struct cell c;
		double a;
		int k = 0;

		if (!hl_text_line(t, &s, &n))
			break;
		if (skippable(s, n))
			continue;
		p = s;
		end = s + n;
		if (n_rows == cap_rows) {
			int cap = cap_rows ? cap_rows * 2 : 64;
			double *r;
			float *v;

			if (cap > MAX_ANGLES || (long)cap * n_cols > MAX_VALUES)
				cap = n_rows + 1;
			if (n_rows >= MAX_ANGLES || (long)(n_rows + 1) * n_cols > MAX_VALUES) {
				rc = hl_text_fail_at(t, line, 1, -EBADMSG,
						     "expected at most %d rows and %ld values",
						     MAX_ANGLES, MAX_VALUES);
				goto out;
			}
			r = realloc(rows, sizeof(double) * cap);
			if (r)
				rows = r;
			v = realloc(vals, sizeof(float) * (size_t)cap * n_cols);
			if (v)
				vals = v;
			if (!r || !v) {
				rc = -ENOMEM;
				goto out;
			}
			cap_rows = cap;
		}
		next_cell(s, &p, end, &more, &c);
		if (hl_number_parse(c.s, c.n, &a) < 0) {
			rc = hl_text_fail_at(t, line, c.col, -EBADMSG,
					     "expected the row angle (a finite decimal number) in "
					     "the first cell");
			goto out;
		}
		rc = check_angle(t, line, c.col, system == HL_GONIO_C ? "gamma (row)" : "V (row)",
				 a, i_lo, i_hi, n_rows ? &rows[n_rows - 1] : NULL, &row_dir);
		if (rc < 0)
			goto out;
		rows[n_rows] = a;
		while (next_cell(s, &p, end, &more, &c)) {
			double v;

			if (k == n_cols) {
				rc = hl_text_fail_at(
					t, line, c.col, -EBADMSG,
					"expected %d values after the row angle, found "
					"more",
					n_cols);
				goto out;
			}
			if (hl_number_parse(c.s, c.n, &v) < 0) {
				rc = hl_text_fail_at(t, line, c.col, -EBADMSG,
						     "expected value %d of the row (cd, a finite "
						     "decimal number)",
						     k + 1);
				goto out;
			}
			if (v < 0.0 || v > 3.0e38) {
				rc = hl_text_fail_at(t, line, c.col, -EBADMSG,
						     "expected value %d of the row in 0..3e38 cd, "
						     "found %g",
						     k + 1, v);
				goto out;
			}
			vals[(size_t)n_rows * n_cols + k++] = (float)v;
		}
		if (k != n_cols) {
			rc = hl_text_fail_at(t, line, (int)n + 1, -EBADMSG,
					     "expected %d values after the row angle, found %d",
					     n_cols, k);
			goto out;
		}
		n_rows++;
	}
	if (n_rows < 2) {
		rc = hl_text_fail(t, -EBADMSG, "expected at least 2 rows after the header");
		goto out;
	}

	/* transpose into [plane][in], both increasing */
	planes = malloc(sizeof(double) * n_cols);
	in = malloc(sizeof(double) * n_rows);
	table = malloc(sizeof(float) * (size_t)n_cols * n_rows);
	if (!planes || !in || !table) {
		rc = -ENOMEM;
		goto out;
	}
	for (int i = 0; i < n_cols; i++)
		planes[i] = cols[col_dir > 0 ? i : n_cols - 1 - i];
	for (int j = 0; j < n_rows; j++)
		in[j] = rows[row_dir > 0 ? j : n_rows - 1 - j];
	for (int i = 0; i < n_cols; i++) {
		const int ci = col_dir > 0 ? i : n_cols - 1 - i;

		for (int j = 0; j < n_rows; j++) {
			const int rj = row_dir > 0 ? j : n_rows - 1 - j;

			table[(size_t)i * n_rows + j] = vals[(size_t)rj * n_cols + ci];
		}
	}
	rc = hl_gonio_new(system, n_cols, planes, n_rows, in, table, ret);
	if (rc == -EINVAL)
		rc = hl_text_fail_at(t, header_line, 1, -EBADMSG,
				     "a type C table may span at most 360 degrees of C");
out:
	free(cols);
	free(rows);
	free(vals);
	free(planes);
	free(in);
	free(table);
	return rc;
}

int hl_csv_parse(const char *buf, size_t len, const char *name, struct hl_gonio **ret,
		 struct hl_import_error *err)
{
	struct hl_text t;

	hl_text_init(&t, buf, len, name, err);
	return parse(&t, ret);
}

int hl_csv_read(const char *path, struct hl_gonio **ret, struct hl_import_error *err)
{
	char *buf;
	size_t len;
	int rc = hl_import_read_file(path, &buf, &len, err);

	if (rc < 0)
		return rc;
	rc = hl_csv_parse(buf, len, path, ret, err);
	free(buf);
	return rc;
}
