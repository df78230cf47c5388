/* SPDX-License-Identifier: MIT */
/*
 * fmu/fmu: FMI 2.0 co-simulation FMUs imported: a gain stepped to exact values, its log, an
 * fmi2Error from fmi2DoStep, a crash and a hang in a step, a variable of the wrong type, and
 * archives that are refused (not a zip, no binary, zip slip, XML that does not parse, FMI 1.0
 * and 3.0, no co-simulation); close removes the directory and reaps the child.
 * The archives are packed here from the binaries built in fmus/ and the descriptions there.
 */
#include <errno.h>
#include <limits.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmocka.h>
#include <zip.h>

#include "fmu/fmu.h"
#include "testutil.h"

#define GUID "{6d1e4f0a-hdlamp-gain}"

/* tests/unit/fmu/fmus/<name>, its text with @ID@ and @GUID@ replaced (malloc'd) */
static char *description(const char *name, const char *id)
{
	const char *src = getenv("HL_SOURCE_DIR");
	char path[PATH_MAX], *text, *out;
	size_t len = 0, at = 0;
	FILE *fp;

	assert_non_null(src);
	snprintf(path, sizeof(path), "%s/tests/unit/fmu/fmus/%s", src, name);
	fp = fopen(path, "r");
	assert_non_null(fp);
	text = calloc(1, 65536);
	len = fread(text, 1, 65535, fp);
	fclose(fp);
	out = calloc(1, len + 4096);
	for (size_t i = 0; i < len;) {
		if (strncmp(text + i, "@ID@", 4) == 0) {
			at += (size_t)sprintf(out + at, "%s", id);
			i += 4;
		} else if (strncmp(text + i, "@GUID@", 6) == 0) {
			at += (size_t)sprintf(out + at, "%s", GUID);
			i += 6;
		} else {
			out[at++] = text[i++];
		}
	}
	free(text);
	return out;
}

/*
 * Packs an FMU at $HL_TEST_TMPDIR/<pid>-<file>: modelDescription.xml from md (NULL: none), the
 * binary so (NULL: none) as binaries/linux64/<id>.so, and an extra entry (NULL: none).
 */
static const char *pack(char *buf, size_t size, const char *file, const char *md, const char *so,
			const char *id, const char *extra)
{
	char entry[256];
	zip_t *z;
	int zerr;

	test_path(buf, size, file);
	z = zip_open(buf, ZIP_CREATE | ZIP_TRUNCATE, &zerr);
	assert_non_null(z);
	if (md) {
		char *text = description(md, id);
		zip_source_t *s = zip_source_buffer(z, text, strlen(text), 1);

		assert_true(zip_file_add(z, "modelDescription.xml", s, 0) >= 0);
	}
	if (so) {
		snprintf(entry, sizeof(entry), "binaries/linux64/%s.so", id);
		assert_true(zip_file_add(z, entry, zip_source_file(z, so, 0, -1), 0) >= 0);
	}
	assert_true(zip_dir_add(z, "resources", 0) >= 0);
	if (extra)
		assert_true(zip_file_add(z, extra, zip_source_buffer(z, "x", 1, 0), 0) >= 0);
	assert_int_equal(zip_close(z), 0);
	return buf;
}

struct run {
	char path[PATH_MAX];
	char *log_text;
	size_t log_len;
	FILE *log;
	struct hl_fmu *f;
	char err[1024];
};

static int open_run(struct run *r, const char *file, const char *md, const char *so, const char *id,
		    int timeout_ms)
{
	const struct hl_fmu_options o = { .step_s = 0.25, .timeout_ms = timeout_ms };
	struct hl_fmu_options oo = o;

	pack(r->path, sizeof(r->path), file, md, so, id, NULL);
	r->log = open_memstream(&r->log_text, &r->log_len);
	assert_non_null(r->log);
	oo.log = r->log;
	return hl_fmu_open(r->path, 0.0, &oo, &r->f, r->err, sizeof(r->err));
}

