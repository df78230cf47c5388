/* SPDX-License-Identifier: MIT */
/*
 * The low and high beam the ECU starts from (docs/ecu.md, "Beams"), as relative currents per
 * source:
 *   - the HD84 lamp (95 sources, the first named "row1_led01", as hdlamp model writes it): its
 *     presets "low" and "high" (lamp/model.h);
 *   - any other lamp: high beam every source at full current; low beam the sources whose whole
 *     window (ecu/windows.h, against that high beam) lies at or below V = 0, at full current.
 * Preset files (lamp/preset.h) replace either in `hdlamp ecu --low/--high`.
 *
 * Thread-safety: pure functions of read-only data.
 */
#ifndef HL_ECU_BEAMS_H
#define HL_ECU_BEAMS_H

#include <stdbool.h>

#include "lamp/lid.h"
#include "lamp/preset.h"

/* Whether lid is the HD84 lamp by the rule above. */
bool hl_ecu_beams_is_hd84(const struct hl_lid *lid);

/* Fills low and high (n_sources floats each) for the lamp of side. 0, -ENOMEM. */
int hl_ecu_beams_default(const struct hl_lid *lid, enum hl_side side, double window_fraction,
			 float *low, float *high);

#endif
