/* SPDX-License-Identifier: MIT */
/*
 * What the goniometer-table fuzz targets (fuzz_ies, fuzz_eulumdat, fuzz_csv_lid) require of a
 * reader's result (header-only; each target is its own executable): a sane table, or no table
 * and an error that says where (line and column) and what. Anything else aborts.
 */
#ifndef HL_TESTS_FUZZ_GONIO_CHECK_H
#define HL_TESTS_FUZZ_GONIO_CHECK_H

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>

#include "import/gonio.h"
#include "import/error.h"

static void check_table(const struct hl_gonio *g)
{
	const int n_p = hl_gonio_n_planes(g), n_q = hl_gonio_n_in(g);
	const double *p = hl_gonio_planes(g), *q = hl_gonio_in(g);
	const float *v = hl_gonio_values(g);

	if (n_p < 2 || n_q < 2)
		abort();
	for (int i = 1; i < n_p; i++)
		if (!(p[i] > p[i - 1]))
			abort();
	for (int j = 1; j < n_q; j++)
		if (!(q[j] > q[j - 1]))
			abort();
	for (long k = 0; k < (long)n_p * n_q; k++)
		if (!isfinite(v[k]) || v[k] < 0.0f)
			abort();
	/* lookups anywhere, including between and beyond the table, are finite and >= 0 */
	for (int i = 0; i < 16; i++) {
		const double x = hl_gonio_lookup(g, -200.0 + 47.0 * i, -100.0 + 23.0 * i);

		if (!isfinite(x) || x < 0.0)
			abort();
	}
}

/* rc, g and err of one parse; enotsup: the reader may refuse a valid file it does not handle. */
static void check_result(int rc, struct hl_gonio *g, const struct hl_import_error *err,
			 bool enotsup)
{
	if (rc == 0) {
		check_table(g);
		hl_gonio_free(g);
	} else if (g || (rc != -EBADMSG && !(enotsup && rc == -ENOTSUP) && rc != -ENOMEM) ||
		   (rc != -ENOMEM && (err->line < 1 || err->column < 1 || !err->msg[0]))) {
		abort();
	}
}

#endif
