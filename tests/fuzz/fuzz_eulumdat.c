/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target: the EULUMDAT reader never crashes; it either returns a sane table or an
 * error that says where (line and column) and what.
 */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "tools/import/eulumdat.h"

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

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct hl_import_error err = { 0 };
	struct hl_gonio *g = NULL;
	int rc = hl_eulumdat_parse((const char *)data, size, "fuzz.ldt", &g, NULL, &err);

	if (rc == 0) {
		check_table(g);
		hl_gonio_free(g);
	} else if (g || (rc != -EBADMSG && rc != -ENOMEM) ||
		   (rc != -ENOMEM && (err.line < 1 || err.column < 1 || !err.msg[0]))) {
		abort();
	}
	return 0;
}
