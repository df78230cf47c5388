/* SPDX-License-Identifier: MIT */
/* The live page, daemon/out/live.html, built into the binary (daemon/out/embed_file.cmake). */
#ifndef HL_DAEMON_OUT_LIVE_HTML_H
#define HL_DAEMON_OUT_LIVE_HTML_H

#include <stddef.h>

extern const char hl_live_html[];
extern const size_t hl_live_html_size; /* bytes, without a terminating NUL */

#endif
