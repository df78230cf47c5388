/* SPDX-License-Identifier: MIT */
/*
 * The FMI 2.0 functions the reference ECU's FMU does not support (model exchange's, the FMU
 * state, derivatives, asynchronous steps, the non-Real variables): present, as the standard
 * requires of a co-simulation FMU, each returning fmi2Error with a log message. See
 * ecu/fmu/reference_fmu.c for the FMU.
 */
#include <stddef.h>

#include "ecu/fmu/fmi2_export.h"
#include "ecu/fmu/reference_fmu.h"

/* --- what this FMU does not support (present, as the standard requires) --- */

static fmi2Status unsupported(fmi2Component comp, const char *fn)
{
	hl_refmu_not_supported(comp, fn);
	return fmi2Error;
}

HL_FMI2_EXPORT fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
					 fmi2Integer value[])
{
	(void)vr, (void)nvr, (void)value;
	return unsupported(c, "fmi2GetInteger");
}

HL_FMI2_EXPORT fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
					 fmi2Boolean value[])
{
	(void)vr, (void)nvr, (void)value;
	return unsupported(c, "fmi2GetBoolean");
}

HL_FMI2_EXPORT fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
					fmi2String value[])
{
	(void)vr, (void)nvr, (void)value;
	return unsupported(c, "fmi2GetString");
}

HL_FMI2_EXPORT fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
					 const fmi2Integer value[])
{
	(void)vr, (void)nvr, (void)value;
	return unsupported(c, "fmi2SetInteger");
}

HL_FMI2_EXPORT fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
					 const fmi2Boolean value[])
{
	(void)vr, (void)nvr, (void)value;
	return unsupported(c, "fmi2SetBoolean");
}

HL_FMI2_EXPORT fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
					const fmi2String value[])
{
	(void)vr, (void)nvr, (void)value;
	return unsupported(c, "fmi2SetString");
}

HL_FMI2_EXPORT fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *state)
{
	(void)state;
	return unsupported(c, "fmi2GetFMUstate");
}

HL_FMI2_EXPORT fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate state)
{
	(void)state;
	return unsupported(c, "fmi2SetFMUstate");
}

HL_FMI2_EXPORT fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *state)
{
	(void)state;
	return unsupported(c, "fmi2FreeFMUstate");
}

HL_FMI2_EXPORT fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate state,
						     size_t *size)
{
	(void)state, (void)size;
	return unsupported(c, "fmi2SerializedFMUstateSize");
}

HL_FMI2_EXPORT fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate state,
						fmi2Byte bytes[], size_t size)
{
	(void)state, (void)bytes, (void)size;
	return unsupported(c, "fmi2SerializeFMUstate");
}

HL_FMI2_EXPORT fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte bytes[],
						  size_t size, fmi2FMUstate *state)
{
	(void)bytes, (void)size, (void)state;
	return unsupported(c, "fmi2DeSerializeFMUstate");
}

HL_FMI2_EXPORT fmi2Status fmi2GetDirectionalDerivative(fmi2Component c,
						       const fmi2ValueReference unknown[],
						       size_t n_unknown,
						       const fmi2ValueReference known[],
						       size_t n_known, const fmi2Real dv_known[],
						       fmi2Real dv_unknown[])
{
	(void)unknown, (void)n_unknown, (void)known, (void)n_known, (void)dv_known,
		(void)dv_unknown;
	return unsupported(c, "fmi2GetDirectionalDerivative");
}

HL_FMI2_EXPORT fmi2Status fmi2SetRealInputDerivatives(fmi2Component c,
						      const fmi2ValueReference vr[], size_t nvr,
						      const fmi2Integer order[],
						      const fmi2Real value[])
{
	(void)vr, (void)nvr, (void)order, (void)value;
	return unsupported(c, "fmi2SetRealInputDerivatives");
}

HL_FMI2_EXPORT fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c,
						       const fmi2ValueReference vr[], size_t nvr,
						       const fmi2Integer order[], fmi2Real value[])
{
	(void)vr, (void)nvr, (void)order, (void)value;
	return unsupported(c, "fmi2GetRealOutputDerivatives");
}

HL_FMI2_EXPORT fmi2Status fmi2CancelStep(fmi2Component c)
{
	return unsupported(c, "fmi2CancelStep");
}

HL_FMI2_EXPORT fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value)
{
	(void)s, (void)value;
	return unsupported(c, "fmi2GetStatus");
}

HL_FMI2_EXPORT fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s,
					    fmi2Real *value)
{
	(void)s, (void)value;
	return unsupported(c, "fmi2GetRealStatus");
}

HL_FMI2_EXPORT fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s,
					       fmi2Integer *value)
{
	(void)s, (void)value;
	return unsupported(c, "fmi2GetIntegerStatus");
}

HL_FMI2_EXPORT fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s,
					       fmi2Boolean *value)
{
	(void)s, (void)value;
	return unsupported(c, "fmi2GetBooleanStatus");
}

HL_FMI2_EXPORT fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s,
					      fmi2String *value)
{
	(void)s, (void)value;
	return unsupported(c, "fmi2GetStringStatus");
}
