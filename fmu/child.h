/* SPDX-License-Identifier: MIT */
/*
 * The child process that runs an FMU's binary, and the messages it and the parent exchange
 * (docs/fmu.md, "The child process"). One SOCK_SEQPACKET socket pair: every message is one
 * datagram, a struct hl_fmu_msg and its payload, so that no message is ever read in halves.
 *
 *   parent -> child  HL_FMU_MSG_STEP: n_set value references and values, fmi2SetReal, then
 *                    fmi2DoStep(t_s, h_s, fmi2True), then fmi2GetReal of n_get references.
 *                    HL_FMU_MSG_END: fmi2Terminate and fmi2FreeInstance, then the child exits.
 *   child -> parent  HL_FMU_MSG_LOG: a message of fmi2CallbackLogger, any time;
 *                    HL_FMU_MSG_REPLY: once after start-up and once per request.
 *
 * Thread-safety: hl_fmu_child_start forks; the child runs only code of this file (and the
 * FMU's). Call it from one thread of the parent at a time.
 */
#ifndef HL_FMU_CHILD_H
#define HL_FMU_CHILD_H

#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>

#define HL_FMU_MAX_BATCH 4096 /* value references per set or get of one step */
#define HL_FMU_MAX_LOG 2048 /* bytes of one log message (category and text), longer ones cut */
#define HL_FMU_MSG_MAX \
	(sizeof(struct hl_fmu_msg) + 2 * HL_FMU_MAX_BATCH * (sizeof(uint32_t) + sizeof(double)))

enum hl_fmu_msg_kind {
	HL_FMU_MSG_STEP = 1,
	HL_FMU_MSG_END,
	HL_FMU_MSG_LOG,
	HL_FMU_MSG_REPLY,
};

/* What a reply is about: the call that failed, or the last one made. */
enum hl_fmu_call {
	HL_FMU_CALL_LOAD, /* dlopen, dlsym, fmi2GetVersion, fmi2GetTypesPlatform */
	HL_FMU_CALL_INSTANTIATE,
	HL_FMU_CALL_SETUP_EXPERIMENT,
	HL_FMU_CALL_ENTER_INIT,
	HL_FMU_CALL_EXIT_INIT,
	HL_FMU_CALL_SET_REAL,
	HL_FMU_CALL_DO_STEP,
	HL_FMU_CALL_GET_REAL,
	HL_FMU_CALL_TERMINATE,
};

/*
 * The header of every message. status: a reply's fmi2Status, or -1 when the child could not
 * load the binary (the payload is then the reason as text); a log message's fmi2Status.
 * Payloads: STEP  uint32_t vr_set[n_set], double v[n_set], uint32_t vr_get[n_get];
 *           REPLY double v[n_get] after a step, or text when status is -1;
 *           LOG   "category\0message\0".
 */
struct hl_fmu_msg {
	uint32_t kind;
	int32_t status;
	uint32_t call;
	uint32_t n_set;
	uint32_t n_get;
	uint32_t pad;
	double t_s;
	double h_s;
};

struct hl_fmu_child_args {
	const char *so_path; /* binaries/linux64/<modelIdentifier>.so, absolute */
	const char *instance;
	const char *guid;
	const char *resource_uri; /* file:///.../resources */
	double start_s;
};

/*
 * Forks the child, which loads the binary, instantiates and initializes and then serves
 * requests on its end of the socket pair. The parent's end (SOCK_CLOEXEC) goes to ret_fd, the
 * child's id to ret_pid; the start-up's reply is the parent's to read. 0 or -errno.
 */
int hl_fmu_child_start(const struct hl_fmu_child_args *a, pid_t *ret_pid, int *ret_fd);

/* "fmi2DoStep", ... */
const char *hl_fmu_call_name(enum hl_fmu_call c);

#endif
