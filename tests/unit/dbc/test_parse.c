/* SPDX-License-Identifier: MIT */
/* dbc/parse: every section into the database, and every parse error with line and column. */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "dbc/database.h"

static const char sample[] =
	"VERSION \"1.2.3\"\n"
	"\n"
	"NS_ :\n"
	"\tNS_DESC_\n"
	"\tCM_\n"
	"\n"
	"BS_:\n"
	"\n"
	"BU_: ECU Lamp Tester\n"
	"VAL_TABLE_ OnOff 1 \"On\" 0 \"Off\" ;\n"
	"\n"
	"BO_ 100 Simple: 8 ECU\n" /* line 12 */
	" SG_ Speed : 0|16@1+ (0.01,0) [0|655.35] \"km/h\" Lamp,Tester\n"
	" SG_ Temp : 16|8@1- (1,-40) [-168|87] \"degC\" Lamp\n"
	"\n"
	"BO_ 2566848766 ExtMsg: 8 Lamp\n" /* line 16: 0x98FF00FE */
	" SG_ Flag : 7|1@0+ (1,0) [0|1] \"\" Vector__XXX\n"
	"\n"
	"BO_ 200 Mux: 8 ECU\n" /* line 19 */
	" SG_ Sel M : 0|8@1+ (1,0) [0|255] \"\" Lamp\n"
	" SG_ A m0 : 8|16@1+ (1,0) [0|0] \"\" Lamp\n"
	" SG_ B m1 : 8|8@1+ (1,0) [0|0] \"\" Lamp\n"
	" SG_ Sub m2M : 8|8@1+ (1,0) [0|0] \"\" Lamp\n"
	" SG_ C m3 : 16|8@1+ (1,0) [0|0] \"\" Lamp\n"
	"\n"
	"BO_ 300 Floats: 16 ECU\n"
	" SG_ F : 0|32@1- (1,0) [0|0] \"\" Lamp\n"
	" SG_ D : 64|64@1- (1,0) [0|0] \"\" Lamp\n"
	"\n"
	"BO_ 3221225472 VECTOR__INDEPENDENT_SIG_MSG: 0 Vector__XXX\n"
	" SG_ Orphan : 0|8@1+ (1,0) [0|0] \"\" Vector__XXX\n"
	"\n"
	"BO_TX_BU_ 100 : ECU,Tester;\n"
	"\n"
	"EV_ Foo: 0 [0|1] \"\" 0 1 DUMMY_NODE_VECTOR0 Vector__XXX;\n" /* line 35 */
	"CM_ \"network\n comment\";\n"
	"CM_ BU_ Lamp \"the lamp\";\n"
	"CM_ BO_ 100 \"simple message\";\n"
	"CM_ SG_ 100 Speed \"vehicle \\\"speed\\\"\";\n"
	"CM_ EV_ Foo \"ignored\";\n"
	"BA_DEF_  \"DBName\" STRING ;\n"
	"BA_DEF_ BU_  \"NodeAddr\" HEX 0 255;\n"
	"BA_DEF_ BO_  \"GenMsgCycleTime\" INT 0 10000;\n"
	"BA_DEF_ SG_  \"Scale\" FLOAT -1.5 1E+1;\n"
	"BA_DEF_ BO_  \"SendType\" ENUM  \"Cyclic\",\"Event\";\n"
	"BA_DEF_ EV_  \"EvAttr\" INT 0 1;\n"
	"BA_DEF_DEF_  \"DBName\" \"\";\n"
	"BA_DEF_DEF_  \"GenMsgCycleTime\" 100;\n"
	"BA_DEF_DEF_  \"SendType\" \"Cyclic\";\n"
	"BA_ \"DBName\" \"testdb\";\n"
	"BA_ \"NodeAddr\" BU_ Lamp 42;\n"
	"BA_ \"GenMsgCycleTime\" BO_ 100 20;\n"
	"BA_ \"Scale\" SG_ 100 Speed 2.5;\n"
	"BA_ \"SendType\" BO_ 200 1;\n"
	"BA_ \"EvAttr\" EV_ Foo 1;\n"
	"VAL_ 100 Temp -40 \"very cold\" 0 \"zero\" ;\n"
	"VAL_ Foo 0 \"env\" ;\n"
	"SIG_VALTYPE_ 300 F : 1;\n"
	"SIG_VALTYPE_ 300 D : 2;\n"
	"SG_MUL_VAL_ 200 C Sub 3-3, 5-7;\n"
	"SG_MUL_VAL_ 200 Sub Sel 2-2;\n"
	"BU_SG_REL_ SG_ \"x\" ECU;\n" /* line 63: the network comment has two */
	"// a line comment\n";

static struct hl_dbc *parse(const char *text)
{
	struct hl_dbc *db = NULL;
	struct hl_dbc_error err;
	int rc = hl_dbc_parse(text, strlen(text), &db, &err);

	if (rc < 0)
		print_error("%d:%d: %s\n", err.line, err.column, err.msg);
	assert_int_equal(rc, 0);
	return db;
}