static void close_run(struct run *r)
{
	hl_fmu_close(r->f);
	r->f = NULL;
	fclose(r->log);
	free(r->log_text);
	unlink(r->path);
}

static void assert_contains(const char *text, const char *part)
{
	if (!strstr(text, part))
		fail_msg("\"%s\" does not contain \"%s\"", text, part);
}

static void fmu_gain_steps_to_exact_values(void **state)
{
	struct run r = { 0 };
	int u, y, lg, idx[2];
	double v = 1.5, out[2];

	(void)state;
	assert_int_equal(open_run(&r, "gain.fmu", "gain.xml", HL_TEST_FMU_GAIN, "gain", 0), 0);
	assert_string_equal(hl_fmu_model_name(r.f), "Gain");
	assert_string_equal(hl_fmu_identifier(r.f), "gain");
	assert_int_equal(hl_fmu_n_vars(r.f), 3);
	u = hl_fmu_find(r.f, "u");
	y = hl_fmu_find(r.f, "y");
	lg = hl_fmu_find(r.f, "log");
	assert_int_equal(u, 0);
	assert_int_equal(y, 1);
	assert_int_equal(lg, 2);
	assert_int_equal(hl_fmu_find(r.f, "z"), -ENOENT);
	assert_int_equal(hl_fmu_var(r.f, y)->vr, 1);
	assert_int_equal(hl_fmu_var(r.f, y)->type, HL_FMU_REAL);
	assert_int_equal(hl_fmu_var(r.f, y)->causality, HL_FMU_OUTPUT);
	assert_int_equal(hl_fmu_var(r.f, u)->causality, HL_FMU_INPUT);
	assert_int_equal(hl_fmu_var(r.f, u)->line, 11);
	assert_int_equal(hl_fmu_var(r.f, y)->line, 15); /* libxml2: where the start tag ends */
	assert_null(hl_fmu_var(r.f, 3));
	assert_true(hl_fmu_pid(r.f) > 0);

	assert_int_equal(hl_fmu_set_real(r.f, &u, &v, 1), 0);
	idx[0] = y;
	idx[1] = u;
	/* y = 2 u + time, time the end of the step: 0.25 s steps are exact in binary */
	for (int i = 0; i < 4; i++) {
		assert_int_equal(
			hl_fmu_step(r.f, 0.25 * i, 0.25, idx, out, 2, r.err, sizeof(r.err)), 0);
		assert_true(out[0] == 3.0 + 0.25 * (i + 1));
		assert_true(out[1] == 1.5);
	}
	assert_true(out[0] == 4.0);
	/* a set travels with the next step only; the last of two sets wins */
	v = 10.0;
	assert_int_equal(hl_fmu_set_real(r.f, &u, &v, 1), 0);
	v = -2.0;
	assert_int_equal(hl_fmu_set_real(r.f, &u, &v, 1), 0);
	assert_int_equal(hl_fmu_step(r.f, 1.0, 0.5, idx, out, 2, r.err, sizeof(r.err)), 0);
	assert_true(out[0] == -2.5);
	assert_true(out[1] == -2.0);
	assert_string_equal(hl_fmu_error(r.f), "");
	close_run(&r);
}

