/* SPDX-License-Identifier: MIT */
/*
 * The DBC reader's token level, apart from the section readers (parse.c, attributes.c) so that
 * each stays a readable size: the lexer (identifiers, numbers, strings, punctuation, each with
 * its line and column), the typed readers the sections build on (names, strings, integers,
 * reals), the errors and warnings with their positions, and the references to nodes, messages
 * and signals that several sections resolve. Signs are separate tokens so that "@1-" and the
 * SG_MUL_VAL_ ranges "3-5" read naturally.
 */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dbc/lexer.h"

/* Whether s (after a newline inside a string) starts like a section: blanks, then a keyword of
 * capitals, digits and '_' ending in '_', then a blank or ':'. */
static bool starts_section(const char *s, const char *end)
{
	const char *w;

	while (s < end && (*s == ' ' || *s == '\t'))
		s++;
	for (w = s; s < end && ((*s >= 'A' && *s <= 'Z') || (*s >= '0' && *s <= '9') || *s == '_');
	     s++)
		;
	return s - w >= 3 && s[-1] == '_' && s < end && (*s == ' ' || *s == ':');
}

int dbc_fail_at(struct parser *p, int line, int col, const char *fmt, ...)
{
	va_list ap;

	if (p->err) {
		p->err->line = line;
		p->err->column = col;
		va_start(ap, fmt);
		vsnprintf(p->err->msg, sizeof(p->err->msg), fmt, ap);
		va_end(ap);
	}
	return -EBADMSG;
}

static void describe(const struct token *t, char *buf, size_t size)
{
	switch (t->kind) {
	case TOK_EOF:
		snprintf(buf, size, "end of file");
		break;
	case TOK_IDENT:
		snprintf(buf, size, "'%.*s'", (int)(t->n > 40 ? 40 : t->n), t->p);
		break;
	case TOK_NUMBER:
		snprintf(buf, size, "number %.*s", (int)(t->n > 40 ? 40 : t->n), t->p);
		break;
	case TOK_STRING:
		snprintf(buf, size, "a string");
		break;
	case TOK_PUNCT:
		snprintf(buf, size, "'%c'", t->p[0]);
		break;
	}
}

/* "expected <what>, found <the current token>" at the current token. */
int dbc_expected(struct parser *p, const char *what)
{
	char found[64];

	describe(&p->tok, found, sizeof(found));
	return dbc_fail_at(p, p->tok.line, p->tok.col, "expected %s, found %s", what, found);
}

static void advance(struct parser *p)
{
	if (*p->s == '\n') {
		p->line++;
		p->col = 1;
	} else {
		p->col++;
	}
	p->s++;
}

static bool is_alpha(char c)
{
	return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
}

bool dbc_is_digit(char c)
{
	return c >= '0' && c <= '9';
}

/* Reads the next token into p->tok. 0 or -EBADMSG for a character no DBC token starts with. */
int dbc_next(struct parser *p)
{
	struct token *t = &p->tok;

	p->prev_line = t->end_line;
	for (;;) {
		while (p->s < p->end && (*p->s == ' ' || *p->s == '\t' || *p->s == '\r' ||
					 *p->s == '\n' || *p->s == '\f' || *p->s == '\v'))
			advance(p);
		/* '//' line comments, as some hand-written files have them */
		if (p->end - p->s >= 2 && p->s[0] == '/' && p->s[1] == '/') {
			while (p->s < p->end && *p->s != '\n')
				advance(p);
			continue;
		}
		break;
	}
	t->line = p->line;
	t->col = p->col;
	t->p = p->s;
	if (p->s == p->end) {
		t->kind = TOK_EOF;
		t->n = 0;
	} else if (is_alpha(*p->s)) {
		t->kind = TOK_IDENT;
		while (p->s < p->end && (is_alpha(*p->s) || dbc_is_digit(*p->s)))
			advance(p);
	} else if (dbc_is_digit(*p->s) ||
		   (*p->s == '.' && p->s + 1 < p->end && dbc_is_digit(p->s[1]))) {
		t->kind = TOK_NUMBER;
		while (p->s < p->end && dbc_is_digit(*p->s))
			advance(p);
		if (p->s < p->end && *p->s == '.') {
			advance(p);
			while (p->s < p->end && dbc_is_digit(*p->s))
				advance(p);
		}
		if (p->s < p->end && (*p->s == 'e' || *p->s == 'E')) {
			const char *e = p->s + 1;

			if (e < p->end && (*e == '+' || *e == '-'))
				e++;
			if (e < p->end && dbc_is_digit(*e)) {
				while (p->s < e)
					advance(p);
				while (p->s < p->end && dbc_is_digit(*p->s))
					advance(p);
			}
		}
	} else if (*p->s == '"') {
		advance(p);
		t->kind = TOK_STRING;
		t->p = p->s;
		while (p->s < p->end && *p->s != '"') {
			if (*p->s == '\\' && p->s + 1 < p->end)
				advance(p);
			if (*p->s == '\n' && !p->open_line && starts_section(p->s + 1, p->end)) {
				p->open_line = t->line;
				p->open_col = t->col;
				p->open_swallowed = p->line + 1;
			}
			advance(p);
		}
		if (p->s == p->end && p->open_line)
			return dbc_fail_at(
				p, p->open_line, p->open_col,
				"unterminated string: expected a closing '\"' before line %d, where a section starts",
				p->open_swallowed);
		if (p->s == p->end)
			return dbc_fail_at(p, t->line, t->col,
					   "unterminated string: expected a closing '\"'");
		t->n = p->s - t->p;
		t->end_line = p->line;
		advance(p);
		return 0;
	} else if (strchr(":;,|@()[]+-", *p->s) && *p->s) {
		t->kind = TOK_PUNCT;
		advance(p);
	} else {
		unsigned char c = *p->s;

		if (c >= 0x21 && c < 0x7f)
			return dbc_fail_at(p, t->line, t->col, "unexpected character '%c'", c);
		return dbc_fail_at(p, t->line, t->col, "unexpected byte 0x%02x", c);
	}
	t->n = p->s - t->p;
	t->end_line = p->line;
	return 0;
}

