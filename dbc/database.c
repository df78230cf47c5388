/* SPDX-License-Identifier: MIT */
/*
 * The database object: storage, accessors, attribute lookup, and the step after parsing that
 * resolves multiplexing and precomputes everything the decoder needs (extraction per signal,
 * dependents per multiplexor value, the ID table).
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dbc/internal.h"

#define ARENA_BLOCK 16384
#define DENSE_MUX_LIMIT 65536 /* entries of a dense multiplexor table, else ranges */

char *hl_dbc_strndup(struct hl_dbc *db, const char *s, size_t n)
{
	struct arena_block *b = db->arena;
	char *r;

	if (!b || b->size - b->used < n + 1) {
		size_t size = n + 1 > ARENA_BLOCK ? n + 1 : ARENA_BLOCK;

		b = malloc(sizeof(*b) + size);
		if (!b)
			return NULL;
		b->size = size;
		b->used = 0;
		b->next = db->arena;
		db->arena = b;
	}
	r = b->data + b->used;
	memcpy(r, s, n);
	r[n] = '\0';
	b->used += n + 1;
	return r;
}

int hl_dbc_grow(void *array, int *cap, int n, size_t elem)
{
	void **a = array;
	void *g;
	int c;

	if (n < *cap)
		return 0;
	c = *cap ? 2 * *cap : 8;
	g = realloc(*a, elem * c);
	if (!g)
		return -ENOMEM;
	*a = g;
	*cap = c;
	return 0;
}

static void free_plan(struct hl_dbc_plan *plan)
{
	if (!plan)
		return;
	for (int i = 0; i < plan->n_tables; i++) {
		free(plan->tables[i].offsets);
		free(plan->tables[i].children);
		free(plan->tables[i].ranges);
	}
	free(plan->tables);
	free(plan->roots);
	free(plan);
}

void hl_dbc_free(struct hl_dbc *db)
{
	if (!db)
		return;
	for (int i = 0; i < db->n_msgs; i++) {
		struct hl_dbc_message *m = &db->msgs[i];

		for (int j = 0; j < m->n_signals; j++) {
			const struct hl_dbc_signal *s = &m->signals[j];

			free((void *)s->receivers);
			free((void *)s->values);
			free((void *)s->mux_ranges);
		}
		free((void *)m->signals);
		free((void *)m->tx_nodes);
		free_plan((struct hl_dbc_plan *)m->plan);
		if (db->where)
			free(db->where[i]);
	}
	free(db->msgs);
	free(db->cap_sigs);
	free(db->where);
	free(db->hash);
	free(db->nodes);
	for (int i = 0; i < db->n_tables; i++)
		free(db->tables[i].entries);
	free(db->tables);
	for (int i = 0; i < db->n_defs; i++)
		free((void *)db->defs[i].labels);
	free(db->defs);
	free(db->assigns);
	free(db->warnings);
	while (db->arena) {
		struct arena_block *next = db->arena->next;

		free(db->arena);
		db->arena = next;
	}
	free(db);
}

const char *hl_dbc_version(const struct hl_dbc *db)
{
	return db->version;
}

const char *hl_dbc_comment(const struct hl_dbc *db)
{
	return db->comment;
}

int hl_dbc_n_warnings(const struct hl_dbc *db)
{
	return db->n_warnings;
}

const char *hl_dbc_warning(const struct hl_dbc *db, int i, int *ret_line, int *ret_column)
{
	if (i < 0 || i >= db->n_warnings)
		return NULL;
	if (ret_line)
		*ret_line = db->warnings[i].line;
	if (ret_column)
		*ret_column = db->warnings[i].column;
	return db->warnings[i].msg;
}

int hl_dbc_n_nodes(const struct hl_dbc *db)
{
	return db->n_nodes;
}

const char *hl_dbc_node(const struct hl_dbc *db, int i)
{
	return i >= 0 && i < db->n_nodes ? db->nodes[i].name : NULL;
}

