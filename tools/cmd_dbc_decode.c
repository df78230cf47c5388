/* SPDX-License-Identifier: MIT */
/*
 * hdlamp dbc decode: candump -L lines to one JSON object per frame, with the E2E check of
 * every protected message. Apart from the dispatcher (cmd_dbc.c) because it is one of the
 * larger subcommands.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "can/candump.h"
#include "can/e2e.h"
#include "dbc/database.h"
#include "tools/cmd_dbc.h"
#include "tools/commands.h"
#include "tools/json_out.h"

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

int decode(const char *dbc_path, unsigned flags, const char *log_path)
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
