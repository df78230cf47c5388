/* SPDX-License-Identifier: MIT */
/*
 * hdlamp scenario osi: a scenario as an ASAM OSI trace (docs/osi.md, "Writing a trace"): at
 * every step of --rate (50 Hz) from 0 to its duration one message (GroundTruth, or a SensorView
 * holding it) with the timestamp of the step, the ego as the host vehicle (id 1) and every road
 * user present as a moving object (id 2 + its index) with its body, kind and lamps; the first
 * message also carries the road's lane boundaries as polylines (its edges and the lines between
 * lanes, a point every metre). Replayed with --world osi:file:, the world is the scenario's.
 */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tools/commands.h"
#include "world/osi_msg.h"
#include "world/osi_trace.h"
#include "world/osi_world.h"
#include "world/road.h"
#include "world/scenario.h"
#include "world/world.h"

#define EGO_ID 1
#define POINT_STEP_M 1.0 /* between boundary points, at most */

/* The ego's body: a scenario gives none; a medium car's (world/scenario.h's car default). */
static const double ego_size_m[3] = { 4.5, 1.8, 1.45 };

static void usage(FILE *f)
{
	fprintf(f,
		"usage: hdlamp scenario osi SCENARIO.json --out FILE.osi [--rate HZ]\n"
		"                           [--message ground-truth|sensor-view]\n"
		"\n"
		"Writes the scenario as an ASAM OSI trace (docs/osi.md): one message per step of\n"
		"1/HZ s (default 50 Hz; HZ must divide 1e9 ns evenly) from 0 to the scenario's\n"
		"duration, each a length-prefixed osi3::GroundTruth (default) or SensorView: the ego\n"
		"is the host vehicle (id 1), road user i the moving object 2 + i; the first message\n"
		"also holds the road's lane boundaries. Name the file after OSI's convention\n"
		"(..._gt_... or ..._sv_...) or give --osi-message when reading it back.\n");
}

static void object_of(struct hl_osi_object *o, uint64_t id, const struct hl_body_pose *pose,
		      const double size_m[3], enum hl_actor_kind kind, bool lit)
{
	*o = (struct hl_osi_object){ .id = id, .has_id = true };
	hl_osi_pose_to_centre(pose, size_m, o->pos_m, &o->rpy_rad[2]);
	o->rpy_rad[0] = o->rpy_rad[1] = 0.0;
	memcpy(o->dim_m, size_m, sizeof(o->dim_m));
	o->vel_mps[0] = pose->speed_mps * cos(pose->heading_rad);
	o->vel_mps[1] = pose->speed_mps * sin(pose->heading_rad);
	o->vel_mps[2] = 0.0;
	if (isnan(pose->speed_mps))
		o->vel_mps[0] = o->vel_mps[1] = o->vel_mps[2] = NAN;
	o->type = kind == HL_ACTOR_PEDESTRIAN ? HL_OSI_TYPE_PEDESTRIAN : HL_OSI_TYPE_VEHICLE;
	if (kind == HL_ACTOR_PEDESTRIAN)
		return;
	o->has_classification = true;
	o->vehicle_type = kind == HL_ACTOR_CYCLIST   ? HL_OSI_VEHICLE_BICYCLE :
			  kind == HL_ACTOR_TRUCK     ? HL_OSI_VEHICLE_HEAVY_TRUCK :
			  kind == HL_ACTOR_MOTORBIKE ? HL_OSI_VEHICLE_MOTORBIKE :
						       HL_OSI_VEHICLE_MEDIUM_CAR;
	o->head_light = o->tail_light = lit ? HL_OSI_LIGHT_ON : HL_OSI_LIGHT_OFF;
	o->high_beam = HL_OSI_LIGHT_OFF;
}

/* The road's edges and the lines between its lanes, right to left, a point every metre. */
static int boundaries(const struct hl_road *road, struct hl_osi_frame *f)
{
	const int steps = (int)ceil(road->length_m / POINT_STEP_M);
	const double half = hl_road_half_width(road);

	for (int j = 0; j <= road->lanes; j++) {
		struct hl_osi_boundary *b = &f->boundary[f->n_boundaries];
		const bool edge = j == 0 || j == road->lanes;
		const enum hl_marking m = edge ? road->edge : road->separator;

		if (f->n_boundaries == HL_OSI_MAX_BOUNDARIES ||
		    f->n_points + steps + 1 > HL_OSI_MAX_POINTS)
			return -E2BIG;
		*b = (struct hl_osi_boundary){ .id = 1000 + (uint64_t)j, .first = f->n_points };
		b->type = m == HL_MARK_SOLID  ? HL_OSI_BOUNDARY_SOLID_LINE :
			  m == HL_MARK_DASHED ? HL_OSI_BOUNDARY_DASHED_LINE :
			  edge		      ? HL_OSI_BOUNDARY_ROAD_EDGE :
						HL_OSI_BOUNDARY_NO_LINE;
		for (int k = 0; k <= steps; k++) {
			const double s = fmin(k * POINT_STEP_M, road->length_m);

			hl_road_point(road, s, -half + j * road->lane_width_m,
				      f->point[f->n_points]);
			f->point_width_m[f->n_points++] = edge ? road->edge_line_width_m :
								 road->separator_line_width_m;
		}
		b->n = steps + 1;
		f->n_boundaries++;
	}
	return 0;
}