const char *hl_dbc_node_comment(const struct hl_dbc *db, int i)
{
	return i >= 0 && i < db->n_nodes ? db->nodes[i].comment : NULL;
}

int hl_dbc_n_messages(const struct hl_dbc *db)
{
	return db->n_msgs;
}

const struct hl_dbc_message *hl_dbc_message(const struct hl_dbc *db, int i)
{
	return i >= 0 && i < db->n_msgs ? &db->msgs[i] : NULL;
}

static uint32_t hash_id(uint32_t can_id)
{
	return can_id * 0x9e3779b1u;
}

const struct hl_dbc_message *hl_dbc_find_id(const struct hl_dbc *db, uint32_t can_id)
{
	uint32_t h = hash_id(can_id) & db->hash_mask;

	for (;;) {
		uint32_t e = db->hash[h];

		if (e == 0)
			return NULL;
		if (db->msgs[e - 1].can_id == can_id)
			return &db->msgs[e - 1];
		h = (h + 1) & db->hash_mask;
	}
}

const struct hl_dbc_message *hl_dbc_find_message(const struct hl_dbc *db, const char *name)
{
	for (int i = 0; i < db->n_msgs; i++)
		if (strcmp(db->msgs[i].name, name) == 0)
			return &db->msgs[i];
	return NULL;
}

const struct hl_dbc_signal *hl_dbc_find_signal(const struct hl_dbc_message *m, const char *name)
{
	for (int i = 0; i < m->n_signals; i++)
		if (strcmp(m->signals[i].name, name) == 0)
			return &m->signals[i];
	return NULL;
}

int hl_dbc_max_signals(const struct hl_dbc *db)
{
	return db->max_signals;
}

int hl_dbc_n_value_tables(const struct hl_dbc *db)
{
	return db->n_tables;
}

const char *hl_dbc_value_table(const struct hl_dbc *db, int i, int *ret_n,
			       const struct hl_dbc_value_desc **ret)
{
	if (i < 0 || i >= db->n_tables)
		return NULL;
	*ret_n = db->tables[i].n;
	*ret = db->tables[i].entries;
	return db->tables[i].name;
}

int hl_dbc_n_attr_defs(const struct hl_dbc *db)
{
	return db->n_defs;
}

const struct hl_dbc_attr_def *hl_dbc_attr_def(const struct hl_dbc *db, int i)
{
	return i >= 0 && i < db->n_defs ? &db->defs[i] : NULL;
}

static int attr(const struct hl_dbc *db, enum hl_dbc_object object, int index, int signal,
		const char *name, struct hl_dbc_attr_value *ret)
{
	int d;

	for (d = 0; d < db->n_defs; d++)
		if (db->defs[d].object == object && strcmp(db->defs[d].name, name) == 0)
			break;
	if (d == db->n_defs)
		return -ENOENT;
	for (int i = db->n_assigns - 1; i >= 0; i--) { /* the last BA_ wins */
		const struct attr_assign *a = &db->assigns[i];

		if (a->def == d && a->object == object && a->index == index &&
		    a->signal == signal) {
			*ret = a->value;
			return 0;
		}
	}
	if (!db->defs[d].has_default)
		return -ENOENT;
	*ret = db->defs[d].def;
	return 1;
}

int hl_dbc_network_attr(const struct hl_dbc *db, const char *name, struct hl_dbc_attr_value *ret)
{
	return attr(db, HL_DBC_NETWORK, -1, -1, name, ret);
}

int hl_dbc_node_attr(const struct hl_dbc *db, const char *node, const char *name,
		     struct hl_dbc_attr_value *ret)
{
	for (int i = 0; i < db->n_nodes; i++)
		if (strcmp(db->nodes[i].name, node) == 0)
			return attr(db, HL_DBC_NODE, i, -1, name, ret);
	return -ENOENT;
}

int hl_dbc_message_attr(const struct hl_dbc *db, const struct hl_dbc_message *m, const char *name,
			struct hl_dbc_attr_value *ret)
{
	return attr(db, HL_DBC_MESSAGE, (int)(m - db->msgs), -1, name, ret);
}

