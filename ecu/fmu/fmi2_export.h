/* SPDX-License-Identifier: MIT */
/*
 * The FMI 2.0 types the reference ECU's FMU (ecu/fmu/reference_fmu.c) exports its functions
 * with, written here for that one file (to be unified with the importer's fmu/fmi2.h). The
 * platform "default" types: opaque pointers for the instance, its environment and FMU states,
 * unsigned int value references, double Reals, int Integers and Booleans, char strings (as the
 * FMI 2.0 fmi2TypesPlatform.h describes them, e.g. the copy in code-saturne/code_saturne,
 * extras/FMI/fmi/fmi2TypesPlatform.h); the status, type and status-kind enumerations and the
 * callback structure in the standard's order (their names as listed by the fmi-sys crate,
 * https://docs.rs/fmi-sys/0.5.0/fmi_sys/fmi2/index.html).
 */
#ifndef HL_ECU_FMU_FMI2_EXPORT_H
#define HL_ECU_FMU_FMI2_EXPORT_H

#include <stddef.h>

typedef void *fmi2Component;
typedef void *fmi2ComponentEnvironment;
typedef void *fmi2FMUstate;
typedef unsigned int fmi2ValueReference;
typedef double fmi2Real;
typedef int fmi2Integer;
typedef int fmi2Boolean;
typedef char fmi2Char;
typedef const fmi2Char *fmi2String;
typedef char fmi2Byte;

#define fmi2True 1
#define fmi2False 0

typedef enum { fmi2OK, fmi2Warning, fmi2Discard, fmi2Error, fmi2Fatal, fmi2Pending } fmi2Status;
typedef enum { fmi2ModelExchange, fmi2CoSimulation } fmi2Type;
typedef enum {
	fmi2DoStepStatus,
	fmi2PendingStatus,
	fmi2LastSuccessfulTime,
	fmi2Terminated
} fmi2StatusKind;

typedef void (*fmi2CallbackLogger)(fmi2ComponentEnvironment env, fmi2String instance_name,
				   fmi2Status status, fmi2String category, fmi2String message, ...);
typedef void *(*fmi2CallbackAllocateMemory)(size_t nobj, size_t size);
typedef void (*fmi2CallbackFreeMemory)(void *obj);
typedef void (*fmi2StepFinished)(fmi2ComponentEnvironment env, fmi2Status status);

typedef struct {
	fmi2CallbackLogger logger;
	fmi2CallbackAllocateMemory allocateMemory;
	fmi2CallbackFreeMemory freeMemory;
	fmi2StepFinished stepFinished;
	fmi2ComponentEnvironment componentEnvironment;
} fmi2CallbackFunctions;

/* The only symbols the shared object exports. */
#define HL_FMI2_EXPORT __attribute__((visibility("default")))

#endif
