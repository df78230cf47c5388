/* SPDX-License-Identifier: MIT */
/* hdlamp dbc: show a CAN database, decode candump logs with it, encode frames. */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>

#include "can/candump.h"
#include "can/e2e.h"
#include "dbc/database.h"
#include "tools/commands.h"
#include "tools/json_out.h"

static void usage(FILE *f)
{
	fprintf(f,
		"usage: hdlamp dbc info [--strict] FILE\n"
		"       hdlamp dbc decode [--strict] --dbc FILE [LOG|-]\n"
		"       hdlamp dbc encode [--strict] --dbc FILE --message NAME [--e2e] [--counter N]\n"
		"                         [--time SEC.USEC] [--iface NAME] [SIGNAL=VALUE ...]\n"
		"\n"
		"The .dbc is loaded leniently: what real files get wrong but can be read (comments\n"
		"or values for signals that do not exist, signals past their message, exponents\n"
		"in integers, ...) is read and printed as a warning with file:line:column on\n"
		"stderr. --strict refuses such files instead (the daemon: dbc.strict = true).\n"
		"See docs/dbc-compat.md.\n"
		"\n"
		"info    messages, signals, multiplexing, value tables, comments and every\n"
		"        attribute (set or default) of a .dbc file\n"
		"decode  reads candump -L lines (classic and CAN FD) from LOG or stdin and writes\n"
		"        one JSON object per frame: t, iface, id, name, signals (physical values),\n"
		"        e2e: ok | crc | repeated | lost (with \"lost\": n) | counter | none\n"
		"        (unknown IDs: \"name\": null; short frames: \"error\"; error frames:\n"
		"        \"error_frame\": true, counted apart). A float value that is NaN or\n"
		"        infinite is written as the string \"NaN\", \"Infinity\" or \"-Infinity\"\n"
		"encode  prints one candump -L line of message NAME; unset signals are 0, a VALUE\n"
		"        is a physical value or a VAL_ description; --e2e computes the CRC of the\n"
		"        message's HdlE2E profile and writes --counter N (default: the counter the\n"
		"        payload already has)\n");
}

static int load(const char *path, unsigned flags, struct hl_dbc **ret)
{
	struct hl_dbc_error err;
	int rc = hl_dbc_parse_file_flags(path, flags, ret, &err);

	if (rc < 0) {
		if (err.line)
			fprintf(stderr, "hdlamp dbc: '%s':%d:%d: %s\n", path, err.line, err.column,
				err.msg);
		else
			fprintf(stderr, "hdlamp dbc: '%s': %s\n", path, err.msg);
		return rc;
	}
	for (int i = 0; i < hl_dbc_n_warnings(*ret); i++) {
		int line, col;
		const char *w = hl_dbc_warning(*ret, i, &line, &col);

		fprintf(stderr, "hdlamp dbc: '%s':%d:%d: warning: %s\n", path, line, col, w);
	}
	return 0;
}

/* --- info --- */

/* The shortest %g that reads back as the same double, into buf (32 bytes). */
static void format_double(char *buf, double v)
{
	if (!isfinite(v)) {
		strcpy(buf, "null");
		return;
	}
	for (int prec = 15; prec <= 17; prec++) {
		snprintf(buf, 32, "%.*g", prec, v);
		if (strtod(buf, NULL) == v)
			break;
	}
}

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

static int info(const char *path, unsigned flags)
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

/* --- decode --- */

static void format_value(char *buf, const struct hl_dbc_signal *s, uint64_t raw, double phys)
{
	/* JSON has no NaN or infinity: strings with the names Python's json gives them, so
	 * that the three stay apart (docs/dbc-compat.md) */
	if (isnan(phys)) {
		strcpy(buf, "\"NaN\"");
		return;
	}
	if (isinf(phys)) {
		strcpy(buf, phys > 0 ? "\"Infinity\"" : "\"-Infinity\"");
		return;
	}
	/* plain integers print exactly, also beyond 2^53 */
	if (s->type == HL_DBC_INTEGER && s->factor == 1 && s->offset == 0) {
		if (s->is_signed)
			snprintf(buf, 32, "%lld", (long long)(int64_t)raw);
		else
			snprintf(buf, 32, "%llu", (unsigned long long)raw);
		return;
	}
	format_double(buf, phys);
}

