/* SPDX-License-Identifier: MIT */
/*
 * Where and why an import failed. every reader of import/ fills one of these (when the
 * caller passes it) and returns -errno; nothing in the library logs.
 */
#ifndef HL_IMPORT_ERROR_H
#define HL_IMPORT_ERROR_H

struct hl_import_error {
	int line, column; /* 1-based; 0 when the fault has no place (e.g. a missing file) */
	/* Whole message, naming the file: "'lamp.ies':12:5: expected 45 vertical angles, ..." */
	char msg[768];
};

#endif
