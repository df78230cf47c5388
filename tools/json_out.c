/* SPDX-License-Identifier: MIT */
#include "tools/json_out.h"

#include <math.h>

void hl_tool_json_num(FILE *f, double x)
{
	if (isfinite(x))
		fprintf(f, "%.12g", x);
	else
		fputs("null", f);
}

void hl_tool_json_str(FILE *f, const char *s)
{
	fputc('"', f);
	for (; *s; s++) {
		if (*s == '"' || *s == '\\')
			fprintf(f, "\\%c", *s);
		else if ((unsigned char)*s < 0x20)
			fprintf(f, "\\u%04x", *s);
		else
			fputc(*s, f);
	}
	fputc('"', f);
}
