/* SPDX-License-Identifier: MIT */
/* libFuzzer target: the preset JSON reader never crashes and either succeeds or says where. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "lamp/preset.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct hl_preset_error err;
	struct hl_preset *p = NULL;
	char *text = malloc(size + 1);

	if (!text)
		return 0;
	memcpy(text, data, size);
	text[size] = '\0';
	if (hl_preset_parse(text, &p, &err) == 0) {
		if (p->n_sources < 1 || p->n_sources > 4096)
			abort();
		for (int k = 0; k < p->n_sources; k++)
			if (p->dim[0][k] > HL_DIM_MAX || p->dim[1][k] > HL_DIM_MAX)
				abort();
		hl_preset_free(p);
	} else if (err.line < 1 || err.column < 1 || !err.msg[0]) {
		abort();
	}
	free(text);
	return 0;
}