int hl_dbc_signal_attr(const struct hl_dbc *db, const struct hl_dbc_message *m,
		       const struct hl_dbc_signal *s, const char *name,
		       struct hl_dbc_attr_value *ret)
{
	return attr(db, HL_DBC_SIGNAL, (int)(m - db->msgs), s->index, name, ret);
}

/* --- after parsing --- */

static int fail(struct hl_dbc_error *err, int line, int col, const char *fmt, const char *a,
		const char *b)
{
	err->line = line;
	err->column = col;
	snprintf(err->msg, sizeof(err->msg), fmt, a, b);
	return -EBADMSG;
}

static int cmp_range(const void *a, const void *b)
{
	const struct hl_dbc_mux_range *x = a, *y = b;

	return x->lo < y->lo ? -1 : x->lo > y->lo;
}

/* Sorted, overlaps merged: a value then matches at most one range of a signal. */
static void normalize_ranges(struct hl_dbc_signal *s)
{
	struct hl_dbc_mux_range *r = (struct hl_dbc_mux_range *)s->mux_ranges;
	int n = 0;

	if (s->n_mux_ranges < 2)
		return;
	qsort(r, s->n_mux_ranges, sizeof(*r), cmp_range);
	for (int i = 1; i < s->n_mux_ranges; i++) {
		if (r[i].lo <= r[n].hi || (r[n].hi != UINT64_MAX && r[i].lo == r[n].hi + 1)) {
			if (r[i].hi > r[n].hi)
				r[n].hi = r[i].hi;
		} else {
			r[++n] = r[i];
		}
	}
	s->n_mux_ranges = n + 1;
}

static bool in_ranges(const struct hl_dbc_signal *s, uint64_t v)
{
	for (int i = 0; i < s->n_mux_ranges; i++)
		if (v >= s->mux_ranges[i].lo && v <= s->mux_ranges[i].hi)
			return true;
	return false;
}

static int build_table(struct hl_dbc_message *m, int mux, struct mux_table *t)
{
	uint64_t top = 0;
	int n_children = 0;

	for (int i = 0; i < m->n_signals; i++) {
		const struct hl_dbc_signal *s = &m->signals[i];

		if (s->mux_parent != mux)
			continue;
		n_children++;
		for (int r = 0; r < s->n_mux_ranges; r++)
			if (s->mux_ranges[r].hi > top)
				top = s->mux_ranges[r].hi;
	}
	if (top < DENSE_MUX_LIMIT && (top + 1) * n_children <= DENSE_MUX_LIMIT) {
		uint32_t k = 0;

		t->n_values = (uint32_t)top + 1;
		t->offsets = malloc(sizeof(uint32_t) * (t->n_values + 1));
		t->children = malloc(sizeof(uint16_t) * ((size_t)t->n_values * n_children + 1));
		if (!t->offsets || !t->children)
			return -ENOMEM;
		for (uint32_t v = 0; v < t->n_values; v++) {
			t->offsets[v] = k;
			for (int i = 0; i < m->n_signals; i++)
				if (m->signals[i].mux_parent == mux && in_ranges(&m->signals[i], v))
					t->children[k++] = (uint16_t)i;
		}
		t->offsets[t->n_values] = k;
		return 0;
	}
	for (int i = 0; i < m->n_signals; i++) {
		const struct hl_dbc_signal *s = &m->signals[i];

		if (s->mux_parent != mux)
			continue;
		for (int r = 0; r < s->n_mux_ranges; r++) {
			if (hl_dbc_grow(&t->ranges, &(int){ t->n_ranges }, t->n_ranges,
					sizeof(*t->ranges)) < 0)
				return -ENOMEM;
			t->ranges[t->n_ranges].lo = s->mux_ranges[r].lo;
			t->ranges[t->n_ranges].hi = s->mux_ranges[r].hi;
			t->ranges[t->n_ranges].child = (uint16_t)i;
			t->n_ranges++;
		}
	}
	return 0;
}

