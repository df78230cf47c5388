/* SPDX-License-Identifier: MIT */
#include "lamp/exr_error.h"

#include <stdarg.h>
#include <stdio.h>

void hl_exr_keep_message(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
	void *ud = NULL;

	(void)code;
	if (exr_get_user_data(ctxt, &ud) == EXR_ERR_SUCCESS && ud)
		snprintf(((struct hl_exr_msg *)ud)->text, sizeof(((struct hl_exr_msg *)ud)->text),
			 "%s", msg);
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
