/* SPDX-License-Identifier: MIT */
/* The syntax of configuration values (daemon/core/config_syntax.h). */
#include "daemon/core/config_syntax.h"

#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>

#include "can/assembler.h"
#include "base/addr.h"

/* A set id is a file name in the regulations directory: letters, digits, '.', '_', '+', '-'. */
bool hl_cfg_valid_set_id(const char *s, size_t n)
{
	if (n == 0 || n >= HL_CONFIG_SET_ID || s[0] == '.')
		return false;
	for (size_t i = 0; i < n; i++)
		if (!isalnum((unsigned char)s[i]) && !strchr("._+-", s[i]))
			return false;
	return true;
}

/* MODE:ID+ID,... : names and ids of the set id's characters, each entry with one ':'. */
bool hl_cfg_valid_modes(const char *v)
{
	const char *entry = v;

	while (*entry) {
		const char *end = strchr(entry, ','), *colon = strchr(entry, ':');

		if (!end)
			end = entry + strlen(entry);
		if (!colon || colon >= end || colon == entry)
			return false;
		for (const char *c = entry; c < end; c++)
			if (c != colon && !isalnum((unsigned char)*c) && !strchr("._+-", *c))
				return false;
		if (!*end)
			break;
		entry = end + 1;
		if (!*entry)
			return false;
	}
	return true;
}

int hl_cfg_parse_sets(const char *value, char (*ret_ids)[HL_CONFIG_SET_ID], int *ret_n, char *what,
		      size_t what_size)
{
	char ids[HL_CONFIG_MAX_SETS][HL_CONFIG_SET_ID];
	const char *p = value;
	int n = 0;

	while (*p == ' ' || *p == '\t')
		p++;
	while (*p) {
		const char *end = strchr(p, ','), *last;
		size_t len;

		if (!end)
			end = p + strlen(p);
		last = end;
		while (last > p && (last[-1] == ' ' || last[-1] == '\t'))
			last--;
		len = (size_t)(last - p);
		if (!hl_cfg_valid_set_id(p, len)) {
			snprintf(what, what_size,
				 "'%.*s': expected set ids (letters, digits, . _ + -, at most %d "
				 "characters) separated by commas",
				 (int)(end - p), p, HL_CONFIG_SET_ID - 1);
			return -EINVAL;
		}
		if (n == HL_CONFIG_MAX_SETS) {
			snprintf(what, what_size,
				 "at most %d sets (one bit each in the frame header)",
				 HL_CONFIG_MAX_SETS);
			return -EINVAL;
		}
		memcpy(ids[n], p, len);
		ids[n][len] = '\0';
		for (int i = 0; i < n; i++)
			if (strcmp(ids[i], ids[n]) == 0) {
				snprintf(what, what_size, "'%.*s' is named twice", HL_CONFIG_SET_ID,
					 ids[n]);
				return -EINVAL;
			}
		n++;
		p = *end ? end + 1 : end;
		while (*p == ' ' || *p == '\t')
			p++;
		if (*end && !*p) {
			snprintf(what, what_size, "a set id after the last comma");
			return -EINVAL;
		}
	}
	memcpy(ret_ids, ids, sizeof(ids[0]) * n);
	*ret_n = n;
	return 0;
}

int hl_cfg_copy_string(char *dst, size_t size, const char *v)
{
	if (strlen(v) >= size)
		return -EINVAL;
	strcpy(dst, v);
	return 0;
}

/* choices "a|b|c" holds v as a whole word. */
bool hl_cfg_is_choice(const char *choices, const char *v)
{
	const size_t n = strlen(v);

	if (strchr(v, '|')) /* "cpu|gles" is not one of "auto|cpu|gles" */
		return false;
	for (const char *c = choices; n && c; c = strchr(c, '|') ? strchr(c, '|') + 1 : NULL)
		if (strncmp(c, v, n) == 0 && (c[n] == '|' || c[n] == '\0'))
			return true;
	return false;
}

/* "a|b|c" as "a, b or c". */
void hl_cfg_choices_text(const char *choices, char *buf, size_t size)
{
	size_t o = 0;

	for (const char *c = choices; *c && o + 5 < size; c++) {
		if (*c != '|') {
			buf[o++] = *c;
		} else if (strchr(c + 1, '|')) {
			o += (size_t)snprintf(buf + o, size - o, ", ");
		} else {
			o += (size_t)snprintf(buf + o, size - o, " or ");
		}
		if (o >= size)
			o = size - 1;
	}
	buf[o] = '\0';
}

/* HOST:PORT (or empty: off); 0 or -EINVAL with what filled. */
int hl_cfg_check_address(const char *v, char *what, size_t size)
{
	const char *colon = strrchr(v, ':');
	struct sockaddr_storage ss;
	char *end;
	long port;

	if (!*v)
		return 0;
	if (!colon || colon == v) {
		snprintf(what, size,
			 "'%s': expected HOST:PORT (an IPv4 address, [IPv6] or localhost; port "
			 "0..65535, 0 = any free port), or empty for off",
			 v);
		return -EINVAL;
	}
	errno = 0;
	port = strtol(colon + 1, &end, 10);
	if (!colon[1] || *end || errno || port < 0 || port > 65535 || !isdigit(colon[1])) {
		snprintf(what, size, "'%s': port '%s': expected 0..65535 (0 = any free port)", v,
			 colon + 1);
		return -EINVAL;
	}
	if (hl_addr_parse(v, &ss, NULL) < 0) {
		snprintf(what, size,
			 "'%s': host '%.*s': expected an IPv4 address, [IPv6 address] or localhost",
			 v, (int)(colon - v), v);
		return -EINVAL;
	}
	return 0;
}

/* A network interface name: 1..15 bytes, no '/', ':' or white space, not "." or "..". */
bool hl_cfg_valid_iface(const char *v)
{
	const size_t n = strlen(v);

	if (n >= 16 || strcmp(v, ".") == 0 || strcmp(v, "..") == 0)
		return false;
	for (const char *c = v; *c; c++)
		if (*c == '/' || *c == ':' || isspace((unsigned char)*c) ||
		    !isprint((unsigned char)*c))
			return false;
	return true;
}

/* Lamp names: 1..8, comma separated, each letters, digits, '_' or '-'. */
bool hl_cfg_valid_lamps(const char *v)
{
	int n = 0;
	size_t len = 0;

	for (const char *c = v;; c++) {
		if (*c == ',' || *c == '\0') {
			if (len == 0 || ++n > HL_ASM_MAX_LAMPS)
				return false;
			if (!*c)
				return true;
			len = 0;
		} else if (isalnum((unsigned char)*c) || *c == '_' || *c == '-') {
			len++;
		} else {
			return false;
		}
	}
}
