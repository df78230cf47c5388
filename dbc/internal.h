/* SPDX-License-Identifier: MIT */
/*
 * The body of struct hl_dbc, shared by the parser (parse.c, lexer.c, attributes.c), database.c
 * and codec.c only. Dependencies point one way: the parser -> database.c -> codec.c (codec.c only
 * reads the structs declared here).
 */
#ifndef HL_DBC_INTERNAL_H
#define HL_DBC_INTERNAL_H

#include "dbc/database.h"

/* Strings live in blocks freed together with the database. */
struct arena_block {
	struct arena_block *next;
	size_t used, size;
	char data[];
};

struct attr_assign {
	int def;
	enum hl_dbc_object object;
	int index; /* node or message index; -1 for the network */
	int signal; /* signal index for HL_DBC_SIGNAL */
	struct hl_dbc_attr_value value;
};

struct value_table {
	const char *name;
	int n;
	struct hl_dbc_value_desc *entries;
};

struct node {
	const char *name;
	const char *comment;
};

/* A multiplexor's dependents by multiplexor value: dense (value < n_values) or a range list. */
struct mux_table {
	uint32_t n_values; /* dense: offsets has n_values + 1 entries */
	uint32_t *offsets;
	uint16_t *children; /* dense: the children of value v are children[offsets[v]..offsets[v+1]) */
	int n_ranges; /* sparse */
	struct {
		uint64_t lo, hi;
		uint16_t child;
	} * ranges;
};

struct hl_dbc_plan {
	int n_roots; /* signals present in every frame */
	uint16_t *roots;
	int n_tables;
	struct mux_table *tables;
};

/* Where a signal and its SG_MUL_VAL_ came from, to report faults found after parsing. */
struct sig_where {
	int line, column; /* the SG_'s multiplex indicator or name */
	int mul_line, mul_column; /* its SG_MUL_VAL_, line 0 when none */
	bool mux_value; /* has an mN indicator */
};

struct hl_dbc {
	struct arena_block *arena;
	const char *version;
	const char *comment;

	int n_nodes, cap_nodes;
	struct node *nodes;

	int n_msgs, cap_msgs;
	struct hl_dbc_message *msgs;
	int *cap_sigs; /* per message, while parsing */
	struct sig_where **where; /* per message and signal */

	uint32_t *hash; /* open addressing: message index + 1, 0 empty */
	uint32_t hash_mask;
	int max_signals;

	int n_tables, cap_tables;
	struct value_table *tables;

	int n_defs, cap_defs;
	struct hl_dbc_attr_def *defs;
	int n_assigns, cap_assigns;
	struct attr_assign *assigns;

	int n_warnings, cap_warnings;
	struct {
		int line, column;
		char *msg;
	} * warnings;
};

char *hl_dbc_strndup(struct hl_dbc *db, const char *s, size_t n);
/* Grows *array (of elem bytes, *cap entries) to hold n + 1: 0 or -ENOMEM. */
int hl_dbc_grow(void *array, int *cap, int n, size_t elem);
/* After parsing (database.c): builds every message's plan, then the ID table. 0 or -EBADMSG /
 * -ENOMEM with err set. */
int hl_dbc_finish(struct hl_dbc *db, struct hl_dbc_error *err);

/* --- codec.c: uses the types above, never database.c or parse.c --- */

/* Resolves m's multiplexing (w: where each signal came from, for the errors), precomputes each
 * signal's extraction and builds m->plan. 0, -EBADMSG with err set, or -ENOMEM (a partly built
 * plan stays in m->plan for hl_dbc_plan_free). */
int hl_dbc_plan_build(struct hl_dbc_message *m, const struct sig_where *w,
		      struct hl_dbc_error *err);
void hl_dbc_plan_free(struct hl_dbc_plan *plan); /* NULL is fine */
/* Precomputes s->x from start bit, length, order and sign. */
void hl_dbc_extract_init(struct hl_dbc_signal *s);
/* Highest byte index + 1 a signal touches. */
int hl_dbc_signal_end_byte(int start_bit, int length, enum hl_dbc_byte_order order);

#endif
