/* SPDX-License-Identifier: MIT */
#include "fmu/fmu.h"

#include <errno.h>
#include <limits.h>
#include <poll.h>
#include <signal.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include "base/clock.h"
#include "fmu/child.h"
#include "fmu/fmi2.h"
#include "fmu/model_description.h"
#include "fmu/unzip.h"

#define DEFAULT_TIMEOUT_MS 10000
#define REAP_POLL_MS 5 /* between waitpid(WNOHANG) tries while a child exits */

struct hl_fmu {
	char *path;
	char *instance;
	struct hl_fmu_md *md;
	char dir[PATH_MAX];
	FILE *log;
	int timeout_ms;
	pid_t pid; /* 0 once reaped */
	int fd;
	bool failed; /* a call returned fmi2Error or worse: no more steps (2.1.3) */
	char gone[160]; /* how the child ended, once it did */
	char last_log[512]; /* the FMU's last message, "[category] text" */
	char error[512]; /* hl_fmu_error() */
	int *pending_at; /* per variable: its slot among the pending sets, or -1 */
	int *pending_idx; /* per slot: the variable */
	double *pending_v; /* per slot: the value */
	int n_pending;
	unsigned char *buf; /* one message, HL_FMU_MSG_MAX bytes */
};

const char *hl_fmu_type_name(enum hl_fmu_type t)
{
	static const char *const names[] = { "Real", "Integer", "Boolean", "String",
					     "Enumeration" };

	return (unsigned)t < sizeof(names) / sizeof(names[0]) ? names[t] : "?";
}

const char *hl_fmu_causality_name(enum hl_fmu_causality c)
{
	static const char *const names[] = { "parameter", "calculatedParameter", "input", "output",
					     "local",	  "independent" };

	return (unsigned)c < sizeof(names) / sizeof(names[0]) ? names[c] : "?";
}

static const char *status_name(int s)
{
	static const char *const names[] = { "fmi2OK",	  "fmi2Warning", "fmi2Discard",
					     "fmi2Error", "fmi2Fatal",	 "fmi2Pending" };

	return s >= 0 && s < (int)(sizeof(names) / sizeof(names[0])) ? names[s] :
								       "an unknown status";
}

/* One line per message: control characters of the FMU's text become spaces. */
static void log_line(struct hl_fmu *f, const char *category, const char *text)
{
	fprintf(f->log, "fmu %s: [%s] ", f->instance, category);
	for (const char *s = text; *s; s++)
		fputc((unsigned char)*s < 0x20 ? ' ' : *s, f->log);
	fputc('\n', f->log);
	fflush(f->log);
}

static void on_log(struct hl_fmu *f, size_t len)
{
	const char *category = (const char *)f->buf + sizeof(struct hl_fmu_msg);
	const char *end = (const char *)f->buf + len, *text;

	/* the child sends "category\0text\0"; a short one is shown as far as it goes */
	text = memchr(category, '\0', (size_t)(end - category));
	if (!text)
		return;
	text++;
	if (!memchr(text, '\0', (size_t)(end - text)))
		return;
	log_line(f, category, text);
	snprintf(f->last_log, sizeof(f->last_log), "[%s] %s", category, text);
}

/* "; its last message: [...] ..." or nothing: the FMU's own words on what went wrong. */
static const char *last_words(const struct hl_fmu *f, char *buf, size_t size)
{
	if (!f->last_log[0])
		return "";
	snprintf(buf, size, "; the FMU's last message: %s", f->last_log);
	return buf;
}

static void describe_exit(struct hl_fmu *f, int st)
{
	if (WIFSIGNALED(st)) {
		const char *abbrev = sigabbrev_np(WTERMSIG(st));

		snprintf(f->gone, sizeof(f->gone), "killed by signal SIG%s (%s)",
			 abbrev ? abbrev : "?", strsignal(WTERMSIG(st)));
	} else if (WIFEXITED(st)) {
		snprintf(f->gone, sizeof(f->gone), "exited with status %d", WEXITSTATUS(st));
	}
}

