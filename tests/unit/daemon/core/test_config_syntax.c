/* SPDX-License-Identifier: MIT */
/*
 * The syntax of configuration values: set ids (length, characters, a leading dot), verdict
 * modes, the sets list (trimmed, duplicates, a trailing comma, too many; cfg untouched on
 * refusal), bounded copies, enum choices and their text, HOST:PORT, interface and lamp names.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "daemon/core/config_syntax.h"

static void cfg_set_id_characters_length_and_leading_dot(void **state)
{
	char long_id[HL_CONFIG_SET_ID + 1];
	(void)state;

	assert_true(hl_cfg_valid_set_id("ece-r149.class-c+v", 18));
	assert_true(hl_cfg_valid_set_id("a_b", 3));
	/* n bounds what is looked at: "ab/c" is fine up to the '/' */
	assert_true(hl_cfg_valid_set_id("ab/c", 2));
	assert_false(hl_cfg_valid_set_id("ab/c", 4));
	assert_false(hl_cfg_valid_set_id("", 0));
	assert_false(hl_cfg_valid_set_id(".hidden", 7));
	assert_false(hl_cfg_valid_set_id("..", 2));
	assert_false(hl_cfg_valid_set_id("a b", 3));
	assert_false(hl_cfg_valid_set_id("a\xc3\xa9", 3));
	memset(long_id, 'x', sizeof(long_id));
	assert_true(hl_cfg_valid_set_id(long_id, HL_CONFIG_SET_ID - 1));
	assert_false(hl_cfg_valid_set_id(long_id, HL_CONFIG_SET_ID));
}

static void cfg_modes_one_colon_per_entry_and_no_empty_entry(void **state)
{
	(void)state;
	assert_true(hl_cfg_valid_modes("low:a+b,high:c"));
	assert_true(hl_cfg_valid_modes("off:")); /* a mode without sets */
	assert_true(hl_cfg_valid_modes("")); /* no modes */
	assert_false(hl_cfg_valid_modes("low"));
	assert_false(hl_cfg_valid_modes(":a"));
	assert_false(hl_cfg_valid_modes("low:a:b"));
	assert_false(hl_cfg_valid_modes("low:a,"));
	assert_false(hl_cfg_valid_modes("low:a,,high:b"));
	assert_false(hl_cfg_valid_modes(",low:a"));
	assert_false(hl_cfg_valid_modes("low:a b"));
	assert_false(hl_cfg_valid_modes("low:a;rm"));
}

static void cfg_parse_sets_trims_and_refuses_with_reason(void **state)
{
	/* what config.c passes: the verdict sets of a configuration */
	struct {
		char ids[HL_CONFIG_MAX_SETS][HL_CONFIG_SET_ID];
		int n;
	} cfg;
	char what[256];
	char many[40 * 4];
	(void)state;

	memset(&cfg, 0, sizeof(cfg));
	assert_int_equal(hl_cfg_parse_sets("\t ece-r149 ,sae-j1383,  x+y  ", cfg.ids, &cfg.n, what,
					   sizeof(what)),
			 0);
	assert_int_equal(cfg.n, 3);
	assert_string_equal(cfg.ids[0], "ece-r149");
	assert_string_equal(cfg.ids[1], "sae-j1383");
	assert_string_equal(cfg.ids[2], "x+y");
	assert_int_equal(hl_cfg_parse_sets("", cfg.ids, &cfg.n, what, sizeof(what)), 0);
	assert_int_equal(cfg.n, 0);

	/* refusals leave cfg as it was */
	assert_int_equal(hl_cfg_parse_sets("a,b", cfg.ids, &cfg.n, what, sizeof(what)), 0);
	assert_int_equal(hl_cfg_parse_sets("a, b, a", cfg.ids, &cfg.n, what, sizeof(what)),
			 -EINVAL);
	assert_string_equal(what, "'a' is named twice");
	assert_int_equal(hl_cfg_parse_sets("a, ", cfg.ids, &cfg.n, what, sizeof(what)), -EINVAL);
	assert_string_equal(what, "a set id after the last comma");
	assert_int_equal(hl_cfg_parse_sets("a,,b", cfg.ids, &cfg.n, what, sizeof(what)), -EINVAL);
	assert_string_equal(what, "'': expected set ids (letters, digits, . _ + -, at most 47 "
				  "characters) separated by commas");
	assert_int_equal(hl_cfg_parse_sets("a, b/../c", cfg.ids, &cfg.n, what, sizeof(what)),
			 -EINVAL);
	assert_string_equal(what, "'b/../c': expected set ids (letters, digits, . _ + -, at most "
				  "47 characters) separated by commas");
	/* 33 sets: one more than the frame header has bits */
	many[0] = '\0';
	for (int i = 0; i <= HL_CONFIG_MAX_SETS; i++)
		snprintf(many + strlen(many), sizeof(many) - strlen(many), "%s%d", i ? "," : "", i);
	assert_int_equal(hl_cfg_parse_sets(many, cfg.ids, &cfg.n, what, sizeof(what)), -EINVAL);
	assert_string_equal(what, "at most 32 sets (one bit each in the frame header)");
	assert_int_equal(cfg.n, 2);
	assert_string_equal(cfg.ids[0], "a");
	assert_string_equal(cfg.ids[1], "b");
	/* exactly 32 are fine */
	*strrchr(many, ',') = '\0';
	assert_int_equal(hl_cfg_parse_sets(many, cfg.ids, &cfg.n, what, sizeof(what)), 0);
	assert_int_equal(cfg.n, HL_CONFIG_MAX_SETS);
	assert_string_equal(cfg.ids[31], "31");
}

