/* SPDX-License-Identifier: MIT */
/*
 * `hdlamp ecu --fmu OUT.fmu`: the reference ECU as it is configured, packed as an FMI 2.0
 * co-simulation FMU (docs/ecu.md, "The ECU as an FMU"): modelDescription.xml,
 * binaries/linux64/hdlamp_ecu.so (ecu/fmu/reference_fmu.c) and resources/ (ecu.json, the input
 * database, the lamp files). The same inputs give the same bytes.
 */
#ifndef HL_TOOLS_ECU_FMU_EXPORT_H
#define HL_TOOLS_ECU_FMU_EXPORT_H

#include "can/inputs.h"
#include "ecu/lighting.h"
#include "lamp/lid.h"

struct hl_ecu_fmu_lamp {
	const char *name; /* "left", "right" */
	const struct hl_lid *lid;
	const char *lid_path; /* the LID file copied in, NULL: the built-in HD84 lamp of builtin */
	const char *builtin; /* "hd84_left" / "hd84_right" when lid_path is NULL */
	struct hl_ecu_mount mount;
	const float *low, *high; /* n_sources each */
};

/*
 * Writes the FMU to out_path. cfg is the ECU's configuration (timeouts already set),
 * inputs_dbc_path the input database file that map was built from. Prints what failed to
 * stderr as "hdlamp ecu: ..."; 0 or a negative errno.
 */
/*
 * The FMU's own faults, for tests of an importer (`hdlamp ecu --fault step-error=N`,
 * `step-crash=N`): its Nth fmi2DoStep returns fmi2Error, or crashes the process with a
 * segmentation fault; 0: none.
 */
struct hl_ecu_fmu_faults {
	int step_error, step_crash;
};

int hl_ecu_fmu_export(const char *out_path, const struct hl_ecu_config *cfg,
		      const struct hl_ecu_fmu_faults *faults, const char *inputs_dbc_path,
		      const struct hl_inputs_map *map, const struct hl_ecu_fmu_lamp *lamps,
		      int n_lamps);

#endif
