/* SPDX-License-Identifier: MIT */
/*
 * hdlamp batch slurm PLAN.jsonl --out DIR: the plan's unfinished tasks submitted as Slurm job
 * arrays (sbatch --array=LIST%P; each array task runs `hdlamp batch run DIR/plan.jsonl --index
 * env --out DIR`, its index from SLURM_ARRAY_TASK_ID), and a merge job that runs after all of
 * them (--dependency=afterany). Submitting again submits only what has no finished result.
 */
#include <errno.h>
#include <getopt.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "commands.h"
#include "base/make_dirs.h"
#include "tools/batch.h"
#include "tools/batch_task.h"

#define PROG "hdlamp batch slurm"
#define MAX_CHUNKS 1024

struct slurm {
	const char *out, *partition, *time_limit, *mem, *sbatch;
	unsigned max_parallel, max_array, chunk;
	bool dry_run;
	char plan[PATH_MAX + 32], dir[PATH_MAX], self[PATH_MAX];
};

static void usage(FILE *f)
{
	fputs("usage: hdlamp batch slurm PLAN.jsonl --out DIR [--max-parallel P] [--partition NAME]\n"
	      "                          [--time LIMIT] [--mem SIZE] [--max-array-size M]\n"
	      "                          [--chunk K] [--sbatch PATH] [--dry-run]\n"
	      "Copies the plan to DIR/plan.jsonl, writes DIR/slurm/array.sh and merge.sh and\n"
	      "submits the tasks without a finished result as one job array (sbatch\n"
	      "--array=LIST%P, P = --max-parallel, default 2; an array per M indices when the plan\n"
	      "has more than --max-array-size, default 1001 as Slurm's MaxArraySize) and a merge\n"
	      "job after them (--dependency=afterany) writing DIR/merged/junit.xml, index.html and\n"
	      "summary.json. Run it again after a lost node or a scancel: only the tasks without a\n"
	      "finished result are submitted. --chunk K: each array element runs K tasks one\n"
	      "after the other (for short tasks: Slurm's cost per element is about a second).\n"
	      "--dry-run prints the sbatch commands only.\n"
	      "Exit: 0 submitted (or nothing left to do), 2 bad input, 1 sbatch failed.\n",
	      f);
}

/* s single-quoted for sh. */
static void sh_quote(FILE *f, const char *s)
{
	fputc('\'', f);
	for (; *s; s++)
		if (*s == '\'')
			fputs("'\\''", f);
		else
			fputc(*s, f);
	fputc('\'', f);
}

static int write_script(const char *path, const char *self, const char *const *args)
{
	FILE *f = fopen(path, "w");

	if (!f)
		return -errno;
	fputs("#!/bin/sh\n# Written by hdlamp batch slurm (docs/scale.md); submitted with sbatch.\n"
	      "exec ",
	      f);
	sh_quote(f, self);
	for (; *args; args++) {
		fputc(' ', f);
		sh_quote(f, *args);
	}
	fputc('\n', f);
	if (fchmod(fileno(f), 0755) < 0 || fclose(f))
		return -EIO;
	return 0;
}

/* Runs argv, its stdout into buf (the job id with --parsable). 0, or -1 (reported). */
static int run_capture(char *const argv[], char *buf, size_t size)
{
	int fds[2], status;
	ssize_t n, used = 0;
	pid_t pid;

	if (pipe(fds) < 0)
		return -1;
	pid = fork();
	if (pid == 0) {
		dup2(fds[1], 1);
		close(fds[0]);
		close(fds[1]);
		execvp(argv[0], argv);
		fprintf(stderr, PROG ": %s: %s (is Slurm's client, slurm-client, installed?)\n",
			argv[0], strerror(errno));
		_exit(127);
	}
	close(fds[1]);
	while (pid > 0 && (n = read(fds[0], buf + used, size - 1 - (size_t)used)) > 0)
		used += n;
	close(fds[0]);
	buf[used] = '\0';
	if (pid < 0 || waitpid(pid, &status, 0) < 0)
		return -1;
	buf[strcspn(buf, ";\n")] = '\0'; /* "JOBID" or "JOBID;CLUSTER" */
	if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !buf[0]) {
		fprintf(stderr, PROG ": %s failed (exit %d)\n", argv[0],
			WIFEXITED(status) ? WEXITSTATUS(status) : -1);
		return -1;
	}
	return 0;
}

