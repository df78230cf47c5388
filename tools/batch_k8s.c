/* SPDX-License-Identifier: MIT */
/*
 * hdlamp batch k8s (docs/scale.md, "Kubernetes"): a plan as a Kubernetes Indexed Job. The
 * manifest is a batch/v1 Job with one completion per task; each pod runs `hdlamp batch run
 * PLAN --index env --out /results`, and the Job controller sets JOB_COMPLETION_INDEX in every
 * pod of an Indexed Job (https://kubernetes.io/docs/tasks/job/indexed-parallel-processing-static/:
 * "the control plane automatically sets the downward API to expose the index in the
 * JOB_COMPLETION_INDEX environment variable"), so the pod needs no env of its own.
 *
 * The fields and their limits are the Job API's (v1.29 or later for backoffLimitPerIndex,
 * https://kubernetes.io/docs/reference/kubernetes-api/workload-resources/job-v1/):
 * backoffLimitPerIndex needs completionMode Indexed and the pod's restartPolicy Never;
 * parallelism of an Indexed Job is at most 10^5; maxFailedIndexes is at most completions and,
 * for more than 10^5 completions, required and at most 10^4. The YAML is written by hand: the
 * user's strings are validated and double-quoted, nothing else is user text.
 */
#include <errno.h>
#include <getopt.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/file_replace.h"
#include "tools/batch.h"
#include "tools/commands.h"

#define K8S_PARALLELISM_MAX 100000UL /* Indexed Jobs: .spec.parallelism <= 10^5 */
#define K8S_COMPLETIONS_FREE 100000U /* above: maxFailedIndexes required ... */
#define K8S_MAX_FAILED_BIG 10000UL /* ... and at most 10^4 */
#define K8S_INT32_MAX 2147483647UL
#define K8S_LABEL_MAX 63 /* DNS-1123 label */
#define K8S_SUBDOMAIN_MAX 253 /* DNS-1123 subdomain */

#define RESULTS_DIR "/results"
#define PLAN_DIR "/plan" /* the ConfigMap's mount */
#define PLAN_FILE "plan.jsonl"

struct k8s_job {
	const char *plan, *out; /* as given, for the comments; out NULL: stdout */
	unsigned tasks;
	const char *name, *image, *claim, *configmap, *cpu, *memory;
	unsigned long parallelism, backoff_per_index, max_failed, deadline_s;
	bool has_max_failed, has_deadline;
};

static void usage(FILE *f)
{
	fputs("usage: hdlamp batch k8s PLAN.jsonl [--out MANIFEST.yaml] [--name NAME] [--image IMAGE]\n"
	      "                        [--parallelism P] [--backoff-limit-per-index B]\n"
	      "                        [--max-failed-indexes M] [--results-claim PVC]\n"
	      "                        [--plan-configmap NAME] [--cpu C] [--memory M]\n"
	      "                        [--active-deadline-s S]\n"
	      "Writes a Kubernetes Indexed Job (batch/v1, Kubernetes 1.29 or later) that runs the\n"
	      "plan's tasks, one pod per task: `hdlamp batch run PLAN --index env --out /results`,\n"
	      "the index from JOB_COMPLETION_INDEX, which the Job controller sets.\n"
	      "--out: the manifest's file (default: stdout). --name: the Job's name, a DNS-1123\n"
	      "label (default hdlamp-batch). --image: the container image (default hdlamp:" HL_VERSION
	      ",\n"
	      "packaging/Containerfile). --parallelism: pods at once (default 2, at most 100000).\n"
	      "--backoff-limit-per-index: retries of a task's pod (default 1); exit 2 (bad input) or\n"
	      "3 (verdict failed) fails the index without a retry. --max-failed-indexes: the Job\n"
	      "stops when more tasks than M failed (default: all tasks run; required for more than\n"
	      "100000 tasks). --results-claim: the PersistentVolumeClaim mounted at /results\n"
	      "(default hdlamp-results); the plan is read from /results/plan.jsonl on it, or with\n"
	      "--plan-configmap from that ConfigMap's key plan.jsonl (mounted at /plan). --cpu and\n"
	      "--memory: each pod's request and limit, Kubernetes quantities (default 1 and 2Gi).\n"
	      "--active-deadline-s: a pod running longer is stopped (and retried as a failure).\n"
	      "Exit: 0 written, 2 bad option or plan, 1 the manifest could not be written.\n",
	      f);
}

