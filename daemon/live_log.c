/* SPDX-License-Identifier: MIT */
/* hdlampd's log line: see daemon/live_log.h. */
#include "daemon/live_log.h"

#include <stdarg.h>
#include <stdio.h>

static const char *prefix = "hdlampd";

void hl_live_log_prefix(const char *name)
{
	prefix = name;
}

void hl_live_log(const char *fmt, ...)
{
	va_list ap;

	va_start(ap, fmt);
	fprintf(stderr, "%s: ", prefix);
	vfprintf(stderr, fmt, ap);
	fputc('\n', stderr);
	va_end(ap);
}