/* Waits up to wait_ms for the child to end, then kills it; it is reaped either way. */
static void reap(struct hl_fmu *f, int wait_ms)
{
	const int64_t deadline = hl_clock_monotonic_ns() + (int64_t)wait_ms * 1000000;
	int st = 0;
	pid_t r;

	if (!f->pid)
		return;
	for (;;) {
		r = waitpid(f->pid, &st, WNOHANG);
		if (r == f->pid || (r < 0 && errno != EINTR))
			break;
		if (r == 0 && hl_clock_monotonic_ns() >= deadline) {
			kill(f->pid, SIGKILL);
			while ((r = waitpid(f->pid, &st, 0)) < 0 && errno == EINTR)
				;
			break;
		}
		if (r == 0)
			poll(NULL, 0, REAP_POLL_MS);
	}
	if (r == f->pid)
		describe_exit(f, st);
	else
		snprintf(f->gone, sizeof(f->gone), "lost (waitpid: %s)", strerror(errno));
	f->pid = 0;
}

/*
 * Reads the child's messages until its reply, the FMU's log messages written as they come,
 * all within the timeout. 0 and the reply's length; -ETIMEDOUT (the child killed), -EPIPE (it
 * died); err then says so, naming what: the call or calls under way.
 */
static int await_reply(struct hl_fmu *f, const char *what, size_t *ret_len, char *err,
		       size_t err_size)
{
	const int64_t deadline = hl_clock_monotonic_ns() + (int64_t)f->timeout_ms * 1000000;
	char words[600];

	for (;;) {
		const int64_t left_ns = deadline - hl_clock_monotonic_ns();
		struct pollfd p = { .fd = f->fd, .events = POLLIN };
		const struct hl_fmu_msg *m = (const struct hl_fmu_msg *)f->buf;
		ssize_t n;
		int r;

		r = left_ns > 0 ? poll(&p, 1, (int)((left_ns + 999999) / 1000000)) : 0;
		if (r < 0 && errno == EINTR)
			continue;
		if (r == 0) {
			kill(f->pid, SIGKILL);
			reap(f, f->timeout_ms);
			snprintf(f->gone, sizeof(f->gone), "killed after a timeout");
			snprintf(err, err_size,
				 "'%s': %s timed out after %d ms; the FMU's process was killed%s",
				 f->path, what, f->timeout_ms, last_words(f, words, sizeof(words)));
			return -ETIMEDOUT;
		}
		n = recv(f->fd, f->buf, HL_FMU_MSG_MAX, MSG_DONTWAIT);
		if (n < 0 && (errno == EINTR || errno == EAGAIN))
			continue;
		if (n <= 0) {
			/* EOF or a reset: the child is ending; it has the timeout to do so */
			reap(f, f->timeout_ms);
			snprintf(err, err_size, "'%s': %s: the FMU's process %s%s", f->path, what,
				 f->gone, last_words(f, words, sizeof(words)));
			return -EPIPE;
		}
		if ((size_t)n < sizeof(*m))
			continue;
		if (m->kind == HL_FMU_MSG_LOG) {
			on_log(f, (size_t)n);
			continue;
		}
		if (m->kind == HL_FMU_MSG_REPLY) {
			*ret_len = (size_t)n;
			return 0;
		}
	}
}

static int send_msg(struct hl_fmu *f, size_t len, const char *what, char *err, size_t err_size)
{
	char words[600];

	/* MSG_NOSIGNAL: a dead child is an error to report, not a SIGPIPE that ends us */
	while (send(f->fd, f->buf, len, MSG_NOSIGNAL) < 0) {
		if (errno == EINTR)
			continue;
		reap(f, f->timeout_ms);
		snprintf(err, err_size, "'%s': %s: the FMU's process %s%s", f->path, what, f->gone,
			 last_words(f, words, sizeof(words)));
		return -EPIPE;
	}
	return 0;
}

/* A reply's status: fmi2OK and fmi2Warning go on; anything else fails the call. */
static int check_status(struct hl_fmu *f, const char *what, char *err, size_t err_size)
{
	const struct hl_fmu_msg *m = (const struct hl_fmu_msg *)f->buf;
	char words[600];

	if (m->status == fmi2OK || m->status == fmi2Warning)
		return 0;
	f->failed = true;
	snprintf(err, err_size, "'%s': %s%s returned %s%s", f->path,
		 hl_fmu_call_name((enum hl_fmu_call)m->call), what, status_name(m->status),
		 last_words(f, words, sizeof(words)));
	return -EIO;
}