static void dbc_parse_every_section(void **state)
{
	struct hl_dbc *db = parse(sample);
	const struct hl_dbc_message *m;
	const struct hl_dbc_signal *s;

	(void)state;
	assert_string_equal(hl_dbc_version(db), "1.2.3");
	assert_string_equal(hl_dbc_comment(db), "network\n comment");
	assert_int_equal(hl_dbc_n_nodes(db), 3);
	assert_string_equal(hl_dbc_node(db, 2), "Tester");
	assert_string_equal(hl_dbc_node_comment(db, 1), "the lamp");
	assert_int_equal(hl_dbc_n_messages(db), 5);

	m = hl_dbc_find_message(db, "Simple");
	assert_non_null(m);
	assert_int_equal(m->id, 100);
	assert_false(m->extended);
	assert_int_equal(m->can_id, 100);
	assert_int_equal(m->size, 8);
	assert_string_equal(m->transmitter, "ECU");
	assert_int_equal(m->line, 12);
	assert_string_equal(m->comment, "simple message");
	assert_int_equal(m->n_tx_nodes, 2);
	assert_string_equal(m->tx_nodes[1], "Tester");
	assert_int_equal(m->n_signals, 2);
	s = &m->signals[0];
	assert_string_equal(s->name, "Speed");
	assert_int_equal(s->start_bit, 0);
	assert_int_equal(s->length, 16);
	assert_int_equal(s->order, HL_DBC_INTEL);
	assert_false(s->is_signed);
	assert_true(s->factor == 0.01);
	assert_true(s->max == 655.35);
	assert_string_equal(s->unit, "km/h");
	assert_int_equal(s->n_receivers, 2);
	assert_string_equal(s->receivers[0], "Lamp");
	assert_string_equal(s->receivers[1], "Tester");
	assert_string_equal(s->comment, "vehicle \"speed\"");
	assert_int_equal(s->mux_parent, -1);
	s = &m->signals[1];
	assert_true(s->is_signed);
	assert_true(s->offset == -40);
	assert_true(s->min == -168);
	assert_int_equal(s->n_values, 2);
	assert_int_equal(s->values[0].value, -40);
	assert_string_equal(s->values[0].desc, "very cold");
	assert_string_equal(s->values[1].desc, "zero");

	m = hl_dbc_find_message(db, "ExtMsg");
	assert_true(m->extended);
	assert_int_equal(m->id, 0x18ff00fe);
	assert_int_equal(m->can_id, 0x98ff00feu);
	assert_ptr_equal(hl_dbc_find_id(db, 0x18ff00fe | HL_DBC_EFF_FLAG), m);
	assert_null(hl_dbc_find_id(db, 0x18ff00fe)); /* the standard ID space is another */
	assert_int_equal(m->signals[0].order, HL_DBC_MOTOROLA);
	assert_int_equal(m->signals[0].n_receivers, 0);

	m = hl_dbc_find_message(db, "Mux");
	assert_ptr_equal(hl_dbc_find_id(db, 200), m);
	assert_true(m->signals[0].is_multiplexor);
	assert_int_equal(m->signals[1].mux_parent, 0);
	assert_int_equal(m->signals[1].n_mux_ranges, 1);
	assert_int_equal(m->signals[1].mux_ranges[0].lo, 0);
	assert_int_equal(m->signals[2].mux_ranges[0].lo, 1);
	s = hl_dbc_find_signal(m, "Sub"); /* m2M, placed by SG_MUL_VAL_ */
	assert_true(s->is_multiplexor);
	assert_int_equal(s->mux_parent, 0);
	assert_int_equal(s->mux_ranges[0].lo, 2);
	s = hl_dbc_find_signal(m, "C"); /* m3 in the SG_ line, but SG_MUL_VAL_ rules */
	assert_int_equal(s->mux_parent, 3);
	assert_int_equal(s->n_mux_ranges, 2);
	assert_int_equal(s->mux_ranges[0].lo, 3);
	assert_int_equal(s->mux_ranges[0].hi, 3);
	assert_int_equal(s->mux_ranges[1].lo, 5);
	assert_int_equal(s->mux_ranges[1].hi, 7);

	m = hl_dbc_find_message(db, "Floats");
	assert_int_equal(m->signals[0].type, HL_DBC_FLOAT);
	assert_int_equal(m->signals[1].type, HL_DBC_DOUBLE);

	m = hl_dbc_find_message(db, "VECTOR__INDEPENDENT_SIG_MSG");
	assert_true(m->independent);
	assert_null(hl_dbc_find_id(db, 0xc0000000u));
	assert_int_equal(hl_dbc_max_signals(db), 5);

	assert_int_equal(hl_dbc_n_value_tables(db), 1);
	{
		int n;
		const struct hl_dbc_value_desc *v;

		assert_string_equal(hl_dbc_value_table(db, 0, &n, &v), "OnOff");
		assert_int_equal(n, 2);
		assert_int_equal(v[0].value, 1);
		assert_string_equal(v[0].desc, "On");
	}

	/* the two skipped sections, with where they start */
	assert_int_equal(hl_dbc_n_warnings(db), 2);
	{
		int line, col;

		assert_string_equal(hl_dbc_warning(db, 0, &line, &col),
				    "skipped unknown section 'EV_'");
		assert_int_equal(line, 35);
		assert_int_equal(col, 1);
		assert_string_equal(hl_dbc_warning(db, 1, &line, &col),
				    "skipped unknown section 'BU_SG_REL_'");
		assert_int_equal(line, 63);
	}
	hl_dbc_free(db);
}

static void dbc_parse_attributes(void **state)
{
	struct hl_dbc *db = parse(sample);
	const struct hl_dbc_message *simple = hl_dbc_find_message(db, "Simple");
	const struct hl_dbc_message *mux = hl_dbc_find_message(db, "Mux");
	const struct hl_dbc_attr_def *d;
	struct hl_dbc_attr_value v;

	(void)state;
	assert_int_equal(hl_dbc_n_attr_defs(db), 6);
	d = hl_dbc_attr_def(db, 3);
	assert_string_equal(d->name, "Scale");
	assert_int_equal(d->object, HL_DBC_SIGNAL);
	assert_int_equal(d->type, HL_DBC_ATTR_FLOAT);
	assert_true(d->min == -1.5);
	assert_true(d->max == 10);
	d = hl_dbc_attr_def(db, 4);
	assert_int_equal(d->type, HL_DBC_ATTR_ENUM);
	assert_int_equal(d->n_labels, 2);
	assert_string_equal(d->labels[1], "Event");

	assert_int_equal(hl_dbc_network_attr(db, "DBName", &v), 0);
	assert_int_equal(v.type, HL_DBC_ATTR_STRING);
	assert_string_equal(v.s, "testdb");
	assert_int_equal(hl_dbc_node_attr(db, "Lamp", "NodeAddr", &v), 0);
	assert_int_equal(v.type, HL_DBC_ATTR_HEX);
	assert_int_equal(v.i, 42);
	assert_int_equal(hl_dbc_node_attr(db, "ECU", "NodeAddr", &v), -ENOENT); /* no default */
	assert_int_equal(hl_dbc_message_attr(db, simple, "GenMsgCycleTime", &v), 0);
	assert_int_equal(v.i, 20);
	assert_int_equal(hl_dbc_message_attr(db, mux, "GenMsgCycleTime", &v), 1); /* default */
	assert_int_equal(v.i, 100);
	assert_int_equal(hl_dbc_message_attr(db, mux, "SendType", &v), 0);
	assert_int_equal(v.type, HL_DBC_ATTR_ENUM);
	assert_int_equal(v.i, 1);
	assert_string_equal(v.s, "Event");
	assert_int_equal(hl_dbc_message_attr(db, simple, "SendType", &v), 1);
	assert_string_equal(v.s, "Cyclic");
	assert_int_equal(hl_dbc_signal_attr(db, simple, &simple->signals[0], "Scale", &v), 0);
	assert_true(v.f == 2.5);
	assert_int_equal(hl_dbc_signal_attr(db, simple, &simple->signals[1], "Scale", &v), -ENOENT);
	assert_int_equal(hl_dbc_message_attr(db, simple, "Scale", &v), -ENOENT); /* SG_ only */
	assert_int_equal(hl_dbc_message_attr(db, simple, "Nope", &v), -ENOENT);
	hl_dbc_free(db);
}

