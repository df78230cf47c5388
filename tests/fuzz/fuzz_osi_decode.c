/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target: any bytes decoded as an OSI GroundTruth and as a SensorView never crash,
 * leak or read outside the buffer; a decoded message stays within the frame's limits, and when
 * it makes a world (with and without a base scenario) its mapping gives finite positions for
 * the ego and every road user present.
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "world/osi_msg.h"
#include "world/osi_world.h"
#include "world/scenario.h"
#include "world/world.h"

static const char base_json[] =
	"{\"version\": 1, \"title\": \"base\", \"duration_s\": 10,"
	" \"road\": {\"segments\": [{\"kind\": \"straight\", \"length_m\": 400}]}}";

static struct hl_osi_frame *frame;
static struct hl_scenario *base;

static void check_finite(const double *v, int n)
{
	for (int i = 0; i < n; i++)
		if (!isfinite(v[i]))
			abort();
}

static void check_limits(const struct hl_osi_frame *f)
{
	if (f->n_objects < 0 || f->n_objects > HL_OSI_MAX_OBJECTS || f->n_boundaries < 0 ||
	    f->n_boundaries > HL_OSI_MAX_BOUNDARIES || f->n_points < 0 ||
	    f->n_points > HL_OSI_MAX_POINTS)
		abort();
	for (int i = 0; i < f->n_boundaries; i++) {
		const struct hl_osi_boundary *b = &f->boundary[i];

		if (b->first < 0 || b->n < 0 || b->first + b->n > f->n_points)
			abort();
	}
}

static void world_of(const struct hl_osi_frame *f, const struct hl_scenario *b)
{
	uint64_t counts[HL_OSI_REASONS] = { 0 };
	struct hl_osi_world *w = NULL;
	struct hl_world_state st;
	char why[256];

	if (hl_osi_world_new(f, b, &w, why, sizeof(why)) < 0)
		return;
	hl_osi_world_cast(w, f, counts);
	if (hl_osi_world_map(w, f, 0.0, &st, counts, why, sizeof(why)) == HL_OSI_OK) {
		const struct hl_scenario *sc = hl_osi_world_scenario(w);

		if (st.n_actors != sc->n_actors)
			abort();
		check_finite(st.ego.pos_m, 3);
		for (int i = 0; i < st.n_actors; i++)
			if (hl_world_present(&st, i))
				check_finite(st.actor[i].pos_m, 3);
	}
	hl_osi_world_free(w);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	static const enum hl_osi_kind kinds[2] = { HL_OSI_GROUND_TRUTH, HL_OSI_SENSOR_VIEW };

	if (!frame) {
		frame = hl_osi_frame_new();
		if (!frame || hl_scenario_parse(base_json, "base.json", &base, NULL) < 0)
			abort();
	}
	for (int k = 0; k < 2; k++) {
		char why[256];

		if (hl_osi_decode(data, size, kinds[k], frame, why, sizeof(why)) !=
		    HL_OSI_DECODE_OK)
			continue;
		check_limits(frame);
		world_of(frame, NULL);
		world_of(frame, base);
	}
	return 0;
}