/* file:// and the directory, each byte outside RFC 3986's unreserved ones and '/' escaped. */
static int resource_uri(const char *dir, char *buf, size_t size)
{
	static const char hex[] = "0123456789ABCDEF";
	size_t at = (size_t)snprintf(buf, size, "file://");

	for (const char *s = dir; *s; s++) {
		const unsigned char c = (unsigned char)*s;

		if (at + 4 >= size)
			return -ENAMETOOLONG;
		if ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
		    strchr("/-._~", c)) {
			buf[at++] = (char)c;
		} else {
			buf[at++] = '%';
			buf[at++] = hex[c >> 4];
			buf[at++] = hex[c & 15];
		}
	}
	if ((size_t)snprintf(buf + at, size - at, "/resources") >= size - at)
		return -ENAMETOOLONG;
	return 0;
}

static int start_child(struct hl_fmu *f, double start_s, char *err, size_t err_size)
{
	char so[PATH_MAX + 64], uri[3 * PATH_MAX + 32];
	struct hl_fmu_child_args a = { .instance = f->instance,
				       .guid = f->md->guid,
				       .start_s = start_s };
	const struct hl_fmu_msg *m = (const struct hl_fmu_msg *)f->buf;
	size_t len;
	int r;

	if ((size_t)snprintf(so, sizeof(so), "%s/binaries/linux64/%s.so", f->dir,
			     f->md->identifier) >= sizeof(so) ||
	    resource_uri(f->dir, uri, sizeof(uri)) < 0) {
		snprintf(err, err_size, "'%s': the unpacked paths are too long", f->path);
		return -ENAMETOOLONG;
	}
	if (access(so, R_OK) < 0) {
		r = -errno;
		snprintf(err, err_size,
			 "'%s': no binaries/linux64/%s.so: no binary for linux64 (%s)", f->path,
			 f->md->identifier, strerror(-r));
		return r;
	}
	a.so_path = so;
	a.resource_uri = uri;
	r = hl_fmu_child_start(&a, &f->pid, &f->fd);
	if (r < 0) {
		snprintf(err, err_size, "'%s': cannot start the FMU's process: %s", f->path,
			 strerror(-r));
		return r;
	}
	r = await_reply(f, "loading, fmi2Instantiate and initialization", &len, err, err_size);
	if (r < 0)
		return r;
	if (m->status == -1) {
		f->buf[len - 1] = '\0';
		snprintf(err, err_size, "'%s': binaries/linux64/%s.so: %s", f->path,
			 f->md->identifier, (const char *)f->buf + sizeof(*m));
		return -ENOEXEC;
	}
	if (m->call == HL_FMU_CALL_INSTANTIATE) {
		char words[600];

		snprintf(err, err_size, "'%s': fmi2Instantiate returned NULL%s", f->path,
			 last_words(f, words, sizeof(words)));
		return -EIO;
	}
	return check_status(f, "", err, err_size);
}

int hl_fmu_open(const char *path, double start_s, const struct hl_fmu_options *o,
		struct hl_fmu **ret, char *err, size_t err_size)
{
	char md_path[PATH_MAX + 32];
	struct hl_fmu *f;
	size_t n;
	int r;

	f = calloc(1, sizeof(*f));
	if (!f || !(f->path = strdup(path))) {
		free(f);
		snprintf(err, err_size, "'%s': out of memory", path);
		return -ENOMEM;
	}
	f->fd = -1;
	f->log = o && o->log ? o->log : stderr;
	f->timeout_ms = o && o->timeout_ms > 0 ? o->timeout_ms : DEFAULT_TIMEOUT_MS;
	r = hl_fmu_unzip(path, f->dir, sizeof(f->dir), err, err_size);
	if (r < 0) {
		f->dir[0] = '\0';
		goto err_close;
	}
	snprintf(md_path, sizeof(md_path), "%s/modelDescription.xml", f->dir);
	r = hl_fmu_md_read(md_path, path, &f->md, err, err_size);
	if (r < 0)
		goto err_close;
	f->instance = strdup(o && o->instance ? o->instance : f->md->identifier);
	n = f->md->n_vars ? (size_t)f->md->n_vars : 1;
	f->pending_at = malloc(n * sizeof(int));
	f->pending_idx = malloc(n * sizeof(int));
	f->pending_v = malloc(n * sizeof(double));
	f->buf = malloc(HL_FMU_MSG_MAX);
	if (!f->instance || !f->pending_at || !f->pending_idx || !f->pending_v || !f->buf) {
		snprintf(err, err_size, "'%s': out of memory", path);
		r = -ENOMEM;
		goto err_close;
	}
	for (int i = 0; i < f->md->n_vars; i++)
		f->pending_at[i] = -1;
	r = start_child(f, start_s, err, err_size);
	if (r < 0)
		goto err_close;
	fprintf(f->log,
		"fmu %s: '%s': model '%s', FMI 2.0 co-simulation, %d variables, start %g s, "
		"step %g s, timeout %d ms, process %d\n",
		f->instance, path, f->md->model_name, f->md->n_vars, start_s, o ? o->step_s : 0.0,
		f->timeout_ms, (int)f->pid);
	fflush(f->log);
	*ret = f;
	return 0;

err_close:
	hl_fmu_close(f);
	return r;
}