static void dbc_parse_shipped_databases(void **state)
{
	static const char *const files[] = { HL_DBC_DIR "/hd84.dbc", HL_DBC_DIR "/hd84_fd.dbc" };

	(void)state;
	for (int f = 0; f < 2; f++) {
		struct hl_dbc *db = NULL;
		struct hl_dbc_error err;
		int sources[2][96] = { { 0 } };

		assert_int_equal(hl_dbc_parse_file(files[f], &db, &err), 0);
		assert_int_equal(hl_dbc_n_warnings(db), 0);
		assert_int_equal(hl_dbc_n_messages(db), f == 0 ? 2 : 4);
		for (int i = 0; i < hl_dbc_n_messages(db); i++) {
			const struct hl_dbc_message *m = hl_dbc_message(db, i);
			struct hl_dbc_attr_value v;
			int lamp;

			assert_int_equal(hl_dbc_message_attr(db, m, "GenMsgCycleTime", &v), 0);
			assert_int_equal(v.i, 20);
			assert_int_equal(hl_dbc_message_attr(db, m, "HdlLamp", &v), 0);
			lamp = strcmp(v.s, "left") == 0 ? 0 : 1;
			assert_string_equal(v.s, lamp ? "right" : "left");
			assert_int_equal(hl_dbc_message_attr(db, m, "HdlE2E", &v), 0);
			assert_memory_equal(v.s, f == 0 ? "P1 dataid=0x" : "P5 dataid=0x", 12);
			for (int k = 0; k < m->n_signals; k++) {
				assert_true(hl_dbc_signal_attr(db, m, &m->signals[k], "HdlSource",
							       &v) >= 0);
				if (v.i == 0)
					continue;
				assert_true(v.i >= 1 && v.i <= 95);
				assert_true(m->signals[k].factor == 1.0 / 63);
				assert_int_equal(m->signals[k].length, 6);
				sources[lamp][v.i]++;
			}
		}
		/* each of the 95 sources of each lamp exactly once */
		for (int lamp = 0; lamp < 2; lamp++)
			for (int k = 1; k <= 95; k++)
				assert_int_equal(sources[lamp][k], 1);
		hl_dbc_free(db);
	}
}

static void dbc_parse_bom_fraction_and_last_attribute_wins(void **state)
{
	struct hl_dbc *db = parse("\xef\xbb\xbf"
				  "BO_ 1 A: 8 E\n"
				  " SG_ S : 0|8@1+ (.5,-.25) [0|1E2] \"\" X\n"
				  "BA_DEF_ BO_ \"T\" INT 0 100;\n"
				  "BA_ \"T\" BO_ 1 10;\n"
				  "BA_ \"T\" BO_ 1 20;\n");
	const struct hl_dbc_message *m = hl_dbc_message(db, 0);
	struct hl_dbc_attr_value v;

	(void)state;
	assert_true(m->signals[0].factor == 0.5);
	assert_true(m->signals[0].offset == -0.25);
	assert_true(m->signals[0].max == 100);
	assert_int_equal(hl_dbc_message_attr(db, m, "T", &v), 0);
	assert_int_equal(v.i, 20);
	hl_dbc_free(db);
}

static void dbc_parse_file_missing(void **state)
{
	struct hl_dbc *db = NULL;
	struct hl_dbc_error err;

	(void)state;
	assert_int_equal(hl_dbc_parse_file("/nonexistent/x.dbc", &db, &err), -ENOENT);
	assert_int_equal(err.line, 0);
	assert_string_equal(err.msg, "cannot open: No such file or directory");
	assert_null(db);
}

struct bad {
	const char *text;
	int line, column;
	const char *msg;
};

#define BO "BO_ 1 A: 8 E\n"
#define SG(s) " SG_ S " s " \"\" X\n"

