/* SPDX-License-Identifier: MIT */
#include "tools/json_out.h"

#include "base/json_write.h"

void hl_tool_json_num(FILE *f, double x)
{
	hl_json_write_num(f, x, "%.12g");
}

void hl_tool_json_str(FILE *f, const char *s)
{
	hl_json_write_str(f, s);
}
