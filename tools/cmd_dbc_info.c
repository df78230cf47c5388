/* SPDX-License-Identifier: MIT */
/*
 * hdlamp dbc info: everything a .dbc file defines (messages, signals, multiplexing, value
 * tables, comments, every attribute set or default), as text. Apart from the dispatcher
 * (cmd_dbc.c) because it is one of the larger subcommands.
 */
#include <stdio.h>

#include "dbc/database.h"
#include "tools/cmd_dbc.h"
#include "tools/commands.h"

static void print_value(const struct hl_dbc_attr_value *v)
{
	switch (v->type) {
	case HL_DBC_ATTR_INT:
		printf("%lld", (long long)v->i);
		break;
	case HL_DBC_ATTR_HEX:
		printf("0x%llX", (unsigned long long)v->i);
		break;
	case HL_DBC_ATTR_FLOAT: {
		char buf[32];

		format_double(buf, v->f);
		printf("%s", buf);
		break;
	}
	case HL_DBC_ATTR_STRING:
		printf("\"%s\"", v->s ? v->s : "");
		break;
	case HL_DBC_ATTR_ENUM:
		printf("%s", v->s ? v->s : "?");
		break;
	}
}

static const char *const object_names[] = { "network", "BU_", "BO_", "SG_", "EV_" };
static const char *const type_names[] = { "INT", "HEX", "FLOAT", "STRING", "ENUM" };

/* Every attribute defined for this kind of object, with its value (set or default). */
static void print_attrs(const struct hl_dbc *db, enum hl_dbc_object object,
			const struct hl_dbc_message *m, const struct hl_dbc_signal *s,
			const char *node, const char *prefix)
{
	for (int i = 0; i < hl_dbc_n_attr_defs(db); i++) {
		const struct hl_dbc_attr_def *d = hl_dbc_attr_def(db, i);
		struct hl_dbc_attr_value v;
		int rc;

		if (d->object != object)
			continue;
		switch (object) {
		case HL_DBC_NETWORK:
			rc = hl_dbc_network_attr(db, d->name, &v);
			break;
		case HL_DBC_NODE:
			rc = hl_dbc_node_attr(db, node, d->name, &v);
			break;
		case HL_DBC_MESSAGE:
			rc = hl_dbc_message_attr(db, m, d->name, &v);
			break;
		case HL_DBC_SIGNAL:
			rc = hl_dbc_signal_attr(db, m, s, d->name, &v);
			break;
		default:
			continue;
		}
		if (rc < 0)
			continue;
		printf("%s%s=", prefix, d->name);
		print_value(&v);
		if (rc == 1)
			printf(" (default)");
		printf("\n");
	}
}

static void print_comment(const char *c, const char *indent)
{
	printf("%scomment: ", indent);
	for (; *c; c++) {
		putchar(*c);
		if (*c == '\n')
			printf("%s  ", indent);
	}
	printf("\n");
}

static void print_signal(const struct hl_dbc *db, const struct hl_dbc_message *m,
			 const struct hl_dbc_signal *s)
{
	char mux[64] = "", layout[32], factor[32], offset[32], min[32], max[32];

	if (s->mux_parent >= 0) {
		int n = snprintf(mux, sizeof(mux), "%s=", m->signals[s->mux_parent].name);

		for (int r = 0; r < s->n_mux_ranges && n < (int)sizeof(mux) - 24; r++) {
			if (s->mux_ranges[r].lo == s->mux_ranges[r].hi)
				n += snprintf(mux + n, sizeof(mux) - n, "%s%llu", r ? "," : "",
					      (unsigned long long)s->mux_ranges[r].lo);
			else
				n += snprintf(mux + n, sizeof(mux) - n, "%s%llu-%llu", r ? "," : "",
					      (unsigned long long)s->mux_ranges[r].lo,
					      (unsigned long long)s->mux_ranges[r].hi);
		}
	}
	snprintf(layout, sizeof(layout), "%d|%d@%d%c", s->start_bit, s->length, s->order,
		 s->is_signed ? '-' : '+');
	format_double(factor, s->factor);
	format_double(offset, s->offset);
	format_double(min, s->min);
	format_double(max, s->max);
	printf("    %-20s %-2s %-10s (%s,%s) [%s|%s] \"%s\"%s%s", s->name,
	       s->is_multiplexor ? "M" : "", layout, factor, offset, min, max, s->unit,
	       s->type == HL_DBC_FLOAT	? " float" :
	       s->type == HL_DBC_DOUBLE ? " double" :
					  "",
	       s->n_receivers ? " ->" : "");
	for (int r = 0; r < s->n_receivers; r++)
		printf(" %s", s->receivers[r]);
	printf("\n");
	if (mux[0])
		printf("        present when %s\n", mux);
	if (s->unusable)
		printf("        unusable: extends past the message, never decoded\n");
	print_attrs(db, HL_DBC_SIGNAL, m, s, NULL, "        ");
	if (s->n_values) {
		printf("        values:");
		for (int v = 0; v < s->n_values; v++)
			printf(" %lld=\"%s\"", (long long)s->values[v].value, s->values[v].desc);
		printf("\n");
	}
	if (s->comment)
		print_comment(s->comment, "        ");
}

