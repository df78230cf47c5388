/* SPDX-License-Identifier: MIT */
/*
 * What the EXR readers and writers (lid_exr.c, frame_exr.c) share for errors: OpenEXRCore's
 * last message kept in the context's user data, and messages that name the file.
 */
#ifndef HL_RENDER_EXR_ERROR_H
#define HL_RENDER_EXR_ERROR_H

#include <openexr.h>

#include "lamp/lid.h"

/* Must be the first member of whatever a context's user data points to. */
struct hl_exr_msg {
	char text[256];
	int sys_errno; /* errno of the failed open or write the message reports, else 0 */
};

/*
 * An exr_error_handler_cb_t: keeps the message in the hl_exr_msg named by hl_exr_write_begin on
 * this thread, else in the user data's. A write context calls it with its lock held, where
 * exr_get_user_data would wait on that lock for ever (a full disk hung the writer): writers
 * name their message with hl_exr_write_begin instead.
 */
void hl_exr_keep_message(exr_const_context_t ctxt, exr_result_t code, const char *msg);
/* Until hl_exr_write_end, this thread's messages go to m. */
void hl_exr_write_begin(struct hl_exr_msg *m);
void hl_exr_write_end(void);
/* -errno of the failed open or write that m reports (-ENOSPC, -EFBIG, ...), else -EIO. */
int hl_exr_io_rc(const struct hl_exr_msg *m);
/* The kept message, else OpenEXR's text for rv. */
const char *hl_exr_why(exr_result_t rv, const struct hl_exr_msg *m);
/* Fills err (if any) with "'path': " and the message; returns rc. */
int hl_exr_fail(struct hl_lid_error *err, int rc, const char *path, const char *fmt, ...)
	__attribute__((format(printf, 4, 5)));

#endif
