/* SPDX-License-Identifier: MIT */
/*
 * The database object: storage, accessors, attribute lookup, the ID table, and lookup plus
 * decode of a frame. The decode plan of each message is built by codec.c (hl_dbc_plan_build).
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dbc/internal.h"

#define ARENA_BLOCK 16384

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
		hl_dbc_plan_free((struct hl_dbc_plan *)m->plan);
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

int hl_dbc_finish(struct hl_dbc *db, struct hl_dbc_error *err)
{
	uint32_t size = 16;
	int rc;

	for (int i = 0; i < db->n_msgs; i++) {
		rc = hl_dbc_plan_build(&db->msgs[i], db->where[i], err);
		if (rc < 0)
			return rc;
		if (db->msgs[i].n_signals > db->max_signals)
			db->max_signals = db->msgs[i].n_signals;
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

int hl_dbc_decode_frame(const struct hl_dbc *db, uint32_t can_id, const uint8_t *data, size_t len,
			struct hl_dbc_counters *counters, const struct hl_dbc_message **ret_msg,
			struct hl_dbc_value *ret_values)
{
	const struct hl_dbc_message *m = hl_dbc_find_id(db, can_id);
	int n;

	if (!m) {
		if (counters)
			counters->unknown_id++;
		return -ENOENT;
	}
	*ret_msg = m;
	n = hl_dbc_decode(m, data, len, ret_values);
	if (counters) {
		if (n < 0)
			counters->short_frame++;
		else
			counters->decoded++;
	}
	return n;
}
