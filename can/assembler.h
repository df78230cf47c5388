/* SPDX-License-Identifier: MIT */
/*
 * The cycle assembler (docs/can-input.md): from CAN frames, decoded with the DBC, complete
 * intensity lists per lamp. What is a lamp's frame and which source a signal carries is data:
 * BO_ attribute HdlLamp (the lamp's name), SG_ attribute HdlSource (1-based source index),
 * BO_ attribute HdlE2E (profile and data ID), and optionally SG_ attribute HdlBeamMode (1: this
 * signal of a lamp's message, one per lamp, on a part that carries sources, tells the beam mode
 * of each cycle; its VAL_ descriptions name the modes).
 *
 * A lamp's cycle is made of parts: one per (message, multiplexor value) that carries sources
 * (hd84.dbc: 12 pages of one message; hd84_fd.dbc: two messages). All parts of one cycle carry
 * the same E2E alive counter; the cycle is complete when every part of one counter value has
 * arrived. Then:
 *   crc_errors        frames whose E2E CRC is wrong: dropped;
 *   incomplete        cycles abandoned because a part never came (a new counter began first);
 *   lost_cycles       counter values skipped entirely (no frame of theirs arrived);
 *   repeated_frames   frames repeating the last complete cycle's counter, or a part already
 *                     seen in the current cycle: ignored;
 *   stale             a lamp with no complete cycle for timeout_ms; it recovers on its next
 *                     complete cycle.
 * With profile "none" there is no counter: a part seen twice starts a new cycle.
 *
 * Thread-safety: one thread (the CAN thread) owns an assembler. Nothing allocates after
 * hl_assembler_new.
 */
#ifndef HL_CAN_ASSEMBLER_H
#define HL_CAN_ASSEMBLER_H

#include <stdbool.h>
#include <stdint.h>

#include <linux/can.h>

#include "dbc/database.h"

#define HL_ASM_MAX_LAMPS 8
#define HL_ASM_MAX_PARTS 64 /* per lamp */
/* Lamp messages at most: each carries at least one of its lamp's parts. */
#define HL_ASM_MAX_IDS (HL_ASM_MAX_LAMPS * HL_ASM_MAX_PARTS)

struct hl_lamp_counters {
	uint64_t frames; /* frames of this lamp's messages */
	uint64_t cycles; /* complete cycles */
	uint64_t crc_errors;
	uint64_t incomplete;
	uint64_t lost_cycles;
	uint64_t repeated_frames;
	uint64_t out_of_range; /* values outside [0, 1], clamped */
	uint64_t stale_events;
	uint64_t recoveries;
};

struct hl_asm_counters {
	struct hl_dbc_counters dbc; /* decoded, unknown_id, short_frame */
	uint64_t other_frames; /* decoded, but no lamp's message */
	uint64_t error_frames; /* fed error frames (counted, never decoded) */
};

/* A complete cycle, as hl_assembler_feed hands it back. i is owned by the assembler and valid
 * until the next call. */
struct hl_cycle {
	int lamp;
	uint64_t seq; /* this lamp's complete cycles so far, from 1 */
	unsigned counter; /* the E2E alive counter, 0 for profile none */
	int64_t t_rx_first_ns, t_rx_last_ns; /* receive times of its first and last frame */
	int n_sources;
	const float *i;
	int64_t mode; /* raw value of the lamp's HdlBeamMode signal in this cycle, -1: none */
};

/* What the last call changed in lamp states (bits by lamp index). */
struct hl_asm_events {
	uint32_t stale; /* became stale */
	uint32_t recovered; /* left stale with this cycle */
};

struct hl_asm_error {
	char msg[256];
};

struct hl_assembler;

/*
 * Plans assembly for the lamps named in lamp_names (the configuration's order) from db, which
 * must outlive the assembler. Every message with an HdlLamp attribute must name one of them,
 * every lamp must have messages, and every source 1..K of a lamp must be carried by exactly
 * one signal. 0, -EINVAL (err says which message or signal is wrong), -ENOMEM.
 * now_ns starts every lamp's timeout.
 */
int hl_assembler_new(const struct hl_dbc *db, const char *const *lamp_names, int n_lamps,
		     int timeout_ms, int64_t now_ns, struct hl_assembler **ret,
		     struct hl_asm_error *err);