static int bad(const char *opt, const char *arg, const char *expected)
{
	fprintf(stderr, "hdlamp batch k8s: %s '%s': expected %s\n", opt, arg, expected);
	return HL_EXIT_USAGE;
}

static int parse_ulong(const char *s, unsigned long lo, unsigned long hi, unsigned long *ret)
{
	char *end;

	if (*s < '0' || *s > '9')
		return -EINVAL;
	errno = 0;
	*ret = strtoul(s, &end, 10);
	return errno || *end || *ret < lo || *ret > hi ? -EINVAL : 0;
}

static bool is_lower_alnum(char c)
{
	return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9');
}

/* RFC 1123 label as Kubernetes names use it: [a-z0-9]([-a-z0-9]*[a-z0-9])?, at most 63. */
static bool is_dns_label(const char *s, size_t len)
{
	if (len == 0 || len > K8S_LABEL_MAX || !is_lower_alnum(s[0]) || !is_lower_alnum(s[len - 1]))
		return false;
	for (size_t i = 0; i < len; i++)
		if (!is_lower_alnum(s[i]) && s[i] != '-')
			return false;
	return true;
}

/* DNS-1123 subdomain: labels joined by '.', at most 253 (PVC and ConfigMap names). */
static bool is_dns_subdomain(const char *s)
{
	size_t len = strlen(s);
	const char *label = s;

	if (len == 0 || len > K8S_SUBDOMAIN_MAX)
		return false;
	for (const char *p = s;; p++) {
		if (*p == '.' || *p == '\0') {
			if (!is_dns_label(label, (size_t)(p - label)))
				return false;
			if (*p == '\0')
				return true;
			label = p + 1;
		}
	}
}

/*
 * A resource quantity without sign or exponent: DIGITS[.DIGITS] and an optional suffix
 * (https://kubernetes.io/docs/reference/kubernetes-api/common-definitions/quantity/), not zero.
 */
static bool is_quantity(const char *s)
{
	static const char *const suffixes[] = { "",  "m",  "k",	 "M",  "G",  "T",  "P",
						"E", "Ki", "Mi", "Gi", "Ti", "Pi", "Ei" };
	bool nonzero = false, digits = false;
	const char *p = s;

	for (; *p >= '0' && *p <= '9'; p++)
		digits = true, nonzero |= *p != '0';
	if (*p == '.')
		for (p++; *p >= '0' && *p <= '9'; p++)
			digits = true, nonzero |= *p != '0';
	if (!digits || !nonzero)
		return false;
	for (size_t i = 0; i < sizeof(suffixes) / sizeof(suffixes[0]); i++)
		if (strcmp(p, suffixes[i]) == 0)
			return true;
	return false;
}

/* An image reference: printable ASCII without spaces ("registry.example/hdlamp:0.1.0"). */
static bool is_image(const char *s)
{
	if (*s == '\0' || strlen(s) > 1024)
		return false;
	for (; *s; s++)
		if (*s <= ' ' || *s >= 0x7f)
			return false;
	return true;
}

/* A YAML double-quoted scalar; the validated strings hold no control characters. */
static void put_quoted(FILE *f, const char *s)
{
	fputc('"', f);
	for (; *s; s++) {
		if (*s == '"' || *s == '\\')
			fputc('\\', f);
		fputc(*s, f);
	}
	fputc('"', f);
}

/* User text in a comment: a control character would end the comment line. */
static void put_comment_text(FILE *f, const char *s)
{
	for (; *s; s++)
		fputc((unsigned char)*s < ' ' || *s == 0x7f ? '?' : *s, f);
}