bool dbc_is_punct(const struct parser *p, char c)
{
	return p->tok.kind == TOK_PUNCT && p->tok.p[0] == c;
}

bool dbc_is_word(const struct parser *p, const char *w)
{
	return p->tok.kind == TOK_IDENT && p->tok.n == strlen(w) &&
	       memcmp(p->tok.p, w, p->tok.n) == 0;
}

int dbc_expect_punct(struct parser *p, char c, const char *what)
{
	if (!dbc_is_punct(p, c))
		return dbc_expected(p, what);
	return dbc_next(p);
}

/* An identifier, copied into the arena. */
int dbc_get_ident(struct parser *p, const char *what, const char **ret)
{
	char *s;

	if (p->tok.kind != TOK_IDENT)
		return dbc_expected(p, what);
	s = hl_dbc_strndup(p->db, p->tok.p, p->tok.n);
	if (!s)
		return -ENOMEM;
	*ret = s;
	return dbc_next(p);
}

/* An identifier compared in place: 0 and its text and length. */
int dbc_peek_ident(struct parser *p, const char *what, const char **ret_p, size_t *ret_n)
{
	if (p->tok.kind != TOK_IDENT)
		return dbc_expected(p, what);
	*ret_p = p->tok.p;
	*ret_n = p->tok.n;
	return dbc_next(p);
}

int dbc_get_string(struct parser *p, const char *what, const char **ret)
{
	char *s;
	size_t n = 0;

	if (p->tok.kind != TOK_STRING)
		return dbc_expected(p, what);
	s = hl_dbc_strndup(p->db, p->tok.p, p->tok.n);
	if (!s)
		return -ENOMEM;
	for (size_t i = 0; i < p->tok.n; i++) {
		if (p->tok.p[i] == '\\' && i + 1 < p->tok.n)
			i++;
		s[n++] = p->tok.p[i];
	}
	s[n] = '\0';
	*ret = s;
	return dbc_next(p);
}

/* A number token written as a real (1E+3, 8.0) that is an integer 0..max: lenient, read with a
 * warning; otherwise the error "expected <what>". */
static int real_as_uint(struct parser *p, const char *what, uint64_t max, uint64_t *ret)
{
	char buf[64];
	double d;
	int rc;

	if (p->strict || p->tok.n >= sizeof(buf))
		return dbc_expected(p, what);
	memcpy(buf, p->tok.p, p->tok.n);
	buf[p->tok.n] = '\0';
	d = strtod(buf, NULL);
	if (d != nearbyint(d) || d >= 0x1p64 || (uint64_t)d > max)
		return dbc_expected(p, what);
	rc = dbc_irregular(p, p->tok.line, p->tok.col, "read as an integer",
			   "expected %s, found number %s", what, buf);
	if (rc < 0)
		return rc;
	*ret = (uint64_t)d;
	return dbc_next(p);
}

