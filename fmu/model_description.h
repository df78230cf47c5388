/* SPDX-License-Identifier: MIT */
/*
 * An FMU's modelDescription.xml, read with libxml2 (docs/fmu.md, "modelDescription.xml"): what
 * the importer needs of the FMI 2.0 description schema (FMI 2.0 standard, 2.2 "FMI
 * Description Schema"): the root <fmiModelDescription> with fmiVersion "2.0", modelName and
 * guid (2.2.1), its <CoSimulation modelIdentifier="..."> (4.3.1) and the <ScalarVariable>s of
 * <ModelVariables> (2.2.7): name, valueReference, causality (default "local"), variability
 * (default "continuous", checked, not kept) and the one type element among Real, Integer,
 * Boolean, String and Enumeration. Everything else in the file is left alone. No network
 * access and no entity substitution while parsing.
 *
 * Thread-safety: any thread (libxml2's parser is reentrant once initialized).
 */
#ifndef HL_FMU_MODEL_DESCRIPTION_H
#define HL_FMU_MODEL_DESCRIPTION_H

#include <stddef.h>

#include "fmu/var.h"

struct hl_fmu_md {
	char *model_name;
	char *guid;
	char *identifier; /* <CoSimulation modelIdentifier> */
	struct hl_fmu_var *vars; /* names owned here */
	int n_vars;
};

/*
 * Reads the modelDescription.xml at path. 0; -EBADMSG (not XML, a missing or bad attribute or
 * element), -ENOTSUP (not FMI 2.0, no co-simulation), -ENOENT (no such file), -ENOMEM. err
 * reads "'<fmu>': modelDescription.xml:<line>: what was wrong", fmu the name given for it.
 */
int hl_fmu_md_read(const char *path, const char *fmu, struct hl_fmu_md **ret, char *err,
		   size_t err_size);
/* NULL is fine. */
void hl_fmu_md_free(struct hl_fmu_md *md);

#endif
