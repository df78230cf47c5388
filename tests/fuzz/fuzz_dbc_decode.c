/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target: decoding any frame with the shipped databases and a database of every
 * signal kind never reads out of bounds and stays consistent; and the candump line reader
 * (the decoder's input) never crashes, and what it reads formats back to a line that reads
 * as the same frame.
 *
 * Input: byte 0 picks the database, bytes 1..4 the CAN ID (bit 7 of byte 0: take the ID of a
 * message of that database instead), byte 5 the length, the rest the payload; the whole input
 * is also tried as one candump line.
 */
#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "can/candump.h"
#include "can/e2e.h"
#include "dbc/database.h"

static const char kinds_dbc[] = "BO_ 200 Mux: 8 ECU\n"
				" SG_ Sel M : 0|8@1+ (1,0) [0|255] \"\" X\n"
				" SG_ A m0 : 8|16@1+ (1,0) [0|0] \"\" X\n"
				" SG_ Sub m2M : 8|8@1+ (1,0) [0|0] \"\" X\n"
				" SG_ C m3 : 16|8@1- (0.5,-3) [0|0] \"\" X\n"
				" SG_ M : 39|12@0- (1,0) [0|0] \"\" X\n"
				"BO_ 2566848766 Kinds: 64 ECU\n"
				" SG_ I64 : 4|64@1- (1,0) [0|0] \"\" X\n"
				" SG_ M64 : 75|64@0+ (1,0) [0|0] \"\" X\n"
				" SG_ F : 200|32@1- (1,0) [0|0] \"\" X\n"
				" SG_ D : 447|64@0- (1,0) [0|0] \"\" X\n"
				" SG_ Bit : 511|1@0+ (1,0) [0|0] \"\" X\n"
				"SIG_VALTYPE_ 2566848766 F : 1;\n"
				"SIG_VALTYPE_ 2566848766 D : 2;\n"
				"SG_MUL_VAL_ 200 C Sub 3-3, 5-7;\n"
				"SG_MUL_VAL_ 200 Sub Sel 2-2;\n"
				/* loaded leniently: signals past the message's 2 bytes are
				 * never decoded, nor what they multiplex */
				"BO_ 300 Short: 2 ECU\n"
				" SG_ Sel M : 0|4@1+ (1,0) [0|0] \"\" X\n"
				" SG_ Ok m1 : 8|8@1+ (1,0) [0|0] \"\" X\n"
				" SG_ Past m1 : 500|12@1+ (1,0) [0|0] \"\" X\n"
				" SG_ PastMux m2M : 15|16@0+ (1,0) [0|0] \"\" X\n"
				" SG_ Under m3 : 4|4@1+ (1,0) [0|0] \"\" X\n"
				"SG_MUL_VAL_ 300 Under PastMux 3-3;\n";

static struct hl_dbc *dbs[3];
static struct hl_dbc_value vals[256];

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	(void)argc;
	(void)argv;
	if (hl_dbc_parse_file(HL_DBC_DIR "/hd84.dbc", &dbs[0], NULL) < 0 ||
	    hl_dbc_parse_file(HL_DBC_DIR "/hd84_fd.dbc", &dbs[1], NULL) < 0 ||
	    hl_dbc_parse(kinds_dbc, strlen(kinds_dbc), &dbs[2], NULL) < 0)
		abort();
	return 0;
}

static void decode(const uint8_t *data, size_t size)
{
	struct hl_dbc *db;
	struct hl_dbc_counters c = { 0 };
	const struct hl_dbc_message *m = NULL;
	uint32_t id;
	size_t len;
	uint8_t *payload;
	int n;

	if (size < 6)
		return;
	db = dbs[(data[0] & 0x7f) % 3];
	id = (uint32_t)data[1] << 24 | (uint32_t)data[2] << 16 | (uint32_t)data[3] << 8 | data[4];
	if (data[0] & 0x80)
		id = hl_dbc_message(db, id % hl_dbc_n_messages(db))->can_id;
	len = data[5] % 65;
	if (len > size - 6)
		len = size - 6;
	/* an exact-size heap copy, so that ASan sees any read past the frame */
	payload = malloc(len ? len : 1);
	if (!payload)
		abort();
	memcpy(payload, data + 6, len);
	n = hl_dbc_decode_frame(db, id, payload, len, &c, &m, vals);
	if (n >= 0) {
		if (len < (size_t)m->size || n > m->n_signals || c.decoded != 1)
			abort();
		for (int k = 0; k < n; k++) {
			const struct hl_dbc_signal *s = &m->signals[vals[k].signal];
			uint64_t raw;

			if (s->unusable)
				abort();
			if (hl_dbc_signal_get_raw(s, payload, len, &raw) < 0 || raw != vals[k].raw)
				abort();
			if (!hl_dbc_signal_present(m, s, payload, len))
				abort();
		}
	} else if (n == -EMSGSIZE) {
		if (len >= (size_t)m->size || c.short_frame != 1)
			abort();
	} else if (n != -ENOENT || c.unknown_id != 1) {
		abort();
	}
	for (int p = HL_E2E_P1; p <= HL_E2E_P5; p++) {
		struct hl_e2e_config cfg = { p, 0x1234 };
		int rc = hl_e2e_check(&cfg, payload, len);

		if (len < hl_e2e_min_len(p) ? rc != -EMSGSIZE : (rc != 0 && rc != -EBADMSG))
			abort();
	}
	free(payload);
}

static void candump(const uint8_t *data, size_t size)
{
	struct hl_candump_frame f, g;
	struct hl_candump_error err;
	char line[HL_CANDUMP_MAX_LINE];
	int n;

	if (hl_candump_parse((const char *)data, size, &f, &err) < 0) {
		if (err.column < 1 || (size_t)err.column > size + 1 || !err.msg[0])
			abort();
		return;
	}
	n = hl_candump_format(&f, line, sizeof(line));
	if (n < 0 || hl_candump_parse(line, n, &g, &err) < 0)
		abort();
	if (memcmp(&f.frame, &g.frame, sizeof(f.frame)) != 0 || f.t_us != g.t_us ||
	    strcmp(f.iface, g.iface) != 0 || f.fd != g.fd || f.len8_dlc != g.len8_dlc ||
	    f.dir != g.dir)
		abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	decode(data, size);
	candump(data, size);
	return 0;
}