static const struct bad bads[] = {
	/* lexer */
	{ "BO_ 1 A: 8 E\n SG_ S : 0|8@1* (1,0) [0|1] \"\" X\n", 2, 15, "unexpected character '*'" },
	{ "BO_ 1 A: 8 E\n SG_ S : 0|8@1+ (1,0) [0|1] \"abc", 2, 29,
	  "unterminated string: expected a closing '\"'" },
	/* statements */
	{ "42\n", 1, 1,
	  "expected a section keyword (BO_, SG_, CM_, BA_, VAL_, ...), found number 42" },
	{ "VERSION 1\n", 1, 9, "expected the version string after VERSION, found number 1" },
	{ "NS_ x\n", 1, 5, "expected ':' after NS_, found 'x'" },
	{ "BS_ 1\n", 1, 5, "expected ':' after BS_, found number 1" },
	{ "BU_: A B A\n", 1, 10, "node 'A' listed twice" },
	{ "VAL_TABLE_ T 1 2 ;\n", 1, 16,
	  "expected the value's description string, found number 2" },
	/* BO_ */
	{ "BO_ 2048 A: 8 E\n", 1, 5,
	  "expected a standard ID 0..2047 (extended IDs have bit 31 set), found 2048" },
	{ "BO_ 3221225473 A: 8 E\n", 1, 5,
	  "expected a 29-bit extended ID with bit 31 set, found 3221225473" },
	{ "BO_ 4294967296 A: 8 E\n", 1, 5,
	  "expected a message ID, found 4294967296 (above 4294967295)" },
	{ BO "BO_ 1 B: 8 E\n", 2, 5, "message ID 1 already used by 'A' (line 1)" },
	{ BO "BO_ 2 A: 8 E\n", 2, 7, "message name 'A' already used (line 1)" },
	{ "BO_ 1 A: 65 E\n", 1, 10,
	  "expected the message size in bytes (0..64), found 65 (above 64)" },
	{ "BO_ 1 A 8 E\n", 1, 9, "expected ':' after the message name, found number 8" },
	{ "BO_ 1 A: 8\n", 2, 1,
	  "expected the transmitting node (or Vector__XXX), found end of file" },
	{ "BO_ x A: 8 E\n", 1, 5, "expected a message ID, found 'x'" },
	/* SG_ */
	{ "SG_ S : 0|8@1+ (1,0) [0|1] \"\" X\n", 1, 1,
	  "SG_ outside a message: expected a BO_ line before it" },
	{ BO " SG_ 5 : 0|8@1+ (1,0) [0|1] \"\" X\n", 2, 6,
	  "expected the signal name, found number 5" },
	{ BO SG(": 0|8@1+ (1,0) [0|1]") SG(": 8|8@1+ (1,0) [0|1]"), 3, 6,
	  "signal 'S' already defined in message 'A'" },
	{ BO SG("x : 0|8@1+ (1,0) [0|1]"), 2, 8,
	  "expected ':' or a multiplex indicator (M, m<n>, m<n>M), found 'x'" },
	{ BO SG("m1X : 0|8@1+ (1,0) [0|1]"), 2, 8,
	  "expected ':' or a multiplex indicator (M, m<n>, m<n>M), found 'm1X'" },
	{ BO SG("0|8@1+ (1,0) [0|1]"), 2, 8, "expected ':' after the signal name, found number 0" },
	{ BO SG(": 512|8@1+ (1,0) [0|1]"), 2, 10,
	  "expected the start bit (0..511), found 512 (above 511)" },
	{ BO SG(": 0 8@1+ (1,0) [0|1]"), 2, 12,
	  "expected '|' between start bit and length, found number 8" },
	{ BO SG(": 0|0@1+ (1,0) [0|1]"), 2, 12, "expected the length in bits (1..64), found 0" },
	{ BO SG(": 0|65@1+ (1,0) [0|1]"), 2, 12,
	  "expected the length in bits (1..64), found 65 (above 64)" },
	{ BO SG(": 0|8 1+ (1,0) [0|1]"), 2, 14,
	  "expected '@' before the byte order, found number 1" },
	{ BO SG(": 0|8@2+ (1,0) [0|1]"), 2, 14,
	  "expected the byte order 0 (Motorola) or 1 (Intel) after '@', found number 2" },
	{ BO SG(": 0|8@1 (1,0) [0|1]"), 2, 16,
	  "expected '+' (unsigned) or '-' (signed) after the byte order, found '('" },
	{ BO SG(": 0|8@1+ 1,0) [0|1]"), 2, 17,
	  "expected '(' before factor and offset, found number 1" },
	{ BO SG(": 0|8@1+ (x,0) [0|1]"), 2, 18, "expected the factor, found 'x'" },
	{ BO SG(": 0|8@1+ (0,0) [0|1]"), 2, 18, "expected a non-zero factor, found 0" },
	{ BO SG(": 0|8@1+ (1 0) [0|1]"), 2, 20,
	  "expected ',' between factor and offset, found number 0" },
	{ BO SG(": 0|8@1+ (1,) [0|1]"), 2, 20, "expected the offset, found ')'" },
	{ BO SG(": 0|8@1+ (1,0 [0|1]"), 2, 22, "expected ')' after the offset, found '['" },
	{ BO SG(": 0|8@1+ (1,0) 0|1]"), 2, 23,
	  "expected '[' before minimum and maximum, found number 0" },
	{ BO SG(": 0|8@1+ (1,0) [|1]"), 2, 24, "expected the minimum, found '|'" },
	{ BO SG(": 0|8@1+ (1,0) [0 1]"), 2, 26,
	  "expected '|' between minimum and maximum, found number 1" },
	{ BO SG(": 0|8@1+ (1,0) [0|]"), 2, 26, "expected the maximum, found ']'" },
	{ BO SG(": 0|8@1+ (1,0) [0|1"), 2, 28, "expected ']' after the maximum, found a string" },
	{ BO " SG_ S : 0|8@1+ (1,0) [0|1] X\n", 2, 29, "expected the unit string, found 'X'" },
	{ BO SG(": 60|8@1+ (1,0) [0|1]"), 2, 10,
	  "signal 'S' (start bit 60, 8 bits, Intel) does not fit the 8 bytes of message 'A'" },
	{ "BO_ 1 A: 1 E\n" SG(": 0|2@0+ (1,0) [0|1]"), 2, 10,
	  "signal 'S' (start bit 0, 2 bits, Motorola) does not fit the 1 bytes of message 'A'" },
	/* multiplexing, checked after parsing */
	{ BO SG("m1 : 0|8@1+ (1,0) [0|1]"), 2, 8,
	  "signal 'S' is multiplexed (m<n>) but message 'A' has no multiplexor (M)" },
	{ BO " SG_ P M : 0|4@1+ (1,0) [0|1] \"\" X\n SG_ Q M : 4|4@1+ (1,0) [0|1] \"\" X\n" SG(
		  "m1 : 8|8@1+ (1,0) [0|1]"),
	  4, 8,
	  "signal 'S' is multiplexed (m<n>) but message 'A' has several multiplexors: expected an SG_MUL_VAL_ naming one" },
	{ BO " SG_ P m1M : 0|4@1+ (1,0) [0|1] \"\" X\n SG_ Q m1M : 4|4@1+ (1,0) [0|1] \"\" X\n"
	     "SG_MUL_VAL_ 1 P Q 1-1;\nSG_MUL_VAL_ 1 Q P 1-1;\n",
	  4, 1, "the multiplexor chain of signal 'P' in message 'A' loops" },
	/* SG_MUL_VAL_ */
	{ BO " SG_ P M : 0|4@1+ (1,0) [0|1] \"\" X\n" SG(
		  "m1 : 8|8@1+ (1,0) [0|1]") "SG_MUL_VAL_ 1 S S 1-1;\n",
	  4, 17, "expected a multiplexor (M or m<n>M) of message 'A', found 'S'" },
	{ BO " SG_ P M : 0|4@1+ (1,0) [0|1] \"\" X\n" SG(
		  "m1 : 8|8@1+ (1,0) [0|1]") "SG_MUL_VAL_ 1 S P 5-3;\n",
	  4, 19, "expected a range lo-hi with lo <= hi, found 5-3" },
	{ BO " SG_ P M : 0|4@1+ (1,0) [0|1] \"\" X\n" SG(
		  "m1 : 8|8@1+ (1,0) [0|1]") "SG_MUL_VAL_ 1 S P 3 4;\n",
	  4, 21, "expected '-' inside the range lo-hi, found number 4" },
	{ BO " SG_ P M : 0|4@1+ (1,0) [0|1] \"\" X\n" SG(
		  "m1 : 8|8@1+ (1,0) [0|1]") "SG_MUL_VAL_ 1 S P ;\n",
	  4, 19, "expected at least one multiplexor value range lo-hi, found ';'" },
	{ BO " SG_ P M : 0|4@1+ (1,0) [0|1] \"\" X\n" SG(
		  "m1 : 8|8@1+ (1,0) [0|1]") "SG_MUL_VAL_ 1 S P 1-1;\nSG_MUL_VAL_ 1 S P 2-2;\n",
	  5, 1, "SG_MUL_VAL_ for signal 'S' given twice (line 4)" },
	/* references */
	{ "CM_ BO_ 5 \"x\";\n", 1, 9, "expected the ID of a message defined by BO_, found 5" },
	{ BO "CM_ SG_ 1 Nope \"x\";\n", 2, 11, "expected a signal of message 'A', found 'Nope'" },
	{ "CM_ BU_ Nope \"x\";\n", 1, 9, "expected a node listed in BU_, found 'Nope'" },
	{ "CM_ \"x\"", 1, 8, "expected ';' after the comment, found end of file" },
	{ "CM_ 5 \"x\";\n", 1, 5,
	  "expected a comment string or BU_, BO_, SG_, EV_ after CM_, found number 5" },
	{ BO "BO_TX_BU_ 1 : A B;\n", 2, 17, "expected ',' or ';' after a node, found 'B'" },
	/* attributes */
	{ "BA_DEF_ BO_ \"X\" BOOL;\n", 1, 17,
	  "expected the attribute type INT, HEX, FLOAT, STRING or ENUM, found 'BOOL'" },
	{ "BA_DEF_ BO_ \"X\" STRING;\nBA_DEF_ SG_ \"X\" STRING;\n", 2, 13,
	  "attribute 'X' already defined" },
	{ "BA_DEF_ BO_ \"X\" ENUM \"a\" \"b\";\n", 1, 26,
	  "expected ',' or ';' after an enum label, found a string" },
	{ "BA_DEF_ BO_ \"X\" INT 0 10\n", 2, 1,
	  "expected ';' after the attribute definition, found end of file" },
	{ "BA_DEF_DEF_ \"X\" 1;\n", 1, 13,
	  "expected an attribute defined by BA_DEF_, found \"X\"" },
	{ BO "BA_ \"Nope\" BO_ 1 3;\n", 2, 5,
	  "expected an attribute defined by BA_DEF_, found \"Nope\"" },
	{ BO SG(": 0|8@1+ (1,0) [0|1]") "BA_DEF_ BO_ \"X\" INT 0 10;\nBA_ \"X\" SG_ 1 S 3;\n", 4, 9,
	  "attribute 'X' is defined for messages (BO_), not for signals (SG_)" },
	{ BO "BA_DEF_ BO_ \"X\" INT 0 10;\nBA_ \"X\" BO_ 1 11;\n", 3, 15,
	  "expected a value in [0, 10] for 'X', found 11" },
	{ BO "BA_DEF_ BO_ \"X\" INT 0 10;\nBA_ \"X\" BO_ 1 \"a\";\n", 3, 15,
	  "expected an integer value, found a string" },
	{ BO "BA_DEF_ BO_ \"X\" FLOAT 0 1;\nBA_ \"X\" BO_ 1 1.5;\n", 3, 15,
	  "expected a value in [0, 1] for 'X', found 1.5" },
	{ BO "BA_DEF_ BO_ \"X\" STRING;\nBA_ \"X\" BO_ 1 7;\n", 3, 15,
	  "expected a string value, found number 7" },
	{ BO "BA_DEF_ BO_ \"X\" ENUM \"a\",\"b\";\nBA_ \"X\" BO_ 1 2;\n", 3, 15,
	  "expected an index 0..1 of 'X', found 2" },
	{ BO "BA_DEF_ BO_ \"X\" ENUM \"a\",\"b\";\nBA_ \"X\" BO_ 1 \"c\";\n", 3, 15,
	  "expected one of the labels of 'X', found \"c\"" },
	{ "BA_DEF_ BU_ \"X\" INT 0 10;\nBA_ \"X\" BU_ Nope 1;\n", 2, 13,
	  "expected a node listed in BU_, found 'Nope'" },
	{ BO "BA_DEF_ BO_ \"X\" INT 0 10;\nBA_ \"X\" BO_ 1 1\n", 4, 1,
	  "expected ';' after the attribute value, found end of file" },
	/* VAL_, SIG_VALTYPE_ */
	{ BO SG(": 0|8@1+ (1,0) [0|1]") "VAL_ 1 S 0 ;\n", 3, 12,
	  "expected the value's description string, found ';'" },
	{ BO SG(": 0|8@1+ (1,0) [0|1]") "VAL_ 1 S \"a\" ;\n", 3, 10,
	  "expected a value or ';', found a string" },
	{ BO SG(": 0|8@1+ (1,0) [0|1]") "SIG_VALTYPE_ 1 S : 1;\n", 3, 20,
	  "signal 'S' has 8 bits; a float (1) needs 32" },
	{ BO SG(": 0|32@1+ (1,0) [0|1]") "SIG_VALTYPE_ 1 S : 2;\n", 3, 20,
	  "signal 'S' has 32 bits; a double (2) needs 64" },
	{ BO SG(": 0|32@1+ (1,0) [0|1]") "SIG_VALTYPE_ 1 S : 3;\n", 3, 20,
	  "expected the value type 0 (integer), 1 (float) or 2 (double), found 3 (above 2)" },
	{ BO SG(": 0|32@1+ (1,0) [0|1]") "SIG_VALTYPE_ 1 S 1;\n", 3, 18,
	  "expected ':' after the signal name, found number 1" },
	/* every other "expected" of the grammar */
	{ "BU_ A\n", 1, 5, "expected ':' after BU_, found 'A'" },
	{ "VAL_TABLE_ 5 ;\n", 1, 12, "expected the value table's name, found number 5" },
	{ BO "BO_TX_BU_ 1 A;\n", 2, 13, "expected ':' after the message ID, found 'A'" },
	{ BO "BO_TX_BU_ 1 : 5;\n", 2, 15, "expected a transmitting node, found number 5" },
	{ "BA_DEF_ BO_ \"X\" INT 0 10;\nBA_DEF_DEF_ \"X\" 1 2;\n", 2, 19,
	  "expected ';' after the default value, found number 2" },
	{ BO SG(": 0|32@1+ (1,0) [0|1]") "SIG_VALTYPE_ 1 S : 1 x;\n", 3, 22,
	  "expected ';' after the value type, found 'x'" },
	{ BO "BA_DEF_ BO_ \"X\" ENUM \"a\";\nBA_ \"X\" BO_ 1 x;\n", 3, 15,
	  "expected an enum index or label, found 'x'" },
	{ "BA_DEF_ BO_ \"X\" INT x 1;\n", 1, 21, "expected the attribute's minimum, found 'x'" },
	{ "BA_DEF_ BO_ \"X\" INT 0 ;\n", 1, 23, "expected the attribute's maximum, found ';'" },
	{ "BA_DEF_ BO_ \"X\" FLOAT x 1;\n", 1, 23, "expected the attribute's minimum, found 'x'" },
	{ "BA_DEF_ BO_ \"X\" FLOAT 0 ;\n", 1, 25, "expected the attribute's maximum, found ';'" },
	{ BO "BA_DEF_ BO_ \"X\" FLOAT 0 1;\nBA_ \"X\" BO_ 1 \"a\";\n", 3, 15,
	  "expected a number, found a string" },
	{ "BA_DEF_ BO_ \"X\" ENUM a;\n", 1, 22, "expected an enum label string, found 'a'" },
	{ "BA_DEF_ BO_ X INT 0 1;\n", 1, 13, "expected the attribute name string, found 'X'" },
	{ BO "CM_ BO_ 1 x;\n", 2, 11, "expected the comment string, found 'x'" },
	{ "CM_ BU_ 5 \"x\";\n", 1, 9, "expected a node name, found number 5" },
	{ BO "CM_ SG_ 1 5 \"x\";\n", 2, 11, "expected a signal name, found number 5" },
	{ "CM_ EV_ 5 \"x\";\n", 1, 9, "expected an environment variable name, found number 5" },
	{ BO " SG_ P M : 0|4@1+ (1,0) [0|1] \"\" X\n" SG(
		  "m1 : 8|8@1+ (1,0) [0|1]") "SG_MUL_VAL_ 1 S 5 1-1;\n",
	  4, 17, "expected the multiplexor signal's name, found number 5" },
	{ BO " SG_ P M : 0|4@1+ (1,0) [0|1] \"\" X\n" SG(
		  "m1 : 8|8@1+ (1,0) [0|1]") "SG_MUL_VAL_ 1 S P x;\n",
	  4, 19, "expected a multiplexor value range lo-hi, found 'x'" },
	{ BO " SG_ P M : 0|4@1+ (1,0) [0|1] \"\" X\n" SG(
		  "m1 : 8|8@1+ (1,0) [0|1]") "SG_MUL_VAL_ 1 S P 1-;\n",
	  4, 21, "expected the range's upper value, found ';'" },
	{ BO " SG_ P M : 0|4@1+ (1,0) [0|1] \"\" X\n" SG(
		  "m1 : 8|8@1+ (1,0) [0|1]") "SG_MUL_VAL_ 1 S P 1-1 2-2;\n",
	  4, 23, "expected ',' or ';' after a range, found number 2" },
	{ BO SG(": 0|8@1+ (1111111111111111111111111111111111111111111111111111111111111111111111,0) [0|1]"),
	  2, 18, "expected the factor, found a number of 70 digits" },
};