/* An unsigned integer token up to max. */
int dbc_get_uint(struct parser *p, const char *what, uint64_t max, uint64_t *ret)
{
	uint64_t v = 0;

	if (p->tok.kind != TOK_NUMBER)
		return dbc_expected(p, what);
	for (size_t i = 0; i < p->tok.n; i++) {
		if (!dbc_is_digit(p->tok.p[i]))
			return real_as_uint(p, what, max, ret);
		if (v > (UINT64_MAX - 9) / 10 || v * 10 + (p->tok.p[i] - '0') > max)
			return dbc_fail_at(p, p->tok.line, p->tok.col,
					   "expected %s, found %.*s (above %llu)", what,
					   (int)(p->tok.n > 40 ? 40 : p->tok.n), p->tok.p,
					   (unsigned long long)max);
		v = v * 10 + (p->tok.p[i] - '0');
	}
	*ret = v;
	return dbc_next(p);
}

/*
 * A signed integer: optional sign, then digits, within int64. Errors point at the sign when
 * there is one. Lenient, an integer written as a real (9.22337203685478E+018, -92E+1, 2.0) is
 * read rounded to the nearest integer, and one beyond 63 bits is clamped, each with a warning.
 */
int dbc_get_int(struct parser *p, const char *what, int64_t *ret)
{
	int line = p->tok.line, col = p->tok.col, n, rc;
	bool neg = false, plain = true;
	uint64_t v = 0, max;
	char text[48];

	if (dbc_is_punct(p, '-') || dbc_is_punct(p, '+')) {
		neg = dbc_is_punct(p, '-');
		if ((rc = dbc_next(p)) < 0)
			return rc;
	}
	if (p->tok.kind != TOK_NUMBER) {
		rc = dbc_expected(p, what);
		p->err->line = line;
		p->err->column = col;
		return rc;
	}
	n = (int)(p->tok.n > 40 ? 40 : p->tok.n);
	snprintf(text, sizeof(text), "%.*s", n, p->tok.p); /* as errors always quoted it */
	max = neg ? (uint64_t)INT64_MAX + 1 : (uint64_t)INT64_MAX;
	for (size_t i = 0; i < p->tok.n && plain; i++)
		plain = dbc_is_digit(p->tok.p[i]);
	if (!plain) {
		char buf[64];
		double d;

		if (p->tok.n >= sizeof(buf))
			return dbc_fail_at(p, line, col,
					   "expected %s, found a number of %zu digits", what,
					   p->tok.n);
		memcpy(buf, p->tok.p, p->tok.n);
		buf[p->tok.n] = '\0';
		d = nearbyint(strtod(buf, NULL));
		if (d >= 0x1p63 && !neg)
			*ret = INT64_MAX;
		else if (d >= 0x1p63)
			*ret = INT64_MIN;
		else
			*ret = neg ? -(int64_t)d : (int64_t)d;
		rc = dbc_irregular(p, line, col, "read as an integer",
				   "expected %s, found number %s", what, text);
		return rc < 0 ? rc : dbc_next(p);
	}
	for (size_t i = 0; i < p->tok.n; i++) {
		if (v > (UINT64_MAX - 9) / 10 || v * 10 + (p->tok.p[i] - '0') > max) {
			v = max;
			rc = dbc_irregular(p, line, col, "clamped to the 64-bit range",
					   "expected %s, found %s (above %llu)", what, text,
					   (unsigned long long)max);
			if (rc < 0)
				return rc;
			break;
		}
		v = v * 10 + (p->tok.p[i] - '0');
	}
	*ret = neg ? (int64_t)(0 - v) : (int64_t)v;
	return dbc_next(p);
}

/* A real number: optional sign, digits, fraction, exponent. */
int dbc_get_number(struct parser *p, const char *what, double *ret)
{
	char buf[64];
	bool neg = false;
	int line = p->tok.line, col = p->tok.col, rc; /* errors point at the sign */

	if (dbc_is_punct(p, '-') || dbc_is_punct(p, '+')) {
		neg = dbc_is_punct(p, '-');
		if ((rc = dbc_next(p)) < 0)
			return rc;
	}
	if (p->tok.kind != TOK_NUMBER) {
		rc = dbc_expected(p, what);
		p->err->line = line;
		p->err->column = col;
		return rc;
	}
	if (p->tok.n >= sizeof(buf))
		return dbc_fail_at(p, line, col, "expected %s, found a number of %zu digits", what,
				   p->tok.n);
	memcpy(buf, p->tok.p, p->tok.n);
	buf[p->tok.n] = '\0';
	*ret = neg ? -strtod(buf, NULL) : strtod(buf, NULL);
	return dbc_next(p);
}

