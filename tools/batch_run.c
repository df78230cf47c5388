/* SPDX-License-Identifier: MIT */
/*
 * hdlamp batch run PLAN.jsonl --out DIR (--index N | --index env | --jobs J): one task of a plan
 * by its index (what a Slurm array task or a Kubernetes Indexed Job's pod runs), or every task
 * not finished yet on this machine, J at a time (tools/batch.h, docs/scale.md).
 *
 * A task runs as a child process (hdlamp suite run, hdlamp sil, hdlampd --replay) with its output
 * in DIR/N/log.txt; this process waits for it, forwards SIGTERM and SIGINT to it (a scheduler's
 * scancel or time limit), and writes DIR/N/result.json from how it ended and what it wrote.
 */
#include <errno.h>
#include <fcntl.h>
#include <getopt.h>
#include <jansson.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "commands.h"
#include "base/file_replace.h"
#include "base/make_dirs.h"
#include "tools/batch.h"
#include "tools/batch_task.h"

#define PROG "hdlamp batch run"

static volatile sig_atomic_t stop_signal;
static volatile pid_t child_pid;

static void on_stop(int sig)
{
	stop_signal = sig;
	if (child_pid > 0)
		kill(child_pid, sig);
}

static void usage(FILE *f)
{
	fputs("usage: hdlamp batch run PLAN.jsonl --out DIR (--index N | --index env | --jobs J)\n"
	      "                        [--chunk K] [--force]\n"
	      "--index N: runs task N into DIR/N/ (report.json, junit.xml, log.txt, result.json);\n"
	      "--index env: N from JOB_COMPLETION_INDEX (a Kubernetes Indexed Job),\n"
	      "SLURM_ARRAY_TASK_ID (a Slurm array) or AWS_BATCH_JOB_ARRAY_INDEX (AWS Batch), plus\n"
	      "HL_BATCH_OFFSET; --jobs J: every task not\n"
	      "finished yet, J at a time, on this machine (a copy of the plan goes to\n"
	      "DIR/plan.jsonl for hdlamp batch merge). A finished task (exit 0, 2 or 3 in its\n"
	      "result.json) is not run again unless --force. --chunk K (with --index): tasks N*K to\n"
	      "N*K+K-1, one after the other (an array element for several short tasks).\n"
	      "Exit (--index): the task's: 0 passed, 3 failed, 2 bad input, 1 it could not finish.\n"
	      "Exit (--jobs): 0 every task passed, 3 one failed or erred, 2 bad input, 1 an error.\n",
	      f);
}

static int parse_index(const char *s, unsigned *ret)
{
	char *end;
	unsigned long v;

	errno = 0;
	v = strtoul(s, &end, 10);
	if (errno || end == s || *end || v > 100000000UL || s[0] == '-')
		return -EINVAL;
	*ret = (unsigned)v;
	return 0;
}

/*
 * --index env: the first of these set, plus HL_BATCH_OFFSET (what hdlamp batch slurm passes an
 * array beyond MaxArraySize): JOB_COMPLETION_INDEX (a Kubernetes Indexed Job's pod, set by the
 * Job controller: https://kubernetes.io/docs/tasks/job/indexed-parallel-processing-static/),
 * SLURM_ARRAY_TASK_ID (a Slurm array task: sbatch(1), "OUTPUT ENVIRONMENT VARIABLES"),
 * AWS_BATCH_JOB_ARRAY_INDEX (an AWS Batch child array job, from 0:
 * https://docs.aws.amazon.com/batch/latest/userguide/job_env_vars.html).
 */
