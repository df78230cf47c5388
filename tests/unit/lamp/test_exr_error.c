/* SPDX-License-Identifier: MIT */
/*
 * lamp/exr_error.c: OpenEXRCore's messages kept where the EXR readers and writers can quote them
 * (the context's user data, or this thread's hl_exr_write_begin message), the errno of a failed
 * open or write, and error texts that name the file.
 */
#include <errno.h>
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "lamp/exr_error.h"
#include "testutil.h"

/* A read context on a file that does not exist: OpenEXR reports EXR_ERR_FILE_ACCESS. */
static exr_result_t open_missing(void *user_data)
{
	exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
	exr_context_t ctxt = NULL;
	char path[4096];
	exr_result_t rv;

	test_path(path, sizeof(path), "no-such-file.exr");
	init.error_handler_fn = hl_exr_keep_message;
	init.user_data = user_data;
	rv = exr_start_read(&ctxt, path, &init);
	assert_null(ctxt);
	return rv;
}

/* The message goes to the user data, with the errno of the failed open. */
static void exr_keep_message_keeps_the_text_and_errno_in_the_user_data(void **state)
{
	struct hl_exr_msg m = { .text = "", .sys_errno = 0 };

	(void)state;
	assert_int_equal(open_missing(&m), EXR_ERR_FILE_ACCESS);
	assert_true(strlen(m.text) > 0);
	assert_int_equal(m.sys_errno, ENOENT);
	assert_int_equal(hl_exr_io_rc(&m), -ENOENT);
	assert_ptr_equal(hl_exr_why(EXR_ERR_FILE_ACCESS, &m), m.text);
	/* no user data and no writer's message: nothing kept, nothing crashes */
	assert_int_equal(open_missing(NULL), EXR_ERR_FILE_ACCESS);
}

static void *open_missing_thread(void *user_data)
{
	open_missing(user_data);
	return NULL;
}

/* Between hl_exr_write_begin and _end, this thread's messages go to the writer's message
 * instead of the user data; other threads' still go to theirs. */
static void exr_write_begin_routes_this_threads_messages(void **state)
{
	struct hl_exr_msg ud = { .text = "" }, writer = { .text = "" }, other = { .text = "" };
	pthread_t t;

	(void)state;
	hl_exr_write_begin(&writer);
	assert_int_equal(open_missing(&ud), EXR_ERR_FILE_ACCESS);
	assert_string_equal(ud.text, "");
	assert_int_equal(ud.sys_errno, 0);
	assert_true(strlen(writer.text) > 0);
	assert_int_equal(writer.sys_errno, ENOENT);
	assert_int_equal(pthread_create(&t, NULL, open_missing_thread, &other), 0);
	assert_int_equal(pthread_join(t, NULL), 0);
	assert_true(strlen(other.text) > 0);
	assert_int_equal(other.sys_errno, ENOENT);
	hl_exr_write_end();
	assert_int_equal(open_missing(&ud), EXR_ERR_FILE_ACCESS);
	assert_string_equal(ud.text, writer.text);
	assert_int_equal(ud.sys_errno, ENOENT);
}

/* A message of another kind does not set sys_errno, whatever errno holds. */
static void exr_keep_message_takes_errno_only_for_opens_and_writes(void **state)
{
	struct hl_exr_msg m = { .text = "" };

	(void)state;
	hl_exr_write_begin(&m);
	errno = ENOSPC;
	hl_exr_keep_message(NULL, EXR_ERR_INVALID_ATTR, "bad attribute");
	assert_string_equal(m.text, "bad attribute");
	assert_int_equal(m.sys_errno, 0);
	assert_int_equal(hl_exr_io_rc(&m), -EIO);
	errno = ENOSPC;
	hl_exr_keep_message(NULL, EXR_ERR_WRITE_IO, "short write");
	assert_string_equal(m.text, "short write");
	assert_int_equal(m.sys_errno, ENOSPC);
	assert_int_equal(hl_exr_io_rc(&m), -ENOSPC);
	errno = EFBIG;
	hl_exr_keep_message(NULL, EXR_ERR_FILE_ACCESS, "cannot open");
	assert_int_equal(hl_exr_io_rc(&m), -EFBIG);
	hl_exr_write_end();
}

/* The kept message, else OpenEXR's own text for the code. */
static void exr_why_prefers_the_kept_message(void **state)
{
	struct hl_exr_msg m = { .text = "", .sys_errno = 0 };

	(void)state;
	assert_string_equal(hl_exr_why(EXR_ERR_CORRUPT_CHUNK, &m),
			    exr_get_default_error_message(EXR_ERR_CORRUPT_CHUNK));
	assert_true(strlen(hl_exr_why(EXR_ERR_CORRUPT_CHUNK, &m)) > 0);
	strcpy(m.text, "chunk 3 is bad");
	assert_string_equal(hl_exr_why(EXR_ERR_CORRUPT_CHUNK, &m), "chunk 3 is bad");
}

/* "'path': message", rc returned as given; no err: just rc; a path that fills the message
 * leaves it at the cut path. */
static void exr_fail_names_the_file_and_returns_rc(void **state)
{
	struct hl_lid_error err;
	char path[600];

	(void)state;
	assert_int_equal(hl_exr_fail(&err, -EBADMSG, "a.exr", "%d channels; expected %s", 3, "1"),
			 -EBADMSG);
	assert_string_equal(err.msg, "'a.exr': 3 channels; expected 1");
	assert_int_equal(hl_exr_fail(NULL, -ENOSPC, "a.exr", "full"), -ENOSPC);
	memset(path, 'p', sizeof(path) - 1);
	path[sizeof(path) - 1] = '\0';
	assert_int_equal(hl_exr_fail(&err, -EIO, path, "lost"), -EIO);
	assert_int_equal(strlen(err.msg), sizeof(err.msg) - 1);
	assert_int_equal(err.msg[0], '\'');
	assert_null(strstr(err.msg, "lost"));
	/* a message that does not fit is cut */
	memset(path, 'p', 500);
	path[500] = '\0';
	assert_int_equal(hl_exr_fail(&err, -EIO, path, "%s", "0123456789abcdef"), -EIO);
	assert_int_equal(strlen(err.msg), sizeof(err.msg) - 1);
	assert_string_equal(err.msg + 504, "0123456");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(exr_keep_message_keeps_the_text_and_errno_in_the_user_data),
		cmocka_unit_test(exr_write_begin_routes_this_threads_messages),
		cmocka_unit_test(exr_keep_message_takes_errno_only_for_opens_and_writes),
		cmocka_unit_test(exr_why_prefers_the_kept_message),
		cmocka_unit_test(exr_fail_names_the_file_and_returns_rc),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