static void cfg_copy_string_refuses_what_does_not_fit(void **state)
{
	char dst[4] = "zzz";
	(void)state;

	assert_int_equal(hl_cfg_copy_string(dst, sizeof(dst), "abc"), 0);
	assert_string_equal(dst, "abc");
	assert_int_equal(hl_cfg_copy_string(dst, sizeof(dst), "abcd"), -EINVAL);
	assert_string_equal(dst, "abc");
	assert_int_equal(hl_cfg_copy_string(dst, sizeof(dst), ""), 0);
	assert_string_equal(dst, "");
}

static void cfg_choice_is_a_whole_word_and_its_text(void **state)
{
	char buf[64];
	(void)state;

	assert_true(hl_cfg_is_choice("auto|cpu|gles", "auto"));
	assert_true(hl_cfg_is_choice("auto|cpu|gles", "cpu"));
	assert_true(hl_cfg_is_choice("auto|cpu|gles", "gles"));
	/* a value holding the separator is no single choice */
	assert_false(hl_cfg_is_choice("auto|cpu|gles", "cpu|gles"));
	assert_false(hl_cfg_is_choice("auto|cpu|gles", "|"));
	assert_false(hl_cfg_is_choice("auto|cpu|gles", "gl"));
	assert_false(hl_cfg_is_choice("auto|cpu|gles", "auto|"));
	assert_false(hl_cfg_is_choice("auto|cpu|gles", ""));
	assert_false(hl_cfg_is_choice("auto|cpu|gles", "GLES"));
	hl_cfg_choices_text("auto|cpu|gles", buf, sizeof(buf));
	assert_string_equal(buf, "auto, cpu or gles");
	hl_cfg_choices_text("on|off", buf, sizeof(buf));
	assert_string_equal(buf, "on or off");
	hl_cfg_choices_text("only", buf, sizeof(buf));
	assert_string_equal(buf, "only");
	/* a small buffer: cut, always terminated */
	memset(buf, 'x', sizeof(buf));
	hl_cfg_choices_text("rising|falling|both", buf, 10);
	assert_string_equal(buf, "risin"); /* it stops with room for ", " or " or " to spare */
	hl_cfg_choices_text("rising|falling|both", buf, 12);
	assert_string_equal(buf, "rising, ");
}