int info(const char *path, unsigned flags)
{
	struct hl_dbc *db;

	if (load(path, flags, &db) < 0)
		return HL_EXIT_FAIL;
	printf("file:     %s\n", path);
	printf("version:  \"%s\"\n", hl_dbc_version(db));
	printf("nodes:   ");
	for (int i = 0; i < hl_dbc_n_nodes(db); i++)
		printf(" %s", hl_dbc_node(db, i));
	printf("\nmessages: %d\n", hl_dbc_n_messages(db));
	if (hl_dbc_comment(db))
		print_comment(hl_dbc_comment(db), "");
	printf("attribute definitions:\n");
	for (int i = 0; i < hl_dbc_n_attr_defs(db); i++) {
		const struct hl_dbc_attr_def *d = hl_dbc_attr_def(db, i);

		printf("  %-7s %-20s %s", object_names[d->object], d->name, type_names[d->type]);
		if (d->type == HL_DBC_ATTR_ENUM)
			for (int l = 0; l < d->n_labels; l++)
				printf("%s\"%s\"", l ? "," : " ", d->labels[l]);
		else if (d->type != HL_DBC_ATTR_STRING) {
			char lo[32], hi[32];

			format_double(lo, d->min);
			format_double(hi, d->max);
			printf(" [%s, %s]", lo, hi);
		}
		if (d->has_default) {
			printf(" default ");
			print_value(&d->def);
		}
		printf("\n");
	}
	printf("network attributes:\n");
	print_attrs(db, HL_DBC_NETWORK, NULL, NULL, NULL, "  ");
	for (int i = 0; i < hl_dbc_n_nodes(db); i++) {
		const char *c = hl_dbc_node_comment(db, i);

		printf("node %s\n", hl_dbc_node(db, i));
		print_attrs(db, HL_DBC_NODE, NULL, NULL, hl_dbc_node(db, i), "  ");
		if (c)
			print_comment(c, "  ");
	}
	for (int t = 0; t < hl_dbc_n_value_tables(db); t++) {
		const struct hl_dbc_value_desc *v;
		int n;
		const char *name = hl_dbc_value_table(db, t, &n, &v);

		printf("value table %s:", name);
		for (int k = 0; k < n; k++)
			printf(" %lld=\"%s\"", (long long)v[k].value, v[k].desc);
		printf("\n");
	}
	for (int i = 0; i < hl_dbc_n_messages(db); i++) {
		const struct hl_dbc_message *m = hl_dbc_message(db, i);
		int n_mux = 0;

		printf("\nmessage %s id 0x%X (%s) %d bytes, tx %s", m->name, m->id,
		       m->independent ? "independent signals, never sent" :
		       m->extended    ? "extended" :
					"standard",
		       m->size, m->transmitter ? m->transmitter : "-");
		for (int t = 0; t < m->n_tx_nodes; t++)
			printf("%s%s", t ? "," : " (BO_TX_BU_ ", m->tx_nodes[t]);
		printf("%s\n", m->n_tx_nodes ? ")" : "");
		if (m->comment)
			print_comment(m->comment, "  ");
		print_attrs(db, HL_DBC_MESSAGE, m, NULL, NULL, "  ");
		for (int k = 0; k < m->n_signals; k++)
			n_mux += m->signals[k].is_multiplexor;
		printf("  signals: %d%s\n", m->n_signals,
		       n_mux > 1 ? " (extended multiplexing)" :
		       n_mux	 ? " (multiplexed)" :
				   "");
		for (int k = 0; k < m->n_signals; k++)
			print_signal(db, m, &m->signals[k]);
	}
	hl_dbc_free(db);
	return HL_EXIT_OK;
}