static int index_from_env(unsigned *ret)
{
	static const char *const vars[] = { "JOB_COMPLETION_INDEX", "SLURM_ARRAY_TASK_ID",
					    "AWS_BATCH_JOB_ARRAY_INDEX" };
	const char *off = getenv("HL_BATCH_OFFSET");
	unsigned i, o = 0;

	for (size_t k = 0; k < sizeof(vars) / sizeof(vars[0]); k++) {
		const char *v = getenv(vars[k]);

		if (!v || !v[0])
			continue;
		if (parse_index(v, &i) < 0 || (off && off[0] && parse_index(off, &o) < 0)) {
			fprintf(stderr, PROG ": %s '%s' / HL_BATCH_OFFSET '%s': expected indices\n",
				vars[k], v, off ? off : "");
			return 2;
		}
		*ret = i + o;
		return 0;
	}
	fprintf(stderr, PROG
		": --index env: none of JOB_COMPLETION_INDEX (Kubernetes),\n"
		"SLURM_ARRAY_TASK_ID (Slurm) or AWS_BATCH_JOB_ARRAY_INDEX (AWS Batch) is set\n");
	return 2;
}

static void write_started(const char *dir, unsigned index, const char *id)
{
	char path[PATH_MAX + 32], host[256] = "";
	FILE *f;

	gethostname(host, sizeof(host) - 1);
	snprintf(path, sizeof(path), "%s/started.json", dir);
	f = fopen(path, "w");
	if (!f)
		return;
	struct timespec now;

	clock_gettime(CLOCK_REALTIME, &now);
	json_t *j = json_pack("{s:i, s:s, s:s, s:i, s:f}", "index", index, "id", id, "host", host,
			      "pid", (int)getpid(), "started_unix",
			      (double)now.tv_sec + (double)now.tv_nsec * 1e-9);

	json_dumpf(j, f, JSON_COMPACT | JSON_PRESERVE_ORDER);
	fputc('\n', f);
	fclose(f);
	json_decref(j);
}

