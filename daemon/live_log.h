/* SPDX-License-Identifier: MIT */
/*
 * hdlampd's log line: "hdlampd: " and the message on stderr, one line. The daemon's wiring
 * (daemon/live*.c) logs once where it handles an error, with this.
 *
 * Thread-safety: hl_live_run's thread, where the wiring runs (a line is three stdio calls, so
 * two threads at once could interleave them).
 */
#ifndef HL_DAEMON_LIVE_LOG_H
#define HL_DAEMON_LIVE_LOG_H

void hl_live_log(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* The program name the lines start with ("hdlampd" unless set; set it before any thread runs). */
void hl_live_log_prefix(const char *name);

#endif
