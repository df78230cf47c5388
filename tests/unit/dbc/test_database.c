/* SPDX-License-Identifier: MIT */
/*
 * dbc/database.c: the database object's own functions: the ID table (standard and extended
 * IDs apart, the independent-signals message never on the bus), lookups by name and index,
 * attribute values (the last BA_, else the default, else -ENOENT), and lookup plus decode of a
 * frame with its counters. Parsing and the codec are test_parse.c's and test_codec.c's.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "dbc/database.h"

static const char text[] = "VERSION \"7\"\n"
			   "BU_: ECU Lamp\n"
			   "VAL_TABLE_ OnOff 1 \"On\" 0 \"Off\" ;\n"
			   "VAL_TABLE_ Mode 2 \"Auto\" ;\n"
			   "BO_ 100 Std: 2 ECU\n"
			   " SG_ Speed : 0|16@1+ (0.5,-10) [0|0] \"km/h\" Lamp\n"
			   "BO_ 2147483748 Ext: 1 Lamp\n" /* 100 | 0x80000000: extended ID 100 */
			   " SG_ a : 0|4@1+ (1,0) [0|0] \"\" ECU\n"
			   " SG_ b : 4|4@1+ (1,0) [0|0] \"\" ECU\n"
			   " SG_ c : 7|1@0+ (1,0) [0|0] \"\" ECU\n"
			   "BO_ 101 Empty: 0 ECU\n"
			   "BO_ 3221225472 VECTOR__INDEPENDENT_SIG_MSG: 0 Vector__XXX\n"
			   " SG_ Orphan : 0|8@1+ (1,0) [0|0] \"\" Vector__XXX\n"
			   "CM_ BU_ Lamp \"the lamp\";\n"
			   "BA_DEF_ \"Bus\" STRING ;\n"
			   "BA_DEF_ BU_ \"Addr\" HEX 0 255;\n"
			   "BA_DEF_ BO_ \"Cycle\" INT 0 10000;\n"
			   "BA_DEF_ BO_ \"NoDefault\" INT 0 10;\n"
			   "BA_DEF_ SG_ \"Scale\" FLOAT 0 10;\n"
			   "BA_DEF_DEF_ \"Cycle\" 100;\n"
			   "BA_DEF_DEF_ \"Scale\" 1.5;\n"
			   "BA_ \"Bus\" \"body\";\n"
			   "BA_ \"Addr\" BU_ Lamp 42;\n"
			   "BA_ \"Cycle\" BO_ 100 20;\n"
			   "BA_ \"Cycle\" BO_ 100 40;\n"
			   "BA_ \"Scale\" SG_ 2147483748 b 2.5;\n";

static struct hl_dbc *parse(const char *t)
{
	struct hl_dbc *db = NULL;
	struct hl_dbc_error err;
	int rc = hl_dbc_parse(t, strlen(t), &db, &err);

	if (rc < 0)
		fail_msg("%d:%d: %s", err.line, err.column, err.msg);
	return db;
}

/* The same ID as standard and as extended are two messages; the independent-signals pseudo
 * message is in the list but never found by ID. */
static void database_find_id_tells_standard_from_extended(void **state)
{
	struct hl_dbc *db = parse(text);
	const struct hl_dbc_message *std, *ext, *ind;

	(void)state;
	assert_int_equal(hl_dbc_n_messages(db), 4);
	std = hl_dbc_find_id(db, 100);
	ext = hl_dbc_find_id(db, 100 | HL_DBC_EFF_FLAG);
	assert_non_null(std);
	assert_non_null(ext);
	assert_string_equal(std->name, "Std");
	assert_false(std->extended);
	assert_int_equal(std->can_id, 100);
	assert_string_equal(ext->name, "Ext");
	assert_true(ext->extended);
	assert_int_equal(ext->id, 100);
	assert_int_equal(ext->can_id, 100u | HL_DBC_EFF_FLAG);
	assert_ptr_equal(hl_dbc_find_id(db, 101), hl_dbc_message(db, 2));
	assert_null(hl_dbc_find_id(db, 102));
	assert_null(hl_dbc_find_id(db, 101 | HL_DBC_EFF_FLAG));
	ind = hl_dbc_message(db, 3);
	assert_true(ind->independent);
	assert_null(hl_dbc_find_id(db, ind->can_id));
	hl_dbc_free(db);
	hl_dbc_free(NULL);
}

