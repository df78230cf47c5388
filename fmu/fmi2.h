/* SPDX-License-Identifier: MIT */
/*
 * Our own declarations of the part of the FMI 2.0 C API that the importer calls (docs/fmu.md).
 * Written from the text of the standard, "Functional Mock-up Interface for Model Exchange and
 * Co-Simulation", version 2.0 (2014-07-25) and 2.0.x, not copied from its header files:
 *
 *   2.1.2 Platform Dependent Definitions: the types below for the platform "default", which
 *         is what fmi2GetTypesPlatform() must return for them to hold;
 *   2.1.3 Status Returned by Functions: fmi2Status;
 *   2.1.4 Inquire Platform and Version Number of Header Files: fmi2GetTypesPlatform,
 *         fmi2GetVersion ("2.0");
 *   2.1.5 Creation, Destruction and Logging of FMU Instances: fmi2Type, the callbacks,
 *         fmi2Instantiate, fmi2FreeInstance;
 *   2.1.6 Initialization, Termination, and Resetting an FMU: fmi2SetupExperiment,
 *         fmi2EnterInitializationMode, fmi2ExitInitializationMode, fmi2Terminate;
 *   2.1.7 Getting and Setting Variable Values: fmi2SetReal, fmi2GetReal;
 *   4.2.2 Computation (co-simulation): fmi2DoStep.
 *
 * The function types (not pointer types) let a test FMU declare its functions with them
 * (fmi2DoStep_fn fmi2DoStep;) so that the compiler checks both sides against one text.
 */
#ifndef HL_FMU_FMI2_H
#define HL_FMU_FMI2_H

#include <stddef.h>

/* 2.1.2, platform "default" */
typedef void *fmi2Component; /* an instance of the FMU */
typedef void *fmi2ComponentEnvironment; /* the importer's pointer, handed back to the logger */
typedef void *fmi2FMUstate; /* an FMU's saved state (an exporter must declare its functions) */
typedef unsigned int fmi2ValueReference;
typedef double fmi2Real;
typedef int fmi2Integer;
typedef int fmi2Boolean;
typedef char fmi2Char;
typedef const fmi2Char *fmi2String;
typedef char fmi2Byte; /* a serialized FMU state's bytes */

#define fmi2True 1
#define fmi2False 0

#define HL_FMI2_TYPES_PLATFORM "default" /* 2.1.4: fmi2GetTypesPlatform() for the types above */
#define HL_FMI2_VERSION "2.0" /* 2.1.4: fmi2GetVersion() of every FMI 2.0.x FMU */

/* 2.1.3, in the standard's order (their values are part of the binary interface) */
typedef enum {
	fmi2OK,
	fmi2Warning,
	fmi2Discard,
	fmi2Error,
	fmi2Fatal,
	fmi2Pending,
} fmi2Status;

/* 2.1.5 */
typedef enum {
	fmi2ModelExchange,
	fmi2CoSimulation,
} fmi2Type;

/* 4.2.3: what fmi2Get*Status asks of an asynchronous step */
typedef enum {
	fmi2DoStepStatus,
	fmi2PendingStatus,
	fmi2LastSuccessfulTime,
	fmi2Terminated,
} fmi2StatusKind;

/* 2.1.5: message may hold the escapes #<type><valueReference># (we pass it on as it is). */
typedef void fmi2CallbackLogger_fn(fmi2ComponentEnvironment env, fmi2String instanceName,
				   fmi2Status status, fmi2String category, fmi2String message, ...);
typedef void *fmi2CallbackAllocateMemory_fn(size_t nobj, size_t size);
typedef void fmi2CallbackFreeMemory_fn(void *obj);
typedef void fmi2StepFinished_fn(fmi2ComponentEnvironment env, fmi2Status status);

/* 2.1.5: the members in this order; since 2.0.1 they are no longer const. */
typedef struct {
	fmi2CallbackLogger_fn *logger;
	fmi2CallbackAllocateMemory_fn *allocateMemory;
	fmi2CallbackFreeMemory_fn *freeMemory;
	fmi2StepFinished_fn *stepFinished; /* NULL: we never ask for asynchronous steps */
	fmi2ComponentEnvironment componentEnvironment;
} fmi2CallbackFunctions;

/* 2.1.4 */
typedef const char *fmi2GetTypesPlatform_fn(void);
typedef const char *fmi2GetVersion_fn(void);

/* 2.1.5: NULL when it fails. */
typedef fmi2Component fmi2Instantiate_fn(fmi2String instanceName, fmi2Type fmuType,
					 fmi2String fmuGUID, fmi2String fmuResourceLocation,
					 const fmi2CallbackFunctions *functions,
					 fmi2Boolean visible, fmi2Boolean loggingOn);
typedef void fmi2FreeInstance_fn(fmi2Component c);

/* 2.1.6 */
typedef fmi2Status fmi2SetupExperiment_fn(fmi2Component c, fmi2Boolean toleranceDefined,
					  fmi2Real tolerance, fmi2Real startTime,
					  fmi2Boolean stopTimeDefined, fmi2Real stopTime);
typedef fmi2Status fmi2EnterInitializationMode_fn(fmi2Component c);
typedef fmi2Status fmi2ExitInitializationMode_fn(fmi2Component c);
typedef fmi2Status fmi2Terminate_fn(fmi2Component c);

/* 2.1.7 */
typedef fmi2Status fmi2SetReal_fn(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
				  const fmi2Real value[]);
typedef fmi2Status fmi2GetReal_fn(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
				  fmi2Real value[]);

/* 4.2.2 */
typedef fmi2Status fmi2DoStep_fn(fmi2Component c, fmi2Real currentCommunicationPoint,
				 fmi2Real communicationStepSize,
				 fmi2Boolean noSetFMUStatePriorToCurrentPoint);

#endif
