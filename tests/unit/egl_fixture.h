/* SPDX-License-Identifier: MIT */
/*
 * The EGL context of a GLES unit test as a cmocka group fixture (header-only; each test is its
 * own executable): cmocka_run_group_tests(tests, egl_setup, egl_teardown), then `egl`.
 * No EGL fails the group with the reason, never skips it.
 */
#ifndef HL_TESTS_EGL_FIXTURE_H
#define HL_TESTS_EGL_FIXTURE_H

#include <stdio.h>

#include "render/egl.h"

static struct hl_egl *egl;

static int egl_setup(void **state)
{
	struct hl_egl_error err;

	(void)state;
	if (hl_egl_new(&egl, &err) < 0) {
		fprintf(stderr, "no EGL: %s\n", err.msg);
		return -1;
	}
	return 0;
}

static int egl_teardown(void **state)
{
	(void)state;
	hl_egl_free(egl);
	return 0;
}

#endif
