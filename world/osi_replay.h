/* SPDX-License-Identifier: MIT */
/*
 * An ASAM OSI trace file as a scenario (docs/osi.md, "Replaying a trace"): every message of the
 * trace (world/osi_trace.h) decoded (world/osi_msg.h) and mapped (world/osi_world.h) into a
 * recorded track (world/track.h) at the message's own timestamp, scenario time 0 at the first
 * good message; the scenario lasts until the last one. Every message that is not taken is
 * counted by reason in the report (a truncated end is one "truncated"), the first of each
 * reason described. The world is then the scenario's, for the daemon (scene.world
 * osi:file:PATH) and the CLI (hdlamp render/glare --world) alike.
 *
 * Memory: one world state per message (about 1 kB), e.g. 90 MB for 30 minutes at 50 Hz.
 *
 * Thread-safety: one call, one thread; the scenario is then read-only.
 */
#ifndef HL_WORLD_OSI_REPLAY_H
#define HL_WORLD_OSI_REPLAY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "world/osi_msg.h"
#include "world/osi_world.h"
#include "world/scenario.h"

#define HL_OSI_REPLAY_WHY 256

struct hl_osi_replay_report {
	size_t messages; /* in the file (a truncated last one not counted) */
	size_t taken; /* states of the track */
	uint64_t counts[HL_OSI_REASONS]; /* messages (and objects) by reason; [HL_OSI_OK] = taken */
	char why[HL_OSI_REASONS][HL_OSI_REPLAY_WHY]; /* the first message's fault per reason */
	size_t first[HL_OSI_REASONS]; /* the index of that message */
	enum hl_osi_kind kind; /* the messages' kind read */
	int64_t t0_ns; /* the first taken message's timestamp */
};

/*
 * Reads the trace at path as messages of *kind (NULL: from the file name's convention, else an
 * error), with base (may be NULL) for the ego's lamps and camera and a road when the messages
 * have no lane boundaries. 0 with *ret (the caller's, hl_scenario_free()), or -errno with err
 * saying what: the file cannot be read, no message names the kind, no message is usable.
 */
int hl_osi_replay_load(const char *path, const enum hl_osi_kind *kind,
		       const struct hl_scenario *base, struct hl_scenario **ret,
		       struct hl_osi_replay_report *rep, char *err, size_t err_size);

/* A world source's name (scene.world, --world): "osi:file:PATH" or "osi:udp:HOST:PORT". */
struct hl_osi_spec {
	bool udp;
	char path[4096]; /* osi:file: the trace */
	char listen[512]; /* osi:udp: "udp:HOST:PORT" */
};

/* Parses spec. 0 or -EINVAL (err says what was expected). */
int hl_osi_spec_parse(const char *spec, struct hl_osi_spec *ret, char *err, size_t err_size);

#endif
