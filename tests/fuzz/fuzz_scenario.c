/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target: the scenario reader (jansson, then the location scan and the checks) never
 * crashes; a rejection says where (line and column >= 1 and a message); an accepted scenario
 * gives finite poses at any time.
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "world/scenario.h"
#include "world/road.h"
#include "world/world.h"

static void check_finite(const double *v, int n)
{
	for (int i = 0; i < n; i++)
		if (!isfinite(v[i]))
			abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct hl_json_error err;
	struct hl_scenario *sc = NULL;
	char *text = malloc(size + 1);

	if (!text)
		return 0;
	memcpy(text, data, size);
	text[size] = '\0';
	if (hl_scenario_parse(text, "fuzz.json", &sc, &err) == 0) {
		for (double t = -1.0; t <= sc->duration_s + 1.0; t += sc->duration_s / 7 + 0.01) {
			struct hl_lamp_pose lamps[2];
			struct hl_body_pose pose;
			double eye[3];

			hl_world_ego_lamps_at(sc, t, lamps);
			check_finite(lamps[0].pos_m, 3);
			check_finite(lamps[1].pos_m, 3);
			for (int a = 0; a < sc->n_actors; a++) {
				hl_world_actor_pose_at(sc, a, t, &pose);
				check_finite(pose.pos_m, 3);
				hl_world_actor_eye_at(sc, a, t, eye);
				check_finite(eye, 3);
			}
		}
		hl_scenario_free(sc);
	} else if (err.line < 1 || err.column < 1 || !err.msg[0]) {
		abort();
	}
	free(text);
	return 0;
}