/*
 * The text of every value of the integer signals of up to 8 bits (the dimming values): made
 * once, so that decoding a log prints without formatting doubles. table[m][k] is NULL for
 * other signals.
 */
typedef char value_text[32];

static value_text **value_table_new(const struct hl_dbc *db)
{
	int n = hl_dbc_n_messages(db);
	value_text **t = calloc(n + 1, sizeof(*t));

	if (!t)
		return NULL;
	for (int i = 0; i < n; i++) {
		const struct hl_dbc_message *m = hl_dbc_message(db, i);

		t[i] = calloc((size_t)m->n_signals * 256 + 1, sizeof(value_text));
		if (!t[i])
			return t;
		for (int k = 0; k < m->n_signals; k++) {
			const struct hl_dbc_signal *s = &m->signals[k];

			if (s->type != HL_DBC_INTEGER || s->length > 8)
				continue;
			for (uint64_t r = 0; r < ((uint64_t)1 << s->length); r++) {
				uint64_t raw = r;

				if (s->is_signed && (r >> (s->length - 1)))
					raw = r | ~(((uint64_t)1 << s->length) - 1);
				format_value(t[i][(size_t)k * 256 + r], s, raw,
					     hl_dbc_signal_phys(s, raw));
			}
		}
	}
	return t;
}

static void value_table_free(const struct hl_dbc *db, value_text **t)
{
	if (!t)
		return;
	for (int i = 0; i < hl_dbc_n_messages(db); i++)
		free(t[i]);
	free(t);
}

/*
 * The alive counter steps once per cycle and every page (multiplexor value) of a cycle carries
 * it, so it is followed per page: page p of cycle n+1 must carry counter(n) + 1.
 */
#define E2E_PAGES 64 /* multiplexor values followed; frames of higher pages get CRC checks only */

struct e2e_state {
	struct hl_e2e_config cfg;
	bool seen[E2E_PAGES];
	unsigned counter[E2E_PAGES];
};

static int e2e_configs(const struct hl_dbc *db, const char *path, struct e2e_state **ret)
{
	int n = hl_dbc_n_messages(db);
	struct e2e_state *st = calloc(n + 1, sizeof(*st));

	if (!st)
		return -ENOMEM;
	for (int i = 0; i < n; i++) {
		const struct hl_dbc_message *m = hl_dbc_message(db, i);
		struct hl_dbc_attr_value v;

		if (hl_dbc_message_attr(db, m, "HdlE2E", &v) < 0 || v.type != HL_DBC_ATTR_STRING)
			continue;
		if (hl_e2e_config_parse(v.s, &st[i].cfg) < 0) {
			fprintf(stderr,
				"hdlamp dbc: '%s': message %s: HdlE2E \"%s\": expected \"none\" or \"P1|P5 dataid=N\"\n",
				path, m->name, v.s);
			free(st);
			return -EINVAL;
		}
		if ((size_t)m->size < hl_e2e_min_len(st[i].cfg.profile)) {
			fprintf(stderr,
				"hdlamp dbc: '%s': message %s: %d bytes are too few for %s\n", path,
				m->name, m->size, hl_e2e_profile_name(st[i].cfg.profile));
			free(st);
			return -EINVAL;
		}
	}
	*ret = st;
	return 0;
}

static void put_e2e(FILE *out, struct e2e_state *st, uint64_t page, const uint8_t *data, size_t len)
{
	unsigned cur, lost;
	int rc;

	if (st->cfg.profile == HL_E2E_NONE) {
		fputs(",\"e2e\":\"none\"", out);
		return;
	}
	if (hl_e2e_check(&st->cfg, data, len) < 0) {
		fputs(",\"e2e\":\"crc\"", out);
		return;
	}
	cur = hl_e2e_counter(&st->cfg, data);
	if (cur > hl_e2e_counter_max(st->cfg.profile)) {
		fputs(",\"e2e\":\"counter\"", out);
		return;
	}
	if (page >= E2E_PAGES) {
		fputs(",\"e2e\":\"ok\"", out);
		return;
	}
	rc = st->seen[page] ? hl_e2e_counter_check(hl_e2e_counter_max(st->cfg.profile),
						   st->counter[page], cur, &lost) :
			      HL_E2E_COUNTER_OK;
	st->seen[page] = true;
	st->counter[page] = cur;
	if (rc == HL_E2E_COUNTER_REPEATED)
		fputs(",\"e2e\":\"repeated\"", out);
	else if (rc == HL_E2E_COUNTER_LOST)
		fprintf(out, ",\"e2e\":\"lost\",\"lost\":%u", lost);
	else
		fputs(",\"e2e\":\"ok\"", out);
}