static const char *plan_path(const struct k8s_job *j)
{
	return j->configmap ? PLAN_DIR "/" PLAN_FILE : RESULTS_DIR "/" PLAN_FILE;
}

static void write_header(const struct k8s_job *j, FILE *f)
{
	fprintf(f, "# hdlamp batch k8s (hdlamp %s): the %u tasks of the plan ", HL_VERSION,
		j->tasks);
	put_comment_text(f, j->plan);
	fputs("\n# as a Kubernetes Indexed Job (batch/v1, Kubernetes 1.29 or later). Each pod runs\n"
	      "# the task JOB_COMPLETION_INDEX (set by the Job controller) and writes /results/INDEX/\n"
	      "# on the volume of the PersistentVolumeClaim ",
	      f);
	put_comment_text(f, j->claim);
	fputs(".\n#\n# Before applying: the image ", f);
	put_comment_text(f, j->image);
	fputs(" where the cluster pulls from\n"
	      "# (packaging/build-image), the claim (ReadWriteMany if pods run on several nodes) and\n",
	      f);
	if (j->configmap) {
		fputs("# the plan as a ConfigMap:\n#   kubectl create configmap ", f);
		put_comment_text(f, j->configmap);
		fputs(" --from-file=" PLAN_FILE "=", f);
		put_comment_text(f, j->plan);
		fputc('\n', f);
	} else {
		fputs("# the plan copied to " RESULTS_DIR "/" PLAN_FILE " on the claim.\n", f);
	}
	fputs("# Apply and watch:\n#   kubectl apply -f ", f);
	put_comment_text(f, j->out ? j->out : "MANIFEST.yaml");
	fputs("\n#   kubectl get job ", f);
	put_comment_text(f, j->name);
	fputs(" --watch\n#   kubectl wait --for=condition=complete --timeout=24h job/", f);
	put_comment_text(f, j->name);
	fputs("\n# Then merge, in a pod that mounts the claim (/usr/share/doc/hdlamp/docs/scale.md\n"
	      "# shows one), or here with the results copied out of it:\n",
	      f);
	if (!j->configmap)
		fputs("#   kubectl exec POD -- hdlamp batch merge " RESULTS_DIR
		      " --plan " RESULTS_DIR "/" PLAN_FILE " --junit " RESULTS_DIR
		      "/junit.xml --html " RESULTS_DIR "/index.html --json " RESULTS_DIR
		      "/summary.json\n",
		      f);
	fputs("#   kubectl cp POD:" RESULTS_DIR " results\n#   hdlamp batch merge results --plan ",
	      f);
	put_comment_text(f, j->plan);
	fputs(" --junit junit.xml --html index.html --json summary.json\n", f);
}