/* Many IDs that share hash slots: every one is found, and no ID that is not there. */
static void database_find_id_finds_every_message_of_a_large_table(void **state)
{
	enum { N = 300 };
	size_t size = (size_t)N * 64, n = 0;
	char *t = malloc(size);
	struct hl_dbc *db;

	(void)state;
	assert_non_null(t);
	for (int i = 0; i < N; i++) /* standard 0..149 and extended 0x10000 + 64 * i */
		n += (size_t)snprintf(t + n, size - n, "BO_ %u M%d: 0 ECU\n",
				      i < N / 2 ? (unsigned)i :
						  (0x10000u + 64u * (unsigned)i) | HL_DBC_EFF_FLAG,
				      i);
	assert_true(n < size);
	db = parse(t);
	assert_int_equal(hl_dbc_n_messages(db), N);
	for (int i = 0; i < N; i++) {
		const uint32_t id = i < N / 2 ? (uint32_t)i :
						(0x10000u + 64u * (uint32_t)i) | HL_DBC_EFF_FLAG;
		const struct hl_dbc_message *m = hl_dbc_find_id(db, id);
		char name[16];

		snprintf(name, sizeof(name), "M%d", i);
		assert_non_null(m);
		assert_string_equal(m->name, name);
		assert_ptr_equal(m, hl_dbc_message(db, i));
		assert_ptr_equal(hl_dbc_find_message(db, name), m);
	}
	assert_null(hl_dbc_find_id(db, N / 2));
	assert_null(hl_dbc_find_id(db, 0 | HL_DBC_EFF_FLAG));
	assert_null(hl_dbc_find_id(db, 0x10000u + 64u * N));
	hl_dbc_free(db);
	free(t);
}

/* Names are exact (case counts); indexes outside the lists give NULL. */
static void database_lookups_by_name_and_index_are_exact(void **state)
{
	struct hl_dbc *db = parse(text);
	const struct hl_dbc_message *ext = hl_dbc_find_message(db, "Ext");
	const struct hl_dbc_value_desc *vd = NULL;
	int n = -1, line = -1, col = -1;

	(void)state;
	assert_string_equal(hl_dbc_version(db), "7");
	assert_null(hl_dbc_comment(db));
	assert_null(hl_dbc_find_message(db, "ext"));
	assert_null(hl_dbc_find_message(db, "Ex"));
	assert_null(hl_dbc_find_message(db, ""));
	assert_ptr_equal(hl_dbc_find_signal(ext, "b"), &ext->signals[1]);
	assert_int_equal(hl_dbc_find_signal(ext, "b")->index, 1);
	assert_null(hl_dbc_find_signal(ext, "B"));
	assert_null(hl_dbc_find_signal(hl_dbc_find_message(db, "Empty"), "a"));
	assert_int_equal(hl_dbc_max_signals(db), 3);

	assert_null(hl_dbc_message(db, -1));
	assert_null(hl_dbc_message(db, 4));
	assert_int_equal(hl_dbc_n_nodes(db), 2);
	assert_string_equal(hl_dbc_node(db, 1), "Lamp");
	assert_null(hl_dbc_node_comment(db, 0));
	assert_string_equal(hl_dbc_node_comment(db, 1), "the lamp");
	assert_null(hl_dbc_node(db, 2));
	assert_null(hl_dbc_node(db, -1));
	assert_null(hl_dbc_node_comment(db, 2));

	assert_int_equal(hl_dbc_n_value_tables(db), 2);
	assert_string_equal(hl_dbc_value_table(db, 1, &n, &vd), "Mode");
	assert_int_equal(n, 1);
	assert_int_equal(vd[0].value, 2);
	assert_string_equal(vd[0].desc, "Auto");
	n = -1;
	vd = NULL;
	assert_null(hl_dbc_value_table(db, 2, &n, &vd));
	assert_null(hl_dbc_value_table(db, -1, &n, &vd));
	assert_int_equal(n, -1);
	assert_null(vd);

	assert_int_equal(hl_dbc_n_attr_defs(db), 5);
	assert_string_equal(hl_dbc_attr_def(db, 4)->name, "Scale");
	assert_null(hl_dbc_attr_def(db, 5));
	assert_null(hl_dbc_attr_def(db, -1));
	assert_int_equal(hl_dbc_n_warnings(db), 0);
	assert_null(hl_dbc_warning(db, 0, &line, &col));
	assert_null(hl_dbc_warning(db, -1, NULL, NULL));
	assert_int_equal(line, -1);
	assert_int_equal(col, -1);
	hl_dbc_free(db);
}

/* The last BA_ wins (0); unset, the BA_DEF_DEF_ default (1); no default, another kind of object
 * or an unknown name or node: -ENOENT. */