static void dbc_parse_errors_line_column_message(void **state)
{
	(void)state;
	for (size_t i = 0; i < sizeof(bads) / sizeof(bads[0]); i++) {
		struct hl_dbc *db = NULL;
		struct hl_dbc_error err;
		const struct bad *b = &bads[i];

		print_message("case %zu: %s", i, b->text);
		assert_int_equal(hl_dbc_parse_flags(b->text, strlen(b->text), HL_DBC_STRICT, &db,
						    &err),
				 -EBADMSG);
		assert_null(db);
		print_message("  -> %d:%d: %s\n", err.line, err.column, err.msg);
		assert_string_equal(err.msg, b->msg);
		assert_int_equal(err.line, b->line);
		assert_int_equal(err.column, b->column);
	}
}

static void dbc_parse_nul_byte(void **state)
{
	static const char text[] = "BO_ 1 A: 8 E\n\0";
	struct hl_dbc *db = NULL;
	struct hl_dbc_error err;

	(void)state;
	assert_int_equal(hl_dbc_parse(text, sizeof(text) - 1, &db, &err), -EBADMSG);
	assert_int_equal(err.line, 2);
	assert_int_equal(err.column, 1);
	assert_string_equal(err.msg, "unexpected byte 0x00");
}

/* --- lenient loading: one small database per irregularity real files have --- */