static int write_trace(const struct hl_scenario *sc, long rate, enum hl_osi_kind kind,
		       const char *out, size_t *ret_n)
{
	const int64_t step_ns = 1000000000LL / rate;
	const int64_t n = (int64_t)floor(sc->duration_s * rate + 1e-9) + 1;
	struct hl_osi_frame *f = hl_osi_frame_new();
	FILE *file = fopen(out, "we");
	int rc = f && file ? 0 : -errno;

	for (int64_t k = 0; rc == 0 && k < n; k++) {
		struct hl_world_state w;
		uint8_t *buf = NULL;
		size_t len = 0;

		hl_world_at(sc, (double)(k * step_ns) / 1e9, &w);
		f->has_timestamp = true;
		f->t_ns = k * step_ns;
		f->has_host = true;
		f->host_id = EGO_ID;
		f->n_objects = 0;
		f->n_boundaries = f->n_points = 0;
		object_of(&f->object[f->n_objects++], EGO_ID, &w.ego, ego_size_m, HL_ACTOR_CAR,
			  true);
		for (int i = 0; i < sc->n_actors; i++)
			if (hl_world_present(&w, i))
				object_of(&f->object[f->n_objects++], 2 + (uint64_t)i, &w.actor[i],
					  sc->actor[i].size_m, sc->actor[i].kind,
					  (w.lamps_on >> i) & 1u);
		if (k == 0)
			rc = boundaries(&sc->road, f);
		if (rc == 0)
			rc = hl_osi_encode(f, kind, &buf, &len);
		if (rc == 0)
			rc = hl_osi_trace_write(file, buf, len);
		free(buf);
	}
	if (file && fclose(file) != 0 && rc == 0)
		rc = -errno;
	hl_osi_frame_free(f);
	*ret_n = (size_t)n;
	return rc;
}

int hl_cmd_scenario_osi(int argc, char **argv)
{
	static const struct option longopts[] = {
		{ "out", required_argument, NULL, 'o' },
		{ "rate", required_argument, NULL, 'r' },
		{ "message", required_argument, NULL, 'm' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	enum hl_osi_kind kind = HL_OSI_GROUND_TRUTH;
	const char *out = NULL;
	struct hl_json_error err;
	struct hl_scenario *sc;
	long rate = 50;
	char msg[1024], *end;
	size_t n = 0;
	int c, rc;

	optind = 1;
	while ((c = getopt_long(argc, argv, "", longopts, NULL)) != -1) {
		switch (c) {
		case 'o':
			out = optarg;
			break;
		case 'r':
			rate = strtol(optarg, &end, 10);
			if (*end || rate < 1 || rate > 1000 || 1000000000L % rate) {
				fprintf(stderr,
					"hdlamp scenario osi: --rate '%s': expected 1..1000 Hz "
					"dividing 1e9 ns evenly (e.g. 10, 20, 50, 100)\n",
					optarg);
				return HL_EXIT_USAGE;
			}
			break;
		case 'm':
			if (hl_osi_kind_parse(optarg, &kind) < 0) {
				fprintf(stderr,
					"hdlamp scenario osi: --message '%s': expected ground-truth "
					"or sensor-view\n",
					optarg);
				return HL_EXIT_USAGE;
			}
			break;
		case 'h':
			usage(stdout);
			return HL_EXIT_OK;
		default:
			usage(stderr);
			return HL_EXIT_USAGE;
		}
	}
	if (optind + 1 != argc || !out) {
		usage(stderr);
		return HL_EXIT_USAGE;
	}
	rc = hl_scenario_read(argv[optind], &sc, &err);
	if (rc < 0) {
		hl_json_error_format(&err, msg, sizeof(msg));
		fprintf(stderr, "hdlamp scenario osi: %s\n", msg);
		return HL_EXIT_FAIL;
	}
	rc = write_trace(sc, rate, kind, out, &n);
	if (rc < 0)
		fprintf(stderr, "hdlamp scenario osi: '%s': %s\n", out,
			rc == -E2BIG ? "the road's lane boundaries do not fit one message" :
				       strerror(-rc));
	else
		printf("%s: %zu %s messages at %ld Hz, %.3f s\n", out, n, hl_osi_kind_name(kind),
		       rate, sc->duration_s);
	hl_scenario_free(sc);
	return rc < 0 ? HL_EXIT_FAIL : HL_EXIT_OK;
}
