/* SPDX-License-Identifier: MIT */
#include "fmu/child.h"

#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include "fmu/fmi2.h"

#define CHILD_FD 3 /* the child's end of the socket pair, all other descriptors closed */

/* The FMU's entry points (fmu/fmi2.h) and the instance: the child's whole state. */
struct child {
	int fd;
	void *so;
	fmi2GetTypesPlatform_fn *get_types_platform;
	fmi2GetVersion_fn *get_version;
	fmi2Instantiate_fn *instantiate;
	fmi2SetupExperiment_fn *setup_experiment;
	fmi2EnterInitializationMode_fn *enter_init;
	fmi2ExitInitializationMode_fn *exit_init;
	fmi2SetReal_fn *set_real;
	fmi2GetReal_fn *get_real;
	fmi2DoStep_fn *do_step;
	fmi2Terminate_fn *terminate;
	fmi2FreeInstance_fn *free_instance;
	fmi2CallbackFunctions callbacks;
	fmi2Component c;
	fmi2Status worst; /* of all calls so far: what the end may still call (2.1.3) */
	union {
		struct hl_fmu_msg msg;
		unsigned char bytes[HL_FMU_MSG_MAX];
	} in, out;
};

/* Only for a logger call whose FMU passes no componentEnvironment (a broken FMU); the child
 * is a process of its own with this one instance. */
static struct child *child_of_process;

static const char *const call_names[] = {
	[HL_FMU_CALL_LOAD] = "loading the binary",
	[HL_FMU_CALL_INSTANTIATE] = "fmi2Instantiate",
	[HL_FMU_CALL_SETUP_EXPERIMENT] = "fmi2SetupExperiment",
	[HL_FMU_CALL_ENTER_INIT] = "fmi2EnterInitializationMode",
	[HL_FMU_CALL_EXIT_INIT] = "fmi2ExitInitializationMode",
	[HL_FMU_CALL_SET_REAL] = "fmi2SetReal",
	[HL_FMU_CALL_DO_STEP] = "fmi2DoStep",
	[HL_FMU_CALL_GET_REAL] = "fmi2GetReal",
	[HL_FMU_CALL_TERMINATE] = "fmi2Terminate",
};

const char *hl_fmu_call_name(enum hl_fmu_call c)
{
	return (unsigned)c < sizeof(call_names) / sizeof(call_names[0]) ? call_names[c] : "?";
}

/* A lost parent ends the child: nothing is left to report to. */
static void send_or_exit(struct child *ch, const void *buf, size_t len)
{
	while (send(ch->fd, buf, len, MSG_NOSIGNAL) < 0)
		if (errno != EINTR)
			_exit(3);
}

static void reply(struct child *ch, enum hl_fmu_call call, int status, const void *payload,
		  size_t len)
{
	ch->out.msg =
		(struct hl_fmu_msg){ .kind = HL_FMU_MSG_REPLY, .status = status, .call = call };
	if (len)
		memcpy(ch->out.bytes + sizeof(ch->out.msg), payload, len);
	send_or_exit(ch, ch->out.bytes, sizeof(ch->out.msg) + len);
}

static void __attribute__((noreturn)) fail_load(struct child *ch, const char *fmt, ...)
{
	char text[1024];
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(text, sizeof(text), fmt, ap);
	va_end(ap);
	reply(ch, HL_FMU_CALL_LOAD, -1, text, strlen(text) + 1);
	_exit(2);
}

/* 2.1.5: fmi2CallbackLogger. The message is a printf format with the arguments that follow. */
static void logger(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status,
		   fmi2String category, fmi2String message, ...)
{
	struct child *ch = env ? env : child_of_process;
	char buf[sizeof(struct hl_fmu_msg) + HL_FMU_MAX_LOG];
	struct hl_fmu_msg *m = (struct hl_fmu_msg *)buf;
	char *at = buf + sizeof(*m);
	size_t room = HL_FMU_MAX_LOG, n;
	va_list ap;

	(void)instance; /* ours: the parent knows it */
	*m = (struct hl_fmu_msg){ .kind = HL_FMU_MSG_LOG, .status = (int32_t)status };
	n = (size_t)snprintf(at, 64, "%s", category ? category : "");
	n = n < 63 ? n : 63;
	at += n + 1;
	room -= n + 1;
	va_start(ap, message);
	if (vsnprintf(at, room, message ? message : "", ap) < 0)
		at[0] = '\0';
	va_end(ap);
	send_or_exit(ch, buf, (size_t)(at - buf) + strlen(at) + 1);
}

static void *allocate(size_t nobj, size_t size)
{
	return calloc(nobj, size); /* 2.1.5: zeroed, as calloc */
}

static void note(struct child *ch, fmi2Status s)
{
	if (s > ch->worst && s != fmi2Pending)
		ch->worst = s;
}

