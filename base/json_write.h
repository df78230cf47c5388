/* SPDX-License-Identifier: MIT */
/*
 * JSON values written to a stream: the daemon's /status, reports and JSON lines and the CLI's
 * --json output all write their strings and numbers through these (one escape rule, one rule for
 * numbers JSON cannot hold).
 */
#ifndef HL_BASE_JSON_WRITE_H
#define HL_BASE_JSON_WRITE_H

#include <stdio.h>

/* s as a JSON string: '"' and '\' escaped, control characters as \u00XX; NULL as "". */
void hl_json_write_str(FILE *f, const char *s);
/* x printed with fmt (one double conversion, e.g. "%.9g"); null when it is not finite. */
void hl_json_write_num(FILE *f, double x, const char *fmt);

#endif