/* The value of the message's top-level multiplexor in a decoded frame, 0 without one. */
static uint64_t page_of(const struct hl_dbc_message *m, const struct hl_dbc_value *vals, int nv)
{
	for (int i = 0; i < nv; i++) {
		const struct hl_dbc_signal *s = &m->signals[vals[i].signal];

		if (s->is_multiplexor && s->mux_parent < 0)
			return vals[i].raw;
	}
	return 0;
}

static int decode(const char *dbc_path, unsigned flags, const char *log_path)
{
	struct hl_dbc *db;
	struct hl_dbc_counters counters = { 0 };
	struct hl_dbc_value *vals = NULL;
	struct e2e_state *st = NULL;
	value_text **texts = NULL;
	FILE *in = stdin, *out = stdout;
	char *line = NULL;
	size_t cap = 0;
	ssize_t n;
	long lineno = 0, bad_lines = 0;
	uint64_t error_frames = 0;
	int rc = HL_EXIT_FAIL;

	if (load(dbc_path, flags, &db) < 0)
		return HL_EXIT_FAIL;
	if (e2e_configs(db, dbc_path, &st) < 0)
		goto out;
	vals = malloc(sizeof(*vals) * (hl_dbc_max_signals(db) + 1));
	texts = value_table_new(db);
	if (!vals || !texts) {
		fprintf(stderr, "hdlamp dbc: out of memory\n");
		goto out;
	}
	for (int i = 0; i < hl_dbc_n_messages(db); i++)
		if (!texts[i]) {
			fprintf(stderr, "hdlamp dbc: out of memory\n");
			goto out;
		}
	if (strcmp(log_path, "-") != 0) {
		in = fopen(log_path, "re");
		if (!in) {
			fprintf(stderr, "hdlamp dbc: '%s': %s\n", log_path, strerror(errno));
			goto out;
		}
	}
	setvbuf(out, NULL, _IOFBF, 1 << 20);
	while ((n = getline(&line, &cap, in)) >= 0) {
		struct hl_candump_frame f;
		struct hl_candump_error err;
		const struct hl_dbc_message *m;
		uint32_t id;
		int nv, mi;

		lineno++;
		if (n == 0 || line[0] == '\n' || (line[0] == '\r' && line[1] == '\n'))
			continue;
		if (hl_candump_parse(line, n, &f, &err) < 0) {
			fprintf(stderr, "hdlamp dbc: '%s':%ld:%d: %s\n", log_path, lineno,
				err.column, err.msg);
			bad_lines++;
			continue;
		}
		if (f.frame.can_id & CAN_ERR_FLAG) {
			/* counted, never decoded; python-can writes them with no data bytes */
			fprintf(out, "{\"t\":%lld.%06lld,\"iface\":", (long long)(f.t_us / 1000000),
				(long long)(f.t_us % 1000000));
			hl_tool_json_str(out, f.iface);
			fprintf(out, ",\"id\":\"0x%08x\",\"error_frame\":true,\"len\":%u}\n",
				f.frame.can_id & (CAN_ERR_FLAG | CAN_ERR_MASK), f.frame.len);
			error_frames++;
			continue;
		}
		id = f.frame.can_id & (CAN_EFF_FLAG | CAN_EFF_MASK);
		if (f.frame.can_id & (CAN_ERR_FLAG | CAN_RTR_FLAG))
			id = f.frame.can_id; /* never matches a message */
		fprintf(out, "{\"t\":%lld.%06lld,\"iface\":", (long long)(f.t_us / 1000000),
			(long long)(f.t_us % 1000000));
		hl_tool_json_str(out, f.iface);
		fprintf(out,
			(f.frame.can_id & CAN_EFF_FLAG) ? ",\"id\":\"0x%08x\"" :
							  ",\"id\":\"0x%03x\"",
			f.frame.can_id & CAN_EFF_MASK);
		nv = hl_dbc_decode_frame(db, id, f.frame.data, f.frame.len, &counters, &m, vals);
		if (nv == -ENOENT) {
			fputs(",\"name\":null}\n", out);
			continue;
		}
		mi = (int)(m - hl_dbc_message(db, 0));
		fprintf(out, ",\"name\":\"%s\"", m->name);
		if (nv < 0) {
			fprintf(out, ",\"error\":\"short frame: %u of %d bytes\"}\n", f.frame.len,
				m->size);
			continue;
		}
		/* signals in database order */
		for (int i = 1; i < nv; i++) {
			struct hl_dbc_value v = vals[i];
			int j = i;

			for (; j > 0 && vals[j - 1].signal > v.signal; j--)
				vals[j] = vals[j - 1];
			vals[j] = v;
		}
		fputs_unlocked(",\"signals\":{", out);
		for (int i = 0; i < nv; i++) {
			const struct hl_dbc_signal *s = &m->signals[vals[i].signal];
			char buf[32];
			const char *text = buf;

			if (i)
				putc_unlocked(',', out);
			putc_unlocked('"', out);
			fputs_unlocked(s->name, out);
			fputs_unlocked("\":", out);
			if (s->type == HL_DBC_INTEGER && s->length <= 8)
				text = texts[mi][(size_t)vals[i].signal * 256 +
						 (vals[i].raw & ((1u << s->length) - 1))];
			else
				format_value(buf, s, vals[i].raw, vals[i].phys);
			fputs_unlocked(text, out);
		}
		putc_unlocked('}', out);
		put_e2e(out, &st[mi], page_of(m, vals, nv), f.frame.data, f.frame.len);
		fputs_unlocked("}\n", out);
	}
	if (ferror(in)) {
		fprintf(stderr, "hdlamp dbc: '%s': read error\n", log_path);
		goto out;
	}
	if (fflush(out) != 0) {
		fprintf(stderr, "hdlamp dbc: write error: %s\n", strerror(errno));
		goto out;
	}
	if (bad_lines || counters.unknown_id || counters.short_frame || error_frames)
		fprintf(stderr,
			"hdlamp dbc: %llu frames decoded, %llu with unknown IDs, %llu short, %ld malformed lines, %llu error frames\n",
			(unsigned long long)counters.decoded,
			(unsigned long long)counters.unknown_id,
			(unsigned long long)counters.short_frame, bad_lines,
			(unsigned long long)error_frames);
	rc = bad_lines ? HL_EXIT_FAIL : HL_EXIT_OK;
out:
	if (in && in != stdin)
		fclose(in);
	free(line);
	free(vals);
	value_table_free(db, texts);
	free(st);
	hl_dbc_free(db);
	return rc;
}

