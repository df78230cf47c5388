/* SPDX-License-Identifier: MIT */
/*
 * hdlamp dbc encode: one candump -L line of a message from SIGNAL=VALUE arguments, its E2E
 * protection computed on request. Apart from the dispatcher (cmd_dbc.c) because it is one of
 * the larger subcommands.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "can/candump.h"
#include "can/e2e.h"
#include "dbc/database.h"
#include "tools/cmd_dbc.h"
#include "tools/commands.h"

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

int encode(const char *dbc_path, unsigned flags, const char *msg_name, bool e2e, long counter,
	   int64_t t_us, const char *iface, int n_args, char **args)
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