static void cfg_address_host_port_or_empty(void **state)
{
	char what[256] = "";
	(void)state;

	assert_int_equal(hl_cfg_check_address("", what, sizeof(what)), 0);
	assert_int_equal(hl_cfg_check_address("127.0.0.1:8080", what, sizeof(what)), 0);
	assert_int_equal(hl_cfg_check_address("[::1]:0", what, sizeof(what)), 0);
	assert_int_equal(hl_cfg_check_address("localhost:65535", what, sizeof(what)), 0);
	assert_int_equal(hl_cfg_check_address("8080", what, sizeof(what)), -EINVAL);
	assert_string_equal(what, "'8080': expected HOST:PORT (an IPv4 address, [IPv6] or "
				  "localhost; port 0..65535, 0 = any free port), or empty for off");
	assert_int_equal(hl_cfg_check_address(":80", what, sizeof(what)), -EINVAL);
	assert_int_equal(hl_cfg_check_address("127.0.0.1:65536", what, sizeof(what)), -EINVAL);
	assert_string_equal(what, "'127.0.0.1:65536': port '65536': expected 0..65535 (0 = any "
				  "free port)");
	assert_int_equal(hl_cfg_check_address("127.0.0.1:", what, sizeof(what)), -EINVAL);
	assert_int_equal(hl_cfg_check_address("127.0.0.1:+80", what, sizeof(what)), -EINVAL);
	assert_int_equal(hl_cfg_check_address("127.0.0.1: 80", what, sizeof(what)), -EINVAL);
	assert_int_equal(hl_cfg_check_address("127.0.0.1:80x", what, sizeof(what)), -EINVAL);
	assert_int_equal(hl_cfg_check_address("127.0.0.1:99999999999999999999", what, sizeof(what)),
			 -EINVAL);
	assert_int_equal(hl_cfg_check_address("example.com:80", what, sizeof(what)), -EINVAL);
	assert_string_equal(what, "'example.com:80': host 'example.com': expected an IPv4 "
				  "address, [IPv6 address] or localhost");
}

static void cfg_iface_names_as_the_kernel_takes_them(void **state)
{
	(void)state;
	assert_true(hl_cfg_valid_iface("can0"));
	assert_true(hl_cfg_valid_iface("vcan-test_1.2"));
	assert_true(hl_cfg_valid_iface("a23456789012345")); /* 15 bytes */
	assert_false(hl_cfg_valid_iface("a234567890123456")); /* 16 */
	assert_false(hl_cfg_valid_iface("."));
	assert_false(hl_cfg_valid_iface(".."));
	assert_false(hl_cfg_valid_iface("can/0"));
	assert_false(hl_cfg_valid_iface("can:0"));
	assert_false(hl_cfg_valid_iface("can 0"));
	assert_false(hl_cfg_valid_iface("can\t0"));
	assert_false(hl_cfg_valid_iface("can\x01"));
	assert_false(hl_cfg_valid_iface("can\xc3\xa9"));
}

static void cfg_lamps_one_to_eight_names(void **state)
{
	(void)state;
	assert_true(hl_cfg_valid_lamps("left"));
	assert_true(hl_cfg_valid_lamps("left,right"));
	assert_true(hl_cfg_valid_lamps("a,b,c,d,e,f,g,h"));
	assert_false(hl_cfg_valid_lamps("a,b,c,d,e,f,g,h,i"));
	assert_false(hl_cfg_valid_lamps(""));
	assert_false(hl_cfg_valid_lamps(","));
	assert_false(hl_cfg_valid_lamps("left,"));
	assert_false(hl_cfg_valid_lamps(",left"));
	assert_false(hl_cfg_valid_lamps("left, right"));
	assert_false(hl_cfg_valid_lamps("le.ft"));
	assert_true(hl_cfg_valid_lamps("front_L-1"));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(cfg_set_id_characters_length_and_leading_dot),
		cmocka_unit_test(cfg_modes_one_colon_per_entry_and_no_empty_entry),
		cmocka_unit_test(cfg_parse_sets_trims_and_refuses_with_reason),
		cmocka_unit_test(cfg_copy_string_refuses_what_does_not_fit),
		cmocka_unit_test(cfg_choice_is_a_whole_word_and_its_text),
		cmocka_unit_test(cfg_address_host_port_or_empty),
		cmocka_unit_test(cfg_iface_names_as_the_kernel_takes_them),
		cmocka_unit_test(cfg_lamps_one_to_eight_names),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
