/* SPDX-License-Identifier: MIT */
/*
 * The syntax of configuration values, as daemon/core/config.c checks them: set ids, verdict modes,
 * addresses, interface and lamp names, enum choices. Pure functions: any thread.
 */
#ifndef HL_DAEMON_CORE_CONFIG_SYNTAX_H
#define HL_DAEMON_CORE_CONFIG_SYNTAX_H

#include <stdbool.h>
#include <stddef.h>

#define HL_CONFIG_MAX_SETS 32 /* verdict sets: one bit each in the frame header */
#define HL_CONFIG_SET_ID \
	48 /* a set id's bytes with the NUL (verdict/regulation.h: HL_REG_ID_MAX) */

/* A set id is a file name in the regulations directory: letters, digits, '.', '_', '+', '-'. */
bool hl_cfg_valid_set_id(const char *s, size_t n);
/* MODE:ID+ID,... : names and ids of the set id's characters, each entry with one ':'. */
bool hl_cfg_valid_modes(const char *v);
/*
 * "a, b, c" into ret_ids (HL_CONFIG_MAX_SETS ids) and their number; what says why not. 0 or
 * -EINVAL (ret_ids and ret_n untouched).
 */
int hl_cfg_parse_sets(const char *value, char (*ret_ids)[HL_CONFIG_SET_ID], int *ret_n, char *what,
		      size_t what_size);
/* v into dst (size bytes); -EINVAL when it does not fit. */
int hl_cfg_copy_string(char *dst, size_t size, const char *v);
/* choices "a|b|c" holds v as a whole word. */
bool hl_cfg_is_choice(const char *choices, const char *v);
/* "a|b|c" as "a, b or c". */
void hl_cfg_choices_text(const char *choices, char *buf, size_t size);
/* HOST:PORT (or empty: off); 0 or -EINVAL with what filled. */
int hl_cfg_check_address(const char *v, char *what, size_t size);
/* A network interface name: 1..15 bytes, no '/', ':' or white space, not "." or "..". */
bool hl_cfg_valid_iface(const char *v);
/* Lamp names: 1..8, comma separated, each letters, digits, '_' or '-'. */
bool hl_cfg_valid_lamps(const char *v);

#endif
