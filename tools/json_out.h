/* SPDX-License-Identifier: MIT */
/* JSON values for the CLI's machine-readable output (the --json lines of its commands). */
#ifndef HL_TOOLS_JSON_OUT_H
#define HL_TOOLS_JSON_OUT_H

#include <stdio.h>

/* x with 12 significant digits; null when it is not finite (NAN: no value). */
void hl_tool_json_num(FILE *f, double x);
/* s as a JSON string: '"' and '\' escaped, control characters as \u00XX. */
void hl_tool_json_str(FILE *f, const char *s);

#endif
