/* SPDX-License-Identifier: MIT */
/*
 * The ECU as a node of the virtual bus (docs/sil.md, "The ECU in the loop"): the reference ECU
 * in process (ecu/lighting.h) or an FMI 2.0 FMU (fmu/fmu.h), behind the same communication
 * stack. It receives the input database's frames from the bus (can/inputs.h: decoded,
 * E2E-checked, camera cycles assembled), keeps the ECU's named inputs (ecu/io.h) up to date,
 * and at every step of its period computes the cycle — the reference ECU through ecu/io.h's
 * model side, the FMU through fmi2DoStep — and sends both lamps' dimming frames through the
 * lamp database's encoder (E2E alive counter stepping once per cycle, the profile's CRC) onto
 * the bus, as `hdlamp ecu` does on SocketCAN, with its faults: late (every cycle sent that
 * much after its step), stuck-counter, bad-crc.
 *
 * Thread-safety: a node belongs to the thread that drives its bus (in virtual time `hdlamp
 * sil`'s loop, in real time can/vbus_rt.h's thread).
 */
#ifndef HL_ECU_NODE_H
#define HL_ECU_NODE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "can/assembler.h"
#include "can/inputs.h"
#include "can/vbus.h"
#include "ecu/lighting.h"
#include "lamp/lid.h"

struct hl_ecu_node_config {
	const char *ecu; /* "reference", or the path of an FMU */
	const struct hl_ecu_config *ref; /* the reference ECU's options (its faults included) */
	int n_lamps; /* 2 */
	struct hl_lid *const *lids; /* the lamps' LIDs: the names of the outputs, the reference's */
	const char *const *lamp_names;
	const struct hl_inputs_map *map; /* the input database */
	const struct hl_assembler *a; /* the lamp database's encoder */
	int64_t period_ns; /* 20 ms */
	int64_t start_ns; /* its first step, on the bus's clock (0 in virtual time) */
	int late_ms; /* the late fault, 0: none */
	bool stuck_counter, bad_crc;
	FILE *log;
};

#define HL_ECU_NODE_MAX_LATE_MS 10000

/*
 * One fault by name, as `hdlamp ecu --fault` takes them: ignore-objects and no-failsafe (the
 * reference ECU's, into ref->faults), late=MS (1..HL_ECU_NODE_MAX_LATE_MS), stuck-counter,
 * bad-crc (the node's, for any ECU). 0 or -EINVAL.
 */
int hl_ecu_node_fault(const char *name, struct hl_ecu_node_config *cfg, struct hl_ecu_config *ref);
/* The faults' names for an error message. */
#define HL_ECU_NODE_FAULTS \
	"ignore-objects, no-failsafe, late=MS (1..10000), stuck-counter or bad-crc"

struct hl_ecu_node_counts {
	uint64_t steps;
	uint64_t frames_sent, tx_errors;
	uint64_t rx_frames;
	uint64_t failsafe_steps; /* the reference ECU: steps in the fail-safe */
	struct hl_inputs_counters inputs;
};

struct hl_ecu_node;

/* 0, or -errno with err naming the file, variable or option. */
int hl_ecu_node_new(const struct hl_ecu_node_config *cfg, struct hl_vbus *bus,
		    struct hl_ecu_node **ret, char *err, size_t err_size);
void hl_ecu_node_free(struct hl_ecu_node *n);

/* The time of its next step (the first at start_ns; then every period). */
int64_t hl_ecu_node_next_step(const struct hl_ecu_node *n);
/* The time its next late cycle goes out, INT64_MAX: none pending. */
int64_t hl_ecu_node_next_send(const struct hl_ecu_node *n);
/*
 * Runs what is due at t: the step (hl_ecu_node_next_step() == t) and the sends due. 0, or -EIO
 * / -EPIPE / -ETIMEDOUT from the FMU with err saying what (the run must end).
 */
int hl_ecu_node_run(struct hl_ecu_node *n, int64_t t, char *err, size_t err_size);

void hl_ecu_node_counts(const struct hl_ecu_node *n, struct hl_ecu_node_counts *ret);
/* "reference" or the FMU's file name. */
const char *hl_ecu_node_name(const struct hl_ecu_node *n);

#endif