/* A clean database; each case below appends one irregularity to it (from line 11). */
#define CLEAN                                            \
	"VERSION \"\"\n"                                 \
	"BU_: ECU Lamp\n"                                \
	"BO_ 256 Good: 8 ECU\n"                          \
	" SG_ Sel M : 0|8@1+ (1,0) [0|255] \"\" Lamp\n"  \
	" SG_ A m0 : 8|16@1- (0.5,-3) [0|0] \"\" Lamp\n" \
	" SG_ B m1 : 8|8@0+ (1,0) [0|0] \"\" Lamp\n"     \
	" SG_ C : 39|16@0- (1,0) [0|0] \"\" Lamp\n"      \
	"BO_ 2147483904 Ext: 8 ECU\n"                    \
	" SG_ F : 0|32@1- (1,0) [0|0] \"\" Lamp\n"       \
	"SIG_VALTYPE_ 2147483904 F : 1;\n"

struct irregular_case {
	const char *text;
	int line, column; /* of the warning, and of the strict error */
	const char *strict; /* today's refusal; NULL: strict loads as before */
	const char *warning; /* lenient */
};

static const struct irregular_case irregular_cases[] = {
	/* 0: CM_ SG_ of a signal the message does not have */
	{ CLEAN "CM_ SG_ 256 Gone \"removed long ago\";\n", 11, 13,
	  "expected a signal of message 'Good', found 'Gone'",
	  "expected a signal of message 'Good', found 'Gone': statement skipped" },
	/* 1: VAL_ for a message no BO_ defines (a fragment of another file) */
	{ CLEAN "VAL_ 999 A 0 \"zero\" 1 \"one\" ;\n", 11, 6,
	  "expected the ID of a message defined by BO_, found 999",
	  "expected the ID of a message defined by BO_, found 999: statement skipped" },
	/* 2: BA_ ... SG_ of a missing signal */
	{ CLEAN "BA_DEF_ SG_ \"X\" INT 0 10;\nBA_ \"X\" SG_ 256 Gone 3;\n", 12, 17,
	  "expected a signal of message 'Good', found 'Gone'",
	  "expected a signal of message 'Good', found 'Gone': statement skipped" },
	/* 3: an ENUM attribute whose default is "" */
	{ CLEAN "BA_DEF_ BO_ \"E\" ENUM \"a\",\"b\";\nBA_DEF_DEF_ \"E\" \"\";\n", 12, 17,
	  "expected one of the labels of 'E', found \"\"",
	  "expected one of the labels of 'E', found \"\": the attribute has no default" },
	/* 4: a signal past the end of its message */
	{ CLEAN "BO_ 257 Short: 2 ECU\n"
		" SG_ Ok : 0|8@1+ (1,0) [0|0] \"\" Lamp\n"
		" SG_ Past : 8|16@1+ (1,0) [0|0] \"\" Lamp\n",
	  13, 13,
	  "signal 'Past' (start bit 8, 16 bits, Intel) does not fit the 2 bytes of message 'Short'",
	  "signal 'Past' (start bit 8, 16 bits, Intel) does not fit the 2 bytes of message 'Short': the signal is never decoded" },
	/* 5: the same node twice in BU_ */
	{ CLEAN "BU_: Lamp\n", 11, 6, "node 'Lamp' listed twice",
	  "node 'Lamp' listed twice: read once" },
	/* 6: VECTOR__INDEPENDENT_SIG_MSG with bit 30 (0x40000000) instead of 0xC0000000 */
	{ CLEAN "BO_ 1073741824 VECTOR__INDEPENDENT_SIG_MSG: 0 Vector__XXX\n"
		" SG_ Orphan : 0|8@1+ (1,0) [0|0] \"\" Vector__XXX\n",
	  11, 5, "expected a standard ID 0..2047 (extended IDs have bit 31 set), found 1073741824",
	  "expected a standard ID 0..2047 (extended IDs have bit 31 set), found 1073741824: read as a message never on the bus (as VECTOR__INDEPENDENT_SIG_MSG)" },
	/* 7: an integer in exponent notation, beyond 63 bits */
	{ CLEAN "BA_DEF_ BO_ \"Big\" INT 0 9.22337203685478E+018;\n", 11, 25,
	  "expected the attribute's maximum, found number 9.22337203685478E+018",
	  "expected the attribute's maximum, found number 9.22337203685478E+018: read as an integer" },
	/* 8: a negative one: the column is the '-' */
	{ CLEAN "BA_DEF_ BO_ \"Neg\" INT -92E+1 0;\n", 11, 23,
	  "expected the attribute's minimum, found number 92E+1",
	  "expected the attribute's minimum, found number 92E+1: read as an integer" },
	/* 9: an integer beyond 63 bits in an attribute range */
	{ CLEAN "BA_DEF_ BO_ \"Huge\" HEX 0 18446744073709551615;\n", 11, 26,
	  "expected the attribute's maximum, found 18446744073709551615 (above 9223372036854775807)",
	  "expected the attribute's maximum, found 18446744073709551615 (above 9223372036854775807): clamped to the 64-bit range" },
	/* 10: a bare m */
	{ CLEAN "BO_ 258 Bare: 8 ECU\n SG_ X m : 0|8@1+ (1,0) [0|0] \"\" Lamp\n", 12, 8,
	  "expected ':' or a multiplex indicator (M, m<n>, m<n>M), found 'm'",
	  "expected ':' or a multiplex indicator (M, m<n>, m<n>M), found 'm': read as a signal always present" },
	/* 11: BU_: with its nodes on the next lines (strict: lost, as before) */
	{ CLEAN "BU_:\n  Extra1 Extra2\n  Extra3\n", 12, 3, NULL,
	  "node names of BU_ (line 11) continue on the next lines: read as nodes" },
	/* 12: a real where an unsigned integer stands (here the message size) */
	{ CLEAN "BO_ 259 Sized: 8.0 ECU\n SG_ S : 0|8@1+ (1,0) [0|0] \"\" Lamp\n", 11, 16,
	  "expected the message size in bytes (0..64), found number 8.0",
	  "expected the message size in bytes (0..64), found number 8.0: read as an integer" },
};

