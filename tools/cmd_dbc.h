/* SPDX-License-Identifier: MIT */
/*
 * What the files of hdlamp dbc share (cmd_dbc.c and its subcommands cmd_dbc_info.c,
 * cmd_dbc_decode.c, cmd_dbc_encode.c); not for the other commands. Errors are printed as
 * "hdlamp dbc: ...".
 */
#ifndef HL_TOOLS_CMD_DBC_H
#define HL_TOOLS_CMD_DBC_H

#include <stdbool.h>
#include <stdint.h>

struct hl_dbc;

/* Parses path (flags: HL_DBC_STRICT), its warnings printed with file:line:column. 0 or -errno,
 * the error printed. */
int load(const char *path, unsigned flags, struct hl_dbc **ret);
/* The shortest %g that reads back as the same double, into buf (32 bytes). */
void format_double(char *buf, double v);

/* The subcommands (cmd_dbc_<sub>.c); each returns the exit code. */
int info(const char *path, unsigned flags);
int decode(const char *dbc_path, unsigned flags, const char *log_path);
int encode(const char *dbc_path, unsigned flags, const char *msg_name, bool e2e, long counter,
	   int64_t t_us, const char *iface, int n_args, char **args);

#endif
