/* SPDX-License-Identifier: MIT */
/*
 * hdlampd --no-render (docs/can-input.md): the main thread consumes the ring and
 * prints JSON lines: link and bus events, each lamp's cycles (with --print-cycles), stale and
 * recovered events, and at exit a summary of every counter.
 *
 * Thread-safety: the main thread only (it owns the ring's consumer end in this mode).
 */
#ifndef HL_DAEMON_CORE_DECODE_REPORT_H
#define HL_DAEMON_CORE_DECODE_REPORT_H

#include <stdbool.h>
#include <stdint.h>

#include "can/assembler.h"
#include "daemon/core/can_input.h"
#include "daemon/core/ring.h"

/* What was last printed, to report changes; zeroed before the first report. */
struct hl_decode_seen {
	uint64_t cycle_seq[HL_RING_MAX_LAMPS];
	uint32_t lamp_status[HL_RING_MAX_LAMPS];
	uint32_t status, bus;
	int32_t link_errno;
};

/* Prints what snapshot s changed since seen; true when it is the replay's last. */
bool hl_decode_report(const char *iface, bool print_cycles, const struct hl_assembler *a,
		      const struct hl_snapshot *s, struct hl_decode_seen *seen);
/* Every counter, once at exit: one JSON line {"event":"summary",...}. */
void hl_decode_summary(const struct hl_assembler *a, const struct hl_ring *ring,
		       struct hl_can_input *in);

#endif