static int finish_message(struct hl_dbc *db, int mi, struct hl_dbc_error *err)
{
	struct hl_dbc_message *m = &db->msgs[mi];
	struct hl_dbc_signal *sigs = (struct hl_dbc_signal *)m->signals;
	struct sig_where *w = db->where[mi];
	struct hl_dbc_plan *plan;
	int top = -1, n_top = 0;

	for (int i = 0; i < m->n_signals; i++)
		if (sigs[i].is_multiplexor && !w[i].mux_value && !w[i].mul_line) {
			top = i;
			n_top++;
		}
	for (int i = 0; i < m->n_signals; i++) {
		struct hl_dbc_signal *s = &sigs[i];

		hl_dbc_extract_init(s);
		if (w[i].mul_line || !w[i].mux_value)
			continue;
		/* mN without SG_MUL_VAL_: the message's one plain multiplexor selects it */
		if (n_top == 0)
			return fail(
				err, w[i].line, w[i].column,
				"signal '%s' is multiplexed (m<n>) but message '%s' has no multiplexor (M)",
				s->name, m->name);
		if (n_top > 1)
			return fail(
				err, w[i].line, w[i].column,
				"signal '%s' is multiplexed (m<n>) but message '%s' has several multiplexors: expected an SG_MUL_VAL_ naming one",
				s->name, m->name);
		if (top == i)
			return fail(err, w[i].line, w[i].column,
				    "signal '%s' of message '%s' is multiplexed by itself", s->name,
				    m->name);
		s->mux_parent = top;
	}
	for (int i = 0; i < m->n_signals; i++) {
		int steps = 0;

		normalize_ranges(&sigs[i]);
		for (int j = sigs[i].mux_parent; j >= 0; j = sigs[j].mux_parent)
			if (++steps > m->n_signals)
				return fail(
					err, w[i].mul_line ? w[i].mul_line : w[i].line,
					w[i].mul_line ? w[i].mul_column : w[i].column,
					"the multiplexor chain of signal '%s' in message '%s' loops",
					sigs[i].name, m->name);
	}
	plan = calloc(1, sizeof(*plan));
	if (!plan)
		return -ENOMEM;
	m->plan = plan;
	plan->roots = malloc(sizeof(uint16_t) * (m->n_signals + 1));
	if (!plan->roots)
		return -ENOMEM;
	for (int i = 0; i < m->n_signals; i++) {
		if (sigs[i].mux_parent < 0)
			plan->roots[plan->n_roots++] = (uint16_t)i;
		if (sigs[i].is_multiplexor)
			plan->n_tables++;
	}
	plan->tables = calloc(plan->n_tables + 1, sizeof(*plan->tables));
	if (!plan->tables)
		return -ENOMEM;
	for (int i = 0, t = 0; i < m->n_signals; i++) {
		if (!sigs[i].is_multiplexor)
			continue;
		sigs[i].mux_table = t;
		if (build_table(m, i, &plan->tables[t++]) < 0)
			return -ENOMEM;
	}
	if (m->n_signals > db->max_signals)
		db->max_signals = m->n_signals;
	return 0;
}

int hl_dbc_finish(struct hl_dbc *db, struct hl_dbc_error *err)
{
	uint32_t size = 16;
	int rc;

	for (int i = 0; i < db->n_msgs; i++) {
		rc = finish_message(db, i, err);
		if (rc < 0)
			return rc;
	}
	while (size < 2u * (uint32_t)db->n_msgs)
		size *= 2;
	db->hash = calloc(size, sizeof(uint32_t));
	if (!db->hash)
		return -ENOMEM;
	db->hash_mask = size - 1;
	for (int i = 0; i < db->n_msgs; i++) {
		uint32_t h;

		if (db->msgs[i].independent)
			continue;
		h = hash_id(db->msgs[i].can_id) & db->hash_mask;
		while (db->hash[h])
			h = (h + 1) & db->hash_mask;
		db->hash[h] = (uint32_t)i + 1;
	}
	return 0;
}
