/* SPDX-License-Identifier: MIT */
/*
 * dbc/lexer.c, the DBC reader's token level (a private header of dbc/): tokens with their kind,
 * text, line and column; signs as tokens of their own; '//' comments skipped; an unterminated
 * string an error at its start; numbers read exactly.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "dbc/lexer.h"

static void start(struct parser *p, struct hl_dbc_error *err, const char *text)
{
	memset(p, 0, sizeof(*p));
	memset(err, 0, sizeof(*err));
	p->s = text;
	p->end = text + strlen(text);
	p->line = p->col = 1;
	p->err = err;
	p->cur_msg = p->last_msg = -1;
}

static void expect_tok(struct parser *p, enum tok_kind kind, const char *text, int line, int col)
{
	assert_int_equal(dbc_next(p), 0);
	assert_int_equal(p->tok.kind, kind);
	assert_int_equal(p->tok.n, strlen(text));
	assert_memory_equal(p->tok.p, text, p->tok.n);
	assert_int_equal(p->tok.line, line);
	assert_int_equal(p->tok.col, col);
}

static void lexer_tokens_with_their_place(void **state)
{
	struct parser p;
	struct hl_dbc_error err;
	(void)state;

	start(&p, &err,
	      "BO_ 800 HL_Dim_L: 8 ECU\n // a comment\n SG_ x : 0|6@1- (0.5,-2)\n"
	      "\t\"a \\\"b\\\" c\" .5 1e3 2.5E-2");
	expect_tok(&p, TOK_IDENT, "BO_", 1, 1);
	expect_tok(&p, TOK_NUMBER, "800", 1, 5);
	expect_tok(&p, TOK_IDENT, "HL_Dim_L", 1, 9);
	expect_tok(&p, TOK_PUNCT, ":", 1, 17);
	expect_tok(&p, TOK_NUMBER, "8", 1, 19);
	expect_tok(&p, TOK_IDENT, "ECU", 1, 21);
	expect_tok(&p, TOK_IDENT, "SG_", 3, 2);
	expect_tok(&p, TOK_IDENT, "x", 3, 6);
	expect_tok(&p, TOK_PUNCT, ":", 3, 8);
	expect_tok(&p, TOK_NUMBER, "0", 3, 10);
	expect_tok(&p, TOK_PUNCT, "|", 3, 11);
	expect_tok(&p, TOK_NUMBER, "6", 3, 12);
	expect_tok(&p, TOK_PUNCT, "@", 3, 13);
	expect_tok(&p, TOK_NUMBER, "1", 3, 14);
	expect_tok(&p, TOK_PUNCT, "-", 3, 15); /* the sign is a token of its own */
	expect_tok(&p, TOK_PUNCT, "(", 3, 17);
	expect_tok(&p, TOK_NUMBER, "0.5", 3, 18);
	expect_tok(&p, TOK_PUNCT, ",", 3, 21);
	expect_tok(&p, TOK_PUNCT, "-", 3, 22);
	expect_tok(&p, TOK_NUMBER, "2", 3, 23);
	expect_tok(&p, TOK_PUNCT, ")", 3, 24);
	expect_tok(&p, TOK_STRING, "a \\\"b\\\" c", 4, 2); /* inside the quotes, still escaped */
	expect_tok(&p, TOK_NUMBER, ".5", 4, 14);
	expect_tok(&p, TOK_NUMBER, "1e3", 4, 17);
	expect_tok(&p, TOK_NUMBER, "2.5E-2", 4, 21);
	expect_tok(&p, TOK_EOF, "", 4, 27);
	expect_tok(&p, TOK_EOF, "", 4, 27);
}

static void lexer_numbers_read_exactly(void **state)
{
	struct parser p;
	struct hl_dbc_error err;
	double d;
	uint64_t u;
	(void)state;

	start(&p, &err, "-1.5e3 0.015873015873015872 4095 4096");
	assert_int_equal(dbc_next(&p), 0);
	assert_int_equal(dbc_get_number(&p, "a factor", &d), 0);
	assert_true(d == -1500.0);
	assert_int_equal(dbc_get_number(&p, "a factor", &d), 0);
	assert_true(d == 1.0 / 63.0);
	assert_int_equal(dbc_get_uint(&p, "a source", 4095, &u), 0);
	assert_int_equal(u, 4095);
	assert_int_equal(dbc_get_uint(&p, "a source", 4095, &u), -EBADMSG);
	assert_int_equal(err.line, 1);
	assert_int_equal(err.column, 34);
}

static void lexer_unterminated_string_is_an_error_at_its_start(void **state)
{
	struct parser p;
	struct hl_dbc_error err;
	int rc;
	(void)state;

	start(&p, &err, "CM_ \"no end\nBO_ 1 X: 8 ECU\n");
	assert_int_equal(dbc_next(&p), 0);
	rc = dbc_next(&p);
	assert_int_equal(rc, -EBADMSG);
	assert_int_equal(err.line, 1);
	assert_int_equal(err.column, 5);
	assert_non_null(strstr(err.msg, "\""));
}

static void lexer_expected_names_what_it_found(void **state)
{
	struct parser p;
	struct hl_dbc_error err;
	(void)state;

	start(&p, &err, "BO_ 800 :");
	assert_int_equal(dbc_next(&p), 0);
	assert_true(dbc_is_word(&p, "BO_"));
	assert_false(dbc_is_word(&p, "BO"));
	assert_int_equal(dbc_next(&p), 0);
	assert_int_equal(dbc_next(&p), 0);
	assert_true(dbc_is_punct(&p, ':'));
	assert_int_equal(dbc_expected(&p, "a message name"), -EBADMSG);
	assert_int_equal(err.line, 1);
	assert_int_equal(err.column, 9);
	assert_string_equal(err.msg, "expected a message name, found ':'");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(lexer_tokens_with_their_place),
		cmocka_unit_test(lexer_numbers_read_exactly),
		cmocka_unit_test(lexer_unterminated_string_is_an_error_at_its_start),
		cmocka_unit_test(lexer_expected_names_what_it_found),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