static void fmu_gain_logs_through_the_parent(void **state)
{
	struct run r = { 0 };
	int lg = 2, y = 1;
	double on = 1.0, out;

	(void)state;
	assert_int_equal(open_run(&r, "log.fmu", "gain.xml", HL_TEST_FMU_GAIN, "gain", 0), 0);
	assert_int_equal(hl_fmu_set_real(r.f, &lg, &on, 1), 0);
	assert_int_equal(hl_fmu_step(r.f, 0.0, 0.5, &y, &out, 1, r.err, sizeof(r.err)), 0);
	assert_int_equal(hl_fmu_step(r.f, 0.5, 0.5, &y, &out, 1, r.err, sizeof(r.err)), 0);
	assert_true(out == 1.0);
	hl_fmu_close(r.f);
	r.f = NULL;
	fflush(r.log);
	/* the resources URI: file:// and the absolute unpacked directory */
	assert_contains(r.log_text, "fmu gain: [logAll] resources at file:///");
	assert_contains(r.log_text, "/resources\n");
	assert_contains(r.log_text, "fmu gain: [logAll] step 1: t = 0.5 s, y = 0.5\n");
	assert_contains(r.log_text, "fmu gain: [logAll] step 2: t = 1 s, y = 1\n");
	assert_contains(r.log_text, "fmu gain: [logAll] terminated after 2 steps\n");
	assert_contains(r.log_text, "model 'Gain', FMI 2.0 co-simulation, 3 variables");
	close_run(&r);
}

static void fmu_do_step_error_names_the_call_and_the_message(void **state)
{
	struct run r = { 0 };
	int y = 1;
	double out;

	(void)state;
	assert_int_equal(
		open_run(&r, "err.fmu", "gain.xml", HL_TEST_FMU_GAIN_ERROR, "gain_error", 0), 0);
	for (int i = 0; i < 9; i++)
		assert_int_equal(hl_fmu_step(r.f, i, 1.0, &y, &out, 1, r.err, sizeof(r.err)), 0);
	assert_true(out == 9.0);
	assert_int_equal(hl_fmu_step(r.f, 9.0, 1.0, &y, &out, 1, r.err, sizeof(r.err)), -EIO);
	assert_contains(r.err, "fmi2DoStep at t=9 s returned fmi2Error");
	assert_contains(r.err, "[logStatusError] step 10: u = 0 is out of range");
	assert_contains(r.err, r.path);
	assert_string_equal(hl_fmu_error(r.f), r.err);
	/* 2.1.3: after fmi2Error no step; close still frees the instance and reaps */
	assert_int_equal(hl_fmu_step(r.f, 10.0, 1.0, &y, &out, 1, r.err, sizeof(r.err)), -EIO);
	assert_contains(r.err, "an earlier call failed");
	close_run(&r);
}

static void fmu_segfault_in_a_step_is_reported_not_shared(void **state)
{
	struct run r = { 0 };
	int y = 1;
	double out;

	(void)state;
	assert_int_equal(
		open_run(&r, "segv.fmu", "gain.xml", HL_TEST_FMU_GAIN_SEGV, "gain_segv", 0), 0);
	for (int i = 0; i < 4; i++)
		assert_int_equal(hl_fmu_step(r.f, i, 1.0, &y, &out, 1, r.err, sizeof(r.err)), 0);
	assert_int_equal(hl_fmu_step(r.f, 4.0, 1.0, &y, &out, 1, r.err, sizeof(r.err)), -EPIPE);
	assert_contains(r.err, "the step at t=4 s (fmi2SetReal, fmi2DoStep, fmi2GetReal)");
	assert_contains(r.err, "killed by signal SIGSEGV");
	assert_contains(r.err, "[logAll] step 5: about to crash");
	assert_int_equal(hl_fmu_pid(r.f), 0); /* reaped at once */
	/* the socket's peer is gone: no SIGPIPE, the same answer */
	assert_int_equal(hl_fmu_step(r.f, 5.0, 1.0, &y, &out, 1, r.err, sizeof(r.err)), -EPIPE);
	assert_contains(r.err, "killed by signal SIGSEGV");
	close_run(&r);
}