static void write_job(void *ctx, FILE *f)
{
	const struct k8s_job *j = ctx;

	write_header(j, f);
	fputs("apiVersion: batch/v1\nkind: Job\nmetadata:\n  name: ", f);
	put_quoted(f, j->name);
	fputs("\n  labels:\n    app.kubernetes.io/name: hdlamp\n", f);
	fprintf(f,
		"spec:\n  completionMode: Indexed\n  completions: %u\n  parallelism: %lu\n"
		"  backoffLimitPerIndex: %lu\n",
		j->tasks, j->parallelism, j->backoff_per_index);
	if (j->has_max_failed)
		fprintf(f, "  maxFailedIndexes: %lu\n", j->max_failed);
	/* exit 2 and 3 are results (tools/batch.h): a second run gives the same; a pod evicted
	 * or preempted is no failure of its task */
	fputs("  podFailurePolicy:\n    rules:\n"
	      "      - action: FailIndex\n        onExitCodes:\n          containerName: hdlamp\n"
	      "          operator: In\n          values: [2, 3]\n"
	      "      - action: Ignore\n        onPodConditions:\n"
	      "          - type: DisruptionTarget\n            status: \"True\"\n",
	      f);
	fputs("  template:\n    metadata:\n      labels:\n        app.kubernetes.io/name: hdlamp\n"
	      "    spec:\n      restartPolicy: Never\n",
	      f);
	if (j->has_deadline)
		fprintf(f, "      activeDeadlineSeconds: %lu\n", j->deadline_s);
	fputs("      containers:\n        - name: hdlamp\n          image: ", f);
	put_quoted(f, j->image);
	fprintf(f,
		"\n          command: [\"hdlamp\", \"batch\", \"run\", \"%s\", \"--index\", \"env\","
		" \"--out\", \"" RESULTS_DIR "\"]\n",
		plan_path(j));
	fputs("          resources:\n            requests:\n              cpu: ", f);
	put_quoted(f, j->cpu);
	fputs("\n              memory: ", f);
	put_quoted(f, j->memory);
	fputs("\n            limits:\n              cpu: ", f);
	put_quoted(f, j->cpu);
	fputs("\n              memory: ", f);
	put_quoted(f, j->memory);
	fputs("\n          volumeMounts:\n            - name: results\n"
	      "              mountPath: " RESULTS_DIR "\n",
	      f);
	if (j->configmap)
		fputs("            - name: plan\n              mountPath: " PLAN_DIR "\n"
		      "              readOnly: true\n",
		      f);
	fputs("      volumes:\n        - name: results\n          persistentVolumeClaim:\n"
	      "            claimName: ",
	      f);
	put_quoted(f, j->claim);
	fputc('\n', f);
	if (j->configmap) {
		fputs("        - name: plan\n          configMap:\n            name: ", f);
		put_quoted(f, j->configmap);
		fputs("\n            items:\n              - key: " PLAN_FILE
		      "\n                path: " PLAN_FILE "\n",
		      f);
	}
}

/* The options that need the plan's size, and the plan's header. 0 or an exit code. */
static int check_job(struct k8s_job *j)
{
	char msg[512];

	if (hl_batch_plan_count(j->plan, &j->tasks, msg, sizeof(msg)) < 0) {
		fprintf(stderr, "hdlamp batch k8s: %s\n", msg);
		return HL_EXIT_USAGE;
	}
	if (j->tasks == 0) {
		fprintf(stderr, "hdlamp batch k8s: %s: the plan has no tasks; a Job needs one\n",
			j->plan);
		return HL_EXIT_USAGE;
	}
	if (j->has_max_failed && j->max_failed > j->tasks) {
		fprintf(stderr,
			"hdlamp batch k8s: --max-failed-indexes '%lu': expected at most the plan's "
			"%u tasks\n",
			j->max_failed, j->tasks);
		return HL_EXIT_USAGE;
	}
	if (j->tasks > K8S_COMPLETIONS_FREE &&
	    (!j->has_max_failed || j->max_failed > K8S_MAX_FAILED_BIG)) {
		fprintf(stderr,
			"hdlamp batch k8s: the plan has %u tasks: over 100000, Kubernetes requires "
			"--max-failed-indexes, at most 10000\n",
			j->tasks);
		return HL_EXIT_USAGE;
	}
	return 0;
}

