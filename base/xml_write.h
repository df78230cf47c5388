/* SPDX-License-Identifier: MIT */
/*
 * XML text written to a stream, for attribute values and element content: the JUnit files of
 * `hdlamp sil` and the FMU's modelDescription.xml. '&', '<', '>' and '"' as entities; the
 * control characters XML 1.0 does not allow (all below 0x20 but tab, newline and carriage
 * return; XML 1.0, 2.2 "Characters") are left out.
 */
#ifndef HL_BASE_XML_WRITE_H
#define HL_BASE_XML_WRITE_H

#include <stdio.h>

/* s as XML text (NULL: nothing). */
void hl_xml_write_text(FILE *f, const char *s);

#endif
