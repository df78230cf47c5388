/* SPDX-License-Identifier: MIT */
/*
 * The DBC reader's token level (lexer.c), shared by the section readers in parse.c and
 * attributes.c only: the parser state, the lexer, the typed token readers, the errors and
 * warnings, and the references to nodes, messages and signals. Every reader returns 0 or a
 * negative errno (-EBADMSG with p->err set, -ENOMEM) and leaves p->tok on the next token.
 */
#ifndef HL_DBC_LEXER_H
#define HL_DBC_LEXER_H

#include "dbc/internal.h"

enum tok_kind {
	TOK_EOF,
	TOK_IDENT,
	TOK_NUMBER,
	TOK_STRING,
	TOK_PUNCT,
};

struct token {
	enum tok_kind kind;
	const char *p; /* text (for strings: inside the quotes, still escaped) */
	size_t n;
	int line, col;
	int end_line; /* line of its last character */
};

struct parser {
	const char *s, *end;
	int line, col;
	struct token tok;
	int prev_line; /* end line of the token before tok */
	struct hl_dbc *db;
	struct hl_dbc_error *err;
	int cur_msg; /* the BO_ whose SG_ lines may follow, -1 */
	int last_msg; /* cache for message lookups by ID */
	bool strict; /* HL_DBC_STRICT: every irregularity is an error */
	/* The first string with a line inside that starts like a section ("BO_ "): where a
	 * missing '"' most likely is when the quotes turn out unbalanced at the end. */
	int open_line, open_col, open_swallowed;
};

/* A reference to an object the file does not define: the statement is skipped (lenient). */
#define SKIP 1

/* --- errors and warnings --- */

/* The error fmt at line:col; -EBADMSG. */
int dbc_fail_at(struct parser *p, int line, int col, const char *fmt, ...)
	__attribute__((format(printf, 4, 5)));
/* "expected <what>, found <the current token>" at the current token; -EBADMSG. */
int dbc_expected(struct parser *p, const char *what);
int dbc_add_warning(struct parser *p, int line, int col, const char *msg);
/* Strict: the error fmt describes. Lenient: a warning of fmt plus action; 0. */
int dbc_irregular(struct parser *p, int line, int col, const char *action, const char *fmt, ...)
	__attribute__((format(printf, 5, 6)));

/* --- tokens --- */

bool dbc_is_digit(char c);
/* Reads the next token into p->tok. */
int dbc_next(struct parser *p);
bool dbc_is_punct(const struct parser *p, char c);
bool dbc_is_word(const struct parser *p, const char *w);
int dbc_expect_punct(struct parser *p, char c, const char *what);
/* An identifier, copied into the arena. */
int dbc_get_ident(struct parser *p, const char *what, const char **ret);
/* An identifier compared in place: its text and length. */
int dbc_peek_ident(struct parser *p, const char *what, const char **ret_p, size_t *ret_n);
/* A string, unescaped into the arena. */
int dbc_get_string(struct parser *p, const char *what, const char **ret);
/* An unsigned integer token up to max. */
int dbc_get_uint(struct parser *p, const char *what, uint64_t max, uint64_t *ret);
/* A signed integer within int64 (lenient: reals rounded, overflow clamped, warned). */
int dbc_get_int(struct parser *p, const char *what, int64_t *ret);
/* A real number: optional sign, digits, fraction, exponent. */
int dbc_get_number(struct parser *p, const char *what, double *ret);

/* --- lookups while parsing --- */

int dbc_find_node(const struct hl_dbc *db, const char *s, size_t n);
int dbc_find_signal_n(const struct hl_dbc_message *m, const char *s, size_t n);
/* A message ID that must name a BO_: 0, SKIP (lenient, warned) or -errno. */
int dbc_get_msg_ref(struct parser *p, int *ret);
/* A message ID and a signal name in it: 0, SKIP or -errno. */
int dbc_get_sig_ref(struct parser *p, int *ret_msg, int *ret_sig);
/* Skips to the end of a statement: past its ';', or to the next line starting with a word. */
int dbc_skip_statement(struct parser *p, int start_line);
/* After a reference that returned SKIP: the rest of the statement is skipped. */
int dbc_skipped(struct parser *p, int rc);

#endif
