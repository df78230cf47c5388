/* SPDX-License-Identifier: MIT */
/*
 * The DBC sections that attach attributes and values to what BU_, BO_ and SG_ defined:
 * VAL_TABLE_ and VAL_ (value descriptions), BA_DEF_, BA_DEF_DEF_ and BA_ (attributes),
 * SIG_VALTYPE_ and SG_MUL_VAL_, and CANdb++'s long names applied from the attributes once the
 * file is read. Apart from parse.c so that each file stays a readable size; they read tokens
 * through dbc/lexer.h like every other section.
 */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "dbc/attributes.h"
#include "dbc/lexer.h"

/* value "description" pairs up to ';' */
static int parse_value_descs(struct parser *p, struct hl_dbc_value_desc **ret, int *ret_n)
{
	struct hl_dbc_value_desc *v = NULL;
	int n = 0, cap = 0, rc = 0;

	while (!dbc_is_punct(p, ';')) {
		if (hl_dbc_grow(&v, &cap, n, sizeof(*v))) {
			rc = -ENOMEM;
			break;
		}
		rc = dbc_get_int(p, "a value or ';'", &v[n].value);
		if (rc == 0)
			rc = dbc_get_string(p, "the value's description string", &v[n].desc);
		if (rc < 0)
			break;
		n++;
	}
	if (rc == 0)
		rc = dbc_next(p);
	if (rc < 0) {
		free(v);
		return rc;
	}
	*ret = v;
	*ret_n = n;
	return 0;
}

int dbc_parse_val_table(struct parser *p)
{
	struct hl_dbc *db = p->db;
	struct value_table *t;
	int rc;

	if (hl_dbc_grow(&db->tables, &db->cap_tables, db->n_tables, sizeof(*db->tables)))
		return -ENOMEM;
	t = &db->tables[db->n_tables];
	*t = (struct value_table){ 0 };
	rc = dbc_get_ident(p, "the value table's name", &t->name);
	if (rc == 0)
		rc = parse_value_descs(p, &t->entries, &t->n);
	if (rc == 0)
		db->n_tables++;
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
		if (dbc_is_word(p, kinds[i].word)) {
			*ret = kinds[i].obj;
			return dbc_next(p);
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

int dbc_parse_ba_def(struct parser *p)
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
		rc = dbc_get_string(p, "the attribute name string", &d.name);
	if (rc < 0)
		return rc;
	if (find_def(db, d.name) >= 0)
		return dbc_fail_at(p, line, col, "attribute '%s' already defined", d.name);
	if (dbc_is_word(p, "INT") || dbc_is_word(p, "HEX")) {
		int64_t lo = 0, hi = 0;

		d.type = dbc_is_word(p, "INT") ? HL_DBC_ATTR_INT : HL_DBC_ATTR_HEX;
		rc = dbc_next(p);
		if (rc == 0)
			rc = dbc_get_int(p, "the attribute's minimum", &lo);
		if (rc == 0)
			rc = dbc_get_int(p, "the attribute's maximum", &hi);
		d.min = (double)lo;
		d.max = (double)hi;
	} else if (dbc_is_word(p, "FLOAT")) {
		d.type = HL_DBC_ATTR_FLOAT;
		rc = dbc_next(p);
		if (rc == 0)
			rc = dbc_get_number(p, "the attribute's minimum", &d.min);
		if (rc == 0)
			rc = dbc_get_number(p, "the attribute's maximum", &d.max);
	} else if (dbc_is_word(p, "STRING")) {
		d.type = HL_DBC_ATTR_STRING;
		rc = dbc_next(p);
	} else if (dbc_is_word(p, "ENUM")) {
		d.type = HL_DBC_ATTR_ENUM;
		rc = dbc_next(p);
		while (rc == 0 && !dbc_is_punct(p, ';')) {
			if (d.n_labels > 0)
				rc = dbc_expect_punct(p, ',', "',' or ';' after an enum label");
			if (rc == 0 && hl_dbc_grow(&labels, &cap, d.n_labels, sizeof(*labels)))
				rc = -ENOMEM;
			if (rc == 0)
				rc = dbc_get_string(p, "an enum label string", &labels[d.n_labels]);
			if (rc == 0)
				d.n_labels++;
		}
		d.labels = labels;
	} else {
		return dbc_expected(p, "the attribute type INT, HEX, FLOAT, STRING or ENUM");
	}
	if (rc == 0)
		rc = dbc_expect_punct(p, ';', "';' after the attribute definition");
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
		rc = dbc_get_int(p, "an integer value", &v->i);
		v->f = (double)v->i;
		break;
	case HL_DBC_ATTR_FLOAT:
		rc = dbc_get_number(p, "a number", &v->f);
		break;
	case HL_DBC_ATTR_STRING:
		return dbc_get_string(p, "a string value", &v->s);
	case HL_DBC_ATTR_ENUM:
		if (p->tok.kind == TOK_STRING) {
			rc = dbc_get_string(p, "an enum label", &v->s);
			if (rc < 0)
				return rc;
			for (int i = 0; i < d->n_labels; i++)
				if (strcmp(d->labels[i], v->s) == 0) {
					v->i = i;
					v->f = i;
					return 0;
				}
			return dbc_fail_at(p, line, col,
					   "expected one of the labels of '%s', found \"%s\"",
					   d->name, v->s);
		}
		rc = dbc_get_int(p, "an enum index or label", &v->i);
		if (rc < 0)
			return rc;
		if (v->i < 0 || v->i >= d->n_labels)
			return dbc_fail_at(p, line, col,
					   "expected an index 0..%d of '%s', found %lld",
					   d->n_labels - 1, d->name, (long long)v->i);
		v->s = d->labels[v->i];
		v->f = (double)v->i;
		return 0;
	default:
		return -EINVAL;
	}
	if (rc == 0 && d->min < d->max && (v->f < d->min || v->f > d->max))
		return dbc_fail_at(p, line, col, "expected a value in [%g, %g] for '%s', found %g",
				   d->min, d->max, d->name, v->f);
	return rc;
}

