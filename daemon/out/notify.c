/* SPDX-License-Identifier: MIT */
#include "daemon/out/notify.h"

#include <errno.h>
#include <inttypes.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <string.h>
#include <systemd/sd-daemon.h>
#include <time.h>

#define STATUS_MAX 256 /* bytes of a STATUS line */

enum kind { READY, STATUS, RELOADING, STOPPING, WATCHDOG, EXTEND_TIMEOUT, WATCHDOG_USEC };

static const char *const kind_name[] = {
	[READY] = "READY=1",
	[STATUS] = "STATUS",
	[RELOADING] = "RELOADING=1",
	[STOPPING] = "STOPPING=1",
	[WATCHDOG] = "WATCHDOG=1",
	[EXTEND_TIMEOUT] = "EXTEND_TIMEOUT_USEC",
	[WATCHDOG_USEC] = "WATCHDOG_USEC",
};

/*
 * The kinds whose failure was logged, a bit each: the first failure of a kind is logged, later
 * ones only returned (a watchdog ping would fail at every interval once systemd is gone).
 * Process state, as NOTIFY_SOCKET itself is.
 */
static atomic_uint logged;

static int failed(enum kind k, int rc)
{
	if (!(atomic_fetch_or(&logged, 1u << k) & (1u << k)))
		fprintf(stderr, "hdlampd: systemd notification %s: %s (logged once)\n",
			kind_name[k], strerror(-rc));
	return rc;
}

/* sd_notify returns 0 without NOTIFY_SOCKET: exactly the no-op this module promises. */
static int notify(enum kind k, const char *msg)
{
	const int rc = sd_notify(0, msg);

	return rc < 0 ? failed(k, rc) : rc;
}

int hl_notify_ready(const char *status)
{
	char msg[STATUS_MAX + 32];

	if (!status)
		return notify(READY, "READY=1");
	snprintf(msg, sizeof(msg), "READY=1\nSTATUS=%.*s", STATUS_MAX, status);
	return notify(READY, msg);
}

int hl_notify_status(const char *fmt, ...)
{
	char msg[STATUS_MAX + 8] = "STATUS=";
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(msg + 7, STATUS_MAX + 1, fmt, ap);
	va_end(ap);
	return notify(STATUS, msg);
}

int hl_notify_reloading(void)
{
	struct timespec ts;
	char msg[64];

	clock_gettime(CLOCK_MONOTONIC, &ts);
	snprintf(msg, sizeof(msg), "RELOADING=1\nMONOTONIC_USEC=%" PRIu64,
		 (uint64_t)ts.tv_sec * 1000000u + (uint64_t)ts.tv_nsec / 1000u);
	return notify(RELOADING, msg);
}

int hl_notify_stopping(void)
{
	return notify(STOPPING, "STOPPING=1");
}

int hl_notify_watchdog(void)
{
	return notify(WATCHDOG, "WATCHDOG=1");
}

int hl_notify_watchdog_interval_us(uint64_t *ret_interval_us)
{
	uint64_t usec = 0;
	int r;

	r = sd_watchdog_enabled(0, &usec);
	if (r < 0)
		return failed(WATCHDOG_USEC, r);
	*ret_interval_us = r > 0 ? usec / 2 : 0;
	return r > 0;
}

int hl_notify_extend_timeout_us(uint64_t usec)
{
	char msg[64];

	snprintf(msg, sizeof(msg), "EXTEND_TIMEOUT_USEC=%" PRIu64, usec);
	return notify(EXTEND_TIMEOUT, msg);
}