/* --- encode --- */

static int depth(const struct hl_dbc_message *m, const struct hl_dbc_signal *s)
{
	int d = 0;

	while (s->mux_parent >= 0) {
		s = &m->signals[s->mux_parent];
		d++;
	}
	return d;
}

/* A physical value, or the raw value a VAL_ description names. */
static int set_signal(const struct hl_dbc_signal *s, const char *text, uint8_t *data, size_t len)
{
	char *end;
	double v;

	errno = 0;
	v = strtod(text, &end);
	if (end != text && *end == '\0' && errno == 0) {
		int rc = hl_dbc_signal_encode(s, v, data, len);

		if (rc < 0)
			fprintf(stderr,
				"hdlamp dbc: %s=%s: out of range (min %.17g, max %.17g, %d bits %s)\n",
				s->name, text, s->min, s->max, s->length,
				s->is_signed ? "signed" : "unsigned");
		return rc;
	}
	for (int i = 0; i < s->n_values; i++)
		if (strcmp(s->values[i].desc, text) == 0)
			return hl_dbc_signal_set_raw(s, (uint64_t)s->values[i].value, data, len);
	fprintf(stderr, "hdlamp dbc: %s=%s: expected a number or one of the signal's VAL_ names\n",
		s->name, text);
	return -EINVAL;
}

static int fd_len(int size)
{
	static const int lens[] = { 12, 16, 20, 24, 32, 48, 64 };

	if (size <= 8)
		return size;
	for (size_t i = 0; i < sizeof(lens) / sizeof(lens[0]); i++)
		if (size <= lens[i])
			return lens[i];
	return 64;
}