static int get_def_ref(struct parser *p, int *ret)
{
	const char *name = NULL; /* set by get_string only when it returns 0 */
	int line = p->tok.line, col = p->tok.col, rc;

	rc = dbc_get_string(p, "the attribute name string", &name);
	if (rc < 0)
		return rc;
	*ret = find_def(p->db, name);
	if (*ret < 0)
		return dbc_fail_at(p, line, col,
				   "expected an attribute defined by BA_DEF_, found \"%s\"", name);
	return 0;
}

int dbc_parse_ba_def_def(struct parser *p)
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
			rc = dbc_irregular(p, p->tok.line, p->tok.col,
					   "the attribute has no default",
					   "expected one of the labels of '%s', found \"\"",
					   d->name);
			if (rc == 0)
				rc = dbc_next(p);
			if (rc == 0)
				rc = dbc_expect_punct(p, ';', "';' after the default value");
			return rc;
		}
	}
	rc = parse_attr_value(p, d, &d->def);
	if (rc == 0)
		rc = dbc_expect_punct(p, ';', "';' after the default value");
	if (rc == 0)
		d->has_default = true;
	return rc;
}

int dbc_parse_ba(struct parser *p)
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
		return dbc_fail_at(p, line, col, "attribute '%s' is defined for %s, not for %s",
				   d->name, object_name(d->object), object_name(a.object));
	switch (a.object) {
	case HL_DBC_NODE: {
		const char *w = NULL;
		size_t wn = 0;

		line = p->tok.line;
		col = p->tok.col;
		rc = dbc_peek_ident(p, "a node name", &w, &wn);
		if (rc < 0)
			return rc;
		a.index = dbc_find_node(db, w, wn);
		if (a.index < 0) {
			rc = dbc_irregular(p, line, col, "statement skipped",
					   "expected a node listed in BU_, found '%.*s'",
					   (int)(wn > 40 ? 40 : wn), w);
			return dbc_skipped(p, rc < 0 ? rc : SKIP);
		}
		break;
	}
	case HL_DBC_MESSAGE:
		rc = dbc_get_msg_ref(p, &a.index);
		if (rc != 0)
			return dbc_skipped(p, rc);
		break;
	case HL_DBC_SIGNAL:
		rc = dbc_get_sig_ref(p, &a.index, &a.signal);
		if (rc != 0)
			return dbc_skipped(p, rc);
		break;
	case HL_DBC_ENVVAR: {
		const char *w = NULL;
		size_t wn = 0;

		rc = dbc_peek_ident(p, "an environment variable name", &w, &wn);
		break;
	}
	default:
		break;
	}
	if (rc == 0)
		rc = parse_attr_value(p, d, &a.value);
	if (rc == 0)
		rc = dbc_expect_punct(p, ';', "';' after the attribute value");
	if (rc < 0 || a.object == HL_DBC_ENVVAR)
		return rc;
	/* kept in file order: lookups search from the end, so a later BA_ wins */
	if (hl_dbc_grow(&db->assigns, &db->cap_assigns, db->n_assigns, sizeof(*db->assigns)))
		return -ENOMEM;
	db->assigns[db->n_assigns++] = a;
	return 0;
}

