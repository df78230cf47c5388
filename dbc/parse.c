/* SPDX-License-Identifier: MIT */
/*
 * The DBC reader: the top-level loop, the entry points, and one function per section of the
 * network's structure (VERSION, NS_, BS_, BU_, BO_, SG_, BO_TX_BU_, CM_). The lexer and the
 * typed token readers are in lexer.c, the attribute and value sections in attributes.c.
 * Statements ending in ';' are read to the ';'; BO_, SG_, BU_ and BS_ end with their line, as
 * every tool writes them.
 */
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "dbc/attributes.h"
#include "dbc/lexer.h"

#define MAX_FILE_BYTES (64 << 20)

static int warn(struct parser *p, int line, int col, const char *fmt, const char *arg)
{
	char msg[160];

	snprintf(msg, sizeof(msg), fmt, arg);
	return dbc_add_warning(p, line, col, msg);
}

/* --- sections --- */

static int parse_version(struct parser *p)
{
	return dbc_get_string(p, "the version string after VERSION", &p->db->version);
}

static int parse_ns(struct parser *p)
{
	int rc = dbc_expect_punct(p, ':', "':' after NS_");

	/* the symbol list: indented words */
	while (rc == 0 && p->tok.kind == TOK_IDENT && p->tok.col > 1)
		rc = dbc_next(p);
	return rc;
}

static int parse_bs(struct parser *p)
{
	int line = p->tok.line, rc;

	rc = dbc_expect_punct(p, ':', "':' after BS_");
	/* optional "baudrate : BTR1 , BTR2", obsolete: read to the end of the line */
	while (rc == 0 && p->tok.kind != TOK_EOF && p->tok.line == line)
		rc = dbc_next(p);
	return rc;
}

/* A word that starts a section: every DBC keyword ends in '_' but VERSION and FILTER. */
static bool is_section_word(const struct parser *p)
{
	return p->tok.kind == TOK_IDENT && (p->tok.p[p->tok.n - 1] == '_' ||
					    dbc_is_word(p, "VERSION") || dbc_is_word(p, "FILTER"));
}