static void print_argv(char *const argv[])
{
	for (int i = 0; argv[i]; i++)
		fprintf(stdout, "%s%s", i ? " " : "", argv[i]);
	fputc('\n', stdout);
}

/* sbatch of one array: indices of list in [lo, lo + max_array), as offsets from lo. */
static int submit_chunk(struct slurm *s, const char *list, unsigned lo, char *job, size_t size)
{
	char chunk[65536], array[65600], output[PATH_MAX + 64], script[PATH_MAX + 64];
	char exp[64], part[300], tl[300], mem[300];
	const char *p = list;
	size_t used = 0;
	char *argv[16];
	int n = 0;

	chunk[0] = '\0';
	while (*p) {
		char *end;
		unsigned long a = strtoul(p, &end, 10), b = a;

		if (*end == '-')
			b = strtoul(end + 1, &end, 10);
		p = *end == ',' ? end + 1 : end;
		if (b < lo || a >= lo + s->max_array)
			continue;
		a = a < lo ? lo : a;
		b = b >= lo + s->max_array ? lo + s->max_array - 1 : b;
		used += (size_t)snprintf(chunk + used, sizeof(chunk) - used,
					 a == b ? "%s%lu" : "%s%lu-%lu", used ? "," : "", a - lo,
					 b - lo);
		if (used >= sizeof(chunk))
			return -E2BIG;
	}
	if (!chunk[0]) {
		job[0] = '\0';
		return 0;
	}
	snprintf(array, sizeof(array), "--array=%s%%%u", chunk, s->max_parallel);
	snprintf(output, sizeof(output), "--output=%s/slurm/%%A_%%a.out", s->dir);
	snprintf(exp, sizeof(exp), "--export=ALL,HL_BATCH_OFFSET=%u", lo);
	snprintf(script, sizeof(script), "%s/slurm/array.sh", s->dir);
	argv[n++] = (char *)s->sbatch;
	argv[n++] = "--parsable";
	argv[n++] = "--job-name=hdlamp-batch";
	argv[n++] = array;
	argv[n++] = output;
	argv[n++] = exp;
	if (s->partition) {
		snprintf(part, sizeof(part), "--partition=%s", s->partition);
		argv[n++] = part;
	}
	if (s->time_limit) {
		snprintf(tl, sizeof(tl), "--time=%s", s->time_limit);
		argv[n++] = tl;
	}
	if (s->mem) {
		snprintf(mem, sizeof(mem), "--mem=%s", s->mem);
		argv[n++] = mem;
	}
	argv[n++] = script;
	argv[n] = NULL;
	if (s->dry_run) {
		print_argv(argv);
		snprintf(job, size, "ARRAY%u", lo);
		return 0;
	}
	return run_capture(argv, job, size) < 0 ? -EIO : 0;
}