int dbc_parse_val(struct parser *p)
{
	struct hl_dbc_signal *s;
	struct hl_dbc_value_desc *v;
	int mi, si, n, rc;

	if (p->tok.kind == TOK_IDENT) /* an environment variable's values: not kept */
		return dbc_skip_statement(p, p->tok.line);
	rc = dbc_get_sig_ref(p, &mi, &si);
	if (rc != 0)
		return dbc_skipped(p, rc);
	rc = parse_value_descs(p, &v, &n);
	if (rc < 0)
		return rc;
	s = &((struct hl_dbc_signal *)p->db->msgs[mi].signals)[si];
	free((void *)s->values);
	s->values = v;
	s->n_values = n;
	return 0;
}

int dbc_parse_sig_valtype(struct parser *p)
{
	struct hl_dbc_signal *s;
	int mi, si, line, col, rc;
	uint64_t t;

	rc = dbc_get_sig_ref(p, &mi, &si);
	if (rc != 0)
		return dbc_skipped(p, rc);
	rc = dbc_expect_punct(p, ':', "':' after the signal name");
	line = p->tok.line;
	col = p->tok.col;
	if (rc == 0)
		rc = dbc_get_uint(p, "the value type 0 (integer), 1 (float) or 2 (double)", 2, &t);
	if (rc == 0)
		rc = dbc_expect_punct(p, ';', "';' after the value type");
	if (rc < 0)
		return rc;
	s = &((struct hl_dbc_signal *)p->db->msgs[mi].signals)[si];
	if ((t == 1 && s->length != 32) || (t == 2 && s->length != 64))
		return dbc_fail_at(p, line, col, "signal '%s' has %d bits; a %s needs %d", s->name,
				   s->length, t == 1 ? "float (1)" : "double (2)",
				   t == 1 ? 32 : 64);
	s->type = t == 0 ? HL_DBC_INTEGER : t == 1 ? HL_DBC_FLOAT : HL_DBC_DOUBLE;
	return 0;
}

int dbc_parse_sg_mul_val(struct parser *p, int kw_line, int kw_col)
{
	struct hl_dbc *db = p->db;
	struct hl_dbc_message *m;
	struct hl_dbc_signal *s;
	struct hl_dbc_mux_range *r = NULL;
	const char *w = NULL;
	size_t wn = 0;
	int mi, si, mux, line, col, n = 0, cap = 0, rc;

	rc = dbc_get_sig_ref(p, &mi, &si);
	if (rc != 0)
		return dbc_skipped(p, rc);
	m = &db->msgs[mi];
	s = &((struct hl_dbc_signal *)m->signals)[si];
	line = p->tok.line;
	col = p->tok.col;
	rc = dbc_peek_ident(p, "the multiplexor signal's name", &w, &wn);
	if (rc < 0)
		return rc;
	mux = dbc_find_signal_n(m, w, wn);
	if (mux < 0)
		return dbc_fail_at(p, line, col, "expected a signal of message '%s', found '%.*s'",
				   m->name, (int)(wn > 40 ? 40 : wn), w);
	if (!m->signals[mux].is_multiplexor || mux == si)
		return dbc_fail_at(
			p, line, col,
			"expected a multiplexor (M or m<n>M) of message '%s', found '%s'", m->name,
			m->signals[mux].name);
	if (db->where[mi][si].mul_line)
		return dbc_fail_at(p, kw_line, kw_col,
				   "SG_MUL_VAL_ for signal '%s' given twice (line %d)", s->name,
				   db->where[mi][si].mul_line);
	while (rc == 0 && !dbc_is_punct(p, ';')) {
		uint64_t lo = 0, hi = 0;
		int rl, rcol;

		if (n > 0)
			rc = dbc_expect_punct(p, ',', "',' or ';' after a range");
		rl = p->tok.line;
		rcol = p->tok.col;
		if (rc == 0)
			rc = dbc_get_uint(p, "a multiplexor value range lo-hi", UINT64_MAX, &lo);
		if (rc == 0)
			rc = dbc_expect_punct(p, '-', "'-' inside the range lo-hi");
		if (rc == 0)
			rc = dbc_get_uint(p, "the range's upper value", UINT64_MAX, &hi);
		if (rc == 0 && hi < lo)
			rc = dbc_fail_at(p, rl, rcol,
					 "expected a range lo-hi with lo <= hi, found %llu-%llu",
					 (unsigned long long)lo, (unsigned long long)hi);
		if (rc == 0 && hl_dbc_grow(&r, &cap, n, sizeof(*r)))
			rc = -ENOMEM;
		if (rc == 0)
			r[n++] = (struct hl_dbc_mux_range){ lo, hi };
	}
	if (rc == 0 && n == 0)
		rc = dbc_expected(p, "at least one multiplexor value range lo-hi");
	if (rc == 0)
		rc = dbc_next(p);
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
void dbc_apply_long_names(struct hl_dbc *db)
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