static void load(struct child *ch, const struct hl_fmu_child_args *a)
{
	const struct {
		const char *name;
		void **slot;
	} syms[] = {
		{ "fmi2GetTypesPlatform", (void **)&ch->get_types_platform },
		{ "fmi2GetVersion", (void **)&ch->get_version },
		{ "fmi2Instantiate", (void **)&ch->instantiate },
		{ "fmi2SetupExperiment", (void **)&ch->setup_experiment },
		{ "fmi2EnterInitializationMode", (void **)&ch->enter_init },
		{ "fmi2ExitInitializationMode", (void **)&ch->exit_init },
		{ "fmi2SetReal", (void **)&ch->set_real },
		{ "fmi2GetReal", (void **)&ch->get_real },
		{ "fmi2DoStep", (void **)&ch->do_step },
		{ "fmi2Terminate", (void **)&ch->terminate },
		{ "fmi2FreeInstance", (void **)&ch->free_instance },
	};
	const char *s;

	ch->so = dlopen(a->so_path, RTLD_NOW | RTLD_LOCAL);
	if (!ch->so)
		fail_load(ch, "dlopen: %s", dlerror());
	for (size_t i = 0; i < sizeof(syms) / sizeof(syms[0]); i++) {
		*syms[i].slot = dlsym(ch->so, syms[i].name);
		if (!*syms[i].slot)
			fail_load(ch, "the binary has no symbol %s", syms[i].name);
	}
	s = ch->get_version();
	if (!s || strcmp(s, HL_FMI2_VERSION) != 0)
		fail_load(ch, "fmi2GetVersion() is \"%s\", not \"%s\"", s ? s : "(null)",
			  HL_FMI2_VERSION);
	s = ch->get_types_platform();
	if (!s || strcmp(s, HL_FMI2_TYPES_PLATFORM) != 0)
		fail_load(ch, "fmi2GetTypesPlatform() is \"%s\", not \"%s\"", s ? s : "(null)",
			  HL_FMI2_TYPES_PLATFORM);
}

/* Instantiate and initialize (2.1.5, 2.1.6; the co-simulation state machine of 4.2.4). */
static void start(struct child *ch, const struct hl_fmu_child_args *a)
{
	fmi2Status s;

	ch->callbacks = (fmi2CallbackFunctions){
		.logger = logger,
		.allocateMemory = allocate,
		.freeMemory = free,
		.stepFinished = NULL,
		.componentEnvironment = ch,
	};
	ch->c = ch->instantiate(a->instance, fmi2CoSimulation, a->guid, a->resource_uri,
				&ch->callbacks, fmi2False, fmi2True);
	if (!ch->c) {
		reply(ch, HL_FMU_CALL_INSTANTIATE, fmi2Error, NULL, 0);
		_exit(2);
	}
	s = ch->setup_experiment(ch->c, fmi2False, 0.0, a->start_s, fmi2False, 0.0);
	note(ch, s);
	if (s > fmi2Warning) {
		reply(ch, HL_FMU_CALL_SETUP_EXPERIMENT, s, NULL, 0);
		return;
	}
	s = ch->enter_init(ch->c);
	note(ch, s);
	if (s > fmi2Warning) {
		reply(ch, HL_FMU_CALL_ENTER_INIT, s, NULL, 0);
		return;
	}
	s = ch->exit_init(ch->c);
	note(ch, s);
	reply(ch, HL_FMU_CALL_EXIT_INIT, s, NULL, 0);
}

static void step(struct child *ch, size_t len)
{
	const struct hl_fmu_msg *m = &ch->in.msg;
	const unsigned char *p = ch->in.bytes + sizeof(*m);
	const fmi2ValueReference *vr_set = (const fmi2ValueReference *)p;
	const double *v = (const double *)(p + m->n_set * sizeof(uint32_t));
	const fmi2ValueReference *vr_get =
		(const fmi2ValueReference *)(p + m->n_set * (sizeof(uint32_t) + sizeof(double)));
	double *out = (double *)(ch->out.bytes + sizeof(struct hl_fmu_msg));
	fmi2Status s = fmi2OK;

	/* the parent builds these; a wrong size is a bug of ours, never the FMU's */
	if (m->n_set > HL_FMU_MAX_BATCH || m->n_get > HL_FMU_MAX_BATCH ||
	    len != sizeof(*m) + m->n_set * (sizeof(uint32_t) + sizeof(double)) +
			    m->n_get * sizeof(uint32_t))
		_exit(4);
	/* copied: after 4 * n_set bytes of references the values need not be aligned */
	if (m->n_set) {
		double vals[HL_FMU_MAX_BATCH];

		memcpy(vals, v, m->n_set * sizeof(double));
		s = ch->set_real(ch->c, vr_set, m->n_set, vals);
		note(ch, s);
		if (s > fmi2Warning) {
			reply(ch, HL_FMU_CALL_SET_REAL, s, NULL, 0);
			return;
		}
	}
	s = ch->do_step(ch->c, m->t_s, m->h_s, fmi2True);
	note(ch, s);
	if (s > fmi2Warning) {
		reply(ch, HL_FMU_CALL_DO_STEP, s, NULL, 0);
		return;
	}
	if (m->n_get) {
		double vals[HL_FMU_MAX_BATCH];

		s = ch->get_real(ch->c, vr_get, m->n_get, vals);
		note(ch, s);
		if (s > fmi2Warning) {
			reply(ch, HL_FMU_CALL_GET_REAL, s, NULL, 0);
			return;
		}
		memcpy(out, vals, m->n_get * sizeof(double));
	}
	ch->out.msg = (struct hl_fmu_msg){ .kind = HL_FMU_MSG_REPLY,
					   .status = s,
					   .call = HL_FMU_CALL_DO_STEP,
					   .n_get = m->n_get };
	send_or_exit(ch, ch->out.bytes, sizeof(ch->out.msg) + m->n_get * sizeof(double));
}

