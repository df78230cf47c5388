/* SPDX-License-Identifier: MIT */
/* can/candump: candump -L lines in (every frame kind) and out (byte-identical), and errors. */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "can/candump.h"

static struct hl_candump_frame parse_ok(const char *line)
{
	struct hl_candump_frame f;
	struct hl_candump_error err;

	assert_int_equal(hl_candump_parse(line, strlen(line), &f, &err), 0);
	return f;
}

/* format(parse(line)) == line */
static void assert_round_trip(const char *line)
{
	struct hl_candump_frame f = parse_ok(line);
	char buf[HL_CANDUMP_MAX_LINE];

	assert_int_equal(hl_candump_format(&f, buf, sizeof(buf)), (int)strlen(line));
	assert_string_equal(buf, line);
}

static void candump_classic_standard(void **state)
{
	struct hl_candump_frame f = parse_ok("(1436509052.249713) can0 123#11223344\n");

	(void)state;
	assert_int_equal(f.t_us, 1436509052249713LL);
	assert_string_equal(f.iface, "can0");
	assert_false(f.fd);
	assert_int_equal(f.frame.can_id, 0x123);
	assert_int_equal(f.frame.len, 4);
	assert_memory_equal(f.frame.data, "\x11\x22\x33\x44", 4);
	assert_int_equal(f.dir, 0);
	assert_round_trip("(1436509052.249713) can0 123#11223344");
	assert_round_trip("(0000000000.000001) vcan0 7FF#");
}

static void candump_extended_id(void **state)
{
	struct hl_candump_frame f = parse_ok("(1.000000) can1 18FEF100#0102");

	(void)state;
	assert_int_equal(f.frame.can_id, 0x18fef100u | CAN_EFF_FLAG);
	assert_int_equal(f.frame.len, 2);
	assert_int_equal(f.t_us, 1000000);
	f = parse_ok("(1.000000) can1 00000123#");
	assert_int_equal(f.frame.can_id, 0x123u | CAN_EFF_FLAG); /* 8 digits: extended */
	assert_round_trip("(0000000001.000000) can1 18FEF100#0102");
	assert_round_trip("(0000000001.000000) can1 00000123#");
}

static void candump_fd_64_bytes(void **state)
{
	char line[256] = "(1436509052.249713) can0 332##1";
	struct hl_candump_frame f;

	(void)state;
	for (int i = 0; i < 64; i++)
		sprintf(line + strlen(line), "%02X", (unsigned)(i * 7 + 1) & 0xff);
	f = parse_ok(line);
	assert_true(f.fd);
	assert_int_equal(f.frame.flags, CANFD_BRS);
	assert_int_equal(f.frame.len, 64);
	for (int i = 0; i < 64; i++)
		assert_int_equal(f.frame.data[i], (i * 7 + 1) & 0xff);
	assert_round_trip(line);
	f = parse_ok("(1.5) can0 123##0112233445566778899AABBCC");
	assert_int_equal(f.frame.len, 12);
	assert_int_equal(f.frame.flags, 0);
	assert_round_trip("(0000000001.500000) can0 123##0112233445566778899AABBCC");
	assert_round_trip("(0000000001.500000) can0 12345678##3");
}

static void candump_remote_error_len8_dir(void **state)
{
	struct hl_candump_frame f = parse_ok("(1.5) can0 123#R");

	(void)state;
	assert_int_equal(f.frame.can_id, 0x123u | CAN_RTR_FLAG);
	assert_int_equal(f.frame.len, 0);
	f = parse_ok("(1.5) can0 123#R4");
	assert_int_equal(f.frame.len, 4);
	assert_round_trip("(0000000001.500000) can0 123#R4");
	assert_round_trip("(0000000001.500000) can0 123#R");
	f = parse_ok("(1.5) can0 20000004#0000080000000000");
	assert_int_equal(f.frame.can_id, CAN_ERR_FLAG | 0x4);
	assert_int_equal(f.frame.len, 8);
	assert_int_equal(f.frame.data[2], 0x08);
	assert_round_trip("(0000000001.500000) can0 20000004#0000080000000000");
	/* python-can's writer gives an error frame no data bytes: DLC 0 */
	f = parse_ok("(2.501000) can0 20000080#");
	assert_int_equal(f.frame.can_id, CAN_ERR_FLAG | 0x80); /* CAN_ERR_BUSERROR */
	assert_int_equal(f.frame.len, 0);
	assert_false(f.fd);
	assert_round_trip("(0000000002.501000) can0 20000080#");
	f = parse_ok("(1.5) can0 123#1122334455667788_C");
	assert_int_equal(f.len8_dlc, 12);
	assert_round_trip("(0000000001.500000) can0 123#1122334455667788_C");
	f = parse_ok("(1.5) can0 123#11 T");
	assert_int_equal(f.dir, 'T');
	assert_round_trip("(0000000001.500000) can0 123#11 R");
	/* '.' between bytes as cansend takes them, lower case hex */
	f = parse_ok("(1.5) can0 1ab#11.22.aa\r\n");
	assert_int_equal(f.frame.can_id, 0x1ab);
	assert_int_equal(f.frame.len, 3);
	assert_int_equal(f.frame.data[2], 0xaa);
}

