/* SPDX-License-Identifier: MIT */
/*
 * An FMU's variable as modelDescription.xml declares it (FMI 2.0 standard, 2.2.7): shared by
 * the description's reader (fmu/model_description.h) and the importer (fmu/fmu.h), which
 * includes it. The enums follow the standard's order of the type elements and causalities.
 */
#ifndef HL_FMU_VAR_H
#define HL_FMU_VAR_H

#include <stdint.h>

enum hl_fmu_type {
	HL_FMU_REAL,
	HL_FMU_INTEGER,
	HL_FMU_BOOLEAN,
	HL_FMU_STRING,
	HL_FMU_ENUMERATION,
};

enum hl_fmu_causality {
	HL_FMU_PARAMETER,
	HL_FMU_CALCULATED_PARAMETER,
	HL_FMU_INPUT,
	HL_FMU_OUTPUT,
	HL_FMU_LOCAL,
	HL_FMU_INDEPENDENT,
};

struct hl_fmu_var {
	const char *name;
	uint32_t vr; /* valueReference */
	enum hl_fmu_type type;
	enum hl_fmu_causality causality;
	int line; /* its line in modelDescription.xml */
};

#endif
