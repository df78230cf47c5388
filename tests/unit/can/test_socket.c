/* SPDX-License-Identifier: MIT */
/*
 * can/socket.c without a CAN interface (the host has none; the sends on vcan are checked in the
 * VM by tests/vm/daemon/test_restbus_vcan.py): what hl_can_socket_send refuses before it
 * touches the socket, and a closed socket.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "can/socket.h"

static void socket_send_checks_the_length_first(void **state)
{
	struct hl_can_socket *s = NULL;
	const uint8_t data[64] = { 0 };
	static const uint8_t fd_ok[] = { 0, 1, 8, 12, 16, 20, 24, 32, 48, 64 };
	static const uint8_t fd_bad[] = { 9, 10, 11, 13, 31, 33, 63, 65 };

	(void)state;
	assert_int_equal(hl_can_socket_new("vcan0", NULL, 0, &s), 0);
	/* classic frames: 0..8 bytes */
	assert_int_equal(hl_can_socket_send(s, 0x110, data, 9, false), -EINVAL);
	assert_int_equal(hl_can_socket_send(s, 0x110, data, 8, false), -ENETDOWN);
	assert_int_equal(hl_can_socket_send(s, 0x110, data, 0, false), -ENETDOWN);
	/* CAN FD: the lengths a DLC can say (ISO 11898-1), else refused */
	for (size_t i = 0; i < sizeof(fd_ok); i++)
		assert_int_equal(hl_can_socket_send(s, 0x110, data, fd_ok[i], true), -ENETDOWN);
	for (size_t i = 0; i < sizeof(fd_bad); i++)
		assert_int_equal(hl_can_socket_send(s, 0x110, data, fd_bad[i], true), -EINVAL);
	/* never opened: no fd */
	assert_int_equal(hl_can_socket_fd(s), -1);
	hl_can_socket_free(s);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(socket_send_checks_the_length_first),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