static const uint8_t frames[][8] = {
	{ 0, 0x34, 0x92, 0x80, 0x7f, 0x01, 0x02, 0x03 },
	{ 1, 0xfe, 0x12, 0x00, 0x81, 0xff, 0xff, 0xff },
	{ 7, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff },
	{ 0x00, 0x00, 0xc0, 0x7f, 0, 0, 0, 0 }, /* F: NaN */
};

/* Every message of clean decodes in db to the same signals, raw bits and values. */
static void assert_decodes_as(const struct hl_dbc *clean, const struct hl_dbc *db)
{
	struct hl_dbc_value a[16], b[16];

	for (int i = 0; i < hl_dbc_n_messages(clean); i++) {
		const struct hl_dbc_message *mc = hl_dbc_message(clean, i);
		const struct hl_dbc_message *md = hl_dbc_find_message(db, mc->name);

		assert_non_null(md);
		assert_ptr_equal(hl_dbc_find_id(db, mc->can_id), md);
		for (size_t f = 0; f < sizeof(frames) / sizeof(frames[0]); f++) {
			int n = hl_dbc_decode(mc, frames[f], 8, a);

			assert_true(n > 0);
			assert_int_equal(hl_dbc_decode(md, frames[f], 8, b), n);
			for (int k = 0; k < n; k++) {
				assert_string_equal(mc->signals[a[k].signal].name,
						    md->signals[b[k].signal].name);
				assert_true(a[k].raw == b[k].raw);
				assert_memory_equal(&a[k].phys, &b[k].phys, sizeof(double));
			}
		}
	}
}

static void dbc_lenient_loads_each_irregularity_strict_refuses_it(void **state)
{
	struct hl_dbc *clean = NULL;
	struct hl_dbc_error err;

	(void)state;
	assert_int_equal(hl_dbc_parse_flags(CLEAN, strlen(CLEAN), HL_DBC_STRICT, &clean, &err), 0);
	assert_int_equal(hl_dbc_n_warnings(clean), 0);
	for (size_t i = 0; i < sizeof(irregular_cases) / sizeof(irregular_cases[0]); i++) {
		const struct irregular_case *c = &irregular_cases[i];
		struct hl_dbc *db = NULL;
		int line = 0, col = 0;

		print_message("case %zu\n", i);
		assert_int_equal(hl_dbc_parse(c->text, strlen(c->text), &db, &err), 0);
		assert_int_equal(hl_dbc_n_warnings(db), 1);
		assert_string_equal(hl_dbc_warning(db, 0, &line, &col), c->warning);
		assert_int_equal(line, c->line);
		assert_int_equal(col, c->column);
		assert_decodes_as(clean, db);
		hl_dbc_free(db);

		db = NULL;
		if (!c->strict) {
			assert_int_equal(hl_dbc_parse_flags(c->text, strlen(c->text), HL_DBC_STRICT,
							    &db, &err),
					 0);
			hl_dbc_free(db);
			continue;
		}
		assert_int_equal(hl_dbc_parse_flags(c->text, strlen(c->text), HL_DBC_STRICT, &db,
						    &err),
				 -EBADMSG);
		assert_null(db);
		assert_string_equal(err.msg, c->strict);
		assert_int_equal(err.line, c->line);
		assert_int_equal(err.column, c->column);
	}
	hl_dbc_free(clean);
}

static struct hl_dbc *lenient(int i)
{
	struct hl_dbc *db = NULL;
	struct hl_dbc_error err;

	assert_int_equal(hl_dbc_parse(irregular_cases[i].text, strlen(irregular_cases[i].text), &db,
				      &err),
			 0);
	return db;
}

/* What the lenient reading of each case made of the irregular part. */
static void dbc_lenient_reads_what_can_be_read(void **state)
{
	struct hl_dbc *db;
	const struct hl_dbc_message *m;
	struct hl_dbc_attr_value v;
	struct hl_dbc_value vals[4];
	static const uint8_t long_frame[8] = { 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88 };

	(void)state;
	db = lenient(3); /* ENUM default "": no default */
	m = hl_dbc_find_message(db, "Good");
	assert_int_equal(hl_dbc_message_attr(db, m, "E", &v), -ENOENT);
	hl_dbc_free(db);

	db = lenient(4); /* the signal past the end: never decoded, never present */
	m = hl_dbc_find_message(db, "Short");
	assert_false(m->signals[0].unusable);
	assert_true(m->signals[1].unusable);
	assert_int_equal(hl_dbc_decode(m, long_frame, 2, vals), 1);
	assert_int_equal(hl_dbc_decode(m, long_frame, 8, vals), 1);
	assert_int_equal(vals[0].signal, 0);
	assert_true(vals[0].raw == 0x11);
	assert_false(hl_dbc_signal_present(m, &m->signals[1], long_frame, 8));
	hl_dbc_free(db);

	db = lenient(5); /* the node once */
	assert_int_equal(hl_dbc_n_nodes(db), 2);
	hl_dbc_free(db);

	db = lenient(6); /* the bit-30 pseudo message: loaded, never on the bus */
	m = hl_dbc_find_message(db, "VECTOR__INDEPENDENT_SIG_MSG");
	assert_true(m->independent);
	assert_false(m->extended);
	assert_int_equal(m->n_signals, 1);
	assert_null(hl_dbc_find_id(db, 0x40000000u));
	assert_int_equal(hl_dbc_decode(m, long_frame, 8, vals), -ENOENT);
	hl_dbc_free(db);

	db = lenient(7); /* clamped to INT64_MAX */
	assert_true(hl_dbc_attr_def(db, 0)->max == 0x1p63);
	hl_dbc_free(db);
	db = lenient(8);
	assert_true(hl_dbc_attr_def(db, 0)->min == -920);
	hl_dbc_free(db);
	db = lenient(9);
	assert_true(hl_dbc_attr_def(db, 0)->max == 0x1p63);
	hl_dbc_free(db);

	db = lenient(10); /* bare m: always present, no multiplexor */
	m = hl_dbc_find_message(db, "Bare");
	assert_int_equal(m->signals[0].mux_parent, -1);
	assert_false(m->signals[0].is_multiplexor);
	assert_int_equal(hl_dbc_decode(m, long_frame, 8, vals), 1);
	hl_dbc_free(db);

	db = lenient(12); /* size 8.0 is 8 */
	assert_int_equal(hl_dbc_find_message(db, "Sized")->size, 8);
	hl_dbc_free(db);

	db = lenient(11); /* BU_ names on the following lines */
	assert_int_equal(hl_dbc_n_nodes(db), 5);
	assert_string_equal(hl_dbc_node(db, 2), "Extra1");
	assert_string_equal(hl_dbc_node(db, 4), "Extra3");
	hl_dbc_free(db);
	{
		struct hl_dbc_error err;
		const char *t = irregular_cases[11].text;
		int line, col;

		/* strict: as before, the names are lost to an unknown section */
		assert_int_equal(hl_dbc_parse_flags(t, strlen(t), HL_DBC_STRICT, &db, &err), 0);
		assert_int_equal(hl_dbc_n_nodes(db), 2);
		assert_string_equal(hl_dbc_warning(db, 0, &line, &col),
				    "skipped unknown section 'Extra1'");
		assert_int_equal(line, 12);
		hl_dbc_free(db);
	}
}