int hl_batch_k8s_cmd(int argc, char **argv)
{
	static const struct option long_opts[] = {
		{ "out", required_argument, NULL, 'o' },
		{ "name", required_argument, NULL, 'n' },
		{ "image", required_argument, NULL, 'i' },
		{ "parallelism", required_argument, NULL, 'p' },
		{ "backoff-limit-per-index", required_argument, NULL, 'b' },
		{ "max-failed-indexes", required_argument, NULL, 'm' },
		{ "results-claim", required_argument, NULL, 'r' },
		{ "plan-configmap", required_argument, NULL, 'c' },
		{ "cpu", required_argument, NULL, 'C' },
		{ "memory", required_argument, NULL, 'M' },
		{ "active-deadline-s", required_argument, NULL, 'd' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	struct k8s_job j = {
		.name = "hdlamp-batch",
		.image = "hdlamp:" HL_VERSION,
		.claim = "hdlamp-results",
		.cpu = "1",
		.memory = "2Gi",
		.parallelism = 2,
		.backoff_per_index = 1,
	};
	int c, rc = 0;

	while (rc == 0 && (c = getopt_long(argc, argv, "h", long_opts, NULL)) != -1) {
		switch (c) {
		case 'o':
			j.out = optarg;
			break;
		case 'n':
			j.name = optarg;
			if (!is_dns_label(optarg, strlen(optarg)))
				rc = bad("--name", optarg,
					 "a DNS-1123 label: at most 63 of a-z, 0-9 and '-', "
					 "starting and ending with a letter or digit");
			break;
		case 'i':
			j.image = optarg;
			if (!is_image(optarg))
				rc = bad("--image", optarg,
					 "an image reference such as registry.example/hdlamp:"
					 "0.1.0 (printable ASCII, no spaces)");
			break;
		case 'p':
			if (parse_ulong(optarg, 1, K8S_PARALLELISM_MAX, &j.parallelism) < 0)
				rc = bad("--parallelism", optarg,
					 "1 to 100000 (an Indexed Job's limit)");
			break;
		case 'b':
			if (parse_ulong(optarg, 0, K8S_INT32_MAX, &j.backoff_per_index) < 0)
				rc = bad("--backoff-limit-per-index", optarg, "0 to 2147483647");
			break;
		case 'm':
			j.has_max_failed = true;
			if (parse_ulong(optarg, 0, K8S_INT32_MAX, &j.max_failed) < 0)
				rc = bad("--max-failed-indexes", optarg, "0 to the plan's tasks");
			break;
		case 'r':
		case 'c':
			if (!is_dns_subdomain(optarg))
				rc = bad(
					c == 'r' ? "--results-claim" : "--plan-configmap", optarg,
					"a Kubernetes object name (DNS-1123 subdomain): at most 253 "
					"of a-z, 0-9, '-' and '.', each part starting and ending "
					"with a letter or digit");
			else if (c == 'r')
				j.claim = optarg;
			else
				j.configmap = optarg;
			break;
		case 'C':
		case 'M':
			if (!is_quantity(optarg))
				rc = bad(c == 'C' ? "--cpu" : "--memory", optarg,
					 c == 'C' ? "a Kubernetes quantity above 0 such as 1, 0.5 "
						    "or 500m" :
						    "a Kubernetes quantity above 0 such as 2Gi, "
						    "512Mi or 4G");
			else if (c == 'C')
				j.cpu = optarg;
			else
				j.memory = optarg;
			break;
		case 'd':
			j.has_deadline = true;
			if (parse_ulong(optarg, 1, K8S_INT32_MAX, &j.deadline_s) < 0)
				rc = bad("--active-deadline-s", optarg, "seconds, 1 to 2147483647");
			break;
		case 'h':
			usage(stdout);
			return HL_EXIT_OK;
		default:
			usage(stderr);
			rc = HL_EXIT_USAGE;
		}
	}
	if (rc)
		return rc;
	if (optind != argc - 1) {
		usage(stderr);
		return HL_EXIT_USAGE;
	}
	j.plan = argv[optind];
	rc = check_job(&j);
	if (rc)
		return rc;
	if (j.out) {
		rc = hl_file_replace(j.out, write_job, &j);
		if (rc < 0) {
			fprintf(stderr, "hdlamp batch k8s: '%s': %s\n", j.out, strerror(-rc));
			return HL_EXIT_FAIL;
		}
		return HL_EXIT_OK;
	}
	write_job(&j, stdout);
	if (fflush(stdout) != 0 || ferror(stdout)) {
		fprintf(stderr, "hdlamp batch k8s: stdout: %s\n", strerror(errno));
		return HL_EXIT_FAIL;
	}
	return HL_EXIT_OK;
}