/* Runs argv with stdout and stderr into log; fills how it ended. */
static void run_child(char *const argv[], const char *log, struct hl_batch_outcome *oc)
{
	struct sigaction sa = { .sa_handler = on_stop }, old_term, old_int;
	int status, fd;
	pid_t pid;

	sigemptyset(&sa.sa_mask);
	sigaction(SIGTERM, &sa, &old_term);
	sigaction(SIGINT, &sa, &old_int);
	fd = open(log, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
	if (fd < 0) {
		oc->exit = 1;
		snprintf(oc->reason, sizeof(oc->reason), "its log.txt: %s", strerror(errno));
		goto out;
	}
	pid = fork();
	if (pid == 0) {
		dup2(fd, 1);
		dup2(fd, 2);
		signal(SIGTERM, SIG_DFL);
		signal(SIGINT, SIG_DFL);
		execv(argv[0], argv);
		fprintf(stderr, "%s: %s\n", argv[0], strerror(errno));
		_exit(127);
	}
	close(fd);
	if (pid < 0) {
		oc->exit = 1;
		snprintf(oc->reason, sizeof(oc->reason), "fork: %s", strerror(errno));
		goto out;
	}
	child_pid = pid;
	if (stop_signal) /* arrived between fork and here */
		kill(pid, stop_signal);
	while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
		;
	child_pid = 0;
	oc->ran = true;
	if (WIFEXITED(status)) {
		oc->exit = WEXITSTATUS(status);
	} else {
		oc->exit = 1;
		oc->signal = WTERMSIG(status);
	}
	oc->stop_signal = stop_signal;
out:
	sigaction(SIGTERM, &old_term, NULL);
	sigaction(SIGINT, &old_int, NULL);
}

/* Task index of plan into out/index; its exit code. */
static int run_index(const char *plan, const char *out, unsigned index, bool force)
{
	char dir[PATH_MAX], path[PATH_MAX + 32], msg[1024], self[PATH_MAX], daemon[PATH_MAX];
	struct hl_batch_task t;
	struct hl_batch_outcome oc = { 0 };
	struct timespec t0, t1;
	char **argv = NULL;
	int rc;

	rc = hl_batch_task_read(plan, index, &t, msg, sizeof(msg));
	if (rc < 0) {
		fprintf(stderr, PROG ": %s\n", msg);
		return 2;
	}
	if (snprintf(dir, sizeof(dir), "%s/%u", out, index) >= (int)sizeof(dir)) {
		fprintf(stderr, PROG ": --out '%s': path too long\n", out);
		hl_batch_task_free(&t);
		return 2;
	}
	if (!force && hl_batch_task_finished(out, index, t.id)) {
		fprintf(stderr,
			PROG ": task %u (%s) already finished in %s (--force runs it again)\n",
			index, t.id, dir);
		hl_batch_task_free(&t);
		return 0;
	}
	rc = hl_make_dirs(dir);
	if (rc < 0) {
		fprintf(stderr, PROG ": '%s': %s\n", dir, strerror(-rc));
		hl_batch_task_free(&t);
		return 1;
	}
	snprintf(path, sizeof(path), "%s/result.json", dir);
	unlink(path);
	write_started(dir, index, t.id);
	clock_gettime(CLOCK_MONOTONIC, &t0);
	{
		struct timespec now;

		clock_gettime(CLOCK_REALTIME, &now);
		oc.started_unix = (double)now.tv_sec + (double)now.tv_nsec * 1e-9;
	}
	ssize_t len = readlink("/proc/self/exe", self, sizeof(self) - 1);

	if (len < 0) {
		oc.exit = 1;
		snprintf(oc.reason, sizeof(oc.reason), "/proc/self/exe: %s", strerror(errno));
	} else {
		self[len] = '\0';
		if (t.kind == HL_BATCH_DRIVE && hl_cli_hdlampd_path(daemon, sizeof(daemon)) < 0) {
			oc.exit = 1;
			snprintf(oc.reason, sizeof(oc.reason), "cannot find hdlampd beside hdlamp");
		} else {
			rc = hl_batch_task_argv(&t, self, daemon, dir, &argv);
			if (rc < 0) {
				oc.exit = 1;
				snprintf(oc.reason, sizeof(oc.reason), "its command: %s",
					 strerror(-rc));
			} else {
				snprintf(path, sizeof(path), "%s/log.txt", dir);
				fprintf(stderr, PROG ": task %u: %s\n", index, t.id);
				run_child(argv, path, &oc);
			}
		}
	}
	clock_gettime(CLOCK_MONOTONIC, &t1);
	oc.duration_s = (double)(t1.tv_sec - t0.tv_sec) + (double)(t1.tv_nsec - t0.tv_nsec) * 1e-9;
	rc = hl_batch_result_write(&t, dir, &oc, msg, sizeof(msg));
	if (rc < 0)
		fprintf(stderr, PROG ": %s\n", msg);
	fprintf(stderr, PROG ": task %u: %s%s%s\n", index, hl_batch_status_name(oc.status),
		oc.reason[0] ? ": " : "", oc.reason);
	free(argv);
	hl_batch_task_free(&t);
	if (rc < 0)
		return 1;
	/* a task stopped by a signal dies of it, as a scheduler expects */
	if (oc.stop_signal) {
		signal(oc.stop_signal, SIG_DFL);
		raise(oc.stop_signal);
	}
	return oc.status == HL_BATCH_PASSED ? 0 :
	       oc.status == HL_BATCH_FAILED ? 3 :
	       oc.exit == 2		    ? 2 :
					      1;
}

static int copy_plan(const char *plan, const char *out)
{
	char dst[PATH_MAX + 32], buf[65536];
	FILE *in, *o;
	size_t n;
	int rc = 0;

	snprintf(dst, sizeof(dst), "%s/plan.jsonl", out);
	in = fopen(plan, "r");
	if (!in)
		return -errno;
	o = fopen(dst, "w");
	if (!o) {
		rc = -errno;
		fclose(in);
		return rc;
	}
	while ((n = fread(buf, 1, sizeof(buf), in)) > 0)
		if (fwrite(buf, 1, n, o) != n)
			rc = -EIO;
	if (ferror(in))
		rc = -EIO;
	fclose(in);
	if (fclose(o) && !rc)
		rc = -EIO;
	return rc;
}

int hl_batch_copy_plan(const char *plan, const char *out)
{
	char a[PATH_MAX], b[PATH_MAX + 32], rb[PATH_MAX];
	int rc = hl_make_dirs(out);

	if (rc < 0)
		return rc;
	snprintf(b, sizeof(b), "%s/plan.jsonl", out);
	if (realpath(plan, a) && realpath(b, rb) && !strcmp(a, rb))
		return 0; /* the plan is already there */
	return copy_plan(plan, out);
}

/* Task index (the next line of plan_f) finished in out, for the id the plan gives it. */
static bool task_finished(FILE *plan_f, const char *out, unsigned index)
{
	char *line = NULL;
	size_t cap = 0;
	json_t *j = getline(&line, &cap, plan_f) >= 0 ? json_loads(line, 0, NULL) : NULL;
	const char *id = json_string_value(json_object_get(j, "id"));
	bool done = id && hl_batch_task_finished(out, index, id);

	free(line);
	json_decref(j);
	return done;
}

/* Every unfinished task, jobs at a time, each as `hdlamp batch run PLAN --index N`. */
static int run_jobs(const char *plan, const char *out, unsigned jobs, bool force)
{
	char self[PATH_MAX], msg[512], idx[32];
	unsigned n, next = 0, running = 0, failed = 0, errors = 0, skipped = 0, ran = 0;
	int rc;

	rc = hl_batch_plan_count(plan, &n, msg, sizeof(msg));
	if (rc < 0) {
		fprintf(stderr, PROG ": %s\n", msg);
		return 2;
	}
	rc = hl_batch_copy_plan(plan, out);
	if (rc < 0) {
		fprintf(stderr, PROG ": --out '%s': %s\n", out, strerror(-rc));
		return 1;
	}
	ssize_t len = readlink("/proc/self/exe", self, sizeof(self) - 1);
	FILE *plan_f = fopen(plan, "r");
	char *header = NULL;
	size_t header_cap = 0;

	if (len < 0 || !plan_f || getline(&header, &header_cap, plan_f) < 0) {
		fprintf(stderr, PROG ": %s: %s\n", len < 0 ? "/proc/self/exe" : plan,
			strerror(errno));
		if (plan_f)
			fclose(plan_f);
		free(header);
		return 1;
	}
	free(header);
	self[len] = '\0';
	signal(SIGINT, on_stop);
	signal(SIGTERM, on_stop);
	while ((next < n || running > 0) && !stop_signal) {
		if (next < n && running < jobs) {
			pid_t pid;

			if (!force && task_finished(plan_f, out, next)) {
				next++;
				skipped++;
				continue;
			}
			snprintf(idx, sizeof(idx), "%u", next);
			pid = fork();
			if (pid == 0) {
				char *argv[] = {
					self,	      "batch",	   "run",
					(char *)plan, "--index",   idx,
					"--out",      (char *)out, force ? "--force" : NULL,
					NULL
				};

				signal(SIGINT, SIG_DFL);
				signal(SIGTERM, SIG_DFL);
				execv(self, argv);
				_exit(127);
			}
			if (pid < 0) {
				fprintf(stderr, PROG ": fork: %s\n", strerror(errno));
				break;
			}
			next++;
			running++;
			ran++;
			continue;
		}
		int status;
		pid_t pid = wait(&status);

		if (pid < 0) {
			if (errno == EINTR)
				continue;
			break;
		}
		running--;
		if (!WIFEXITED(status) || (WEXITSTATUS(status) != 0 && WEXITSTATUS(status) != 3))
			errors++;
		else if (WEXITSTATUS(status) == 3)
			failed++;
	}
	if (stop_signal) {
		kill(0, SIGTERM);
		while (wait(NULL) > 0 || errno == EINTR)
			;
	}
	fclose(plan_f);
	fprintf(stderr,
		PROG ": %u tasks: %u run (%u failed, %u errors), %u already finished%s; "
		     "hdlamp batch merge %s merges them\n",
		n, ran, failed, errors, skipped, stop_signal ? ", stopped by a signal" : "", out);
	return stop_signal ? 1 : failed || errors ? 3 : 0;
}

/*
 * --index I --chunk K: tasks I*K .. I*K+K-1 (those the plan has), one after the other (a
 * scheduler's array element running several short tasks). The worst exit: 1, then 2, then 3.
 */
static int run_chunk(const char *plan, const char *out, unsigned index, unsigned chunk, bool force)
{
	char msg[512];
	unsigned n;
	int worst = 0;

	if (hl_batch_plan_count(plan, &n, msg, sizeof(msg)) < 0) {
		fprintf(stderr, PROG ": %s\n", msg);
		return 2;
	}
	if ((unsigned long long)index * chunk >= n) {
		fprintf(stderr,
			PROG ": --index %u --chunk %u: the plan has %u tasks (chunks 0..%u)\n",
			index, chunk, n, (n - 1) / chunk);
		return 2;
	}
	for (unsigned i = index * chunk; i < n && i < (index + 1) * chunk; i++) {
		int rc = run_index(plan, out, i, force);

		if (rc == 1 || (rc == 2 && worst != 1) || (rc == 3 && worst == 0))
			worst = rc;
	}
	return worst;
}

int hl_batch_run_cmd(int argc, char **argv)
{
	static const struct option opts[] = {
		{ "out", required_argument, NULL, 'o' },
		{ "index", required_argument, NULL, 'i' },
		{ "jobs", required_argument, NULL, 'j' },
		{ "force", no_argument, NULL, 'f' },
		{ "chunk", required_argument, NULL, 'k' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	const char *out = NULL, *index_arg = NULL;
	unsigned jobs = 0, index, chunk = 0;
	bool force = false;
	int c;

	optind = 1;
	while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
		switch (c) {
		case 'o':
			out = optarg;
			break;
		case 'i':
			index_arg = optarg;
			break;
		case 'j':
			if (parse_index(optarg, &jobs) < 0 || jobs < 1 || jobs > 1024) {
				fprintf(stderr, PROG ": --jobs '%s': expected 1..1024\n", optarg);
				return 2;
			}
			break;
		case 'f':
			force = true;
			break;
		case 'k':
			if (parse_index(optarg, &chunk) < 0 || chunk < 1 || chunk > 100000) {
				fprintf(stderr, PROG ": --chunk '%s': expected 1..100000\n",
					optarg);
				return 2;
			}
			break;
		case 'h':
			usage(stdout);
			return 0;
		default:
			usage(stderr);
			return 2;
		}
	}
	if (optind != argc - 1 || !out || !index_arg == !jobs) {
		if (optind == argc - 1 && out && index_arg && jobs)
			fprintf(stderr, PROG ": --index and --jobs: one of the two\n");
		usage(stderr);
		return 2;
	}
	if (jobs && chunk) {
		fprintf(stderr, PROG ": --chunk goes with --index\n");
		return 2;
	}
	if (jobs)
		return run_jobs(argv[optind], out, jobs, force);
	if (!strcmp(index_arg, "env")) {
		if (index_from_env(&index))
			return 2;
	} else if (parse_index(index_arg, &index) < 0) {
		fprintf(stderr, PROG ": --index '%s': expected a task's index or 'env'\n",
			index_arg);
		return 2;
	}
	if (!chunk)
		return run_index(argv[optind], out, index, force);
	return run_chunk(argv[optind], out, index, chunk, force);
}
