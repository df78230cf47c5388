/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target: the CSV goniometer table reader never crashes; it either returns a sane table or an
 * error that says where (line and column) and what (tests/fuzz/gonio_check.h).
 */
#include <stdint.h>

#include "import/csv.h"
#include "gonio_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct hl_import_error err = { 0 };
	struct hl_gonio *g = NULL;
	int rc = hl_csv_parse((const char *)data, size, "fuzz.csv", &g, &err);

	check_result(rc, g, &err, false);
	return 0;
}
