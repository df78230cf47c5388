/* SPDX-License-Identifier: MIT */
/*
 * An FMI 2.0 co-simulation FMU for linux64, imported (docs/fmu.md): the archive is unzipped
 * (libzip) into a private directory, its modelDescription.xml read with libxml2 (fmiVersion
 * "2.0", a <CoSimulation> with its modelIdentifier, the <ModelVariables>: name,
 * valueReference, causality, variability and type of each), and the binary
 * binaries/linux64/<modelIdentifier>.so is run in a child process of ours: the child dlopens
 * it, instantiates it (fmi2Instantiate with the resources directory's file: URI), sets up the
 * experiment, enters and leaves initialization and then serves set, step and get requests over
 * a socket pair. A child, not this process: an FMU is foreign code that can crash or hang in a
 * step; in the child, a crash is a lost connection and a waitpid() status, a hang a timeout,
 * and the caller (hdlampd, hdlamp sil) ends the run with a clear error and its report instead
 * of dying with it. The FMU's log messages (fmi2CallbackLogger) come back over the socket and
 * go to the log this was opened with, each as "fmu <instance>: [<category>] <message>".
 *
 * Errors name the file and what was wrong: not a zip, no modelDescription.xml, XML that does
 * not parse (its line), not FMI 2.0, no co-simulation, no binaries/linux64/<id>.so, a symbol
 * the binary lacks, fmi2Instantiate returning NULL, a status fmi2Error or fmi2Fatal of any
 * call (with the call's name and the FMU's last log line), a crash (the signal) or a call that
 * took longer than the timeout.
 *
 * Thread-safety: an hl_fmu belongs to one thread.
 */
#ifndef HL_FMU_FMU_H
#define HL_FMU_FMU_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "fmu/var.h"

struct hl_fmu_options {
	double step_s; /* the communication step the caller will use (for the log only) */
	int timeout_ms; /* longest a call may take before the child is killed; 0: 10000 */
	FILE *log; /* the FMU's messages and ours; NULL: stderr */
	const char *instance; /* the instance name; NULL: the model identifier */
};

struct hl_fmu;

/*
 * Opens path, starts the child, instantiates and initializes at start_s. 0, or -errno with a
 * message in err naming path (and the variable, line, call or signal).
 */
int hl_fmu_open(const char *path, double start_s, const struct hl_fmu_options *o,
		struct hl_fmu **ret, char *err, size_t err_size);
/* fmi2Terminate, fmi2FreeInstance, the child reaped, the directory removed. NULL is fine. */
void hl_fmu_close(struct hl_fmu *f);

const char *hl_fmu_model_name(const struct hl_fmu *f); /* modelName */
const char *hl_fmu_identifier(const struct hl_fmu *f); /* the co-simulation modelIdentifier */
int hl_fmu_n_vars(const struct hl_fmu *f);
const struct hl_fmu_var *hl_fmu_var(const struct hl_fmu *f, int i);
/* The index of the variable called name, or -ENOENT. */
int hl_fmu_find(const struct hl_fmu *f, const char *name);

/*
 * Sets n Real variables (indices idx[], values v[]) for the next step. Batched: the values
 * travel with the next hl_fmu_step. 0, -EINVAL (not a Real, not an input or parameter);
 * hl_fmu_error() then says which variable and why. Nothing is set when one of them is wrong.
 */
int hl_fmu_set_real(struct hl_fmu *f, const int *idx, const double *v, int n);
/*
 * fmi2DoStep(t_s, h_s, fmi2True) after the pending sets, then reads the n Real variables idx[]
 * into ret[]. 0, or -EIO (fmi2Error/fmi2Fatal/fmi2Discard), -EPIPE (the child died: *err says
 * of what signal or exit status), -ETIMEDOUT; err names the call and the FMU's last message.
 */
int hl_fmu_step(struct hl_fmu *f, double t_s, double h_s, const int *idx, double *ret, int n,
		char *err, size_t err_size);

/*
 * The message of the last hl_fmu_set_real or hl_fmu_step that failed, "" after one that did
 * not. Owned by f, valid until the next call on it.
 */
const char *hl_fmu_error(const struct hl_fmu *f);
/* The child process's id while it runs, 0 once it has been reaped. */
int hl_fmu_pid(const struct hl_fmu *f);
/* The absolute path of the directory the archive was unpacked into (removed by close). */
const char *hl_fmu_dir(const struct hl_fmu *f);

const char *hl_fmu_type_name(enum hl_fmu_type t);
const char *hl_fmu_causality_name(enum hl_fmu_causality c);

#endif
