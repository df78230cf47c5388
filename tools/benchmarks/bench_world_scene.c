/* SPDX-License-Identifier: MIT */
/*
 * hdlamp-bench-world-scene: the cost of ray casting a scenario's moving scene into the G-buffer
 * (render/world_scene.h) on one thread, as one JSON object on standard output.
 *
 *   hdlamp-bench-world-scene SCENARIO.json [WxH [FRAMES]]
 *
 * Frames at times spread over the scenario's duration, default 1280x720 and 50 frames.
 */
#include <stdio.h>
#include <stdlib.h>

#include "world/scenario.h"
#include "world/world.h"
#include "render/world_scene.h"
#include "tools/benchmarks/bench_stats.h"

int main(int argc, char **argv)
{
	struct hl_scenario *sc = NULL;
	struct hl_json_error err;
	struct hl_world_scene *ws = NULL;
	struct hl_gbuffer *gb = NULL;
	struct hl_world_state st;
	struct hl_camera cam;
	int w = 1280, h = 720, frames = 50;
	double *t_ms;
	char msg[1024];
	struct stats s;

	if (argc < 2 || argc > 4 || (argc > 2 && sscanf(argv[2], "%dx%d", &w, &h) != 2) ||
	    (argc > 3 && sscanf(argv[3], "%d", &frames) != 1) || frames < 1 || w < 2 || h < 2) {
		fprintf(stderr, "usage: hdlamp-bench-world-scene SCENARIO.json [WxH [FRAMES]]\n");
		return 2;
	}
	if (hl_scenario_read(argv[1], &sc, &err) < 0) {
		fprintf(stderr, "hdlamp-bench-world-scene: %s\n",
			hl_json_error_format(&err, msg, sizeof(msg)));
		return 1;
	}
	t_ms = malloc(sizeof(double) * frames);
	if (!t_ms || hl_world_scene_new(sc, &ws) < 0 || hl_gbuffer_new(w, h, &gb) < 0) {
		fprintf(stderr, "hdlamp-bench-world-scene: out of memory\n");
		return 1;
	}
	cam = sc->ego.camera;
	cam.width = w;
	cam.height = h;
	for (int i = 0; i < frames; i++) {
		double t0;

		hl_world_at(sc, sc->duration_s * i / frames, &st);
		t0 = hl_bench_now_ms();
		hl_world_scene_render(ws, &st, &cam, gb);
		t_ms[i] = hl_bench_now_ms() - t0;
	}
	s = hl_bench_summarise(t_ms, frames);
	printf("{\"scenario\": \"%s\", \"width\": %d, \"height\": %d, \"threads\": 1, "
	       "\"ray_cast\": {\"median_ms\": %.3f, \"min_ms\": %.3f, \"max_ms\": %.3f, \"n\": %d}}\n",
	       argv[1], w, h, s.median, s.min, s.max, s.n);
	free(t_ms);
	hl_gbuffer_free(gb);
	hl_world_scene_free(ws);
	hl_scenario_free(sc);
	return 0;
}
