/* SPDX-License-Identifier: MIT */
/*
 * A recorded world (docs/osi.md, "Replaying a trace"): the world states of a recording at their own times,
 * e.g. every message of an ASAM OSI trace. A scenario that carries one (hl_scenario.track)
 * takes its ego and road-user poses from it instead of its paths: hl_world_at() and the
 * hl_world_*_at() functions give the state at t, each message at its own time: between two the
 * poses interpolated linearly (the heading the shorter way; a road user only if it is in both),
 * presence and lamps the earlier one's; before the first the first, after the last the last. So
 * every consumer of a scenario (renderer, glare, verdicts, restbus, the CLI) replays a
 * recording unchanged.
 *
 * Thread-safety: built by one thread (hl_world_track_push), read-only afterwards; lookups are
 * pure (any thread) and allocate nothing.
 */
#ifndef HL_WORLD_TRACK_H
#define HL_WORLD_TRACK_H

#include <stddef.h>

#include "world/state.h"

struct hl_world_track;

/* An empty track. 0 or -ENOMEM. */
int hl_world_track_new(struct hl_world_track **ret);
void hl_world_track_free(struct hl_world_track *t);

/* Appends a state; its t_s must be greater than the last one's. 0, -EINVAL, -ENOMEM. */
int hl_world_track_push(struct hl_world_track *t, const struct hl_world_state *st);

size_t hl_world_track_count(const struct hl_world_track *t);
/* State i (< count), NULL beyond. */
const struct hl_world_state *hl_world_track_state(const struct hl_world_track *t, size_t i);
/* The index of the newest state at or before t_s (0 before the first); the track not empty. */
size_t hl_world_track_index(const struct hl_world_track *t, double t_s);
/* The state at t_s (interpolated between two, as above), its t_s set to t_s. */
void hl_world_track_at(const struct hl_world_track *t, double t_s, struct hl_world_state *ret);

#endif