static void database_attr_is_the_last_assignment_else_the_default(void **state)
{
	struct hl_dbc *db = parse(text);
	const struct hl_dbc_message *std = hl_dbc_find_message(db, "Std");
	const struct hl_dbc_message *ext = hl_dbc_find_message(db, "Ext");
	struct hl_dbc_attr_value v;

	(void)state;
	assert_int_equal(hl_dbc_network_attr(db, "Bus", &v), 0);
	assert_int_equal(v.type, HL_DBC_ATTR_STRING);
	assert_string_equal(v.s, "body");
	assert_int_equal(hl_dbc_node_attr(db, "Lamp", "Addr", &v), 0);
	assert_int_equal(v.type, HL_DBC_ATTR_HEX);
	assert_int_equal(v.i, 42);
	assert_int_equal(hl_dbc_node_attr(db, "ECU", "Addr", &v), -ENOENT);
	assert_int_equal(hl_dbc_node_attr(db, "Nobody", "Addr", &v), -ENOENT);

	assert_int_equal(hl_dbc_message_attr(db, std, "Cycle", &v), 0);
	assert_int_equal(v.type, HL_DBC_ATTR_INT);
	assert_int_equal(v.i, 40);
	assert_int_equal(hl_dbc_message_attr(db, ext, "Cycle", &v), 1);
	assert_int_equal(v.i, 100);
	assert_int_equal(hl_dbc_message_attr(db, ext, "NoDefault", &v), -ENOENT);
	assert_int_equal(hl_dbc_message_attr(db, ext, "Scale", &v), -ENOENT); /* a signal's */
	assert_int_equal(hl_dbc_message_attr(db, ext, "Nope", &v), -ENOENT);
	assert_int_equal(hl_dbc_network_attr(db, "Cycle", &v), -ENOENT);

	assert_int_equal(hl_dbc_signal_attr(db, ext, &ext->signals[1], "Scale", &v), 0);
	assert_int_equal(v.type, HL_DBC_ATTR_FLOAT);
	assert_true(v.f == 2.5);
	assert_int_equal(hl_dbc_signal_attr(db, ext, &ext->signals[0], "Scale", &v), 1);
	assert_true(v.f == 1.5);
	/* the same signal index in another message is another signal */
	assert_int_equal(hl_dbc_signal_attr(db, std, &std->signals[0], "Scale", &v), 1);
	assert_true(v.f == 1.5);
	assert_int_equal(hl_dbc_signal_attr(db, ext, &ext->signals[1], "Cycle", &v), -ENOENT);
	hl_dbc_free(db);
}

/* Lookup plus decode: the values, and each outcome counted once in the caller's counters. */
static void database_decode_frame_counts_each_outcome(void **state)
{
	struct hl_dbc *db = parse(text);
	struct hl_dbc_counters cnt = { 0 };
	const struct hl_dbc_message *m = NULL;
	struct hl_dbc_value v[3];
	const uint8_t speed[2] = { 0x2c, 0x01 }; /* 300 raw: 300 * 0.5 - 10 = 140 km/h */
	const uint8_t bits[1] = { 0xa5 };

	(void)state;
	assert_int_equal(hl_dbc_decode_frame(db, 100, speed, 2, &cnt, &m, v), 1);
	assert_string_equal(m->name, "Std");
	assert_int_equal(v[0].signal, 0);
	assert_int_equal(v[0].raw, 300);
	assert_true(v[0].phys == 140.0);

	assert_int_equal(hl_dbc_decode_frame(db, 100 | HL_DBC_EFF_FLAG, bits, 1, &cnt, &m, v), 3);
	assert_string_equal(m->name, "Ext");
	assert_int_equal(v[0].raw, 0x5);
	assert_int_equal(v[1].raw, 0xa);
	assert_int_equal(v[2].raw, 1);

	m = NULL;
	assert_int_equal(hl_dbc_decode_frame(db, 0x123, speed, 2, &cnt, &m, v), -ENOENT);
	assert_null(m);
	assert_int_equal(hl_dbc_decode_frame(db, 0xC0000000u, bits, 1, &cnt, &m, v), -ENOENT);
	assert_null(m);
	/* short: the message is named, nothing decoded */
	v[0].raw = 77;
	assert_int_equal(hl_dbc_decode_frame(db, 100, speed, 1, &cnt, &m, v), -EMSGSIZE);
	assert_non_null(m);
	assert_string_equal(m->name, "Std");
	assert_int_equal(v[0].raw, 77);
	/* a frame longer than its message is fine; an empty message decodes to nothing */
	assert_int_equal(hl_dbc_decode_frame(db, 100, speed, 2, &cnt, &m, v), 1);
	assert_int_equal(hl_dbc_decode_frame(db, 101, bits, 0, &cnt, &m, v), 0);
	assert_string_equal(m->name, "Empty");

	assert_int_equal(cnt.decoded, 4);
	assert_int_equal(cnt.unknown_id, 2);
	assert_int_equal(cnt.short_frame, 1);
	/* no counters */
	assert_int_equal(hl_dbc_decode_frame(db, 100, speed, 2, NULL, &m, v), 1);
	assert_int_equal(hl_dbc_decode_frame(db, 7, speed, 2, NULL, &m, v), -ENOENT);
	assert_int_equal(hl_dbc_decode_frame(db, 100, speed, 0, NULL, &m, v), -EMSGSIZE);
	hl_dbc_free(db);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(database_find_id_tells_standard_from_extended),
		cmocka_unit_test(database_find_id_finds_every_message_of_a_large_table),
		cmocka_unit_test(database_lookups_by_name_and_index_are_exact),
		cmocka_unit_test(database_attr_is_the_last_assignment_else_the_default),
		cmocka_unit_test(database_decode_frame_counts_each_outcome),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
