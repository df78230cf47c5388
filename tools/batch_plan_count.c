/* SPDX-License-Identifier: MIT */
/*
 * The plan's header (tools/batch.h): its first line says how many tasks follow. Read alone, so
 * a scheduler's manifest (hdlamp batch k8s, slurm) knows the array's size without reading a
 * plan of many thousand lines.
 */
#include <errno.h>
#include <jansson.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tools/batch.h"

#define HEADER_EXPECTED "{\"plan\": \"hdlamp batch plan\", \"version\": 1, \"tasks\": N}"

static int header_error(char *msg, size_t msg_size, const char *path, const char *what)
{
	snprintf(msg, msg_size, "%s:1: %s; expected the plan's header %s", path, what,
		 HEADER_EXPECTED);
	return -EBADMSG;
}

static int header_count(const json_t *root, const char *path, unsigned *ret_n, char *msg,
			size_t msg_size)
{
	const json_t *plan, *version, *tasks;
	char what[160];

	if (!json_is_object(root))
		return header_error(msg, msg_size, path, "not a JSON object");
	plan = json_object_get(root, "plan");
	if (!json_is_string(plan) || strcmp(json_string_value(plan), "hdlamp batch plan") != 0)
		return header_error(msg, msg_size, path,
				    "\"plan\" is not \"hdlamp batch plan\" (not a plan)");
	version = json_object_get(root, "version");
	if (!json_is_integer(version) || json_integer_value(version) != 1) {
		if (json_is_integer(version))
			snprintf(what, sizeof(what), "\"version\" is %lld, this hdlamp reads 1",
				 (long long)json_integer_value(version));
		else
			snprintf(what, sizeof(what), "\"version\" is missing or not an integer");
		return header_error(msg, msg_size, path, what);
	}
	tasks = json_object_get(root, "tasks");
	if (!json_is_integer(tasks) || json_integer_value(tasks) < 0 ||
	    json_integer_value(tasks) > INT_MAX)
		return header_error(msg, msg_size, path,
				    "\"tasks\" is missing or not an integer from 0 to 2147483647");
	*ret_n = (unsigned)json_integer_value(tasks);
	return 0;
}

int hl_batch_plan_count(const char *path, unsigned *ret_n, char *msg, size_t msg_size)
{
	char *line = NULL, what[256];
	size_t cap = 0;
	json_error_t jerr;
	json_t *root;
	ssize_t len;
	FILE *f;
	int rc;

	f = fopen(path, "re");
	if (!f) {
		rc = -errno;
		snprintf(msg, msg_size, "%s: %s", path, strerror(-rc));
		return rc;
	}
	errno = 0;
	len = getline(&line, &cap, f);
	if (len < 0) {
		rc = errno ? -errno : -EBADMSG;
		if (rc == -EBADMSG)
			header_error(msg, msg_size, path, "the file is empty");
		else
			snprintf(msg, msg_size, "%s: %s", path, strerror(-rc));
		goto err_free;
	}
	root = json_loadb(line, (size_t)len, JSON_REJECT_DUPLICATES, &jerr);
	if (!root) {
		snprintf(what, sizeof(what), "column %d: not JSON (%s)", jerr.column, jerr.text);
		rc = header_error(msg, msg_size, path, what);
		goto err_free;
	}
	rc = header_count(root, path, ret_n, msg, msg_size);
	json_decref(root);
err_free:
	free(line);
	fclose(f);
	return rc;
}
