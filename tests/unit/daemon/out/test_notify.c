/* SPDX-License-Identifier: MIT */
/*
 * daemon/out/notify.c: with NOTIFY_SOCKET pointing at a datagram socket this test owns, each call
 * sends exactly the documented message; without NOTIFY_SOCKET nothing is sent.
 */
#include <errno.h>
#include <inttypes.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <time.h>
#include <unistd.h>
#include <cmocka.h>

#include "daemon/out/notify.h"
#include "testutil.h"

struct listener {
	int fd;
	char path[108];
};

static int setup(void **state)
{
	struct listener *l = calloc(1, sizeof(*l));
	struct sockaddr_un addr = { .sun_family = AF_UNIX };

	if (!l)
		return -1;
	test_path(l->path, sizeof(l->path), "notify.sock");
	unlink(l->path);
	l->fd = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
	if (l->fd < 0)
		return -1;
	snprintf(addr.sun_path, sizeof(addr.sun_path), "%s", l->path);
	if (bind(l->fd, (struct sockaddr *)&addr, sizeof(addr)) < 0)
		return -1;
	setenv("NOTIFY_SOCKET", l->path, 1);
	*state = l;
	return 0;
}

static int teardown(void **state)
{
	struct listener *l = *state;

	unsetenv("NOTIFY_SOCKET");
	close(l->fd);
	unlink(l->path);
	free(l);
	return 0;
}

/* The next datagram, as a string; "" when none is waiting. */
static const char *next_message(struct listener *l, char *buf, size_t size)
{
	ssize_t n = recv(l->fd, buf, size - 1, MSG_DONTWAIT);

	if (n < 0) {
		assert_int_equal(errno, EAGAIN);
		n = 0;
	}
	buf[n] = '\0';
	return buf;
}

static void notify_sends_the_exact_messages(void **state)
{
	struct listener *l = *state;
	char buf[1024];

	assert_true(hl_notify_ready("2 lamps, vcan0 open, rendering 900x250") > 0);
	assert_string_equal(next_message(l, buf, sizeof(buf)),
			    "READY=1\nSTATUS=2 lamps, vcan0 open, rendering 900x250");
	assert_true(hl_notify_ready(NULL) > 0);
	assert_string_equal(next_message(l, buf, sizeof(buf)), "READY=1");
	assert_true(hl_notify_status("%d frames, %s", 1234, "left stale") > 0);
	assert_string_equal(next_message(l, buf, sizeof(buf)), "STATUS=1234 frames, left stale");
	assert_true(hl_notify_watchdog() > 0);
	assert_string_equal(next_message(l, buf, sizeof(buf)), "WATCHDOG=1");
	assert_true(hl_notify_stopping() > 0);
	assert_string_equal(next_message(l, buf, sizeof(buf)), "STOPPING=1");
	assert_true(hl_notify_extend_timeout_us(30000000) > 0);
	assert_string_equal(next_message(l, buf, sizeof(buf)), "EXTEND_TIMEOUT_USEC=30000000");
	assert_string_equal(next_message(l, buf, sizeof(buf)), "");
}

static uint64_t now_us(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (uint64_t)ts.tv_sec * 1000000u + (uint64_t)ts.tv_nsec / 1000u;
}

static void notify_reloading_carries_monotonic_usec(void **state)
{
	struct listener *l = *state;
	uint64_t before, after, t = 0;
	char buf[256];
	int end = 0;

	before = now_us();
	assert_true(hl_notify_reloading() > 0);
	after = now_us();
	next_message(l, buf, sizeof(buf));
	assert_int_equal(sscanf(buf, "RELOADING=1\nMONOTONIC_USEC=%" SCNu64 "%n", &t, &end), 1);
	assert_int_equal(buf[end], '\0');
	assert_true(t >= before && t <= after);
}

static void notify_status_is_cut_at_256_bytes(void **state)
{
	struct listener *l = *state;
	char buf[1024], want[300], text[400];

	memset(text, 'x', 399);
	text[399] = '\0';
	assert_true(hl_notify_status("%s", text) > 0);
	snprintf(want, sizeof(want), "STATUS=%.256s", text);
	assert_string_equal(next_message(l, buf, sizeof(buf)), want);
	assert_int_equal(strlen(buf), 7 + 256);
}

static void notify_abstract_socket(void **state)
{
	struct sockaddr_un addr = { .sun_family = AF_UNIX };
	char name[64], buf[80];
	int fd;
	(void)state;

	/* systemd may hand out "@name" (an abstract socket). */
	snprintf(name, sizeof(name), "hl-test-notify-%d", (int)getpid());
	fd = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
	assert_true(fd >= 0);
	memcpy(addr.sun_path + 1, name, strlen(name));
	assert_int_equal(bind(fd, (struct sockaddr *)&addr,
			      offsetof(struct sockaddr_un, sun_path) + 1 + strlen(name)),
			 0);
	snprintf(buf, sizeof(buf), "@%s", name);
	setenv("NOTIFY_SOCKET", buf, 1);
	assert_true(hl_notify_watchdog() > 0);
	assert_int_equal(recv(fd, buf, sizeof(buf) - 1, MSG_DONTWAIT), 10);
	buf[10] = '\0';
	assert_string_equal(buf, "WATCHDOG=1");
	close(fd);
}

