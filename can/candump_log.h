/* SPDX-License-Identifier: MIT */
/*
 * The log source: a candump -L log (a file or stdin) replayed with its original timing or as
 * fast as possible, once or in a loop.
 *
 * Timing uses absolute deadlines on CLOCK_MONOTONIC: frame n is due at
 * start + (t_n - t_first), so sleeping late once does not shift the rest and long logs do not
 * drift. In a loop, each pass starts one ECU period (HL_LOG_LOOP_GAP_NS) after the previous
 * pass's last frame; a caller that keeps state across frames (the cycle assembler's alive
 * counters) learns of the new pass from hl_candump_log_stats' passes.
 *
 * Malformed lines are skipped and counted; hl_candump_log_next reports each one (line number
 * in the file, the same in every pass; column; what was expected) so the caller can log it.
 * A timestamp earlier than the previous frame's is counted (backwards) and reported the same
 * way; the frame is replayed at the previous frame's time. Recordings of several interfaces
 * with their own hardware clocks legitimately go back by a few microseconds, so this is not
 * an error, but it is never silent.
 *
 * Thread-safety: one thread owns a log.
 */
#ifndef HL_CAN_CANDUMP_LOG_H
#define HL_CAN_CANDUMP_LOG_H

#include <stdbool.h>
#include <stdint.h>

#include "can/candump.h"

#define HL_LOG_LOOP_GAP_NS 20000000 /* between the last frame of a pass and the next pass */

struct hl_candump_log_error {
	long line;
	int column;
	char msg[200];
};

struct hl_candump_log_stats {
	uint64_t lines, frames, malformed, passes;
	uint64_t backwards; /* frames whose timestamp is earlier than the previous frame's */
};

struct hl_candump_log;

/*
 * path "-" is stdin (no loop possible). passes: how often the log is played, 1 once, 0
 * endlessly. A file is read up to its first frame at once: -ENODATA when it has none (empty,
 * only comments or malformed lines). 0, -errno, -EINVAL (more than one pass of stdin).
 */
int hl_candump_log_open(const char *path, uint64_t passes, struct hl_candump_log **ret);
void hl_candump_log_free(struct hl_candump_log *log);

/*
 * The next frame: 1 with *ret and its due time *ret_due_ns on the log's timeline relative to
 * the first frame (0 for the first, growing across loop passes); 2 for a frame whose timestamp
 * is earlier than the previous frame's (err says where; it is due at the previous frame's
 * time); 0 at the end (after the last pass); -EBADMSG for a malformed line (err filled; call
 * again for the next line); -errno for a read error.
 */
int hl_candump_log_next(struct hl_candump_log *log, struct hl_candump_frame *ret,
			int64_t *ret_due_ns, struct hl_candump_log_error *err);

void hl_candump_log_stats(const struct hl_candump_log *log, struct hl_candump_log_stats *ret);

#endif
