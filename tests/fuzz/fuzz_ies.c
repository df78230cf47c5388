/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target: the IES LM-63 reader never crashes; it either returns a sane table or an
 * error that says where (line and column) and what (tests/fuzz/gonio_check.h).
 */
#include <stdint.h>

#include "import/ies.h"
#include "gonio_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct hl_import_error err = { 0 };
	struct hl_gonio *g = NULL;
	int rc = hl_ies_parse((const char *)data, size, "fuzz.ies", &g, NULL, &err);

	check_result(rc, g, &err, true);
	return 0;
}