int dbc_add_warning(struct parser *p, int line, int col, const char *msg)
{
	struct hl_dbc *db = p->db;

	if (hl_dbc_grow(&db->warnings, &db->cap_warnings, db->n_warnings, sizeof(*db->warnings)))
		return -ENOMEM;
	db->warnings[db->n_warnings].msg = hl_dbc_strndup(db, msg, strlen(msg));
	if (!db->warnings[db->n_warnings].msg)
		return -ENOMEM;
	db->warnings[db->n_warnings].line = line;
	db->warnings[db->n_warnings].column = col;
	db->n_warnings++;
	return 0;
}

/*
 * Something real files do that the DBC format does not allow. Strict: the error fmt describes
 * (-EBADMSG). Lenient: the same text plus what was done instead, as a warning; 0.
 */
int dbc_irregular(struct parser *p, int line, int col, const char *action, const char *fmt, ...)
{
	char msg[512];
	va_list ap;
	int n;

	va_start(ap, fmt);
	n = vsnprintf(msg, sizeof(msg), fmt, ap);
	va_end(ap);
	if (p->strict)
		return dbc_fail_at(p, line, col, "%s", msg);
	if (n >= 0 && (size_t)n < sizeof(msg))
		snprintf(msg + n, sizeof(msg) - n, ": %s", action);
	return dbc_add_warning(p, line, col, msg);
}

/* --- lookups while parsing --- */

int dbc_find_node(const struct hl_dbc *db, const char *s, size_t n)
{
	for (int i = 0; i < db->n_nodes; i++)
		if (strlen(db->nodes[i].name) == n && memcmp(db->nodes[i].name, s, n) == 0)
			return i;
	return -1;
}

int dbc_find_signal_n(const struct hl_dbc_message *m, const char *s, size_t n)
{
	for (int i = 0; i < m->n_signals; i++)
		if (strlen(m->signals[i].name) == n && memcmp(m->signals[i].name, s, n) == 0)
			return i;
	return -1;
}

/* A message ID as the file writes it (bit 31 for extended) that must name a BO_: 0, or SKIP
 * (lenient, warned) when none does, the statement then to be skipped. */
int dbc_get_msg_ref(struct parser *p, int *ret)
{
	struct hl_dbc *db = p->db;
	int line = p->tok.line, col = p->tok.col, rc;
	uint64_t id;

	rc = dbc_get_uint(p, "a message ID", UINT32_MAX, &id);
	if (rc < 0)
		return rc;
	if (p->last_msg >= 0 && p->last_msg < db->n_msgs && db->msgs[p->last_msg].can_id == id) {
		*ret = p->last_msg;
		return 0;
	}
	for (int i = 0; i < db->n_msgs; i++)
		if (db->msgs[i].can_id == id) {
			*ret = p->last_msg = i;
			return 0;
		}
	rc = dbc_irregular(p, line, col, "statement skipped",
			   "expected the ID of a message defined by BO_, found %llu",
			   (unsigned long long)id);
	return rc < 0 ? rc : SKIP;
}

/* A message ID and a signal name in it: 0, SKIP (as get_msg_ref) or -errno. */
int dbc_get_sig_ref(struct parser *p, int *ret_msg, int *ret_sig)
{
	const char *name = NULL;
	size_t n = 0;
	int line, col, rc;

	rc = dbc_get_msg_ref(p, ret_msg);
	if (rc != 0)
		return rc;
	line = p->tok.line;
	col = p->tok.col;
	rc = dbc_peek_ident(p, "a signal name", &name, &n);
	if (rc < 0)
		return rc;
	*ret_sig = dbc_find_signal_n(&p->db->msgs[*ret_msg], name, n);
	if (*ret_sig < 0) {
		rc = dbc_irregular(p, line, col, "statement skipped",
				   "expected a signal of message '%s', found '%.*s'",
				   p->db->msgs[*ret_msg].name, (int)(n > 40 ? 40 : n), name);
		return rc < 0 ? rc : SKIP;
	}
	return 0;
}

/* Skips to the end of a statement: past its ';', or to the next line starting with a word. */
int dbc_skip_statement(struct parser *p, int start_line)
{
	int rc;

	while (p->tok.kind != TOK_EOF) {
		if (dbc_is_punct(p, ';'))
			return dbc_next(p);
		if (p->tok.kind == TOK_IDENT && p->tok.col == 1 && p->tok.line > start_line)
			return 0;
		if ((rc = dbc_next(p)) < 0)
			return rc;
	}
	return 0;
}

/* After a reference that returned SKIP: the rest of the statement is skipped. */
int dbc_skipped(struct parser *p, int rc)
{
	return rc == SKIP ? dbc_skip_statement(p, p->tok.line) : rc;
}
