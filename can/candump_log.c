/* SPDX-License-Identifier: MIT */
#include "can/candump_log.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

struct hl_candump_log {
	FILE *f;
	bool own, loop;
	char *line;
	size_t cap;
	struct hl_candump_log_stats st;
	bool have_first;
	int64_t t_first_us, t_last_us; /* of this pass */
	int64_t pass_offset_ns; /* added to due times of the current pass */
};

int hl_candump_log_open(const char *path, bool loop, struct hl_candump_log **ret)
{
	struct hl_candump_log *log;

	if (strcmp(path, "-") == 0 && loop)
		return -EINVAL;
	log = calloc(1, sizeof(*log));
	if (!log)
		return -ENOMEM;
	if (strcmp(path, "-") == 0) {
		log->f = stdin;
	} else {
		log->f = fopen(path, "re");
		if (!log->f) {
			int rc = -errno;

			free(log);
			return rc;
		}
		log->own = true;
	}
	log->loop = loop;
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
	if (!log->loop || log->st.frames == 0)
		return 0;
	/* next pass: continue the timeline one gap after this pass's last frame */
	log->pass_offset_ns += (log->t_last_us - log->t_first_us) * 1000 + HL_LOG_LOOP_GAP_NS;
	log->have_first = false;
	log->st.passes++;
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
		len = (size_t)n;
		while (len && (log->line[len - 1] == '\n' || log->line[len - 1] == '\r'))
			len--;
		if (len == 0 || log->line[0] == '#')
			continue; /* blank lines and comments */
		if (hl_candump_parse(log->line, len, ret, &perr) < 0) {
			log->st.malformed++;
			if (err) {
				err->line = (long)log->st.lines;
				err->column = perr.column;
				snprintf(err->msg, sizeof(err->msg), "%s", perr.msg);
			}
			return -EBADMSG;
		}
		if (!log->have_first) {
			log->have_first = true;
			log->t_first_us = ret->t_us;
		} else if (ret->t_us < log->t_last_us) {
			ret->t_us = log->t_last_us; /* time never runs backwards in a replay */
		}
		log->t_last_us = ret->t_us;
		log->st.frames++;
		*ret_due_ns = log->pass_offset_ns + (ret->t_us - log->t_first_us) * 1000;
		return 1;
	}
}

void hl_candump_log_stats(const struct hl_candump_log *log, struct hl_candump_log_stats *ret)
{
	*ret = log->st;
}

int64_t hl_monotonic_ns(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

void hl_sleep_until(int64_t t_ns, const volatile int *stop)
{
	struct timespec ts = { .tv_sec = t_ns / 1000000000, .tv_nsec = t_ns % 1000000000 };

	while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR)
		if (stop && *stop)
			return;
}
