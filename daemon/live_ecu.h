/* SPDX-License-Identifier: MIT */
/*
 * The ECU in the loop in real time (ecu.model, docs/sil.md "Real time"): the virtual bus
 * HL_CONFIG_VBUS registered for this process, so that the CAN input and the restbus open it as
 * they would a SocketCAN interface (can/vbus_port.h); the ECU — the reference or an FMU — as a
 * node of it (ecu/node.h), its steps every 20 ms on CLOCK_MONOTONIC, driven with the bus by
 * can/vbus_rt.h's thread. No CAN interface, no vcan, no kernel module.
 *
 * Thread-safety: main thread; the node runs on the bus's thread.
 */
#ifndef HL_DAEMON_LIVE_ECU_H
#define HL_DAEMON_LIVE_ECU_H

#include <stdbool.h>
#include <stdio.h>

#include "can/assembler.h"
#include "daemon/core/config.h"
#include "lamp/lid.h"

struct hl_live_ecu;

/*
 * With ecu.model set: the bus, registered (before anything opens HL_CONFIG_VBUS). *ret NULL
 * without. 0 or -errno, logged; *ret_config_error for a fault of the configuration.
 */
int hl_live_ecu_new(const struct hl_config *cfg, const char *trace, struct hl_live_ecu **ret,
		    bool *ret_config_error);
/*
 * The ECU's node on the bus for the lamps (their LIDs and the lamp database's assembler a) and
 * the input database (restbus.dbc or the shipped one), started: its first step now. 0 or -errno,
 * logged.
 */
int hl_live_ecu_start(struct hl_live_ecu *le, const struct hl_config *cfg,
		      const struct hl_assembler *a, struct hl_lid *const *lids,
		      const char *const *lamp_names, bool *ret_config_error);
/* Stops the bus's thread (first, before the CAN input and restbus that use it are freed). */
void hl_live_ecu_stop(struct hl_live_ecu *le);
/* After everything that opened the bus is gone. NULL is fine. */
void hl_live_ecu_free(struct hl_live_ecu *le);
/* The ECU's error that stopped it (an FMU's), 0 while it runs. */
int hl_live_ecu_error(struct hl_live_ecu *le);
/* What stopped it, NULL while it runs (or without one); its name ("reference", the FMU's file). */
const char *hl_live_ecu_error_text(struct hl_live_ecu *le);
const char *hl_live_ecu_name(const struct hl_live_ecu *le);
/* ,"ecu":{...} for /status and the exit summary. */
void hl_live_ecu_status_json(struct hl_live_ecu *le, FILE *f);

#endif