static int submit(struct slurm *s, const char *list, unsigned n)
{
	char jobs[MAX_CHUNKS][64], dep[MAX_CHUNKS * 66 + 32], output[PATH_MAX + 64];
	char script[PATH_MAX + 64], merged[3][PATH_MAX + 64];
	unsigned n_jobs = 0;
	size_t used;
	char *argv[12];
	int argc = 0;

	snprintf(merged[0], sizeof(merged[0]), "%s/merged/junit.xml", s->dir);
	snprintf(merged[1], sizeof(merged[1]), "%s/merged/index.html", s->dir);
	snprintf(merged[2], sizeof(merged[2]), "%s/merged/summary.json", s->dir);
	{
		char chunk[16];
		const char *run[] = { "batch", "run",  s->plan,	  "--index", "env",
				      "--out", s->dir, "--chunk", chunk,     NULL };

		snprintf(chunk, sizeof(chunk), "%u", s->chunk);
		if (s->chunk == 1)
			run[7] = NULL;
		const char *merge[] = { "batch",  "merge",   s->dir,   "--junit", merged[0],
					"--html", merged[1], "--json", merged[2], NULL };
		char path[PATH_MAX + 64];
		int rc;

		snprintf(path, sizeof(path), "%s/slurm", s->dir);
		rc = hl_make_dirs(path);
		snprintf(path, sizeof(path), "%s/slurm/array.sh", s->dir);
		if (!rc)
			rc = write_script(path, s->self, run);
		snprintf(path, sizeof(path), "%s/slurm/merge.sh", s->dir);
		if (!rc)
			rc = write_script(path, s->self, merge);
		if (rc < 0) {
			fprintf(stderr, PROG ": '%s': %s\n", path, strerror(-rc));
			return 1;
		}
	}
	for (unsigned lo = 0; lo < n; lo += s->max_array) {
		if (n_jobs == MAX_CHUNKS) {
			fprintf(stderr, PROG ": more than %u arrays: raise --max-array-size\n",
				MAX_CHUNKS);
			return 2;
		}
		if (submit_chunk(s, list, lo, jobs[n_jobs], sizeof(jobs[0])) < 0)
			return 1;
		if (jobs[n_jobs][0]) {
			printf("array job %s: tasks %u.. (HL_BATCH_OFFSET=%u)\n", jobs[n_jobs], lo,
			       lo);
			n_jobs++;
		}
	}
	used = (size_t)snprintf(dep, sizeof(dep), "--dependency=afterany");
	for (unsigned i = 0; i < n_jobs; i++)
		used += (size_t)snprintf(dep + used, sizeof(dep) - used, ":%s", jobs[i]);
	snprintf(output, sizeof(output), "--output=%s/slurm/merge-%%j.out", s->dir);
	snprintf(script, sizeof(script), "%s/slurm/merge.sh", s->dir);
	argv[argc++] = (char *)s->sbatch;
	argv[argc++] = "--parsable";
	argv[argc++] = "--job-name=hdlamp-merge";
	argv[argc++] = dep;
	argv[argc++] = output;
	argv[argc++] = script;
	argv[argc] = NULL;
	if (s->dry_run) {
		print_argv(argv);
		return 0;
	}
	if (run_capture(argv, jobs[0], sizeof(jobs[0])) < 0)
		return 1;
	printf("merge job %s: after every array task; results in %s/merged/\n", jobs[0], s->dir);
	return 0;
}

/* A list of task indices ("0-3,7") as the list of the chunks of k tasks that hold them. */
static void to_chunks(const char *tasks, unsigned k, char *buf, size_t size)
{
	long first = -1, last = -1;
	size_t used = 0;
	const char *p = tasks;

	buf[0] = '\0';
	while (*p || first >= 0) {
		long a = -1, b = -1;

		if (*p) {
			char *end;

			a = (long)(strtoul(p, &end, 10) / k);
			b = *end == '-' ? (long)(strtoul(end + 1, &end, 10) / k) : a;
			p = *end == ',' ? end + 1 : end;
			if (first >= 0 && a <= last + 1) { /* joins the range so far */
				last = b > last ? b : last;
				continue;
			}
		}
		if (first >= 0) {
			int w = first == last ? snprintf(buf + used, size - used, "%s%ld",
							 used ? "," : "", first) :
						snprintf(buf + used, size - used, "%s%ld-%ld",
							 used ? "," : "", first, last);

			if (w < 0 || (size_t)w >= size - used)
				return;
			used += (size_t)w;
		}
		first = a;
		last = b;
	}
}

static int parse_uint(const char *s, unsigned lo, unsigned hi, unsigned *ret)
{
	char *end;
	unsigned long v;

	errno = 0;
	v = strtoul(s, &end, 10);
	if (errno || end == s || *end || s[0] == '-' || v < lo || v > hi)
		return -EINVAL;
	*ret = (unsigned)v;
	return 0;
}

