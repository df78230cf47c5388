/* SPDX-License-Identifier: MIT */
/*
 * What the commands that run the loop in virtual time share (hdlamp sil, hdlamp suite run): the
 * configuration they start from (hdlampd's keys, the shipped databases, --config read before
 * any --set) and the ECU's --fault names into the loop's options.
 */
#ifndef HL_TOOLS_SIL_ARGS_H
#define HL_TOOLS_SIL_ARGS_H

#include "daemon/core/config.h"
#include "sil/sil.h"

/*
 * cfg's defaults with the shipped hd84.dbc, then every --config FILE of argv, wherever it
 * stands (so that --set overrides it); o's ECU the reference with its defaults. 0, or 2 after
 * telling why on stderr ("hdlamp PROG: ...").
 */
int hl_tool_sil_config(const char *prog, int argc, char **argv, struct hl_config *cfg,
		       struct hl_sil_options *o);

/* A --fault: the reference ECU's and the node's (ecu/node.h) into o. 0 or -EINVAL. */
int hl_tool_sil_fault(const char *name, struct hl_sil_options *o);

#endif
