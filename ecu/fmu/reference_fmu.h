/* SPDX-License-Identifier: MIT */
/*
 * What the reference ECU's FMU (ecu/fmu/reference_fmu.c) shares with its unsupported functions
 * (ecu/fmu/unsupported.c). Private to the FMU's shared object.
 */
#ifndef HL_ECU_FMU_REFERENCE_FMU_H
#define HL_ECU_FMU_REFERENCE_FMU_H

#include "ecu/fmu/fmi2_export.h"

/* Logs "FN: not supported" as an error through the instance's logger (comp may be NULL). */
void hl_refmu_not_supported(fmi2Component comp, const char *fn);

#endif
