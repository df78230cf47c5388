/* SPDX-License-Identifier: MIT */
#include "lamp/exr_error.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>

static _Thread_local struct hl_exr_msg *writing; /* hl_exr_write_begin's */

void hl_exr_keep_message(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
	const int e = errno; /* the failed call's, when code says it was an open or a write */
	struct hl_exr_msg *m = writing;
	void *ud = NULL;

	if (!m && exr_get_user_data(ctxt, &ud) == EXR_ERR_SUCCESS)
		m = ud;
	if (!m)
		return;
	snprintf(m->text, sizeof(m->text), "%s", msg);
	if (code == EXR_ERR_FILE_ACCESS || code == EXR_ERR_WRITE_IO)
		m->sys_errno = e;
}

void hl_exr_write_begin(struct hl_exr_msg *m)
{
	writing = m;
}

void hl_exr_write_end(void)
{
	writing = NULL;
}

int hl_exr_io_rc(const struct hl_exr_msg *m)
{
	return m->sys_errno > 0 ? -m->sys_errno : -EIO;
}

const char *hl_exr_why(exr_result_t rv, const struct hl_exr_msg *m)
{
	return m->text[0] ? m->text : exr_get_default_error_message(rv);
}

int hl_exr_fail(struct hl_lid_error *err, int rc, const char *path, const char *fmt, ...)
{
	va_list ap;
	int n;

	if (!err)
		return rc;
	n = snprintf(err->msg, sizeof(err->msg), "'%s': ", path);
	if (n < 0 || (size_t)n >= sizeof(err->msg))
		return rc;
	va_start(ap, fmt);
	vsnprintf(err->msg + n, sizeof(err->msg) - n, fmt, ap);
	va_end(ap);
	return rc;
}
