/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target: the suite reader never crashes; a rejection says where (line and column >= 1
 * and a message); an accepted suite's variants generate scenarios that the scenario reader
 * accepts (or a clear -EINVAL when the geometry cannot give the range), and the bin rule answers
 * for any range.
 */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "verdict/suite.h"
#include "verdict/suite_judge.h"
#include "verdict/suite_scenario.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct hl_json_error err;
	struct hl_suite *s = NULL;
	char *text = malloc(size + 1);

	if (!text)
		return 0;
	memcpy(text, data, size);
	text[size] = '\0';
	if (hl_suite_parse(text, "fuzz.json", &s, &err) == 0) {
		for (int i = 0; i < s->n_scenarios && i < 3; i++) {
			const struct hl_suite_scenario *d = &s->scenario[i];
			double speed, radius;
			char id[96], msg[1024], *json = NULL;
			int rc;

			hl_suite_variant_params(d, 2, 0, &speed, &radius, id, sizeof(id));
			rc = hl_suite_variant_scenario(s, d, speed, radius, &json, msg,
						       sizeof(msg));
			if (rc == 0) {
				struct hl_scenario *sc = NULL;

				if (hl_scenario_parse(json, id, &sc, &err) < 0)
					abort(); /* we wrote a scenario we cannot read */
				hl_scenario_free(sc);
				free(json);
			} else if (rc != -EINVAL && rc != -ENOMEM) {
				abort();
			} else if (rc == -EINVAL && !msg[0]) {
				abort();
			}
		}
		for (double r = -1.0; r < 1200.0; r += 7.3)
			if (hl_suite_bin_of(s, HL_ROLE_ONCOMING, r) >= s->n_bins)
				abort();
		if (!isfinite(hl_suite_round(s, 1.25)))
			abort();
		hl_suite_free(s);
	} else if (err.line < 1 || err.column < 1 || !err.msg[0]) {
		abort();
	}
	free(text);
	return 0;
}
