/* SPDX-License-Identifier: MIT */
/* base/addr.c: "HOST:PORT" as the daemon's listeners take it, loopback told apart. */
#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "base/addr.h"

static void addr_parse_accepts_addresses_and_rejects_the_rest(void **state)
{
	static const char *const bad[] = {
		"",
		":80",
		"127.0.0.1",
		"127.0.0.1:",
		"127.0.0.1:65536",
		"127.0.0.1:-1",
		"127.0.0.1:8x",
		"example.org:80",
		"[::1:80",
		"::1:80",
		"[]:80",
		"300.1.1.1:80",
		"127.0.0.1:+80",
	};
	struct sockaddr_storage a;
	bool loop;

	(void)state;
	assert_int_equal(hl_addr_parse("127.0.0.1:8080", &a, &loop), 0);
	assert_int_equal(a.ss_family, AF_INET);
	assert_int_equal(ntohs(((struct sockaddr_in *)&a)->sin_port), 8080);
	assert_true(loop);
	assert_int_equal(hl_addr_parse("127.3.2.1:0", &a, &loop), 0);
	assert_true(loop);
	assert_int_equal(hl_addr_parse("localhost:1", &a, &loop), 0);
	assert_true(loop);
	assert_int_equal(hl_addr_parse("[::1]:8080", &a, &loop), 0);
	assert_int_equal(a.ss_family, AF_INET6);
	assert_true(loop);
	assert_int_equal(hl_addr_parse("0.0.0.0:80", &a, &loop), 0);
	assert_false(loop);
	assert_int_equal(hl_addr_parse("[::]:80", &a, &loop), 0);
	assert_false(loop);
	assert_int_equal(hl_addr_parse("192.168.1.10:8080", &a, &loop), 0);
	assert_false(loop);
	for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++)
		assert_int_equal(hl_addr_parse(bad[i], &a, &loop), -EINVAL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(addr_parse_accepts_addresses_and_rejects_the_rest),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
