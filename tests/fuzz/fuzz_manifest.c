/* SPDX-License-Identifier: MIT */
/* libFuzzer target: the import manifest reader never crashes and either succeeds or says where. */
#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "import/manifest.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct hl_import_error err = { 0 };
	struct hl_manifest *m = NULL;
	int rc = hl_manifest_parse((const char *)data, size, "fuzz.ini", "base", &m, &err);

	if (rc == 0) {
		const int n = hl_manifest_n_sources(m);

		if (n < 1 || n > HL_LID_MAX_SOURCES || hl_lid_grid_check(hl_manifest_grid(m)) < 0)
			abort();
		for (int k = 0; k < n; k++)
			if (!hl_manifest_file(m, k) || !hl_manifest_name(m, k) ||
			    strchr(hl_manifest_name(m, k), '\n') || hl_manifest_format(m, k) < 0)
				abort();
		hl_manifest_free(m);
	} else if (m || (rc != -EBADMSG && rc != -ENOMEM) ||
		   (rc == -EBADMSG && (err.line < 1 || err.column < 1 || !err.msg[0]))) {
		abort();
	}
	return 0;
}