static int parse_bu(struct parser *p)
{
	struct hl_dbc *db = p->db;
	int line = p->tok.line, rc = dbc_expect_punct(p, ':', "':' after BU_");
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
				rc = dbc_add_warning(p, p->tok.line, p->tok.col, msg);
				if (rc < 0)
					return rc;
				continued = true;
			}
		}
		if (dbc_find_node(db, p->tok.p, p->tok.n) >= 0) {
			rc = dbc_irregular(p, p->tok.line, p->tok.col, "read once",
					   "node '%.*s' listed twice",
					   (int)(p->tok.n > 40 ? 40 : p->tok.n), p->tok.p);
			if (rc == 0)
				rc = dbc_next(p);
			continue;
		}
		if (hl_dbc_grow(&db->nodes, &db->cap_nodes, db->n_nodes, sizeof(*db->nodes)))
			return -ENOMEM;
		db->nodes[db->n_nodes] = (struct node){ 0 };
		rc = dbc_get_ident(p, "a node name", &db->nodes[db->n_nodes].name);
		db->n_nodes++;
	}
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

	rc = dbc_get_uint(p, "a message ID", UINT32_MAX, &id);
	if (rc < 0)
		return rc;
	if (id == 0xC0000000u) {
		/* VECTOR__INDEPENDENT_SIG_MSG: CANdb++'s holder of unassigned signals */
		independent = true;
	} else if (id & 0x40000000u) {
		/* the same pseudo message as other tools write it: bit 30 without bit 31 */
		rc = dbc_irregular(
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
			return dbc_fail_at(
				p, id_line, id_col,
				"expected a 29-bit extended ID with bit 31 set, found %llu",
				(unsigned long long)id);
	} else if (id > 0x7ff) {
		return dbc_fail_at(
			p, id_line, id_col,
			"expected a standard ID 0..2047 (extended IDs have bit 31 set), found %llu",
			(unsigned long long)id);
	}
	for (int i = 0; i < db->n_msgs; i++)
		if (db->msgs[i].can_id == id)
			return dbc_fail_at(p, id_line, id_col,
					   "message ID %llu already used by '%s' (line %d)",
					   (unsigned long long)id, db->msgs[i].name,
					   db->msgs[i].line);
	name_line = p->tok.line;
	name_col = p->tok.col;
	rc = dbc_get_ident(p, "the message name", &name);
	if (rc < 0)
		return rc;
	for (int i = 0; i < db->n_msgs; i++)
		if (strcmp(db->msgs[i].name, name) == 0)
			return dbc_fail_at(p, name_line, name_col,
					   "message name '%s' already used (line %d)", name,
					   db->msgs[i].line);
	rc = dbc_expect_punct(p, ':', "':' after the message name");
	if (rc == 0)
		rc = dbc_get_uint(p, "the message size in bytes (0..64)", HL_DBC_MAX_PAYLOAD,
				  &size);
	if (rc == 0)
		rc = dbc_get_ident(p, "the transmitting node (or Vector__XXX)", &tx);
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
		return dbc_fail_at(p, sg_line, 1,
				   "SG_ outside a message: expected a BO_ line before it");
	m = &db->msgs[mi];
	rc = dbc_get_ident(p, "the signal name", &name);
	if (rc < 0)
		return rc;
	if (dbc_find_signal_n(m, name, strlen(name)) >= 0)
		return dbc_fail_at(p, sg_line, name_col,
				   "signal '%s' already defined in message '%s'", name, m->name);
	where_line = p->tok.line;
	where_col = p->tok.col;
	if (p->tok.kind == TOK_IDENT) {
		const char *t = p->tok.p;
		size_t n = p->tok.n, i = 1;

		if (n == 1 && t[0] == 'M') {
			is_mux = true;
		} else if (n == 1 && t[0] == 'm') {
			/* a bare m, as some generators write it: no value to select the signal by */
			rc = dbc_irregular(
				p, where_line, where_col, "read as a signal always present",
				"expected ':' or a multiplex indicator (M, m<n>, m<n>M), found 'm'");
			if (rc < 0)
				return rc;
			where_col = name_col;
		} else if (t[0] == 'm' && n >= 2 && dbc_is_digit(t[1])) {
			has_value = true;
			while (i < n && dbc_is_digit(t[i]) && i < 20) {
				mux_value = mux_value * 10 + (t[i] - '0');
				i++;
			}
			if (i < n && t[i] == 'M' && i + 1 == n) {
				is_mux = true;
				i++;
			}
			if (i != n || n > 20)
				return dbc_expected(
					p, "':' or a multiplex indicator (M, m<n>, m<n>M)");
		} else {
			return dbc_expected(p, "':' or a multiplex indicator (M, m<n>, m<n>M)");
		}
		if ((rc = dbc_next(p)) < 0)
			return rc;
	} else {
		where_col = name_col;
	}
	rc = dbc_expect_punct(p, ':', "':' after the signal name");
	if (rc < 0)
		return rc;
	start_line = p->tok.line;
	start_col = p->tok.col;
	rc = dbc_get_uint(p, "the start bit (0..511)", 8 * HL_DBC_MAX_PAYLOAD - 1, &start);
	if (rc == 0)
		rc = dbc_expect_punct(p, '|', "'|' between start bit and length");
	len_line = p->tok.line;
	len_col = p->tok.col;
	if (rc == 0)
		rc = dbc_get_uint(p, "the length in bits (1..64)", 64, &len);
	if (rc == 0 && len == 0)
		return dbc_fail_at(p, len_line, len_col,
				   "expected the length in bits (1..64), found 0");
	if (rc == 0)
		rc = dbc_expect_punct(p, '@', "'@' before the byte order");
	if (rc == 0 && (p->tok.kind != TOK_NUMBER || p->tok.n != 1 ||
			(p->tok.p[0] != '0' && p->tok.p[0] != '1')))
		return dbc_expected(p, "the byte order 0 (Motorola) or 1 (Intel) after '@'");
	if (rc == 0) {
		order = p->tok.p[0] - '0';
		rc = dbc_next(p);
	}
	if (rc == 0 && !dbc_is_punct(p, '+') && !dbc_is_punct(p, '-'))
		return dbc_expected(p, "'+' (unsigned) or '-' (signed) after the byte order");
	if (rc == 0) {
		is_signed = dbc_is_punct(p, '-');
		rc = dbc_next(p);
	}
	if (rc == 0)
		rc = dbc_expect_punct(p, '(', "'(' before factor and offset");
	if (rc == 0 &&
	    (p->tok.kind == TOK_NUMBER || dbc_is_punct(p, '-') || dbc_is_punct(p, '+'))) {
		int fl = p->tok.line, fc = p->tok.col;

		rc = dbc_get_number(p, "the factor", &factor);
		if (rc == 0 && factor == 0)
			return dbc_fail_at(p, fl, fc, "expected a non-zero factor, found 0");
	} else if (rc == 0) {
		return dbc_expected(p, "the factor");
	}
	if (rc == 0)
		rc = dbc_expect_punct(p, ',', "',' between factor and offset");
	if (rc == 0)
		rc = dbc_get_number(p, "the offset", &offset);
	if (rc == 0)
		rc = dbc_expect_punct(p, ')', "')' after the offset");
	if (rc == 0)
		rc = dbc_expect_punct(p, '[', "'[' before minimum and maximum");
	if (rc == 0)
		rc = dbc_get_number(p, "the minimum", &min);
	if (rc == 0)
		rc = dbc_expect_punct(p, '|', "'|' between minimum and maximum");
	if (rc == 0)
		rc = dbc_get_number(p, "the maximum", &max);
	if (rc == 0)
		rc = dbc_expect_punct(p, ']', "']' after the maximum");
	if (rc == 0)
		rc = dbc_get_string(p, "the unit string", &unit);
	if (rc < 0)
		return rc;
	/* receivers: words and commas to the end of the line */
	while (p->tok.line == p->prev_line && (p->tok.kind == TOK_IDENT || dbc_is_punct(p, ','))) {
		if (p->tok.kind == TOK_IDENT) {
			const char *r = NULL;

			if (hl_dbc_grow(&recv, &cap_recv, n_recv, sizeof(*recv))) {
				free(recv);
				return -ENOMEM;
			}
			rc = dbc_get_ident(p, "a receiving node", &r);
			if (rc == 0 && strcmp(r, "Vector__XXX") != 0)
				recv[n_recv++] = r;
		} else {
			rc = dbc_next(p);
		}
		if (rc < 0) {
			free(recv);
			return rc;
		}
	}
	/* CANdb++ keeps unassigned signals in its never-sent 0-byte VECTOR__INDEPENDENT_SIG_MSG */
	if (!m->independent &&
	    hl_dbc_signal_end_byte((int)start, (int)len, (enum hl_dbc_byte_order)order) > m->size) {
		rc = dbc_irregular(
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
		return dbc_fail_at(p, sg_line, 1, "message '%s' has more than %d signals", m->name,
				   HL_DBC_MAX_SIGNALS);
	return 0;
}

static int parse_bo_tx_bu(struct parser *p)
{
	struct hl_dbc_message *m;
	const char **nodes = NULL;
	int mi, n = 0, cap = 0, rc;

	rc = dbc_get_msg_ref(p, &mi);
	if (rc != 0)
		return dbc_skipped(p, rc);
	rc = dbc_expect_punct(p, ':', "':' after the message ID");
	while (rc == 0 && !dbc_is_punct(p, ';')) {
		if (n > 0)
			rc = dbc_expect_punct(p, ',', "',' or ';' after a node");
		if (rc == 0 && hl_dbc_grow(&nodes, &cap, n, sizeof(*nodes)))
			rc = -ENOMEM;
		if (rc == 0)
			rc = dbc_get_ident(p, "a transmitting node", &nodes[n]);
		if (rc == 0)
			n++;
	}
	if (rc == 0)
		rc = dbc_next(p);
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
	} else if (dbc_is_word(p, "BU_")) {
		int line, col, ni;

		rc = dbc_next(p);
		line = p->tok.line;
		col = p->tok.col;
		if (rc == 0)
			rc = dbc_peek_ident(p, "a node name", &w, &wn);
		if (rc < 0)
			return rc;
		ni = dbc_find_node(db, w, wn);
		if (ni < 0) {
			rc = dbc_irregular(p, line, col, "statement skipped",
					   "expected a node listed in BU_, found '%.*s'",
					   (int)(wn > 40 ? 40 : wn), w);
			return dbc_skipped(p, rc < 0 ? rc : SKIP);
		}
		target = &db->nodes[ni].comment;
	} else if (dbc_is_word(p, "BO_")) {
		rc = dbc_next(p);
		if (rc == 0)
			rc = dbc_get_msg_ref(p, &mi);
		if (rc != 0)
			return dbc_skipped(p, rc);
		target = &db->msgs[mi].comment;
	} else if (dbc_is_word(p, "SG_")) {
		rc = dbc_next(p);
		if (rc == 0)
			rc = dbc_get_sig_ref(p, &mi, &si);
		if (rc != 0)
			return dbc_skipped(p, rc);
		target = &((struct hl_dbc_signal *)db->msgs[mi].signals)[si].comment;
	} else if (dbc_is_word(p, "EV_")) {
		rc = dbc_next(p);
		if (rc == 0)
			rc = dbc_peek_ident(p, "an environment variable name", &w, &wn);
	} else {
		return dbc_expected(p, "a comment string or BU_, BO_, SG_, EV_ after CM_");
	}
	if (rc == 0)
		rc = dbc_get_string(p, "the comment string", &text);
	if (rc == 0)
		rc = dbc_expect_punct(p, ';', "';' after the comment");
	if (rc == 0 && target)
		*target = text;
	return rc;
}

static int parse_statement(struct parser *p)
{
	int line = p->tok.line, col = p->tok.col, rc;

	if (p->tok.kind != TOK_IDENT)
		return dbc_expected(p, "a section keyword (BO_, SG_, CM_, BA_, VAL_, ...)");
#define IS(w) dbc_is_word(p, w)
	if (IS("SG_")) {
		rc = dbc_next(p);
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
		rc = dbc_next(p);
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
			return dbc_parse_val_table(p);
		if (!strcmp(kw, "BO_"))
			return parse_bo(p);
		if (!strcmp(kw, "BO_TX_BU_"))
			return parse_bo_tx_bu(p);
		if (!strcmp(kw, "CM_"))
			return parse_cm(p);
		if (!strcmp(kw, "BA_DEF_"))
			return dbc_parse_ba_def(p);
		if (!strcmp(kw, "BA_DEF_DEF_"))
			return dbc_parse_ba_def_def(p);
		if (!strcmp(kw, "BA_"))
			return dbc_parse_ba(p);
		if (!strcmp(kw, "VAL_"))
			return dbc_parse_val(p);
		if (!strcmp(kw, "SIG_VALTYPE_"))
			return dbc_parse_sig_valtype(p);
		return dbc_parse_sg_mul_val(p, line, col);
	}
#undef IS
	{
		char kw[48];

		snprintf(kw, sizeof(kw), "%.*s", (int)(p->tok.n > 40 ? 40 : p->tok.n), p->tok.p);
		p->cur_msg = -1;
		rc = warn(p, line, col, "skipped unknown section '%s'", kw);
		if (rc == 0)
			rc = dbc_next(p);
		if (rc == 0)
			rc = dbc_skip_statement(p, line);
		return rc;
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
	rc = dbc_next(&p);
	while (rc == 0 && p.tok.kind != TOK_EOF)
		rc = parse_statement(&p);
	if (rc == 0) {
		dbc_apply_long_names(p.db);
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
