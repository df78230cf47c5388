/* SPDX-License-Identifier: MIT */
/*
 * The DBC reader: a small lexer (identifiers, numbers, strings, punctuation, each with its line
 * and column) and one function per section. Signs are separate tokens so that "@1-" and the
 * SG_MUL_VAL_ ranges "3-5" read naturally. Statements ending in ';' are read to the ';'; BO_,
 * SG_, BU_ and BS_ end with their line, as every tool writes them.
 */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "dbc/internal.h"

#define MAX_FILE_BYTES (64 << 20)

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

/* A reference to an object the file does not define: the statement is skipped (lenient). */
#define SKIP 1

static int fail_at(struct parser *p, int line, int col, const char *fmt, ...)
	__attribute__((format(printf, 4, 5)));

static int fail_at(struct parser *p, int line, int col, const char *fmt, ...)
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
static int expected(struct parser *p, const char *what)
{
	char found[64];

	describe(&p->tok, found, sizeof(found));
	return fail_at(p, p->tok.line, p->tok.col, "expected %s, found %s", what, found);
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

static bool is_digit(char c)
{
	return c >= '0' && c <= '9';
}

/* Reads the next token into p->tok. 0 or -EBADMSG for a character no DBC token starts with. */
static int next(struct parser *p)
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
		while (p->s < p->end && (is_alpha(*p->s) || is_digit(*p->s)))
			advance(p);
	} else if (is_digit(*p->s) || (*p->s == '.' && p->s + 1 < p->end && is_digit(p->s[1]))) {
		t->kind = TOK_NUMBER;
		while (p->s < p->end && is_digit(*p->s))
			advance(p);
		if (p->s < p->end && *p->s == '.') {
			advance(p);
			while (p->s < p->end && is_digit(*p->s))
				advance(p);
		}
		if (p->s < p->end && (*p->s == 'e' || *p->s == 'E')) {
			const char *e = p->s + 1;

			if (e < p->end && (*e == '+' || *e == '-'))
				e++;
			if (e < p->end && is_digit(*e)) {
				while (p->s < e)
					advance(p);
				while (p->s < p->end && is_digit(*p->s))
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
			return fail_at(
				p, p->open_line, p->open_col,
				"unterminated string: expected a closing '\"' before line %d, where a section starts",
				p->open_swallowed);
		if (p->s == p->end)
			return fail_at(p, t->line, t->col,
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
			return fail_at(p, t->line, t->col, "unexpected character '%c'", c);
		return fail_at(p, t->line, t->col, "unexpected byte 0x%02x", c);
	}
	t->n = p->s - t->p;
	t->end_line = p->line;
	return 0;
}

static bool is_punct(const struct parser *p, char c)
{
	return p->tok.kind == TOK_PUNCT && p->tok.p[0] == c;
}

static bool is_word(const struct parser *p, const char *w)
{
	return p->tok.kind == TOK_IDENT && p->tok.n == strlen(w) &&
	       memcmp(p->tok.p, w, p->tok.n) == 0;
}

static int expect_punct(struct parser *p, char c, const char *what)
{
	if (!is_punct(p, c))
		return expected(p, what);
	return next(p);
}

/* An identifier, copied into the arena. */
static int get_ident(struct parser *p, const char *what, const char **ret)
{
	char *s;

	if (p->tok.kind != TOK_IDENT)
		return expected(p, what);
	s = hl_dbc_strndup(p->db, p->tok.p, p->tok.n);
	if (!s)
		return -ENOMEM;
	*ret = s;
	return next(p);
}

/* An identifier compared in place: 0 and its text and length. */
static int peek_ident(struct parser *p, const char *what, const char **ret_p, size_t *ret_n)
{
	if (p->tok.kind != TOK_IDENT)
		return expected(p, what);
	*ret_p = p->tok.p;
	*ret_n = p->tok.n;
	return next(p);
}

static int get_string(struct parser *p, const char *what, const char **ret)
{
	char *s;
	size_t n = 0;

	if (p->tok.kind != TOK_STRING)
		return expected(p, what);
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
	return next(p);
}

static int irregular(struct parser *p, int line, int col, const char *action, const char *fmt, ...)
	__attribute__((format(printf, 5, 6)));

/* A number token written as a real (1E+3, 8.0) that is an integer 0..max: lenient, read with a
 * warning; otherwise the error "expected <what>". */
static int real_as_uint(struct parser *p, const char *what, uint64_t max, uint64_t *ret)
{
	char buf[64];
	double d;
	int rc;

	if (p->strict || p->tok.n >= sizeof(buf))
		return expected(p, what);
	memcpy(buf, p->tok.p, p->tok.n);
	buf[p->tok.n] = '\0';
	d = strtod(buf, NULL);
	if (d != nearbyint(d) || d >= 0x1p64 || (uint64_t)d > max)
		return expected(p, what);
	rc = irregular(p, p->tok.line, p->tok.col, "read as an integer",
		       "expected %s, found number %s", what, buf);
	if (rc < 0)
		return rc;
	*ret = (uint64_t)d;
	return next(p);
}

/* An unsigned integer token up to max. */
static int get_uint(struct parser *p, const char *what, uint64_t max, uint64_t *ret)
{
	uint64_t v = 0;

	if (p->tok.kind != TOK_NUMBER)
		return expected(p, what);
	for (size_t i = 0; i < p->tok.n; i++) {
		if (!is_digit(p->tok.p[i]))
			return real_as_uint(p, what, max, ret);
		if (v > (UINT64_MAX - 9) / 10 || v * 10 + (p->tok.p[i] - '0') > max)
			return fail_at(p, p->tok.line, p->tok.col,
				       "expected %s, found %.*s (above %llu)", what,
				       (int)(p->tok.n > 40 ? 40 : p->tok.n), p->tok.p,
				       (unsigned long long)max);
		v = v * 10 + (p->tok.p[i] - '0');
	}
	*ret = v;
	return next(p);
}

/*
 * A signed integer: optional sign, then digits, within int64. Errors point at the sign when
 * there is one. Lenient, an integer written as a real (9.22337203685478E+018, -92E+1, 2.0) is
 * read rounded to the nearest integer, and one beyond 63 bits is clamped, each with a warning.
 */
static int get_int(struct parser *p, const char *what, int64_t *ret)
{
	int line = p->tok.line, col = p->tok.col, n, rc;
	bool neg = false, plain = true;
	uint64_t v = 0, max;
	char text[48];

	if (is_punct(p, '-') || is_punct(p, '+')) {
		neg = is_punct(p, '-');
		if ((rc = next(p)) < 0)
			return rc;
	}
	if (p->tok.kind != TOK_NUMBER) {
		rc = expected(p, what);
		p->err->line = line;
		p->err->column = col;
		return rc;
	}
	n = (int)(p->tok.n > 40 ? 40 : p->tok.n);
	snprintf(text, sizeof(text), "%.*s", n, p->tok.p); /* as errors always quoted it */
	max = neg ? (uint64_t)INT64_MAX + 1 : (uint64_t)INT64_MAX;
	for (size_t i = 0; i < p->tok.n && plain; i++)
		plain = is_digit(p->tok.p[i]);
	if (!plain) {
		char buf[64];
		double d;

		if (p->tok.n >= sizeof(buf))
			return fail_at(p, line, col, "expected %s, found a number of %zu digits",
				       what, p->tok.n);
		memcpy(buf, p->tok.p, p->tok.n);
		buf[p->tok.n] = '\0';
		d = nearbyint(strtod(buf, NULL));
		if (d >= 0x1p63 && !neg)
			*ret = INT64_MAX;
		else if (d >= 0x1p63)
			*ret = INT64_MIN;
		else
			*ret = neg ? -(int64_t)d : (int64_t)d;
		rc = irregular(p, line, col, "read as an integer", "expected %s, found number %s",
			       what, text);
		return rc < 0 ? rc : next(p);
	}
	for (size_t i = 0; i < p->tok.n; i++) {
		if (v > (UINT64_MAX - 9) / 10 || v * 10 + (p->tok.p[i] - '0') > max) {
			v = max;
			rc = irregular(p, line, col, "clamped to the 64-bit range",
				       "expected %s, found %s (above %llu)", what, text,
				       (unsigned long long)max);
			if (rc < 0)
				return rc;
			break;
		}
		v = v * 10 + (p->tok.p[i] - '0');
	}
	*ret = neg ? (int64_t)(0 - v) : (int64_t)v;
	return next(p);
}

/* A real number: optional sign, digits, fraction, exponent. */
static int get_number(struct parser *p, const char *what, double *ret)
{
	char buf[64];
	bool neg = false;
	int line = p->tok.line, col = p->tok.col, rc; /* errors point at the sign */

	if (is_punct(p, '-') || is_punct(p, '+')) {
		neg = is_punct(p, '-');
		if ((rc = next(p)) < 0)
			return rc;
	}
	if (p->tok.kind != TOK_NUMBER) {
		rc = expected(p, what);
		p->err->line = line;
		p->err->column = col;
		return rc;
	}
	if (p->tok.n >= sizeof(buf))
		return fail_at(p, line, col, "expected %s, found a number of %zu digits", what,
			       p->tok.n);
	memcpy(buf, p->tok.p, p->tok.n);
	buf[p->tok.n] = '\0';
	*ret = neg ? -strtod(buf, NULL) : strtod(buf, NULL);
	return next(p);
}

static int add_warning(struct parser *p, int line, int col, const char *msg)
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

static int warn(struct parser *p, int line, int col, const char *fmt, const char *arg)
{
	char msg[160];

	snprintf(msg, sizeof(msg), fmt, arg);
	return add_warning(p, line, col, msg);
}

static int irregular(struct parser *p, int line, int col, const char *action, const char *fmt, ...)
	__attribute__((format(printf, 5, 6)));

/*
 * Something real files do that the DBC format does not allow. Strict: the error fmt describes
 * (-EBADMSG). Lenient: the same text plus what was done instead, as a warning; 0.
 */
static int irregular(struct parser *p, int line, int col, const char *action, const char *fmt, ...)
{
	char msg[512];
	va_list ap;
	int n;

	va_start(ap, fmt);
	n = vsnprintf(msg, sizeof(msg), fmt, ap);
	va_end(ap);
	if (p->strict)
		return fail_at(p, line, col, "%s", msg);
	if (n >= 0 && (size_t)n < sizeof(msg))
		snprintf(msg + n, sizeof(msg) - n, ": %s", action);
	return add_warning(p, line, col, msg);
}

/* --- lookups while parsing --- */

static int find_node(const struct hl_dbc *db, const char *s, size_t n)
{
	for (int i = 0; i < db->n_nodes; i++)
		if (strlen(db->nodes[i].name) == n && memcmp(db->nodes[i].name, s, n) == 0)
			return i;
	return -1;
}

static int find_signal_n(const struct hl_dbc_message *m, const char *s, size_t n)
{
	for (int i = 0; i < m->n_signals; i++)
		if (strlen(m->signals[i].name) == n && memcmp(m->signals[i].name, s, n) == 0)
			return i;
	return -1;
}

/* A message ID as the file writes it (bit 31 for extended) that must name a BO_: 0, or SKIP
 * (lenient, warned) when none does, the statement then to be skipped. */
static int get_msg_ref(struct parser *p, int *ret)
{
	struct hl_dbc *db = p->db;
	int line = p->tok.line, col = p->tok.col, rc;
	uint64_t id;

	rc = get_uint(p, "a message ID", UINT32_MAX, &id);
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
	rc = irregular(p, line, col, "statement skipped",
		       "expected the ID of a message defined by BO_, found %llu",
		       (unsigned long long)id);
	return rc < 0 ? rc : SKIP;
}

/* A message ID and a signal name in it: 0, SKIP (as get_msg_ref) or -errno. */
static int get_sig_ref(struct parser *p, int *ret_msg, int *ret_sig)
{
	const char *name = NULL;
	size_t n = 0;
	int line, col, rc;

	rc = get_msg_ref(p, ret_msg);
	if (rc != 0)
		return rc;
	line = p->tok.line;
	col = p->tok.col;
	rc = peek_ident(p, "a signal name", &name, &n);
	if (rc < 0)
		return rc;
	*ret_sig = find_signal_n(&p->db->msgs[*ret_msg], name, n);
	if (*ret_sig < 0) {
		rc = irregular(p, line, col, "statement skipped",
			       "expected a signal of message '%s', found '%.*s'",
			       p->db->msgs[*ret_msg].name, (int)(n > 40 ? 40 : n), name);
		return rc < 0 ? rc : SKIP;
	}
	return 0;
}

/* Skips to the end of a statement: past its ';', or to the next line starting with a word. */
static int skip_statement(struct parser *p, int start_line)
{
	int rc;

	while (p->tok.kind != TOK_EOF) {
		if (is_punct(p, ';'))
			return next(p);
		if (p->tok.kind == TOK_IDENT && p->tok.col == 1 && p->tok.line > start_line)
			return 0;
		if ((rc = next(p)) < 0)
			return rc;
	}
	return 0;
}

/* After a reference that returned SKIP: the rest of the statement is skipped. */
static int skipped(struct parser *p, int rc)
{
	return rc == SKIP ? skip_statement(p, p->tok.line) : rc;
}

/* --- sections --- */

static int parse_version(struct parser *p)
{
	return get_string(p, "the version string after VERSION", &p->db->version);
}

static int parse_ns(struct parser *p)
{
	int rc = expect_punct(p, ':', "':' after NS_");

	/* the symbol list: indented words */
	while (rc == 0 && p->tok.kind == TOK_IDENT && p->tok.col > 1)
		rc = next(p);
	return rc;
}

static int parse_bs(struct parser *p)
{
	int line = p->tok.line, rc;

	rc = expect_punct(p, ':', "':' after BS_");
	/* optional "baudrate : BTR1 , BTR2", obsolete: read to the end of the line */
	while (rc == 0 && p->tok.kind != TOK_EOF && p->tok.line == line)
		rc = next(p);
	return rc;
}

/* A word that starts a section: every DBC keyword ends in '_' but VERSION and FILTER. */
static bool is_section_word(const struct parser *p)
{
	return p->tok.kind == TOK_IDENT &&
	       (p->tok.p[p->tok.n - 1] == '_' || is_word(p, "VERSION") || is_word(p, "FILTER"));
}

static int parse_bu(struct parser *p)
{
	struct hl_dbc *db = p->db;
	int line = p->tok.line, rc = expect_punct(p, ':', "':' after BU_");
	bool continued = false;

	while (rc == 0 && p->tok.kind == TOK_IDENT) {
		if (p->tok.line != line) {
			/* names on the lines below BU_:, as some generators write them */
			if (p->strict || is_section_word(p))
				break;
			if (!continued) {
				char msg[128];

				snprintf(
					msg, sizeof(msg),
					"node names of BU_ (line %d) continue on the next lines: read as nodes",
					line);
				rc = add_warning(p, p->tok.line, p->tok.col, msg);
				if (rc < 0)
					return rc;
				continued = true;
			}
		}
		if (find_node(db, p->tok.p, p->tok.n) >= 0) {
			rc = irregular(p, p->tok.line, p->tok.col, "read once",
				       "node '%.*s' listed twice",
				       (int)(p->tok.n > 40 ? 40 : p->tok.n), p->tok.p);
			if (rc == 0)
				rc = next(p);
			continue;
		}
		if (hl_dbc_grow(&db->nodes, &db->cap_nodes, db->n_nodes, sizeof(*db->nodes)))
			return -ENOMEM;
		db->nodes[db->n_nodes] = (struct node){ 0 };
		rc = get_ident(p, "a node name", &db->nodes[db->n_nodes].name);
		db->n_nodes++;
	}
	return rc;
}

/* value "description" pairs up to ';' */
static int parse_value_descs(struct parser *p, struct hl_dbc_value_desc **ret, int *ret_n)
{
	struct hl_dbc_value_desc *v = NULL;
	int n = 0, cap = 0, rc = 0;

	while (!is_punct(p, ';')) {
		if (hl_dbc_grow(&v, &cap, n, sizeof(*v))) {
			rc = -ENOMEM;
			break;
		}
		rc = get_int(p, "a value or ';'", &v[n].value);
		if (rc == 0)
			rc = get_string(p, "the value's description string", &v[n].desc);
		if (rc < 0)
			break;
		n++;
	}
	if (rc == 0)
		rc = next(p);
	if (rc < 0) {
		free(v);
		return rc;
	}
	*ret = v;
	*ret_n = n;
	return 0;
}

static int parse_val_table(struct parser *p)
{
	struct hl_dbc *db = p->db;
	struct value_table *t;
	int rc;

	if (hl_dbc_grow(&db->tables, &db->cap_tables, db->n_tables, sizeof(*db->tables)))
		return -ENOMEM;
	t = &db->tables[db->n_tables];
	*t = (struct value_table){ 0 };
	rc = get_ident(p, "the value table's name", &t->name);
	if (rc == 0)
		rc = parse_value_descs(p, &t->entries, &t->n);
	if (rc == 0)
		db->n_tables++;
	return rc;
}

static int parse_bo(struct parser *p)
{
	struct hl_dbc *db = p->db;
	struct hl_dbc_message *m;
	int id_line = p->tok.line, id_col = p->tok.col, name_line, name_col, rc;
	uint64_t id, size = 0;
	const char *name = NULL, *tx = NULL;
	bool independent = false;

	rc = get_uint(p, "a message ID", UINT32_MAX, &id);
	if (rc < 0)
		return rc;
	if (id == 0xC0000000u) {
		/* VECTOR__INDEPENDENT_SIG_MSG: CANdb++'s holder of unassigned signals */
		independent = true;
	} else if (id & 0x40000000u) {
		/* the same pseudo message as other tools write it: bit 30 without bit 31 */
		rc = irregular(
			p, id_line, id_col,
			"read as a message never on the bus (as VECTOR__INDEPENDENT_SIG_MSG)",
			(id & HL_DBC_EFF_FLAG) ?
				"expected a 29-bit extended ID with bit 31 set, found %llu" :
				"expected a standard ID 0..2047 (extended IDs have bit 31 set), found %llu",
			(unsigned long long)id);
		if (rc < 0)
			return rc;
		independent = true;
	} else if (id & HL_DBC_EFF_FLAG) {
		if (id & 0x20000000u)
			return fail_at(p, id_line, id_col,
				       "expected a 29-bit extended ID with bit 31 set, found %llu",
				       (unsigned long long)id);
	} else if (id > 0x7ff) {
		return fail_at(
			p, id_line, id_col,
			"expected a standard ID 0..2047 (extended IDs have bit 31 set), found %llu",
			(unsigned long long)id);
	}
	for (int i = 0; i < db->n_msgs; i++)
		if (db->msgs[i].can_id == id)
			return fail_at(p, id_line, id_col,
				       "message ID %llu already used by '%s' (line %d)",
				       (unsigned long long)id, db->msgs[i].name, db->msgs[i].line);
	name_line = p->tok.line;
	name_col = p->tok.col;
	rc = get_ident(p, "the message name", &name);
	if (rc < 0)
		return rc;
	for (int i = 0; i < db->n_msgs; i++)
		if (strcmp(db->msgs[i].name, name) == 0)
			return fail_at(p, name_line, name_col,
				       "message name '%s' already used (line %d)", name,
				       db->msgs[i].line);
	rc = expect_punct(p, ':', "':' after the message name");
	if (rc == 0)
		rc = get_uint(p, "the message size in bytes (0..64)", HL_DBC_MAX_PAYLOAD, &size);
	if (rc == 0)
		rc = get_ident(p, "the transmitting node (or Vector__XXX)", &tx);
	if (rc < 0)
		return rc;
	{
		int old = db->cap_msgs;

		if (hl_dbc_grow(&db->msgs, &db->cap_msgs, db->n_msgs, sizeof(*db->msgs)))
			return -ENOMEM;
		if (db->cap_msgs != old) {
			int *c = realloc(db->cap_sigs, sizeof(int) * db->cap_msgs);
			struct sig_where **w;

			if (!c)
				return -ENOMEM;
			db->cap_sigs = c;
			w = realloc(db->where, sizeof(*w) * db->cap_msgs);
			if (!w)
				return -ENOMEM;
			db->where = w;
		}
	}
	m = &db->msgs[db->n_msgs];
	*m = (struct hl_dbc_message){ 0 };
	db->cap_sigs[db->n_msgs] = 0;
	db->where[db->n_msgs] = NULL;
	m->name = name;
	m->can_id = (uint32_t)id;
	m->independent = independent;
	m->extended = (id & HL_DBC_EFF_FLAG) && !m->independent;
	m->id = (uint32_t)id & (m->extended ? 0x1fffffffu : 0x7fffffffu);
	m->size = (int)size;
	m->transmitter = strcmp(tx, "Vector__XXX") == 0 ? NULL : tx;
	m->line = id_line;
	p->cur_msg = db->n_msgs++;
	return 0;
}

static int parse_sg(struct parser *p, int sg_line)
{
	struct hl_dbc *db = p->db;
	struct hl_dbc_message *m;
	struct hl_dbc_signal *s, *sigs;
	struct sig_where *w;
	const char *name = NULL, *unit = NULL;
	const char **recv = NULL;
	int n_recv = 0, cap_recv = 0, rc, mi = p->cur_msg;
	int name_col = p->tok.col, where_line, where_col, start_line, start_col, len_line, len_col;
	uint64_t start = 0, len = 0, order = 0, mux_value = 0;
	bool is_mux = false, has_value = false, is_signed = false, unusable = false;
	double factor = 1, offset = 0, min = 0, max = 0;

	if (mi < 0)
		return fail_at(p, sg_line, 1,
			       "SG_ outside a message: expected a BO_ line before it");
	m = &db->msgs[mi];
	rc = get_ident(p, "the signal name", &name);
	if (rc < 0)
		return rc;
	if (find_signal_n(m, name, strlen(name)) >= 0)
		return fail_at(p, sg_line, name_col, "signal '%s' already defined in message '%s'",
			       name, m->name);
	where_line = p->tok.line;
	where_col = p->tok.col;
	if (p->tok.kind == TOK_IDENT) {
		const char *t = p->tok.p;
		size_t n = p->tok.n, i = 1;

		if (n == 1 && t[0] == 'M') {
			is_mux = true;
		} else if (n == 1 && t[0] == 'm') {
			/* a bare m, as some generators write it: no value to select the signal by */
			rc = irregular(
				p, where_line, where_col, "read as a signal always present",
				"expected ':' or a multiplex indicator (M, m<n>, m<n>M), found 'm'");
			if (rc < 0)
				return rc;
			where_col = name_col;
		} else if (t[0] == 'm' && n >= 2 && is_digit(t[1])) {
			has_value = true;
			while (i < n && is_digit(t[i]) && i < 20) {
				mux_value = mux_value * 10 + (t[i] - '0');
				i++;
			}
			if (i < n && t[i] == 'M' && i + 1 == n) {
				is_mux = true;
				i++;
			}
			if (i != n || n > 20)
				return expected(p, "':' or a multiplex indicator (M, m<n>, m<n>M)");
		} else {
			return expected(p, "':' or a multiplex indicator (M, m<n>, m<n>M)");
		}
		if ((rc = next(p)) < 0)
			return rc;
	} else {
		where_col = name_col;
	}
	rc = expect_punct(p, ':', "':' after the signal name");
	if (rc < 0)
		return rc;
	start_line = p->tok.line;
	start_col = p->tok.col;
	rc = get_uint(p, "the start bit (0..511)", 8 * HL_DBC_MAX_PAYLOAD - 1, &start);
	if (rc == 0)
		rc = expect_punct(p, '|', "'|' between start bit and length");
	len_line = p->tok.line;
	len_col = p->tok.col;
	if (rc == 0)
		rc = get_uint(p, "the length in bits (1..64)", 64, &len);
	if (rc == 0 && len == 0)
		return fail_at(p, len_line, len_col,
			       "expected the length in bits (1..64), found 0");
	if (rc == 0)
		rc = expect_punct(p, '@', "'@' before the byte order");
	if (rc == 0 && (p->tok.kind != TOK_NUMBER || p->tok.n != 1 ||
			(p->tok.p[0] != '0' && p->tok.p[0] != '1')))
		return expected(p, "the byte order 0 (Motorola) or 1 (Intel) after '@'");
	if (rc == 0) {
		order = p->tok.p[0] - '0';
		rc = next(p);
	}
	if (rc == 0 && !is_punct(p, '+') && !is_punct(p, '-'))
		return expected(p, "'+' (unsigned) or '-' (signed) after the byte order");
	if (rc == 0) {
		is_signed = is_punct(p, '-');
		rc = next(p);
	}
	if (rc == 0)
		rc = expect_punct(p, '(', "'(' before factor and offset");
	if (rc == 0 && (p->tok.kind == TOK_NUMBER || is_punct(p, '-') || is_punct(p, '+'))) {
		int fl = p->tok.line, fc = p->tok.col;

		rc = get_number(p, "the factor", &factor);
		if (rc == 0 && factor == 0)
			return fail_at(p, fl, fc, "expected a non-zero factor, found 0");
	} else if (rc == 0) {
		return expected(p, "the factor");
	}
	if (rc == 0)
		rc = expect_punct(p, ',', "',' between factor and offset");
	if (rc == 0)
		rc = get_number(p, "the offset", &offset);
	if (rc == 0)
		rc = expect_punct(p, ')', "')' after the offset");
	if (rc == 0)
		rc = expect_punct(p, '[', "'[' before minimum and maximum");
	if (rc == 0)
		rc = get_number(p, "the minimum", &min);
	if (rc == 0)
		rc = expect_punct(p, '|', "'|' between minimum and maximum");
	if (rc == 0)
		rc = get_number(p, "the maximum", &max);
	if (rc == 0)
		rc = expect_punct(p, ']', "']' after the maximum");
	if (rc == 0)
		rc = get_string(p, "the unit string", &unit);
	if (rc < 0)
		return rc;
	/* receivers: words and commas to the end of the line */
	while (p->tok.line == p->prev_line && (p->tok.kind == TOK_IDENT || is_punct(p, ','))) {
		if (p->tok.kind == TOK_IDENT) {
			const char *r = NULL;

			if (hl_dbc_grow(&recv, &cap_recv, n_recv, sizeof(*recv))) {
				free(recv);
				return -ENOMEM;
			}
			rc = get_ident(p, "a receiving node", &r);
			if (rc == 0 && strcmp(r, "Vector__XXX") != 0)
				recv[n_recv++] = r;
		} else {
			rc = next(p);
		}
		if (rc < 0) {
			free(recv);
			return rc;
		}
	}
	/* CANdb++ keeps unassigned signals in its never-sent 0-byte VECTOR__INDEPENDENT_SIG_MSG */
	if (!m->independent &&
	    hl_dbc_signal_end_byte((int)start, (int)len, (enum hl_dbc_byte_order)order) > m->size) {
		rc = irregular(
			p, start_line, start_col, "the signal is never decoded",
			"signal '%s' (start bit %d, %d bits, %s) does not fit the %d bytes of message '%s'",
			name, (int)start, (int)len, order ? "Intel" : "Motorola", m->size, m->name);
		if (rc < 0) {
			free(recv);
			return rc;
		}
		unusable = true;
	}
	sigs = (struct hl_dbc_signal *)m->signals;
	if (hl_dbc_grow(&sigs, &db->cap_sigs[mi], m->n_signals, sizeof(*sigs))) {
		free(recv);
		return -ENOMEM;
	}
	m->signals = sigs;
	w = realloc(db->where[mi], sizeof(*w) * db->cap_sigs[mi]);
	if (!w) {
		free(recv);
		return -ENOMEM;
	}
	db->where[mi] = w;
	w[m->n_signals] = (struct sig_where){ where_line, where_col, 0, 0, has_value };
	s = &sigs[m->n_signals];
	*s = (struct hl_dbc_signal){ 0 };
	s->name = name;
	s->index = m->n_signals;
	s->start_bit = (int)start;
	s->length = (int)len;
	s->order = (enum hl_dbc_byte_order)order;
	s->is_signed = is_signed;
	s->type = HL_DBC_INTEGER;
	s->factor = factor;
	s->offset = offset;
	s->min = min;
	s->max = max;
	s->unit = unit;
	s->n_receivers = n_recv;
	s->receivers = recv;
	s->is_multiplexor = is_mux;
	s->unusable = unusable;
	s->mux_parent = -1;
	s->mux_table = -1;
	s->line = sg_line;
	if (has_value) {
		struct hl_dbc_mux_range *r = malloc(sizeof(*r));

		if (!r)
			return -ENOMEM;
		r->lo = r->hi = mux_value;
		s->mux_ranges = r;
		s->n_mux_ranges = 1;
	}
	m->n_signals++;
	if (m->n_signals > HL_DBC_MAX_SIGNALS)
		return fail_at(p, sg_line, 1, "message '%s' has more than %d signals", m->name,
			       HL_DBC_MAX_SIGNALS);
	return 0;
}

static int parse_bo_tx_bu(struct parser *p)
{
	struct hl_dbc_message *m;
	const char **nodes = NULL;
	int mi, n = 0, cap = 0, rc;

	rc = get_msg_ref(p, &mi);
	if (rc != 0)
		return skipped(p, rc);
	rc = expect_punct(p, ':', "':' after the message ID");
	while (rc == 0 && !is_punct(p, ';')) {
		if (n > 0)
			rc = expect_punct(p, ',', "',' or ';' after a node");
		if (rc == 0 && hl_dbc_grow(&nodes, &cap, n, sizeof(*nodes)))
			rc = -ENOMEM;
		if (rc == 0)
			rc = get_ident(p, "a transmitting node", &nodes[n]);
		if (rc == 0)
			n++;
	}
	if (rc == 0)
		rc = next(p);
	if (rc < 0) {
		free(nodes);
		return rc;
	}
	m = &p->db->msgs[mi];
	free((void *)m->tx_nodes);
	m->tx_nodes = nodes;
	m->n_tx_nodes = n;
	return 0;
}

static int parse_cm(struct parser *p)
{
	struct hl_dbc *db = p->db;
	const char **target = NULL;
	const char *text = NULL, *w = NULL;
	size_t wn = 0;
	int rc = 0, mi, si;

	if (p->tok.kind == TOK_STRING) {
		target = &db->comment;
	} else if (is_word(p, "BU_")) {
		int line, col, ni;

		rc = next(p);
		line = p->tok.line;
		col = p->tok.col;
		if (rc == 0)
			rc = peek_ident(p, "a node name", &w, &wn);
		if (rc < 0)
			return rc;
		ni = find_node(db, w, wn);
		if (ni < 0) {
			rc = irregular(p, line, col, "statement skipped",
				       "expected a node listed in BU_, found '%.*s'",
				       (int)(wn > 40 ? 40 : wn), w);
			return skipped(p, rc < 0 ? rc : SKIP);
		}
		target = &db->nodes[ni].comment;
	} else if (is_word(p, "BO_")) {
		rc = next(p);
		if (rc == 0)
			rc = get_msg_ref(p, &mi);
		if (rc != 0)
			return skipped(p, rc);
		target = &db->msgs[mi].comment;
	} else if (is_word(p, "SG_")) {
		rc = next(p);
		if (rc == 0)
			rc = get_sig_ref(p, &mi, &si);
		if (rc != 0)
			return skipped(p, rc);
		target = &((struct hl_dbc_signal *)db->msgs[mi].signals)[si].comment;
	} else if (is_word(p, "EV_")) {
		rc = next(p);
		if (rc == 0)
			rc = peek_ident(p, "an environment variable name", &w, &wn);
	} else {
		return expected(p, "a comment string or BU_, BO_, SG_, EV_ after CM_");
	}
	if (rc == 0)
		rc = get_string(p, "the comment string", &text);
	if (rc == 0)
		rc = expect_punct(p, ';', "';' after the comment");
	if (rc == 0 && target)
		*target = text;
	return rc;
}

static int object_kind(struct parser *p, enum hl_dbc_object *ret)
{
	static const struct {
		const char *word;
		enum hl_dbc_object obj;
	} kinds[] = { { "BU_", HL_DBC_NODE },
		      { "BO_", HL_DBC_MESSAGE },
		      { "SG_", HL_DBC_SIGNAL },
		      { "EV_", HL_DBC_ENVVAR } };

	*ret = HL_DBC_NETWORK;
	for (size_t i = 0; i < sizeof(kinds) / sizeof(kinds[0]); i++)
		if (is_word(p, kinds[i].word)) {
			*ret = kinds[i].obj;
			return next(p);
		}
	return 0;
}

static const char *object_name(enum hl_dbc_object o)
{
	static const char *const names[] = { "the network", "nodes (BU_)", "messages (BO_)",
					     "signals (SG_)", "environment variables (EV_)" };
	return names[o];
}

static int find_def(const struct hl_dbc *db, const char *name)
{
	for (int i = 0; i < db->n_defs; i++)
		if (strcmp(db->defs[i].name, name) == 0)
			return i;
	return -1;
}

static int parse_ba_def(struct parser *p)
{
	struct hl_dbc *db = p->db;
	struct hl_dbc_attr_def d = { 0 };
	int line, col, rc;
	const char **labels = NULL;
	int cap = 0;

	rc = object_kind(p, &d.object);
	line = p->tok.line;
	col = p->tok.col;
	if (rc == 0)
		rc = get_string(p, "the attribute name string", &d.name);
	if (rc < 0)
		return rc;
	if (find_def(db, d.name) >= 0)
		return fail_at(p, line, col, "attribute '%s' already defined", d.name);
	if (is_word(p, "INT") || is_word(p, "HEX")) {
		int64_t lo = 0, hi = 0;

		d.type = is_word(p, "INT") ? HL_DBC_ATTR_INT : HL_DBC_ATTR_HEX;
		rc = next(p);
		if (rc == 0)
			rc = get_int(p, "the attribute's minimum", &lo);
		if (rc == 0)
			rc = get_int(p, "the attribute's maximum", &hi);
		d.min = (double)lo;
		d.max = (double)hi;
	} else if (is_word(p, "FLOAT")) {
		d.type = HL_DBC_ATTR_FLOAT;
		rc = next(p);
		if (rc == 0)
			rc = get_number(p, "the attribute's minimum", &d.min);
		if (rc == 0)
			rc = get_number(p, "the attribute's maximum", &d.max);
	} else if (is_word(p, "STRING")) {
		d.type = HL_DBC_ATTR_STRING;
		rc = next(p);
	} else if (is_word(p, "ENUM")) {
		d.type = HL_DBC_ATTR_ENUM;
		rc = next(p);
		while (rc == 0 && !is_punct(p, ';')) {
			if (d.n_labels > 0)
				rc = expect_punct(p, ',', "',' or ';' after an enum label");
			if (rc == 0 && hl_dbc_grow(&labels, &cap, d.n_labels, sizeof(*labels)))
				rc = -ENOMEM;
			if (rc == 0)
				rc = get_string(p, "an enum label string", &labels[d.n_labels]);
			if (rc == 0)
				d.n_labels++;
		}
		d.labels = labels;
	} else {
		return expected(p, "the attribute type INT, HEX, FLOAT, STRING or ENUM");
	}
	if (rc == 0)
		rc = expect_punct(p, ';', "';' after the attribute definition");
	if (rc == 0 && hl_dbc_grow(&db->defs, &db->cap_defs, db->n_defs, sizeof(*db->defs)))
		rc = -ENOMEM;
	if (rc < 0) {
		free(labels);
		return rc;
	}
	d.def.type = d.type;
	db->defs[db->n_defs++] = d;
	return 0;
}

/* An attribute value of the definition's type, checked against its range or labels. */
static int parse_attr_value(struct parser *p, const struct hl_dbc_attr_def *d,
			    struct hl_dbc_attr_value *v)
{
	int line = p->tok.line, col = p->tok.col, rc;

	*v = (struct hl_dbc_attr_value){ .type = d->type };
	switch (d->type) {
	case HL_DBC_ATTR_INT:
	case HL_DBC_ATTR_HEX:
		rc = get_int(p, "an integer value", &v->i);
		v->f = (double)v->i;
		break;
	case HL_DBC_ATTR_FLOAT:
		rc = get_number(p, "a number", &v->f);
		break;
	case HL_DBC_ATTR_STRING:
		return get_string(p, "a string value", &v->s);
	case HL_DBC_ATTR_ENUM:
		if (p->tok.kind == TOK_STRING) {
			rc = get_string(p, "an enum label", &v->s);
			if (rc < 0)
				return rc;
			for (int i = 0; i < d->n_labels; i++)
				if (strcmp(d->labels[i], v->s) == 0) {
					v->i = i;
					v->f = i;
					return 0;
				}
			return fail_at(p, line, col,
				       "expected one of the labels of '%s', found \"%s\"", d->name,
				       v->s);
		}
		rc = get_int(p, "an enum index or label", &v->i);
		if (rc < 0)
			return rc;
		if (v->i < 0 || v->i >= d->n_labels)
			return fail_at(p, line, col, "expected an index 0..%d of '%s', found %lld",
				       d->n_labels - 1, d->name, (long long)v->i);
		v->s = d->labels[v->i];
		v->f = (double)v->i;
		return 0;
	default:
		return -EINVAL;
	}
	if (rc == 0 && d->min < d->max && (v->f < d->min || v->f > d->max))
		return fail_at(p, line, col, "expected a value in [%g, %g] for '%s', found %g",
			       d->min, d->max, d->name, v->f);
	return rc;
}

static int get_def_ref(struct parser *p, int *ret)
{
	const char *name = NULL; /* set by get_string only when it returns 0 */
	int line = p->tok.line, col = p->tok.col, rc;

	rc = get_string(p, "the attribute name string", &name);
	if (rc < 0)
		return rc;
	*ret = find_def(p->db, name);
	if (*ret < 0)
		return fail_at(p, line, col,
			       "expected an attribute defined by BA_DEF_, found \"%s\"", name);
	return 0;
}

static int parse_ba_def_def(struct parser *p)
{
	struct hl_dbc_attr_def *d;
	int di, rc;

	rc = get_def_ref(p, &di);
	if (rc < 0)
		return rc;
	d = &p->db->defs[di];
	if (d->type == HL_DBC_ATTR_ENUM && p->tok.kind == TOK_STRING && p->tok.n == 0) {
		bool label = false;

		for (int i = 0; i < d->n_labels; i++)
			label |= d->labels[i][0] == '\0';
		if (!label) {
			/* CANdb++ writes "" for an enum whose default was never chosen */
			rc = irregular(p, p->tok.line, p->tok.col, "the attribute has no default",
				       "expected one of the labels of '%s', found \"\"", d->name);
			if (rc == 0)
				rc = next(p);
			if (rc == 0)
				rc = expect_punct(p, ';', "';' after the default value");
			return rc;
		}
	}
	rc = parse_attr_value(p, d, &d->def);
	if (rc == 0)
		rc = expect_punct(p, ';', "';' after the default value");
	if (rc == 0)
		d->has_default = true;
	return rc;
}

static int parse_ba(struct parser *p)
{
	struct hl_dbc *db = p->db;
	struct attr_assign a = { .index = -1, .signal = -1 };
	const struct hl_dbc_attr_def *d;
	int line, col, rc;

	rc = get_def_ref(p, &a.def);
	if (rc < 0)
		return rc;
	d = &db->defs[a.def];
	line = p->tok.line;
	col = p->tok.col;
	rc = object_kind(p, &a.object);
	if (rc < 0)
		return rc;
	if (a.object != d->object)
		return fail_at(p, line, col, "attribute '%s' is defined for %s, not for %s",
			       d->name, object_name(d->object), object_name(a.object));
	switch (a.object) {
	case HL_DBC_NODE: {
		const char *w = NULL;
		size_t wn = 0;

		line = p->tok.line;
		col = p->tok.col;
		rc = peek_ident(p, "a node name", &w, &wn);
		if (rc < 0)
			return rc;
		a.index = find_node(db, w, wn);
		if (a.index < 0) {
			rc = irregular(p, line, col, "statement skipped",
				       "expected a node listed in BU_, found '%.*s'",
				       (int)(wn > 40 ? 40 : wn), w);
			return skipped(p, rc < 0 ? rc : SKIP);
		}
		break;
	}
	case HL_DBC_MESSAGE:
		rc = get_msg_ref(p, &a.index);
		if (rc != 0)
			return skipped(p, rc);
		break;
	case HL_DBC_SIGNAL:
		rc = get_sig_ref(p, &a.index, &a.signal);
		if (rc != 0)
			return skipped(p, rc);
		break;
	case HL_DBC_ENVVAR: {
		const char *w = NULL;
		size_t wn = 0;

		rc = peek_ident(p, "an environment variable name", &w, &wn);
		break;
	}
	default:
		break;
	}
	if (rc == 0)
		rc = parse_attr_value(p, d, &a.value);
	if (rc == 0)
		rc = expect_punct(p, ';', "';' after the attribute value");
	if (rc < 0 || a.object == HL_DBC_ENVVAR)
		return rc;
	/* kept in file order: lookups search from the end, so a later BA_ wins */
	if (hl_dbc_grow(&db->assigns, &db->cap_assigns, db->n_assigns, sizeof(*db->assigns)))
		return -ENOMEM;
	db->assigns[db->n_assigns++] = a;
	return 0;
}

static int parse_val(struct parser *p)
{
	struct hl_dbc_signal *s;
	struct hl_dbc_value_desc *v;
	int mi, si, n, rc;

	if (p->tok.kind == TOK_IDENT) /* an environment variable's values: not kept */
		return skip_statement(p, p->tok.line);
	rc = get_sig_ref(p, &mi, &si);
	if (rc != 0)
		return skipped(p, rc);
	rc = parse_value_descs(p, &v, &n);
	if (rc < 0)
		return rc;
	s = &((struct hl_dbc_signal *)p->db->msgs[mi].signals)[si];
	free((void *)s->values);
	s->values = v;
	s->n_values = n;
	return 0;
}

static int parse_sig_valtype(struct parser *p)
{
	struct hl_dbc_signal *s;
	int mi, si, line, col, rc;
	uint64_t t;

	rc = get_sig_ref(p, &mi, &si);
	if (rc != 0)
		return skipped(p, rc);
	rc = expect_punct(p, ':', "':' after the signal name");
	line = p->tok.line;
	col = p->tok.col;
	if (rc == 0)
		rc = get_uint(p, "the value type 0 (integer), 1 (float) or 2 (double)", 2, &t);
	if (rc == 0)
		rc = expect_punct(p, ';', "';' after the value type");
	if (rc < 0)
		return rc;
	s = &((struct hl_dbc_signal *)p->db->msgs[mi].signals)[si];
	if ((t == 1 && s->length != 32) || (t == 2 && s->length != 64))
		return fail_at(p, line, col, "signal '%s' has %d bits; a %s needs %d", s->name,
			       s->length, t == 1 ? "float (1)" : "double (2)", t == 1 ? 32 : 64);
	s->type = t == 0 ? HL_DBC_INTEGER : t == 1 ? HL_DBC_FLOAT : HL_DBC_DOUBLE;
	return 0;
}

static int parse_sg_mul_val(struct parser *p, int kw_line, int kw_col)
{
	struct hl_dbc *db = p->db;
	struct hl_dbc_message *m;
	struct hl_dbc_signal *s;
	struct hl_dbc_mux_range *r = NULL;
	const char *w = NULL;
	size_t wn = 0;
	int mi, si, mux, line, col, n = 0, cap = 0, rc;

	rc = get_sig_ref(p, &mi, &si);
	if (rc != 0)
		return skipped(p, rc);
	m = &db->msgs[mi];
	s = &((struct hl_dbc_signal *)m->signals)[si];
	line = p->tok.line;
	col = p->tok.col;
	rc = peek_ident(p, "the multiplexor signal's name", &w, &wn);
	if (rc < 0)
		return rc;
	mux = find_signal_n(m, w, wn);
	if (mux < 0)
		return fail_at(p, line, col, "expected a signal of message '%s', found '%.*s'",
			       m->name, (int)(wn > 40 ? 40 : wn), w);
	if (!m->signals[mux].is_multiplexor || mux == si)
		return fail_at(p, line, col,
			       "expected a multiplexor (M or m<n>M) of message '%s', found '%s'",
			       m->name, m->signals[mux].name);
	if (db->where[mi][si].mul_line)
		return fail_at(p, kw_line, kw_col,
			       "SG_MUL_VAL_ for signal '%s' given twice (line %d)", s->name,
			       db->where[mi][si].mul_line);
	while (rc == 0 && !is_punct(p, ';')) {
		uint64_t lo = 0, hi = 0;
		int rl, rcol;

		if (n > 0)
			rc = expect_punct(p, ',', "',' or ';' after a range");
		rl = p->tok.line;
		rcol = p->tok.col;
		if (rc == 0)
			rc = get_uint(p, "a multiplexor value range lo-hi", UINT64_MAX, &lo);
		if (rc == 0)
			rc = expect_punct(p, '-', "'-' inside the range lo-hi");
		if (rc == 0)
			rc = get_uint(p, "the range's upper value", UINT64_MAX, &hi);
		if (rc == 0 && hi < lo)
			rc = fail_at(p, rl, rcol,
				     "expected a range lo-hi with lo <= hi, found %llu-%llu",
				     (unsigned long long)lo, (unsigned long long)hi);
		if (rc == 0 && hl_dbc_grow(&r, &cap, n, sizeof(*r)))
			rc = -ENOMEM;
		if (rc == 0)
			r[n++] = (struct hl_dbc_mux_range){ lo, hi };
	}
	if (rc == 0 && n == 0)
		rc = expected(p, "at least one multiplexor value range lo-hi");
	if (rc == 0)
		rc = next(p);
	if (rc < 0) {
		free(r);
		return rc;
	}
	free((void *)s->mux_ranges);
	s->mux_ranges = r;
	s->n_mux_ranges = n;
	s->mux_parent = mux;
	db->where[mi][si].mul_line = kw_line;
	db->where[mi][si].mul_column = kw_col;
	return 0;
}

static int parse_statement(struct parser *p)
{
	int line = p->tok.line, col = p->tok.col, rc;

	if (p->tok.kind != TOK_IDENT)
		return expected(p, "a section keyword (BO_, SG_, CM_, BA_, VAL_, ...)");
#define IS(w) is_word(p, w)
	if (IS("SG_")) {
		rc = next(p);
		if (rc == 0)
			rc = parse_sg(p, line);
		return rc;
	}
	if (IS("VERSION") || IS("NS_") || IS("BS_") || IS("BU_") || IS("VAL_TABLE_") || IS("BO_") ||
	    IS("BO_TX_BU_") || IS("CM_") || IS("BA_DEF_") || IS("BA_DEF_DEF_") || IS("BA_") ||
	    IS("VAL_") || IS("SIG_VALTYPE_") || IS("SG_MUL_VAL_")) {
		char kw[16];

		snprintf(kw, sizeof(kw), "%.*s", (int)p->tok.n, p->tok.p);
		p->cur_msg = -1;
		rc = next(p);
		if (rc < 0)
			return rc;
		if (!strcmp(kw, "VERSION"))
			return parse_version(p);
		if (!strcmp(kw, "NS_"))
			return parse_ns(p);
		if (!strcmp(kw, "BS_"))
			return parse_bs(p);
		if (!strcmp(kw, "BU_"))
			return parse_bu(p);
		if (!strcmp(kw, "VAL_TABLE_"))
			return parse_val_table(p);
		if (!strcmp(kw, "BO_"))
			return parse_bo(p);
		if (!strcmp(kw, "BO_TX_BU_"))
			return parse_bo_tx_bu(p);
		if (!strcmp(kw, "CM_"))
			return parse_cm(p);
		if (!strcmp(kw, "BA_DEF_"))
			return parse_ba_def(p);
		if (!strcmp(kw, "BA_DEF_DEF_"))
			return parse_ba_def_def(p);
		if (!strcmp(kw, "BA_"))
			return parse_ba(p);
		if (!strcmp(kw, "VAL_"))
			return parse_val(p);
		if (!strcmp(kw, "SIG_VALTYPE_"))
			return parse_sig_valtype(p);
		return parse_sg_mul_val(p, line, col);
	}
#undef IS
	{
		char kw[48];

		snprintf(kw, sizeof(kw), "%.*s", (int)(p->tok.n > 40 ? 40 : p->tok.n), p->tok.p);
		p->cur_msg = -1;
		rc = warn(p, line, col, "skipped unknown section '%s'", kw);
		if (rc == 0)
			rc = next(p);
		if (rc == 0)
			rc = skip_statement(p, line);
		return rc;
	}
}

/* A name set by one of CANdb++'s long-name attributes (STRING, set by BA_), or NULL. */
static const char *long_name(int rc, const struct hl_dbc_attr_value *v)
{
	return rc == 0 && v->type == HL_DBC_ATTR_STRING && v->s && v->s[0] ? v->s : NULL;
}

static void rename_node(const char **ref, const char *old, const char *name)
{
	if (*ref && strcmp(*ref, old) == 0)
		*ref = name;
}

/*
 * CANdb++ cuts names to 32 characters in the sections and keeps the whole name in the
 * attributes SystemNodeLongSymbol, SystemMessageLongSymbol and SystemSignalLongSymbol: the long
 * name replaces the cut one once every reference has been resolved.
 */
static void apply_long_names(struct hl_dbc *db)
{
	struct hl_dbc_attr_value v;
	const char *name;

	for (int i = 0; i < db->n_nodes; i++) {
		const char *old = db->nodes[i].name;

		name = long_name(hl_dbc_node_attr(db, old, "SystemNodeLongSymbol", &v), &v);
		if (!name)
			continue;
		for (int j = 0; j < db->n_msgs; j++) {
			struct hl_dbc_message *m = &db->msgs[j];

			rename_node(&m->transmitter, old, name);
			for (int k = 0; k < m->n_tx_nodes; k++)
				rename_node((const char **)&m->tx_nodes[k], old, name);
			for (int k = 0; k < m->n_signals; k++) {
				const struct hl_dbc_signal *s = &m->signals[k];

				for (int r = 0; r < s->n_receivers; r++)
					rename_node((const char **)&s->receivers[r], old, name);
			}
		}
		db->nodes[i].name = name;
	}
	for (int j = 0; j < db->n_msgs; j++) {
		struct hl_dbc_message *m = &db->msgs[j];

		for (int k = 0; k < m->n_signals; k++) {
			struct hl_dbc_signal *s = (struct hl_dbc_signal *)&m->signals[k];

			name = long_name(hl_dbc_signal_attr(db, m, s, "SystemSignalLongSymbol", &v),
					 &v);
			if (name)
				s->name = name;
		}
		name = long_name(hl_dbc_message_attr(db, m, "SystemMessageLongSymbol", &v), &v);
		if (name)
			m->name = name;
	}
}

int hl_dbc_parse_flags(const char *text, size_t len, unsigned flags, struct hl_dbc **ret,
		       struct hl_dbc_error *ret_err)
{
	struct hl_dbc_error dummy;
	struct parser p = { .s = text, .end = text + len, .line = 1, .col = 1 };
	int rc;

	p.strict = flags & HL_DBC_STRICT;
	p.err = ret_err ? ret_err : &dummy;
	*p.err = (struct hl_dbc_error){ 0 };
	p.cur_msg = -1;
	p.last_msg = -1;
	p.db = calloc(1, sizeof(*p.db));
	if (!p.db) {
		snprintf(p.err->msg, sizeof(p.err->msg), "out of memory");
		return -ENOMEM;
	}
	p.db->version = "";
	/* a UTF-8 byte order mark, as some Windows tools write it */
	if (len >= 3 && memcmp(text, "\xef\xbb\xbf", 3) == 0)
		p.s += 3;
	rc = next(&p);
	while (rc == 0 && p.tok.kind != TOK_EOF)
		rc = parse_statement(&p);
	if (rc == 0) {
		apply_long_names(p.db);
		rc = hl_dbc_finish(p.db, p.err);
	}
	if (rc < 0) {
		if (rc == -ENOMEM)
			*p.err = (struct hl_dbc_error){ 0, 0, "out of memory" };
		hl_dbc_free(p.db);
		return rc;
	}
	*ret = p.db;
	return 0;
}

int hl_dbc_parse(const char *text, size_t len, struct hl_dbc **ret, struct hl_dbc_error *ret_err)
{
	return hl_dbc_parse_flags(text, len, 0, ret, ret_err);
}

int hl_dbc_parse_file(const char *path, struct hl_dbc **ret, struct hl_dbc_error *ret_err)
{
	return hl_dbc_parse_file_flags(path, 0, ret, ret_err);
}

int hl_dbc_parse_file_flags(const char *path, unsigned flags, struct hl_dbc **ret,
			    struct hl_dbc_error *ret_err)
{
	struct hl_dbc_error dummy;
	struct hl_dbc_error *err = ret_err ? ret_err : &dummy;
	struct stat st;
	char *text;
	size_t got = 0;
	int fd, rc;

	*err = (struct hl_dbc_error){ 0 };
	fd = open(path, O_RDONLY | O_CLOEXEC);
	if (fd < 0) {
		rc = -errno;
		snprintf(err->msg, sizeof(err->msg), "cannot open: %s", strerror(-rc));
		return rc;
	}
	if (fstat(fd, &st) < 0 || !S_ISREG(st.st_mode) || st.st_size > MAX_FILE_BYTES) {
		close(fd);
		snprintf(err->msg, sizeof(err->msg), "not a regular file of at most %d MiB",
			 MAX_FILE_BYTES >> 20);
		return -EINVAL;
	}
	text = malloc(st.st_size + 1);
	if (!text) {
		close(fd);
		snprintf(err->msg, sizeof(err->msg), "out of memory");
		return -ENOMEM;
	}
	while (got < (size_t)st.st_size) {
		ssize_t n = read(fd, text + got, st.st_size - got);

		if (n < 0 && errno == EINTR)
			continue;
		if (n <= 0) {
			rc = n < 0 ? -errno : -EIO;
			snprintf(err->msg, sizeof(err->msg), "cannot read: %s", strerror(-rc));
			free(text);
			close(fd);
			return rc;
		}
		got += n;
	}
	close(fd);
	text[got] = '\0';
	rc = hl_dbc_parse_flags(text, got, flags, ret, err);
	free(text);
	return rc;
}
