/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target: the DBC parser, lenient and strict, never crashes, fails only with a place
 * and a message, warns only with a place, and what it accepts decodes and encodes consistently
 * (set_raw then get_raw gives the bits back; a signal past its message is never decoded).
 */
#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "dbc/database.h"

static void check(const uint8_t *data, size_t size, unsigned flags)
{
	struct hl_dbc *db = NULL;
	struct hl_dbc_error err;
	struct hl_dbc_value *vals;
	int rc, lines = 1;

	for (size_t i = 0; i < size; i++)
		lines += data[i] == '\n';
	rc = hl_dbc_parse_flags((const char *)data, size, flags, &db, &err);
	if (rc < 0) {
		if (rc != -EBADMSG || db || err.line < 1 || err.line > lines || err.column < 1 ||
		    !err.msg[0])
			abort();
		return;
	}
	for (int i = 0; i < hl_dbc_n_warnings(db); i++) {
		int line = 0, col = 0;
		const char *w = hl_dbc_warning(db, i, &line, &col);

		if (!w || !w[0] || line < 1 || line > lines || col < 1)
			abort();
	}
	vals = malloc(sizeof(*vals) * (hl_dbc_max_signals(db) + 1));
	if (!vals)
		abort();
	for (int i = 0; i < hl_dbc_n_messages(db); i++) {
		const struct hl_dbc_message *m = hl_dbc_message(db, i);
		uint8_t frame[64] = { 0 };
		struct hl_dbc_attr_value v;
		int n;

		memcpy(frame, data, size < 64 ? size : 64);
		if (!m->independent && hl_dbc_find_id(db, m->can_id) != m)
			abort();
		n = hl_dbc_decode(m, frame, 64, vals);
		if (m->independent ? n != -ENOENT : (n < 0 || n > m->n_signals))
			abort();
		for (int k = 0; k < n; k++)
			if (vals[k].signal >= (uint32_t)m->n_signals ||
			    m->signals[vals[k].signal].unusable)
				abort();
		for (int k = 0; k < m->n_signals; k++) {
			const struct hl_dbc_signal *s = &m->signals[k];
			uint64_t raw = 0x5a5a5a5a5a5a5a5aull ^ (uint64_t)k, back;
			uint64_t mask = s->length == 64 ? UINT64_MAX :
							  ((uint64_t)1 << s->length) - 1;

			(void)hl_dbc_signal_attr(db, m, s, "HdlSource", &v);
			if (m->independent)
				continue;
			if (s->unusable) {
				if ((flags & HL_DBC_STRICT) ||
				    hl_dbc_signal_set_raw(s, raw, frame, m->size) != -EMSGSIZE ||
				    hl_dbc_signal_present(m, s, frame, 64))
					abort();
				continue;
			}
			if (hl_dbc_signal_set_raw(s, raw, frame, m->size) < 0 ||
			    hl_dbc_signal_get_raw(s, frame, m->size, &back) < 0)
				abort();
			if ((back & mask) != (raw & mask))
				abort();
		}
		(void)hl_dbc_message_attr(db, m, "HdlE2E", &v);
	}
	free(vals);
	hl_dbc_free(db);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	check(data, size, 0);
	check(data, size, HL_DBC_STRICT);
	return 0;
}
