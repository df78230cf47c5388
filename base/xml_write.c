/* SPDX-License-Identifier: MIT */
/* XML text written to a stream: see base/xml_write.h. */
#include "base/xml_write.h"

void hl_xml_write_text(FILE *f, const char *s)
{
	for (; s && *s; s++) {
		switch (*s) {
		case '&':
			fputs("&amp;", f);
			break;
		case '<':
			fputs("&lt;", f);
			break;
		case '>':
			fputs("&gt;", f);
			break;
		case '"':
			fputs("&quot;", f);
			break;
		default:
			if ((unsigned char)*s >= 0x20 || *s == '\t' || *s == '\n' || *s == '\r')
				fputc(*s, f);
		}
	}
}