/* Exponent notation in signal fields was always read; no warning. */
static void dbc_numbers_in_exponent_notation(void **state)
{
	static const char text[] = "BO_ 1 M: 8 E\n"
				   " SG_ S : 0|64@1- (1E-1,-92E+1) [-9.22337203685478E+018|"
				   "9.22337203685478E+018] \"\" X\n";
	struct hl_dbc *db;
	const struct hl_dbc_signal *s;

	(void)state;
	db = parse(text);
	assert_int_equal(hl_dbc_n_warnings(db), 0);
	s = &hl_dbc_message(db, 0)->signals[0];
	assert_true(s->factor == 0.1);
	assert_true(s->offset == -920);
	assert_true(s->min == -9.22337203685478e18);
	assert_true(s->max == 9.22337203685478e18);
	hl_dbc_free(db);
}

/* CANdb++'s long names replace the 32-character ones, in references too. */
static void dbc_long_name_attributes(void **state)
{
	static const char text[] =
		"BU_: ShortNode Other\n"
		"BO_ 16 ShortMsg: 8 ShortNode\n"
		" SG_ ShortSig : 0|8@1+ (1,0) [0|0] \"\" ShortNode,Other\n"
		"BO_TX_BU_ 16 : ShortNode,Other;\n"
		"BA_DEF_ BU_ \"SystemNodeLongSymbol\" STRING ;\n"
		"BA_DEF_ BO_ \"SystemMessageLongSymbol\" STRING ;\n"
		"BA_DEF_ SG_ \"SystemSignalLongSymbol\" STRING ;\n"
		"BA_DEF_DEF_ \"SystemNodeLongSymbol\" \"\";\n"
		"BA_DEF_DEF_ \"SystemMessageLongSymbol\" \"\";\n"
		"BA_DEF_DEF_ \"SystemSignalLongSymbol\" \"\";\n"
		"BA_ \"SystemNodeLongSymbol\" BU_ ShortNode \"Headlamp_Control_Unit_Left_Front_Module\";\n"
		"BA_ \"SystemMessageLongSymbol\" BO_ 16 \"Headlamp_Matrix_Intensities_Left_Page\";\n"
		"BA_ \"SystemSignalLongSymbol\" SG_ 16 ShortSig \"Matrix_Segment_Intensity_Number_001\";\n"
		"CM_ SG_ 16 ShortSig \"found by its short name\";\n";
	struct hl_dbc *db = parse(text);
	const struct hl_dbc_message *m;

	(void)state;
	assert_int_equal(hl_dbc_n_warnings(db), 0);
	assert_string_equal(hl_dbc_node(db, 0), "Headlamp_Control_Unit_Left_Front_Module");
	assert_string_equal(hl_dbc_node(db, 1), "Other");
	m = hl_dbc_find_message(db, "Headlamp_Matrix_Intensities_Left_Page");
	assert_non_null(m);
	assert_null(hl_dbc_find_message(db, "ShortMsg"));
	assert_string_equal(m->transmitter, "Headlamp_Control_Unit_Left_Front_Module");
	assert_string_equal(m->tx_nodes[0], "Headlamp_Control_Unit_Left_Front_Module");
	assert_string_equal(m->signals[0].name, "Matrix_Segment_Intensity_Number_001");
	assert_string_equal(m->signals[0].receivers[0], "Headlamp_Control_Unit_Left_Front_Module");
	assert_string_equal(m->signals[0].receivers[1], "Other");
	assert_string_equal(m->signals[0].comment, "found by its short name");
	hl_dbc_free(db);
}

/* An unterminated string is reported where it begins: at the string that swallowed a section
 * when the quotes come out unbalanced further down, else where the last one opens. */
static void dbc_unterminated_string_points_at_its_start(void **state)
{
	static const char swallowed[] = "BO_ 1 M: 8 E\n"
					" SG_ S : 0|8@1+ (1,0) [0|1] \"\" X\n"
					"CM_ SG_ 1 S \"a comment without its end;\n" /* line 3 */
					"BO_ 2 N: 8 E\n"
					" SG_ T : 0|8@1+ (1,0) [0|1] \"\" X\n";
	static const char at_end[] = "BO_ 1 M: 8 E\n"
				     "CM_ BO_ 1 \"runs\n to the end\n";
	struct hl_dbc *db = NULL;
	struct hl_dbc_error err;

	(void)state;
	for (unsigned flags = 0; flags <= HL_DBC_STRICT; flags += HL_DBC_STRICT) {
		assert_int_equal(hl_dbc_parse_flags(swallowed, strlen(swallowed), flags, &db, &err),
				 -EBADMSG);
		assert_int_equal(err.line, 3);
		assert_int_equal(err.column, 13);
		assert_string_equal(
			err.msg,
			"unterminated string: expected a closing '\"' before line 4, where a section starts");
		assert_int_equal(hl_dbc_parse_flags(at_end, strlen(at_end), flags, &db, &err),
				 -EBADMSG);
		assert_int_equal(err.line, 2);
		assert_int_equal(err.column, 11);
		assert_string_equal(err.msg, "unterminated string: expected a closing '\"'");
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(dbc_parse_every_section),
		cmocka_unit_test(dbc_parse_attributes),
		cmocka_unit_test(dbc_parse_shipped_databases),
		cmocka_unit_test(dbc_parse_bom_fraction_and_last_attribute_wins),
		cmocka_unit_test(dbc_parse_file_missing),
		cmocka_unit_test(dbc_parse_errors_line_column_message),
		cmocka_unit_test(dbc_parse_nul_byte),
		cmocka_unit_test(dbc_lenient_loads_each_irregularity_strict_refuses_it),
		cmocka_unit_test(dbc_lenient_reads_what_can_be_read),
		cmocka_unit_test(dbc_numbers_in_exponent_notation),
		cmocka_unit_test(dbc_long_name_attributes),
		cmocka_unit_test(dbc_unterminated_string_points_at_its_start),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
