/* SPDX-License-Identifier: MIT */
/*
 * hdlampd's messages to systemd (sd_notify, Type=notify): READY=1 with a STATUS line once the
 * lamps are loaded, the renderer is up and the bus is open; STATUS lines; WATCHDOG=1 pings from
 * the render loop at half of WATCHDOG_USEC; RELOADING=1 ... READY=1 around a SIGHUP reload;
 * STOPPING=1 on the way out.
 *
 * Every function is a no-op returning 0 when NOTIFY_SOCKET is unset (not run by systemd), and
 * returns > 0 when the message was sent, -errno when sending failed. The first failure of each
 * kind of message (READY=1, STATUS, RELOADING=1, STOPPING=1, WATCHDOG=1, EXTEND_TIMEOUT_USEC, a
 * malformed WATCHDOG_USEC) is logged here, on stderr, so callers need not; later ones are only
 * returned. The daemon never stops because systemd cannot be told something.
 *
 * Thread-safety: all functions from any thread (each call opens, sends on and closes its own
 * socket; nothing is shared). A call costs a few system calls, no heap use of ours: ping the
 * watchdog at its interval, not per frame.
 */
#ifndef HL_DAEMON_OUT_NOTIFY_H
#define HL_DAEMON_OUT_NOTIFY_H

#include <stdint.h>

/* "READY=1\nSTATUS=<status>" (status may be NULL: "READY=1" only). */
int hl_notify_ready(const char *status);
/* "STATUS=<printf>", cut at 256 bytes. */
int hl_notify_status(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/*
 * "RELOADING=1\nMONOTONIC_USEC=<CLOCK_MONOTONIC now>"; systemd 252 needs RELOADING=1 and a
 * READY=1 (hl_notify_ready) when the reload is done; MONOTONIC_USEC is what Type=notify-reload
 * (systemd >= 253) also requires, and older versions ignore it.
 */
int hl_notify_reloading(void);
/* "STOPPING=1" */
int hl_notify_stopping(void);
/* "WATCHDOG=1" */
int hl_notify_watchdog(void);
/*
 * Whether systemd expects watchdog pings for this process (WATCHDOG_USEC, and WATCHDOG_PID if
 * set, equal to getpid()): 1 and *ret_interval_us = half of WATCHDOG_USEC, the ping period;
 * 0 and *ret_interval_us = 0 when not; -errno for a malformed WATCHDOG_USEC.
 */
int hl_notify_watchdog_interval_us(uint64_t *ret_interval_us);
/* "EXTEND_TIMEOUT_USEC=<usec>": more start-up (or stop) time, e.g. while LIDs load. */
int hl_notify_extend_timeout_us(uint64_t usec);

#endif
