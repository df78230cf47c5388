/* SPDX-License-Identifier: MIT */
/*
 * hdlamp ecu on the bus (docs/ecu.md): runs the lighting functions of an hl_ecu every 20 ms on
 * CLOCK_MONOTONIC deadlines, with the inputs received from SocketCAN and decoded by can/inputs.c,
 * and sends the dimming frames of lamps 0 and 1 of an assembler's database (its encoder: the E2E
 * alive counter steps once per cycle, every part carries it, the profile's CRC). Prints JSON
 * lines on stdout: start, mode (at each change of the mode or the fail-safe's reasons) and
 * summary; errors on stderr as "hdlamp ecu: ...".
 */
#ifndef HL_TOOLS_ECU_BUS_H
#define HL_TOOLS_ECU_BUS_H

#include <stdbool.h>

#include "can/assembler.h"
#include "can/inputs.h"
#include "ecu/lighting.h"

#define HL_ECU_BUS_MAX_LATE_MS 10000

struct hl_ecu_bus_opts {
	const char *iface;
	int late_ms; /* the late fault: every cycle sent this much after its deadline, 0: none */
	bool stuck_counter; /* the stuck-counter fault: the alive counter never steps */
	bool bad_crc; /* the bad-crc fault: every frame's CRC wrong */
	long long cycles; /* stop after this many cycles, 0: at SIGINT or SIGTERM */
};

/*
 * Opens the sockets on o->iface and runs until SIGINT/SIGTERM or o->cycles; cfg is the
 * configuration e was made with (its timeouts are printed). Blocks SIGINT and SIGTERM for
 * the calling thread. Returns 0 after a clean stop (the summary printed), or -errno (printed).
 */
int hl_ecu_bus_run(const struct hl_ecu_bus_opts *o, const struct hl_ecu_config *cfg,
		   struct hl_assembler *a, const struct hl_inputs_map *map,
		   struct hl_inputs_decoder *dec, struct hl_ecu *e);

#endif