void hl_assembler_free(struct hl_assembler *a);

/*
 * Feeds one frame received at t_rx_ns; now_ns is the clock timeouts run on (CLOCK_MONOTONIC
 * for a live bus, the log's timeline for a replay). Returns 1 and fills *ret_cycle when the
 * frame completed a cycle, else 0. *ret_events (cleared first) reports a recovery.
 */
int hl_assembler_feed(struct hl_assembler *a, const struct canfd_frame *f, int64_t t_rx_ns,
		      int64_t now_ns, struct hl_cycle *ret_cycle, struct hl_asm_events *ret_events);

/*
 * Forgets what the alive counters led the assembler to expect: the next frame of every lamp
 * starts a cycle as the very first one did, so no lost cycle or repeated frame is counted
 * against the previous counter. For a replayed log starting its next pass (its counters begin
 * again). A cycle still being assembled is abandoned and counted as incomplete. Timeouts, stale
 * states and counters are kept.
 */
void hl_assembler_restart(struct hl_assembler *a);

/* Marks lamps stale whose timeout passed by now_ns; returns the lamps that just became stale. */
uint32_t hl_assembler_expire(struct hl_assembler *a, int64_t now_ns);
/* The earliest time a lamp that is not stale would become stale. */
int64_t hl_assembler_next_deadline(const struct hl_assembler *a);

/* One frame of an encoded cycle. */
struct hl_encoded_frame {
	struct canfd_frame frame;
	bool fd; /* the message is longer than 8 bytes */
};

/*
 * The inverse of assembly, for generators and tests: the frames (parts in order) that carry
 * intensities i (n_sources values in [0, 1]) of lamp with the given alive counter, E2E
 * protected. Returns the number of frames (at most max), -EINVAL for a value a signal cannot
 * carry or a counter above the profile's maximum, -ENOSPC when max is too small.
 */
int hl_assembler_encode(const struct hl_assembler *a, int lamp, const float *i, unsigned counter,
			struct hl_encoded_frame *ret, int max);
/* The same, with the lamp's HdlBeamMode signal set to the raw value mode (>= 0; -1: left 0). */
int hl_assembler_encode_mode(const struct hl_assembler *a, int lamp, const float *i,
			     unsigned counter, int64_t mode, struct hl_encoded_frame *ret, int max);

int hl_assembler_n_lamps(const struct hl_assembler *a);
const char *hl_assembler_lamp_name(const struct hl_assembler *a, int lamp);
int hl_assembler_n_sources(const struct hl_assembler *a, int lamp);
/*
 * The signal that carries source (0-based) of lamp: its factor and offset turn a cycle's value
 * back into the raw bits the ECU sent. Owned by the database. NULL when out of range.
 */
const struct hl_dbc_signal *hl_assembler_source_signal(const struct hl_assembler *a, int lamp,
						       int source);
/* Largest alive counter value of the lamp's E2E profile (14 for P1, 255 for P5, 0 for none). */
unsigned hl_assembler_counter_max(const struct hl_assembler *a, int lamp);
/*
 * The message IDs to receive (for kernel filters), at most max of them into ids; returns how
 * many there are (at most HL_ASM_MAX_IDS), which is more than max when ids was too short.
 */
int hl_assembler_ids(const struct hl_assembler *a, uint32_t *ids, int max);
bool hl_assembler_stale(const struct hl_assembler *a, int lamp);
/* The lamp's HdlBeamMode signal (its values name the modes), NULL for none; the database's. */
const struct hl_dbc_signal *hl_assembler_mode_signal(const struct hl_assembler *a, int lamp);
/*
 * The raw value of the lamp's HdlBeamMode signal whose VAL_ description is name (any case),
 * for hl_assembler_encode_mode. 0, -ENOENT (no such signal, or no value of that name).
 */
int hl_assembler_mode_value(const struct hl_assembler *a, int lamp, const char *name, int64_t *ret);
const struct hl_lamp_counters *hl_assembler_lamp_counters(const struct hl_assembler *a, int lamp);
const struct hl_asm_counters *hl_assembler_counters(const struct hl_assembler *a);

#endif
