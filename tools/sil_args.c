/* SPDX-License-Identifier: MIT */
/* What hdlamp sil and hdlamp suite run share: see tools/sil_args.h. */
#include "tools/sil_args.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "ecu/node.h"

int hl_tool_sil_config(const char *prog, int argc, char **argv, struct hl_config *cfg,
		       struct hl_sil_options *o)
{
	struct hl_config_error cerr;

	hl_config_defaults(cfg);
	cfg->dbc[0] = '\0'; /* the shipped hd84.dbc beside the binary, wherever one runs it */
	o->ecu = "reference";
	hl_ecu_config_default(&o->ref);
	for (int i = 1; i + 1 < argc; i++)
		if (strcmp(argv[i], "--config") == 0 &&
		    hl_config_load(cfg, argv[i + 1], &cerr) < 0) {
			fprintf(stderr, "hdlamp %s: %s\n", prog, cerr.msg);
			return 2;
		}
	return 0;
}

int hl_tool_sil_fault(const char *name, struct hl_sil_options *o)
{
	struct hl_ecu_node_config nc = { .late_ms = o->late_ms,
					 .stuck_counter = o->stuck_counter,
					 .bad_crc = o->bad_crc };

	if (hl_ecu_node_fault(name, &nc, &o->ref) < 0)
		return -EINVAL;
	o->late_ms = nc.late_ms;
	o->stuck_counter = nc.stuck_counter;
	o->bad_crc = nc.bad_crc;
	return 0;
}