static void fmu_hang_in_a_step_times_out(void **state)
{
	struct run r = { 0 };
	int y = 1, pid;
	double out;

	(void)state;
	assert_int_equal(
		open_run(&r, "hang.fmu", "gain.xml", HL_TEST_FMU_GAIN_HANG, "gain_hang", 300), 0);
	pid = hl_fmu_pid(r.f);
	for (int i = 0; i < 2; i++)
		assert_int_equal(hl_fmu_step(r.f, i, 1.0, &y, &out, 1, r.err, sizeof(r.err)), 0);
	assert_int_equal(hl_fmu_step(r.f, 2.0, 1.0, &y, &out, 1, r.err, sizeof(r.err)), -ETIMEDOUT);
	assert_contains(r.err, "fmi2DoStep");
	assert_contains(r.err, "timed out after 300 ms; the FMU's process was killed");
	assert_int_equal(hl_fmu_pid(r.f), 0);
	assert_int_equal(waitpid(pid, NULL, WNOHANG), -1); /* reaped: no zombie */
	assert_int_equal(errno, ECHILD);
	assert_int_equal(hl_fmu_step(r.f, 3.0, 1.0, &y, &out, 1, r.err, sizeof(r.err)), -EPIPE);
	close_run(&r);
}

static void fmu_set_real_of_an_integer_is_refused(void **state)
{
	struct run r = { 0 };
	int u, y = 1;
	double v = 1.0;

	(void)state;
	assert_int_equal(open_run(&r, "type.fmu", "wrong_type.xml", HL_TEST_FMU_GAIN, "gain", 0),
			 0);
	u = hl_fmu_find(r.f, "u");
	assert_int_equal(hl_fmu_var(r.f, u)->type, HL_FMU_INTEGER);
	assert_int_equal(hl_fmu_set_real(r.f, &u, &v, 1), -EINVAL);
	assert_contains(hl_fmu_error(r.f),
			"variable 'u' (modelDescription.xml:6) is Integer, not Real");
	/* an output is read, not set */
	assert_int_equal(hl_fmu_set_real(r.f, &y, &v, 1), -EINVAL);
	assert_contains(hl_fmu_error(r.f), "variable 'y' (modelDescription.xml:9) is an output");
	/* and a step reads Reals only */
	assert_int_equal(hl_fmu_step(r.f, 0.0, 1.0, &u, &v, 1, r.err, sizeof(r.err)), -EINVAL);
	assert_contains(r.err, "variable 'u'");
	close_run(&r);
}

static void fmu_close_removes_the_directory_and_reaps(void **state)
{
	struct run r = { 0 };
	char dir[PATH_MAX];
	struct stat st;
	int pid;

	(void)state;
	assert_int_equal(open_run(&r, "close.fmu", "gain.xml", HL_TEST_FMU_GAIN, "gain", 0), 0);
	snprintf(dir, sizeof(dir), "%s", hl_fmu_dir(r.f));
	pid = hl_fmu_pid(r.f);
	assert_int_equal(dir[0], '/');
	assert_int_equal(stat(dir, &st), 0);
	assert_int_equal(waitpid(pid, NULL, WNOHANG), 0); /* running */
	hl_fmu_close(r.f);
	r.f = NULL;
	assert_int_equal(stat(dir, &st), -1);
	assert_int_equal(errno, ENOENT);
	assert_int_equal(waitpid(pid, NULL, WNOHANG), -1);
	assert_int_equal(errno, ECHILD);
	hl_fmu_close(NULL);
	close_run(&r);
}

/* An archive refused: open's -errno and a message that holds part. */
static void assert_refused(const char *path, int want, const char *part)
{
	struct hl_fmu *f = (struct hl_fmu *)0x1;
	char err[1024] = "";
	FILE *log = fopen("/dev/null", "w");
	const struct hl_fmu_options o = { .log = log };

	assert_int_equal(hl_fmu_open(path, 0.0, &o, &f, err, sizeof(err)), want);
	assert_ptr_equal(f, (struct hl_fmu *)0x1); /* untouched */
	assert_contains(err, path);
	assert_contains(err, part);
	fclose(log);
	unlink(path);
}