void hl_fmu_close(struct hl_fmu *f)
{
	struct hl_fmu_msg *m;
	char err[1024];
	size_t len;

	if (!f)
		return;
	m = (struct hl_fmu_msg *)f->buf;
	if (f->pid && m) {
		*m = (struct hl_fmu_msg){ .kind = HL_FMU_MSG_END };
		if (send_msg(f, sizeof(*m), "fmi2Terminate and fmi2FreeInstance", err,
			     sizeof(err)) < 0 ||
		    await_reply(f, "fmi2Terminate and fmi2FreeInstance", &len, err, sizeof(err)) <
			    0 ||
		    check_status(f, "", err, sizeof(err)) < 0)
			fprintf(f->log, "fmu %s: %s\n", f->instance, err);
	}
	reap(f, f->timeout_ms);
	if (f->fd >= 0)
		close(f->fd);
	if (f->dir[0])
		hl_fmu_unzip_remove(f->dir);
	hl_fmu_md_free(f->md);
	free(f->buf);
	free(f->pending_at);
	free(f->pending_idx);
	free(f->pending_v);
	free(f->instance);
	free(f->path);
	free(f);
}

const char *hl_fmu_model_name(const struct hl_fmu *f)
{
	return f->md->model_name;
}

const char *hl_fmu_identifier(const struct hl_fmu *f)
{
	return f->md->identifier;
}

int hl_fmu_n_vars(const struct hl_fmu *f)
{
	return f->md->n_vars;
}

const struct hl_fmu_var *hl_fmu_var(const struct hl_fmu *f, int i)
{
	return i >= 0 && i < f->md->n_vars ? &f->md->vars[i] : NULL;
}

int hl_fmu_find(const struct hl_fmu *f, const char *name)
{
	for (int i = 0; i < f->md->n_vars; i++)
		if (strcmp(f->md->vars[i].name, name) == 0)
			return i;
	return -ENOENT;
}

const char *hl_fmu_error(const struct hl_fmu *f)
{
	return f->error;
}

int hl_fmu_pid(const struct hl_fmu *f)
{
	return (int)f->pid;
}

const char *hl_fmu_dir(const struct hl_fmu *f)
{
	return f->dir;
}

/* A Real variable: for a get any, for a set an input or a parameter. */
static int check_real(struct hl_fmu *f, int idx, bool set, char *err, size_t err_size)
{
	const struct hl_fmu_var *v = hl_fmu_var(f, idx);

	if (!v) {
		snprintf(err, err_size, "'%s': no variable with index %d", f->path, idx);
		return -EINVAL;
	}
	if (v->type != HL_FMU_REAL) {
		snprintf(err, err_size,
			 "'%s': variable '%s' (modelDescription.xml:%d) is %s, not Real", f->path,
			 v->name, v->line, hl_fmu_type_name(v->type));
		return -EINVAL;
	}
	if (set && v->causality != HL_FMU_INPUT && v->causality != HL_FMU_PARAMETER) {
		snprintf(err, err_size,
			 "'%s': variable '%s' (modelDescription.xml:%d) is an %s, not an input or "
			 "a parameter: it cannot be set",
			 f->path, v->name, v->line, hl_fmu_causality_name(v->causality));
		return -EINVAL;
	}
	return 0;
}