static void notify_without_socket_is_a_noop(void **state)
{
	struct listener *l = *state;
	char buf[256];

	unsetenv("NOTIFY_SOCKET");
	assert_int_equal(hl_notify_ready("up"), 0);
	assert_int_equal(hl_notify_status("x"), 0);
	assert_int_equal(hl_notify_watchdog(), 0);
	assert_int_equal(hl_notify_reloading(), 0);
	assert_int_equal(hl_notify_stopping(), 0);
	assert_int_equal(hl_notify_extend_timeout_us(1), 0);
	/* The socket is still bound: nothing arrived. */
	assert_string_equal(next_message(l, buf, sizeof(buf)), "");
}

/*
 * Failures are logged here, the first of each kind only (callers ignore the results). Runs
 * first: which kinds have failed is process state.
 */
static void notify_failure_is_logged_once_per_kind(void **state)
{
	char path[108], log_path[108], text[1024];
	FILE *log;
	size_t n;
	int saved;
	(void)state;

	test_path(path, sizeof(path), "nobody-listens.sock");
	test_path(log_path, sizeof(log_path), "notify-stderr.txt");
	unlink(path);
	setenv("NOTIFY_SOCKET", path, 1);
	log = fopen(log_path, "w+");
	assert_non_null(log);
	fflush(stderr);
	saved = dup(STDERR_FILENO);
	assert_true(saved >= 0);
	assert_int_equal(dup2(fileno(log), STDERR_FILENO), STDERR_FILENO);
	for (int i = 0; i < 3; i++)
		assert_int_equal(hl_notify_watchdog(), -ENOENT);
	assert_int_equal(hl_notify_status("%s", "x"), -ENOENT);
	assert_int_equal(hl_notify_status("%s", "y"), -ENOENT);
	setenv("WATCHDOG_USEC", "soon", 1);
	for (int i = 0; i < 2; i++) {
		uint64_t us = 1;

		assert_int_equal(hl_notify_watchdog_interval_us(&us), -EINVAL);
	}
	unsetenv("WATCHDOG_USEC");
	fflush(stderr);
	assert_int_equal(dup2(saved, STDERR_FILENO), STDERR_FILENO);
	close(saved);
	rewind(log);
	n = fread(text, 1, sizeof(text) - 1, log);
	text[n] = '\0';
	fclose(log);
	unlink(log_path);
	assert_string_equal(
		text,
		"hdlampd: systemd notification WATCHDOG=1: No such file or directory (logged once)\n"
		"hdlampd: systemd notification STATUS: No such file or directory (logged once)\n"
		"hdlampd: systemd notification WATCHDOG_USEC: Invalid argument (logged once)\n");
}

static void notify_unreachable_socket_is_an_error(void **state)
{
	char path[108];
	(void)state;

	test_path(path, sizeof(path), "nobody-listens.sock");
	unlink(path);
	setenv("NOTIFY_SOCKET", path, 1);
	assert_int_equal(hl_notify_watchdog(), -ENOENT);
}

static void notify_watchdog_interval_is_half(void **state)
{
	char pid[32];
	uint64_t us = 1;
	(void)state;

	unsetenv("WATCHDOG_USEC");
	unsetenv("WATCHDOG_PID");
	assert_int_equal(hl_notify_watchdog_interval_us(&us), 0);
	assert_int_equal(us, 0);

	setenv("WATCHDOG_USEC", "3000000", 1);
	assert_int_equal(hl_notify_watchdog_interval_us(&us), 1);
	assert_int_equal(us, 1500000);

	snprintf(pid, sizeof(pid), "%d", (int)getpid());
	setenv("WATCHDOG_PID", pid, 1);
	assert_int_equal(hl_notify_watchdog_interval_us(&us), 1);
	assert_int_equal(us, 1500000);
	/* Meant for another process (a parent that did not unset it): not ours to ping. */
	snprintf(pid, sizeof(pid), "%d", (int)getpid() + 1);
	setenv("WATCHDOG_PID", pid, 1);
	us = 1;
	assert_int_equal(hl_notify_watchdog_interval_us(&us), 0);
	assert_int_equal(us, 0);
	unsetenv("WATCHDOG_PID");

	setenv("WATCHDOG_USEC", "soon", 1);
	us = 1;
	assert_int_equal(hl_notify_watchdog_interval_us(&us), -EINVAL);
	assert_int_equal(us, 1);
	unsetenv("WATCHDOG_USEC");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(notify_failure_is_logged_once_per_kind),
		cmocka_unit_test_setup_teardown(notify_sends_the_exact_messages, setup, teardown),
		cmocka_unit_test_setup_teardown(notify_reloading_carries_monotonic_usec, setup,
						teardown),
		cmocka_unit_test_setup_teardown(notify_status_is_cut_at_256_bytes, setup, teardown),
		cmocka_unit_test_setup_teardown(notify_without_socket_is_a_noop, setup, teardown),
		cmocka_unit_test(notify_abstract_socket),
		cmocka_unit_test(notify_unreachable_socket_is_an_error),
		cmocka_unit_test(notify_watchdog_interval_is_half),
	};
	int r;

	r = cmocka_run_group_tests(tests, NULL, NULL);
	unsetenv("NOTIFY_SOCKET");
	return r;
}