int hl_batch_slurm_cmd(int argc, char **argv)
{
	static const struct option opts[] = {
		{ "out", required_argument, NULL, 'o' },
		{ "max-parallel", required_argument, NULL, 'P' },
		{ "partition", required_argument, NULL, 'p' },
		{ "time", required_argument, NULL, 't' },
		{ "mem", required_argument, NULL, 'm' },
		{ "max-array-size", required_argument, NULL, 'M' },
		{ "sbatch", required_argument, NULL, 's' },
		{ "dry-run", no_argument, NULL, 'n' },
		{ "chunk", required_argument, NULL, 'k' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	struct slurm s = { .max_parallel = 2, .max_array = 1001, .chunk = 1, .sbatch = "sbatch" };
	char list[65536], msg[1024];
	unsigned n;
	ssize_t len;
	int c, to_run, rc;

	optind = 1;
	while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
		switch (c) {
		case 'o':
			s.out = optarg;
			break;
		case 'P':
			if (parse_uint(optarg, 1, 100000, &s.max_parallel) < 0) {
				fprintf(stderr, PROG ": --max-parallel '%s': expected 1..100000\n",
					optarg);
				return 2;
			}
			break;
		case 'M':
			if (parse_uint(optarg, 2, 4000001, &s.max_array) < 0) {
				fprintf(stderr,
					PROG ": --max-array-size '%s': expected 2..4000001 "
					     "(Slurm's MaxArraySize)\n",
					optarg);
				return 2;
			}
			break;
		case 'p':
			s.partition = optarg;
			break;
		case 'k':
			if (parse_uint(optarg, 1, 100000, &s.chunk) < 0) {
				fprintf(stderr, PROG ": --chunk '%s': expected 1..100000\n",
					optarg);
				return 2;
			}
			break;
		case 't':
			s.time_limit = optarg;
			break;
		case 'm':
			s.mem = optarg;
			break;
		case 's':
			s.sbatch = optarg;
			break;
		case 'n':
			s.dry_run = true;
			break;
		case 'h':
			usage(stdout);
			return 0;
		default:
			usage(stderr);
			return 2;
		}
	}
	if (optind != argc - 1 || !s.out) {
		usage(stderr);
		return 2;
	}
	rc = hl_batch_plan_count(argv[optind], &n, msg, sizeof(msg));
	if (rc < 0) {
		fprintf(stderr, PROG ": %s\n", msg);
		return 2;
	}
	rc = hl_batch_copy_plan(argv[optind], s.out);
	if (rc < 0 || !realpath(s.out, s.dir)) {
		fprintf(stderr, PROG ": --out '%s': %s\n", s.out, strerror(rc < 0 ? -rc : errno));
		return 1;
	}
	snprintf(s.plan, sizeof(s.plan), "%s/plan.jsonl", s.dir);
	len = readlink("/proc/self/exe", s.self, sizeof(s.self) - 1);
	if (len < 0)
		return 1;
	s.self[len] = '\0';
	/* a max array index is MaxArraySize - 1 */
	s.max_array = s.max_array - 1;
	to_run = hl_batch_unfinished_list(s.plan, s.dir, list, sizeof(list), msg, sizeof(msg));
	if (to_run < 0) {
		fprintf(stderr, PROG ": %s\n", msg);
		return 2;
	}
	if (to_run == 0) {
		printf("all %u tasks of %s have a finished result: nothing to submit (hdlamp batch "
		       "merge %s merges them)\n",
		       n, s.plan, s.dir);
		return 0;
	}
	printf("%d of %u tasks to run: %s\n", to_run, n, list);
	if (s.chunk > 1) {
		char tasks[sizeof(list)];

		snprintf(tasks, sizeof(tasks), "%s", list);
		to_chunks(tasks, s.chunk, list, sizeof(list));
		printf("as array elements of %u tasks each: %s\n", s.chunk, list);
	}
	return submit(&s, list, (n + s.chunk - 1) / s.chunk);
}
