/* SPDX-License-Identifier: MIT */
/* The shipped data's directory: beside the running executable's directory, or -ENAMETOOLONG. */
#include <errno.h>
#include <limits.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "base/share_dir.h"

static void share_dir_is_beside_the_executable(void **state)
{
	char exe[PATH_MAX], want[PATH_MAX + 64], got[PATH_MAX + 64];
	ssize_t n;
	(void)state;

	/* the test's own executable, as the kernel names it */
	n = readlink("/proc/self/exe", exe, sizeof(exe) - 1);
	assert_true(n > 0);
	exe[n] = '\0';
	*strrchr(exe, '/') = '\0';
	snprintf(want, sizeof(want), "%s/../share/hdlamp/scenarios", exe);
	assert_int_equal(hl_share_dir("scenarios", got, sizeof(got)), 0);
	assert_string_equal(got, want);
	snprintf(want, sizeof(want), "%s/../share/hdlamp/regulations", exe);
	assert_int_equal(hl_share_dir("regulations", got, sizeof(got)), 0);
	assert_string_equal(got, want);
}

static void share_dir_too_long_for_the_buffer(void **state)
{
	char exe[PATH_MAX], got[PATH_MAX + 64];
	ssize_t n;
	size_t need;
	(void)state;

	n = readlink("/proc/self/exe", exe, sizeof(exe) - 1);
	assert_true(n > 0);
	exe[n] = '\0';
	*strrchr(exe, '/') = '\0';
	need = strlen(exe) + strlen("/../share/hdlamp/x") + 1;
	assert_int_equal(hl_share_dir("x", got, need - 1), -ENAMETOOLONG);
	assert_int_equal(hl_share_dir("x", got, need), 0);
	assert_int_equal(strlen(got), need - 1);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(share_dir_is_beside_the_executable),
		cmocka_unit_test(share_dir_too_long_for_the_buffer),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