static int encode(const char *dbc_path, unsigned flags, const char *msg_name, bool e2e,
		  long counter, int64_t t_us, const char *iface, int n_args, char **args)
{
	struct hl_dbc *db;
	const struct hl_dbc_message *m;
	struct hl_candump_frame f = { 0 };
	struct hl_dbc_attr_value v;
	const struct hl_dbc_signal **sigs = NULL;
	char line[HL_CANDUMP_MAX_LINE];
	int rc = HL_EXIT_FAIL, max_depth = 0;
	bool fd;

	if (load(dbc_path, flags, &db) < 0)
		return HL_EXIT_FAIL;
	m = hl_dbc_find_message(db, msg_name);
	if (!m) {
		fprintf(stderr, "hdlamp dbc: '%s' has no message '%s'\n", dbc_path, msg_name);
		goto out;
	}
	sigs = calloc(n_args + 1, sizeof(*sigs));
	if (!sigs)
		goto out;
	for (int i = 0; i < n_args; i++) {
		char *eq = strchr(args[i], '=');

		if (!eq) {
			fprintf(stderr, "hdlamp dbc: '%s': expected SIGNAL=VALUE\n", args[i]);
			rc = HL_EXIT_USAGE;
			goto out;
		}
		*eq = '\0';
		sigs[i] = hl_dbc_find_signal(m, args[i]);
		*eq = '=';
		if (!sigs[i]) {
			fprintf(stderr, "hdlamp dbc: message %s has no signal '%.*s'\n", m->name,
				(int)(eq - args[i]), args[i]);
			goto out;
		}
		if (depth(m, sigs[i]) > max_depth)
			max_depth = depth(m, sigs[i]);
	}
	/* multiplexors before what they select, so that presence can be checked */
	for (int d = 0; d <= max_depth; d++)
		for (int i = 0; i < n_args; i++)
			if (depth(m, sigs[i]) == d && set_signal(sigs[i], strchr(args[i], '=') + 1,
								 f.frame.data, m->size) < 0)
				goto out;
	for (int i = 0; i < n_args; i++)
		if (!hl_dbc_signal_present(m, sigs[i], f.frame.data, m->size)) {
			fprintf(stderr,
				"hdlamp dbc: signal %s is not selected by the multiplexor values given (%s)\n",
				sigs[i]->name, m->signals[sigs[i]->mux_parent].name);
			goto out;
		}
	if (e2e) {
		struct hl_e2e_config cfg = { HL_E2E_NONE, 0 };

		if (hl_dbc_message_attr(db, m, "HdlE2E", &v) >= 0 && v.type == HL_DBC_ATTR_STRING &&
		    hl_e2e_config_parse(v.s, &cfg) < 0) {
			fprintf(stderr, "hdlamp dbc: message %s: bad HdlE2E \"%s\"\n", m->name,
				v.s);
			goto out;
		}
		if (cfg.profile == HL_E2E_NONE) {
			fprintf(stderr, "hdlamp dbc: message %s has no E2E profile (HdlE2E)\n",
				m->name);
			goto out;
		}
		if (counter < 0)
			counter = hl_e2e_counter(&cfg, f.frame.data);
		if (counter > (long)hl_e2e_counter_max(cfg.profile)) {
			fprintf(stderr, "hdlamp dbc: counter %ld: expected 0..%u for %s\n", counter,
				hl_e2e_counter_max(cfg.profile), hl_e2e_profile_name(cfg.profile));
			rc = HL_EXIT_USAGE;
			goto out;
		}
		if (hl_e2e_protect(&cfg, f.frame.data, m->size, (unsigned)counter) < 0) {
			fprintf(stderr, "hdlamp dbc: message %s: %d bytes are too few for %s\n",
				m->name, m->size, hl_e2e_profile_name(cfg.profile));
			goto out;
		}
	} else if (counter >= 0) {
		fprintf(stderr, "hdlamp dbc: --counter needs --e2e\n");
		rc = HL_EXIT_USAGE;
		goto out;
	}
	fd = m->size > 8 || (hl_dbc_message_attr(db, m, "VFrameFormat", &v) >= 0 &&
			     v.type == HL_DBC_ATTR_ENUM && v.s && strstr(v.s, "_FD"));
	f.t_us = t_us;
	snprintf(f.iface, sizeof(f.iface), "%s", iface);
	f.fd = fd;
	f.frame.len = (uint8_t)(fd ? fd_len(m->size) : m->size);
	f.frame.can_id = m->id | (m->extended ? CAN_EFF_FLAG : 0);
	if (hl_candump_format(&f, line, sizeof(line)) < 0) {
		fprintf(stderr, "hdlamp dbc: cannot format the frame\n");
		goto out;
	}
	puts(line);
	rc = HL_EXIT_OK;
out:
	free(sigs);
	hl_dbc_free(db);
	return rc;
}