static void fmu_refuses_what_is_not_a_zip(void **state)
{
	char path[PATH_MAX];
	FILE *fp = fopen(test_path(path, sizeof(path), "text.fmu"), "w");

	(void)state;
	fputs("this is not a zip archive\n", fp);
	fclose(fp);
	assert_refused(path, -EBADMSG, "not a zip archive");
	test_path(path, sizeof(path), "missing.fmu");
	assert_refused(path, -ENOENT, "No such file");
}

static void fmu_refuses_a_missing_binary_or_description(void **state)
{
	char path[PATH_MAX];

	(void)state;
	pack(path, sizeof(path), "nobin.fmu", "gain.xml", NULL, "gain", NULL);
	assert_refused(path, -ENOENT, "no binaries/linux64/gain.so");
	pack(path, sizeof(path), "nomd.fmu", NULL, HL_TEST_FMU_GAIN, "gain", NULL);
	assert_refused(path, -ENOENT, "no modelDescription.xml");
}

static void fmu_refuses_zip_slip(void **state)
{
	char path[PATH_MAX], outside[PATH_MAX + 16];
	struct stat st;

	(void)state;
	pack(path, sizeof(path), "slip.fmu", "gain.xml", HL_TEST_FMU_GAIN, "gain",
	     "resources/../../hl-fmu-slip");
	assert_refused(path, -EBADMSG, "entry 'resources/../../hl-fmu-slip': refused");
	snprintf(outside, sizeof(outside), "%s/hl-fmu-slip", getenv("HL_TEST_TMPDIR"));
	assert_int_equal(stat(outside, &st), -1);
	pack(path, sizeof(path), "abs.fmu", "gain.xml", HL_TEST_FMU_GAIN, "gain",
	     "/tmp/hl-fmu-abs");
	assert_refused(path, -EBADMSG, "entry '/tmp/hl-fmu-abs': refused");
}

static void fmu_refuses_bad_descriptions(void **state)
{
	char path[PATH_MAX];

	(void)state;
	pack(path, sizeof(path), "syntax.fmu", "syntax_error.xml", HL_TEST_FMU_GAIN, "gain", NULL);
	assert_refused(path, -EBADMSG, "modelDescription.xml:8: XML does not parse");
	pack(path, sizeof(path), "fmi1.fmu", "fmi1.xml", HL_TEST_FMU_GAIN, "gain", NULL);
	assert_refused(path, -ENOTSUP, "fmiVersion \"1.0\": only FMI 2.0");
	pack(path, sizeof(path), "fmi3.fmu", "fmi3.xml", HL_TEST_FMU_GAIN, "gain", NULL);
	assert_refused(path, -ENOTSUP, "modelDescription.xml:2: fmiVersion \"3.0\"");
	pack(path, sizeof(path), "me.fmu", "model_exchange.xml", HL_TEST_FMU_GAIN, "gain", NULL);
	assert_refused(path, -ENOTSUP, "no <CoSimulation>: not an FMU for co-simulation");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(fmu_gain_steps_to_exact_values),
		cmocka_unit_test(fmu_gain_logs_through_the_parent),
		cmocka_unit_test(fmu_do_step_error_names_the_call_and_the_message),
		cmocka_unit_test(fmu_segfault_in_a_step_is_reported_not_shared),
		cmocka_unit_test(fmu_hang_in_a_step_times_out),
		cmocka_unit_test(fmu_set_real_of_an_integer_is_refused),
		cmocka_unit_test(fmu_close_removes_the_directory_and_reaps),
		cmocka_unit_test(fmu_refuses_what_is_not_a_zip),
		cmocka_unit_test(fmu_refuses_a_missing_binary_or_description),
		cmocka_unit_test(fmu_refuses_zip_slip),
		cmocka_unit_test(fmu_refuses_bad_descriptions),
	};

	/* the unpacked directories too go under the test scratch directory, not /tmp */
	if (getenv("HL_TEST_TMPDIR"))
		setenv("TMPDIR", getenv("HL_TEST_TMPDIR"), 1);
	return cmocka_run_group_tests(tests, NULL, NULL);
}
