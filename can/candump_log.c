/* SPDX-License-Identifier: MIT */
#include "can/candump_log.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

struct hl_candump_log {
	FILE *f;
	bool own;
	uint64_t max_passes; /* 0: endless */
	char *line;
	size_t cap;
	long line_no; /* in the file: counted again from 1 in every pass */
	struct hl_candump_log_stats st;
	bool have_first;
	int64_t t_first_us, t_last_us; /* of this pass */
	int64_t pass_offset_ns; /* added to due times of the current pass */
};

/* Whether the file holds a frame: read up to the first one, then rewound. 0, -ENODATA, -EIO. */
static int has_frame(struct hl_candump_log *log)
{
	ssize_t n;
	int rc = -ENODATA;

	while (rc < 0 && (n = getline(&log->line, &log->cap, log->f)) >= 0) {
		struct hl_candump_frame fr;
		struct hl_candump_error perr;
		size_t len = (size_t)n;

		while (len && (log->line[len - 1] == '\n' || log->line[len - 1] == '\r'))
			len--;
		if (len && log->line[0] != '#' && hl_candump_parse(log->line, len, &fr, &perr) == 0)
			rc = 0;
	}
	if (ferror(log->f))
		rc = -EIO;
	rewind(log->f);
	return rc;
}

int hl_candump_log_open(const char *path, uint64_t passes, struct hl_candump_log **ret)
{
	struct hl_candump_log *log;
	struct stat st;
	int rc;

	if (strcmp(path, "-") == 0 && passes != 1)
		return -EINVAL;
	log = calloc(1, sizeof(*log));
	if (!log)
		return -ENOMEM;
	if (strcmp(path, "-") == 0) {
		log->f = stdin;
	} else {
		log->f = fopen(path, "re");
		if (!log->f) {
			rc = -errno;
			free(log);
			return rc;
		}
		log->own = true;
		/* a pipe cannot be read twice: only a regular file is checked ahead */
		rc = fstat(fileno(log->f), &st) == 0 && S_ISREG(st.st_mode) ? has_frame(log) : 0;
		if (rc < 0) {
			hl_candump_log_free(log);
			return rc;
		}
	}
	log->max_passes = passes;
	log->st.passes = 1;
	*ret = log;
	return 0;
}

void hl_candump_log_free(struct hl_candump_log *log)
{
	if (!log)
		return;
	if (log->own)
		fclose(log->f);
	free(log->line);
	free(log);
}

/* Next line without its newline; 0 at the end of a pass (rewinds when looping). */
static ssize_t next_line(struct hl_candump_log *log)
{
	ssize_t n = getline(&log->line, &log->cap, log->f);

	if (n >= 0)
		return n;
	if (ferror(log->f))
		return -EIO;
	if (log->st.passes == log->max_passes || log->st.frames == 0)
		return 0;
	/* next pass: continue the timeline one gap after this pass's last frame */
	log->pass_offset_ns += (log->t_last_us - log->t_first_us) * 1000 + HL_LOG_LOOP_GAP_NS;
	log->have_first = false;
	log->st.passes++;
	log->line_no = 0;
	rewind(log->f);
	n = getline(&log->line, &log->cap, log->f);
	return n >= 0 ? n : (ferror(log->f) ? -EIO : 0);
}

int hl_candump_log_next(struct hl_candump_log *log, struct hl_candump_frame *ret,
			int64_t *ret_due_ns, struct hl_candump_log_error *err)
{
	for (;;) {
		struct hl_candump_error perr;
		ssize_t n = next_line(log);
		size_t len;

		if (n <= 0)
			return (int)n;
		log->st.lines++;
		log->line_no++;
		len = (size_t)n;
		while (len && (log->line[len - 1] == '\n' || log->line[len - 1] == '\r'))
			len--;
		if (len == 0 || log->line[0] == '#')
			continue; /* blank lines and comments */
		if (hl_candump_parse(log->line, len, ret, &perr) < 0) {
			log->st.malformed++;
			if (err) {
				err->line = log->line_no;
				err->column = perr.column;
				snprintf(err->msg, sizeof(err->msg), "%s", perr.msg);
			}
			return -EBADMSG;
		}
		log->st.frames++;
		if (!log->have_first) {
			log->have_first = true;
			log->t_first_us = ret->t_us;
		} else if (ret->t_us < log->t_last_us) {
			/* time never runs backwards in a replay: due with the previous frame */
			log->st.backwards++;
			if (err) {
				err->line = log->line_no;
				err->column = 1;
				snprintf(
					err->msg, sizeof(err->msg),
					"timestamp %lld.%06lld is %lld us before the previous frame's; "
					"expected times that never decrease (replayed at the previous "
					"frame's time)",
					(long long)(ret->t_us / 1000000),
					(long long)(ret->t_us % 1000000),
					(long long)(log->t_last_us - ret->t_us));
			}
			ret->t_us = log->t_last_us;
			*ret_due_ns = log->pass_offset_ns + (ret->t_us - log->t_first_us) * 1000;
			return 2;
		}
		log->t_last_us = ret->t_us;
		*ret_due_ns = log->pass_offset_ns + (ret->t_us - log->t_first_us) * 1000;
		return 1;
	}
}

void hl_candump_log_stats(const struct hl_candump_log *log, struct hl_candump_log_stats *ret)
{
	*ret = log->st;
}
