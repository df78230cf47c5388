/* SPDX-License-Identifier: MIT */
/*
 * What the reference ECU's FMU (ecu/fmu/reference_fmu.c) exports its functions with: the FMI
 * 2.0 types of the importer's declarations (fmu/fmi2.h: one set of declarations for both sides,
 * so the compiler checks that what we export is what we import), and the visibility that makes
 * a function one of the shared object's exported symbols (everything else is hidden).
 */
#ifndef HL_ECU_FMU_FMI2_EXPORT_H
#define HL_ECU_FMU_FMI2_EXPORT_H

#include "fmu/fmi2.h"

#define HL_FMI2_EXPORT __attribute__((visibility("default")))

#endif
