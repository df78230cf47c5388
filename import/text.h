/* SPDX-License-Identifier: MIT */
/*
 * Internal to import/: a cursor over a text buffer that knows its line and column, strict
 * number syntax, and error messages that name the file, the line and what was expected.
 * Buffers are (pointer, length); embedded NUL bytes are ordinary (invalid) characters.
 */
#ifndef HL_IMPORT_TEXT_H
#define HL_IMPORT_TEXT_H

#include <stdbool.h>
#include <stddef.h>

#include "import/error.h"

#define HL_IMPORT_MAX_FILE (256u << 20) /* bytes; larger inputs are refused */

struct hl_text {
	const char *p, *end;
	const char *name; /* file name for messages */
	int line, col; /* of *p, 1-based */
	struct hl_import_error *err;
};

void hl_text_init(struct hl_text *t, const char *buf, size_t len, const char *name,
		  struct hl_import_error *err);

/* Fills err (if any) at the cursor's position and returns rc (a negative errno). */
int hl_text_fail(struct hl_text *t, int rc, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));
/* Same, at an explicit place. */
int hl_text_fail_at(struct hl_text *t, int line, int col, int rc, const char *fmt, ...)
	__attribute__((format(printf, 5, 6)));
/* An error without a place: "'name': msg". */
int hl_import_fail(struct hl_import_error *err, const char *name, int rc, const char *fmt, ...)
	__attribute__((format(printf, 4, 5)));

bool hl_text_eof(const struct hl_text *t);
void hl_text_advance(struct hl_text *t);
/* Skips blanks (space, tab, CR, and LF when also_newlines). Commas too when commas. */
void hl_text_skip_blanks(struct hl_text *t, bool also_newlines, bool commas);

/*
 * The next line without its CR/LF; the cursor moves to the start of the following line.
 * Returns false at end of input.
 */
bool hl_text_line(struct hl_text *t, const char **ret_s, size_t *ret_len);

/*
 * Strict decimal number: [+-] digits [. digits] [(e|E) [+-] digits], at least one digit in the
 * mantissa; "nan", "inf", hex and the like are not numbers. Finite results only.
 * Parses s[0..len) completely. 0 or -EBADMSG (ret untouched).
 */
int hl_number_parse(const char *s, size_t len, double *ret);

/*
 * Reads the next whitespace (and, with commas, comma) separated token across lines as a
 * number; "what" names it in the message. 0, -EBADMSG.
 */
int hl_text_number(struct hl_text *t, bool commas, const char *what, double *ret);
/* The same token rules, but the value must be an integer in [min, max]. */
int hl_text_int(struct hl_text *t, bool commas, const char *what, long min, long max, long *ret);

/* Reads a whole file (at most HL_IMPORT_MAX_FILE bytes). 0, -errno; err names the file. */
int hl_import_read_file(const char *path, char **ret_buf, size_t *ret_len,
			struct hl_import_error *err);

#endif