static int parse_time(const char *s, int64_t *ret)
{
	char *end;
	long long sec;
	long usec = 0;
	int digits = 0;

	errno = 0;
	sec = strtoll(s, &end, 10);
	if (errno || end == s || sec < 0 || sec > 999999999999LL)
		return -EINVAL;
	if (*end == '.') {
		for (end++; *end >= '0' && *end <= '9' && digits < 6; end++, digits++)
			usec = usec * 10 + (*end - '0');
		if (digits == 0)
			return -EINVAL;
		for (; digits < 6; digits++)
			usec *= 10;
	}
	if (*end)
		return -EINVAL;
	*ret = sec * 1000000 + usec;
	return 0;
}

int hl_cmd_dbc(int argc, char **argv)
{
	static const struct option opts[] = {
		{ "dbc", required_argument, NULL, 'd' },
		{ "message", required_argument, NULL, 'm' },
		{ "e2e", no_argument, NULL, 'e' },
		{ "counter", required_argument, NULL, 'c' },
		{ "time", required_argument, NULL, 't' },
		{ "iface", required_argument, NULL, 'i' },
		{ "strict", no_argument, NULL, 's' },
		{ "help", no_argument, NULL, 'h' },
		{ 0 },
	};
	unsigned flags = 0;
	const char *dbc = NULL, *msg = NULL, *iface = "can0", *sub;
	bool e2e = false;
	long counter = -1;
	int64_t t_us = -1;
	int c;

	if (argc < 2) {
		usage(stderr);
		return HL_EXIT_USAGE;
	}
	sub = argv[1];
	if (strcmp(sub, "--help") == 0 || strcmp(sub, "-h") == 0) {
		usage(stdout);
		return HL_EXIT_OK;
	}
	argc--;
	argv++;
	optind = 1;
	while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
		char *end;

		switch (c) {
		case 'd':
			dbc = optarg;
			break;
		case 'm':
			msg = optarg;
			break;
		case 'e':
			e2e = true;
			break;
		case 'c':
			errno = 0;
			counter = strtol(optarg, &end, 0);
			if (errno || *end || end == optarg || counter < 0 || counter > 255) {
				fprintf(stderr, "hdlamp dbc: --counter: expected 0..255\n");
				return HL_EXIT_USAGE;
			}
			break;
		case 't':
			if (parse_time(optarg, &t_us) < 0) {
				fprintf(stderr, "hdlamp dbc: --time: expected SECONDS[.MICROS]\n");
				return HL_EXIT_USAGE;
			}
			break;
		case 'i':
			if (!optarg[0] || strlen(optarg) >= IFNAMSIZ || strpbrk(optarg, " \t\n")) {
				fprintf(stderr,
					"hdlamp dbc: --iface: expected a name of 1..%d chars\n",
					IFNAMSIZ - 1);
				return HL_EXIT_USAGE;
			}
			iface = optarg;
			break;
		case 's':
			flags |= HL_DBC_STRICT;
			break;
		case 'h':
			usage(stdout);
			return HL_EXIT_OK;
		default:
			usage(stderr);
			return HL_EXIT_USAGE;
		}
	}
	if (strcmp(sub, "info") == 0) {
		if (optind != argc - 1 || dbc || msg) {
			usage(stderr);
			return HL_EXIT_USAGE;
		}
		return info(argv[optind], flags);
	}
	if (strcmp(sub, "decode") == 0) {
		if (!dbc || msg || optind < argc - 1) {
			usage(stderr);
			return HL_EXIT_USAGE;
		}
		return decode(dbc, flags, optind < argc ? argv[optind] : "-");
	}
	if (strcmp(sub, "encode") == 0) {
		if (!dbc || !msg) {
			usage(stderr);
			return HL_EXIT_USAGE;
		}
		if (t_us < 0) {
			struct timeval tv;

			gettimeofday(&tv, NULL);
			t_us = (int64_t)tv.tv_sec * 1000000 + tv.tv_usec;
		}
		return encode(dbc, flags, msg, e2e, counter, t_us, iface, argc - optind,
			      argv + optind);
	}
	fprintf(stderr, "hdlamp dbc: unknown subcommand '%s'\n", sub);
	usage(stderr);
	return HL_EXIT_USAGE;
}