/* 2.1.3: after fmi2Error only fmi2FreeInstance (or fmi2Reset); after fmi2Fatal nothing. */
static void __attribute__((noreturn)) end(struct child *ch)
{
	fmi2Status s = fmi2OK;

	if (ch->worst < fmi2Error) {
		s = ch->terminate(ch->c);
		note(ch, s);
	}
	if (ch->worst < fmi2Fatal)
		ch->free_instance(ch->c);
	reply(ch, HL_FMU_CALL_TERMINATE, s, NULL, 0);
	_exit(0);
}

static void __attribute__((noreturn)) serve(struct child *ch)
{
	for (;;) {
		ssize_t n = recv(ch->fd, ch->in.bytes, sizeof(ch->in.bytes), 0);

		if (n < 0 && errno == EINTR)
			continue;
		if (n < (ssize_t)sizeof(struct hl_fmu_msg))
			_exit(n == 0 ? 0 : 3); /* the parent is gone */
		if (ch->in.msg.kind == HL_FMU_MSG_STEP)
			step(ch, (size_t)n);
		else if (ch->in.msg.kind == HL_FMU_MSG_END)
			end(ch);
		else
			_exit(4);
	}
}

/*
 * The child's start: a process that looks like a fresh one to the FMU. Signals as after exec
 * (a crash must kill it, not a handler of the parent's such as a sanitizer's), stdin from
 * /dev/null (the FMU must not read the parent's terminal or pipe), stdout onto stderr (an FMU
 * that prints must not write into the parent's output, which other programs may read), no
 * descriptor of the parent's but the socket, and killed when the parent dies.
 */
static void __attribute__((noreturn))
child_main(int fd, pid_t parent, const struct hl_fmu_child_args *a)
{
	static const int reset[] = { SIGSEGV, SIGBUS, SIGFPE,  SIGILL,	SIGABRT, SIGPIPE, SIGTERM,
				     SIGINT,  SIGHUP, SIGCHLD, SIGALRM, SIGUSR1, SIGUSR2 };
	struct child *ch;
	sigset_t none;
	int null;

	prctl(PR_SET_PDEATHSIG, SIGKILL);
	if (getppid() != parent)
		_exit(3);
	for (size_t i = 0; i < sizeof(reset) / sizeof(reset[0]); i++)
		signal(reset[i], SIG_DFL);
	sigemptyset(&none);
	sigprocmask(SIG_SETMASK, &none, NULL);
	fd = fcntl(fd, F_DUPFD, CHILD_FD + 1); /* out of the way of 0, 1, 2 and CHILD_FD */
	null = open("/dev/null", O_RDONLY);
	if (fd < 0 || null < 0 || dup2(null, STDIN_FILENO) < 0 || dup2(fd, CHILD_FD) != CHILD_FD)
		_exit(3);
	dup2(STDERR_FILENO, STDOUT_FILENO); /* no stderr: stdout stays as it was */
	close_range(CHILD_FD + 1, ~0U, 0);
	ch = calloc(1, sizeof(*ch));
	if (!ch)
		_exit(3);
	ch->fd = CHILD_FD;
	child_of_process = ch;
	load(ch, a);
	start(ch, a);
	serve(ch);
}

int hl_fmu_child_start(const struct hl_fmu_child_args *a, pid_t *ret_pid, int *ret_fd)
{
	const pid_t parent = getpid();
	int sv[2];
	pid_t pid;

	if (socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0, sv) < 0)
		return -errno;
	pid = fork();
	if (pid < 0) {
		int r = -errno;

		close(sv[0]);
		close(sv[1]);
		return r;
	}
	if (pid == 0) {
		close(sv[0]);
		child_main(sv[1], parent, a);
	}
	close(sv[1]);
	*ret_pid = pid;
	*ret_fd = sv[0];
	return 0;
}
