/* SPDX-License-Identifier: MIT */
/*
 * A test FMU for co-simulation (FMI 2.0), built four times (CMakeLists.txt here): "gain" does
 * y = 2 * u + time, time being the end of the step just made; "gain_error" returns fmi2Error
 * from fmi2DoStep at step GAIN_ERROR_AT, "gain_segv" raises SIGSEGV at step GAIN_SEGV_AT,
 * "gain_hang" sleeps forever at step GAIN_HANG_AT. Variables (gain.xml): u (0, input), y (1,
 * output), log (2, input: non-zero logs every step). fmi2Instantiate refuses a guid other than
 * GAIN_GUID and logs the resources URI it was given.
 */
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "fmu/fmi2.h"

#define GAIN_GUID "{6d1e4f0a-hdlamp-gain}"
#define EXPORT __attribute__((visibility("default")))

/* declared with our function types: the compiler checks both sides against one text */
EXPORT fmi2GetTypesPlatform_fn fmi2GetTypesPlatform;
EXPORT fmi2GetVersion_fn fmi2GetVersion;
EXPORT fmi2Instantiate_fn fmi2Instantiate;
EXPORT fmi2FreeInstance_fn fmi2FreeInstance;
EXPORT fmi2SetupExperiment_fn fmi2SetupExperiment;
EXPORT fmi2EnterInitializationMode_fn fmi2EnterInitializationMode;
EXPORT fmi2ExitInitializationMode_fn fmi2ExitInitializationMode;
EXPORT fmi2Terminate_fn fmi2Terminate;
EXPORT fmi2SetReal_fn fmi2SetReal;
EXPORT fmi2GetReal_fn fmi2GetReal;
EXPORT fmi2DoStep_fn fmi2DoStep;

struct gain {
	fmi2CallbackFunctions cb;
	char name[64];
	double u, y, log, time;
	int steps;
};

#define LOG(g, status, category, ...) \
	(g)->cb.logger((g)->cb.componentEnvironment, (g)->name, status, category, __VA_ARGS__)

const char *fmi2GetTypesPlatform(void)
{
	return "default";
}

const char *fmi2GetVersion(void)
{
	return "2.0";
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
			      fmi2String fmuResourceLocation,
			      const fmi2CallbackFunctions *functions, fmi2Boolean visible,
			      fmi2Boolean loggingOn)
{
	struct gain *g;

	(void)visible;
	(void)loggingOn;
	if (!functions || !functions->logger || !functions->allocateMemory)
		return NULL;
	if (fmuType != fmi2CoSimulation || strcmp(fmuGUID, GAIN_GUID) != 0) {
		functions->logger(functions->componentEnvironment, instanceName, fmi2Error,
				  "logStatusError", "guid \"%s\" is not mine", fmuGUID);
		return NULL;
	}
	g = functions->allocateMemory(1, sizeof(*g));
	if (!g)
		return NULL;
	g->cb = *functions;
	snprintf(g->name, sizeof(g->name), "%s", instanceName);
	LOG(g, fmi2OK, "logAll", "resources at %s", fmuResourceLocation);
	return g;
}

void fmi2FreeInstance(fmi2Component c)
{
	struct gain *g = c;

	g->cb.freeMemory(g);
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
			       fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime)
{
	struct gain *g = c;

	(void)toleranceDefined;
	(void)tolerance;
	(void)stopTimeDefined;
	(void)stopTime;
	g->time = startTime;
	return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c)
{
	(void)c;
	return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c)
{
	struct gain *g = c;

	g->y = 2 * g->u + g->time;
	return fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component c)
{
	struct gain *g = c;

	LOG(g, fmi2OK, "logAll", "terminated after %d steps", g->steps);
	return fmi2OK;
}

static double *var(struct gain *g, fmi2ValueReference vr)
{
	return vr == 0 ? &g->u : vr == 1 ? &g->y : vr == 2 ? &g->log : NULL;
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
		       const fmi2Real value[])
{
	struct gain *g = c;

	for (size_t i = 0; i < nvr; i++) {
		if (vr[i] == 1 || !var(g, vr[i])) {
			LOG(g, fmi2Error, "logStatusError", "cannot set value reference %u", vr[i]);
			return fmi2Error;
		}
		*var(g, vr[i]) = value[i];
	}
	return fmi2OK;
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[])
{
	struct gain *g = c;

	for (size_t i = 0; i < nvr; i++) {
		if (!var(g, vr[i])) {
			LOG(g, fmi2Error, "logStatusError", "no value reference %u", vr[i]);
			return fmi2Error;
		}
		value[i] = *var(g, vr[i]);
	}
	return fmi2OK;
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint,
		      fmi2Real communicationStepSize, fmi2Boolean noSetFMUStatePriorToCurrentPoint)
{
	struct gain *g = c;

	(void)noSetFMUStatePriorToCurrentPoint;
	g->steps++;
#ifdef GAIN_ERROR_AT
	if (g->steps == GAIN_ERROR_AT) {
		LOG(g, fmi2Error, "logStatusError", "step %d: u = %g is out of range", g->steps,
		    g->u);
		return fmi2Error;
	}
#endif
#ifdef GAIN_SEGV_AT
	if (g->steps == GAIN_SEGV_AT) {
		LOG(g, fmi2OK, "logAll", "step %d: about to crash", g->steps);
		raise(SIGSEGV);
	}
#endif
#ifdef GAIN_HANG_AT
	if (g->steps == GAIN_HANG_AT)
		for (;;)
			pause();
#endif
	g->time = currentCommunicationPoint + communicationStepSize;
	g->y = 2 * g->u + g->time;
	if (g->log != 0)
		LOG(g, fmi2OK, "logAll", "step %d: t = %g s, y = %g", g->steps, g->time, g->y);
	return fmi2OK;
}
