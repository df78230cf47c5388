/* SPDX-License-Identifier: MIT */
#include "daemon/notify.h"

#include <errno.h>
#include <inttypes.h>
#include <stdarg.h>
#include <stdio.h>
#include <systemd/sd-daemon.h>
#include <time.h>

#define STATUS_MAX 256 /* bytes of a STATUS line */

/* sd_notify returns 0 without NOTIFY_SOCKET: exactly the no-op this module promises. */
static int notify(const char *msg)
{
	return sd_notify(0, msg);
}

int hl_notify_ready(const char *status)
{
	char msg[STATUS_MAX + 32];

	if (!status)
		return notify("READY=1");
	snprintf(msg, sizeof(msg), "READY=1\nSTATUS=%.*s", STATUS_MAX, status);
	return notify(msg);
}

int hl_notify_status(const char *fmt, ...)
{
	char msg[STATUS_MAX + 8] = "STATUS=";
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(msg + 7, STATUS_MAX + 1, fmt, ap);
	va_end(ap);
	return notify(msg);
}

int hl_notify_reloading(void)
{
	struct timespec ts;
	char msg[64];

	clock_gettime(CLOCK_MONOTONIC, &ts);
	snprintf(msg, sizeof(msg), "RELOADING=1\nMONOTONIC_USEC=%" PRIu64,
		 (uint64_t)ts.tv_sec * 1000000u + (uint64_t)ts.tv_nsec / 1000u);
	return notify(msg);
}

int hl_notify_stopping(void)
{
	return notify("STOPPING=1");
}

int hl_notify_watchdog(void)
{
	return notify("WATCHDOG=1");
}

int hl_notify_watchdog_interval_us(uint64_t *ret_interval_us)
{
	uint64_t usec = 0;
	int r;

	r = sd_watchdog_enabled(0, &usec);
	if (r < 0)
		return r;
	*ret_interval_us = r > 0 ? usec / 2 : 0;
	return r > 0;
}

int hl_notify_extend_timeout_us(uint64_t usec)
{
	char msg[64];

	snprintf(msg, sizeof(msg), "EXTEND_TIMEOUT_USEC=%" PRIu64, usec);
	return notify(msg);
}
