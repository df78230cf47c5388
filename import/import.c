/* SPDX-License-Identifier: MIT */
#include "import/import.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "import/csv.h"
#include "import/eulumdat.h"
#include "import/ies.h"
#include "import/resample.h"
#include "import/text.h"

int hl_import_load(const char *path, enum hl_import_format format, struct hl_gonio **ret,
		   struct hl_import_error *err)
{
	switch (format) {
	case HL_IMPORT_IES:
		return hl_ies_read(path, ret, NULL, err);
	case HL_IMPORT_LDT:
		return hl_eulumdat_read(path, ret, NULL, err);
	case HL_IMPORT_CSV:
		return hl_csv_read(path, ret, err);
	}
	return hl_import_fail(err, path, -EINVAL, "unknown format");
}

int hl_import_lid(const struct hl_manifest *m, struct hl_lid **ret, struct hl_import_error *err)
{
	const struct hl_lid_grid *grid = hl_manifest_grid(m);
	const int n = hl_manifest_n_sources(m);
	struct hl_lid *lid;
	float *dense;
	int rc;

	rc = hl_lid_new(n, grid, false, &lid);
	if (rc < 0)
		return hl_import_fail(err, "manifest", rc, "cannot make a lamp of %d sources: %s",
				      n, strerror(-rc));
	dense = malloc(sizeof(float) * (size_t)grid->width * grid->height);
	if (!dense) {
		rc = -ENOMEM;
		goto err_free_lid;
	}
	for (int k = 0; k < n; k++) {
		struct hl_gonio *g;

		rc = hl_import_load(hl_manifest_file(m, k), hl_manifest_format(m, k), &g, err);
		if (rc < 0) {
			if (err) {
				size_t l = strlen(err->msg);

				snprintf(err->msg + l, sizeof(err->msg) - l, " (source %d)", k + 1);
			}
			goto err_free_dense;
		}
		hl_resample(g, grid, dense);
		hl_gonio_free(g);
		rc = hl_lid_set_source(lid, k, dense);
		if (rc == 0)
			rc = hl_lid_set_name(lid, k, hl_manifest_name(m, k));
		if (rc < 0) {
			hl_import_fail(err, hl_manifest_file(m, k), rc,
				       "cannot store source %d: %s", k + 1, strerror(-rc));
			goto err_free_dense;
		}
	}
	free(dense);
	*ret = lid;
	return 0;

err_free_dense:
	free(dense);
err_free_lid:
	hl_lid_free(lid);
	return rc;
}