int hl_fmu_set_real(struct hl_fmu *f, const int *idx, const double *v, int n)
{
	f->error[0] = '\0';
	for (int i = 0; i < n; i++) {
		const int r = check_real(f, idx[i], true, f->error, sizeof(f->error));

		if (r < 0)
			return r;
	}
	/* one slot per variable: a second set before the step replaces the first */
	for (int i = 0; i < n; i++) {
		int at = f->pending_at[idx[i]];

		if (at < 0) {
			at = f->n_pending++;
			f->pending_at[idx[i]] = at;
			f->pending_idx[at] = idx[i];
		}
		f->pending_v[at] = v[i];
	}
	return 0;
}

static void clear_pending(struct hl_fmu *f)
{
	for (int i = 0; i < f->n_pending; i++)
		f->pending_at[f->pending_idx[i]] = -1;
	f->n_pending = 0;
}

/* The request: the header, the references set, their values, the references read. */
static size_t lay_out_step(struct hl_fmu *f, double t_s, double h_s, const int *idx, int n)
{
	struct hl_fmu_msg *m = (struct hl_fmu_msg *)f->buf;
	unsigned char *p = f->buf + sizeof(*m);
	uint32_t vr;

	*m = (struct hl_fmu_msg){ .kind = HL_FMU_MSG_STEP,
				  .n_set = (uint32_t)f->n_pending,
				  .n_get = (uint32_t)n,
				  .t_s = t_s,
				  .h_s = h_s };
	for (int i = 0; i < f->n_pending; i++, p += sizeof(vr)) {
		vr = f->md->vars[f->pending_idx[i]].vr;
		memcpy(p, &vr, sizeof(vr));
	}
	memcpy(p, f->pending_v, (size_t)f->n_pending * sizeof(double));
	p += (size_t)f->n_pending * sizeof(double);
	for (int i = 0; i < n; i++, p += sizeof(vr)) {
		vr = f->md->vars[idx[i]].vr;
		memcpy(p, &vr, sizeof(vr));
	}
	return (size_t)(p - f->buf);
}

int hl_fmu_step(struct hl_fmu *f, double t_s, double h_s, const int *idx, double *ret, int n,
		char *err, size_t err_size)
{
	const struct hl_fmu_msg *m = (const struct hl_fmu_msg *)f->buf;
	char what[128], words[600];
	size_t len;
	int r;

	f->error[0] = '\0';
	if (!f->pid) {
		snprintf(err, err_size, "'%s': the FMU's process %s earlier%s", f->path, f->gone,
			 last_words(f, words, sizeof(words)));
		r = -EPIPE;
		goto out;
	}
	if (f->failed) {
		snprintf(err, err_size, "'%s': an earlier call failed; the FMU cannot step on",
			 f->path);
		r = -EIO;
		goto out;
	}
	if (n < 0 || n > HL_FMU_MAX_BATCH) {
		snprintf(err, err_size, "'%s': %d values read in one step, at most %d", f->path, n,
			 HL_FMU_MAX_BATCH);
		r = -EINVAL;
		goto out;
	}
	if (f->n_pending > HL_FMU_MAX_BATCH) {
		snprintf(err, err_size, "'%s': %d values set for one step, at most %d", f->path,
			 f->n_pending, HL_FMU_MAX_BATCH);
		clear_pending(f);
		r = -EINVAL;
		goto out;
	}
	for (int i = 0; i < n; i++) {
		r = check_real(f, idx[i], false, err, err_size);
		if (r < 0)
			goto out;
	}
	/* one round trip: the sets, the step, the gets */
	snprintf(what, sizeof(what), "the step at t=%g s (fmi2SetReal, fmi2DoStep, fmi2GetReal)",
		 t_s);
	r = send_msg(f, lay_out_step(f, t_s, h_s, idx, n), what, err, err_size);
	clear_pending(f);
	if (r < 0)
		goto out;
	r = await_reply(f, what, &len, err, err_size);
	if (r < 0)
		goto out;
	snprintf(what, sizeof(what), " at t=%g s", t_s);
	r = check_status(f, what, err, err_size);
	if (r < 0)
		goto out;
	if (m->n_get != (uint32_t)n || len != sizeof(*m) + (size_t)n * sizeof(double)) {
		snprintf(err, err_size,
			 "'%s': the FMU's process answered the step at t=%g s "
			 "with %zu bytes",
			 f->path, t_s, len);
		r = -EPROTO;
		goto out;
	}
	memcpy(ret, f->buf + sizeof(*m), (size_t)n * sizeof(double));
	return 0;
out:
	snprintf(f->error, sizeof(f->error), "%s", err);
	return r;
}