struct bad_line {
	const char *line;
	int column;
	const char *msg;
};

static const struct bad_line bad_lines[] = {
	{ "", 1, "expected '(' starting the timestamp" },
	{ "(1436509052249713) can0 123#", 14, "expected 1 to 12 digits of seconds" },
	{ "(1436509052.2497131) can0 123#", 19, "expected 1 to 6 digits of microseconds" },
	{ "(1436509052) can0 123#", 12, "expected '.' between seconds and microseconds" },
	{ "(1.5 can0 123#", 5, "expected ')' closing the timestamp" },
	{ "(1.5)can0 123#", 6, "expected ' ' after the timestamp" },
	{ "(1.5) can0", 11, "expected ' ' after the interface name" },
	{ "(1.5)  123#", 7, "expected an interface name" },
	{ "(1.5) abcdefghijklmnop 123#", 22,
	  "expected an interface name of at most 15 characters" },
	{ "(1.5) can0 12#00", 12, "expected a CAN ID of 3 (standard) or 8 (extended) hex digits" },
	{ "(1.5) can0 123:00", 15, "expected '#' after the CAN ID" },
	{ "(1.5) can0 800#00", 12, "expected a standard ID 000..7FF, found 800" },
	{ "(1.5) can0 40000000#00", 12,
	  "expected an extended ID 00000000..1FFFFFFF, found 40000000" },
	{ "(1.5) can0 123#1", 17, "expected a second hex digit of the data byte" },
	{ "(1.5) can0 123#112233445566778899", 32, "expected at most 8 data bytes" },
	{ "(1.5) can0 123##", 17, "expected one hex digit of CAN FD flags after '##'" },
	{ "(1.5) can0 123##0112233445566778899", 36,
	  "expected a CAN FD length (0..8, 12, 16, 20, 24, 32, 48, 64), found 9 bytes" },
	{ "(1.5) can0 123#00 x", 18, "expected the end of the line after the frame" },
	{ "(1.5) can0 123#11223344_C", 24, "expected '_<DLC>' only after 8 data bytes" },
	{ "(1.5) can0 123#1122334455667788_3", 33, "expected a DLC 9..F after '_'" },
	{ "(1.5) can0 20000004##0", 21, "expected data after an error frame's '#', not CAN FD" },
};

static void candump_errors_name_column(void **state)
{
	(void)state;
	for (size_t i = 0; i < sizeof(bad_lines) / sizeof(bad_lines[0]); i++) {
		struct hl_candump_frame f;
		struct hl_candump_error err;
		const struct bad_line *b = &bad_lines[i];

		print_message("%s\n", b->line);
		assert_int_equal(hl_candump_parse(b->line, strlen(b->line), &f, &err), -EBADMSG);
		assert_int_equal(err.column, b->column);
		assert_string_equal(err.msg, b->msg);
	}
}

static void candump_format_limits(void **state)
{
	struct hl_candump_frame f = parse_ok("(1.5) can0 123#11223344");
	char small[10];

	(void)state;
	assert_int_equal(hl_candump_format(&f, small, sizeof(small)), -ENOSPC);
	f.frame.len = 9; /* a classic frame cannot carry 9 bytes */
	assert_int_equal(hl_candump_format(&f, small, sizeof(small)), -EINVAL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(candump_classic_standard),
		cmocka_unit_test(candump_extended_id),
		cmocka_unit_test(candump_fd_64_bytes),
		cmocka_unit_test(candump_remote_error_len8_dir),
		cmocka_unit_test(candump_errors_name_column),
		cmocka_unit_test(candump_format_limits),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
