/* SPDX-License-Identifier: MIT */
/*
 * A published frame and its wire header (docs/outputs.md, "Frame stream"). The header is sent as is,
 * little endian, before the pixels of every frame on the stream sockets.
 */
#ifndef HL_DAEMON_CORE_FRAME_H
#define HL_DAEMON_CORE_FRAME_H

#include <stddef.h>
#include <stdint.h>

#include "verdict/verdict.h"
#include "verdict/glare.h"
#include "render/headlight.h"

#define HL_FRAME_MAGIC 0x524c4448u /* "HDLR" read as little-endian bytes */
/* 2: verdict set masks and road KPIs, 192 bytes; 3: the scenario's time and glare */
#define HL_FRAME_VERSION 3
#define HL_FRAME_HEADER_SIZE 192
/* lamps a frame shows: fixed by the wire header, and what the renderer lights */
#define HL_FRAME_MAX_LAMPS 2
/* road users' lamps a display frame shows at most (world/scenario.h: 16 users, 8 lamps) */
#define HL_FRAME_MAX_GLOW 128

_Static_assert(HL_FRAME_MAX_LAMPS == HL_HEADLIGHT_MAX_LAMPS,
	       "a frame carries exactly the lamps the renderer lights");

enum hl_pixel_format {
	HL_PIXEL_RGB8 = 1, /* display or lux false colour: 3 bytes per pixel */
	HL_PIXEL_RGBA16F = 2, /* hdr: linear luminance cd/m², half floats */
};

/* Where a frame's scenario time came from (header scene_source, docs/daemon.md). */
enum hl_scene_source {
	HL_SCENE_NONE = 0, /* no scenario */
	HL_SCENE_CLOCK = 1, /* CLOCK_MONOTONIC since the daemon started (a live bus) */
	HL_SCENE_LOG = 2, /* the replayed log's time of the newest cycle in its pass */
	HL_SCENE_POSE = 3, /* the newest message of the pose input */
	HL_SCENE_OSI = 4, /* the newest message of the live ASAM OSI input */
};

/* Frame flags: per lamp l, bit 2l = stale, bit 2l + 1 = fail-safe active. */
#define HL_FRAME_STALE(l) (1u << (2 * (l)))
#define HL_FRAME_FAILSAFE(l) (1u << (2 * (l) + 1))

struct hl_frame_header {
	uint32_t magic;
	uint16_t version;
	uint16_t header_size; /* sizeof(struct hl_frame_header): HL_FRAME_HEADER_SIZE */
	uint64_t seq; /* published frames, from 1; a reader sees gaps when it skipped */
	uint32_t width, height;
	uint32_t stride; /* bytes per row */
	uint32_t pixel_format; /* enum hl_pixel_format */
	uint32_t payload_size; /* bytes of pixels that follow */
	uint32_t flags;
	/* CLOCK_MONOTONIC ns: the newest CAN cycle in this frame (its first frame's kernel receive
	 * time is CLOCK_REALTIME, see t_cycle_rx_ns), render start and end, and when this header
	 * was sent to this client */
	int64_t t_cycle_rx_ns; /* CLOCK_REALTIME: kernel receive time of the cycle's first frame */
	int64_t t_cycle_done_ns;
	int64_t t_render_start_ns;
	int64_t t_render_done_ns;
	int64_t t_sent_ns;
	uint64_t cycle_seq[HL_FRAME_MAX_LAMPS]; /* each lamp's complete cycles in this frame */
	uint8_t counter[HL_FRAME_MAX_LAMPS]; /* each lamp's alive counter */
	uint8_t n_lamps;
	uint8_t reserved0[5];
	/* CLOCK_MONOTONIC ns: when each lamp's newest complete cycle completed */
	int64_t t_lamp_done_ns[HL_FRAME_MAX_LAMPS];
	/* verdicts (daemon/core/verdicts.h): bit i is configured set i (verdict.sets, in order) */
	uint8_t n_sets; /* configured verdict sets, 0..32 */
	uint8_t reserved1[3];
	uint32_t sets_evaluated; /* sets evaluated on this frame */
	uint32_t sets_failed; /* of those, the ones some requirement failed */
	/* road KPIs (render/road_kpi.h) at road.levels and road.width_at; 0 = not reached */
	float centre_range_m[2]; /* along the lane centre, per level */
	float edge_range_m[2]; /* along the right road edge, per level */
	float width_m[2]; /* of the first level's area, per distance */
	/* v3, the scenario (zeros without one): bit i = road user i over its glare limit */
	uint32_t glare_failed;
	float eye_lux_max; /* the highest illuminance at a road user's eye, lux */
	uint8_t n_actors; /* the scenario's road users, 0..16 */
	uint8_t scene_source; /* enum hl_scene_source */
	uint8_t reserved2[2];
	double scene_t_s; /* the frame's scenario time, s */
	uint8_t reserved[16];
};

_Static_assert(sizeof(struct hl_frame_header) == HL_FRAME_HEADER_SIZE,
	       "the wire header is HL_FRAME_HEADER_SIZE bytes");
_Static_assert(offsetof(struct hl_frame_header, glare_failed) == 156 &&
		       offsetof(struct hl_frame_header, scene_t_s) == 168,
	       "the v3 fields sit where docs/daemon.md says");

/* A frame in memory: the header, its pixels, and what captures need. */
struct hl_frame {
	struct hl_frame_header hdr;
	uint8_t *pixels; /* payload_size bytes in the configured view */
	float *lux; /* width * height illuminance, lux */
	float *dist[HL_FRAME_MAX_LAMPS]; /* each lamp's combined distribution, cd (grid size) */
	uint8_t *dims[HL_FRAME_MAX_LAMPS]; /* each lamp's raw dimming values 0..63 */
	int dist_width, dist_height, n_sources;
	/* the verdict sets' results of this frame, laid out by daemon/core/verdicts.h (valid for the
	 * sets in hdr.sets_evaluated) */
	struct hl_req_result *results;
	int n_results;
	int64_t beam_mode; /* the HdlBeamMode value the sets were chosen by, -1: none */
	/*
	 * A moving scene's display view: the pixel boxes (x0, y0, x1, y1) the road users' lamps
	 * were drawn into. The display pass writes only pixels the ego lamps can reach, so the
	 * next frame rendered into this buffer clears them first (daemon/pipeline.c).
	 */
	int n_glow;
	int glow[HL_FRAME_MAX_GLOW][4];
	/* with a scenario: each road user's glare at this frame (hdr.n_actors of them) */
	struct hl_glare_result glare[HL_SCN_MAX_ACTORS];
	int64_t t_pose_rx_ns; /* scene_source pose: when that message arrived (CLOCK_MONOTONIC) */
};

#endif
