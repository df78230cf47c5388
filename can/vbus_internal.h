/* SPDX-License-Identifier: MIT */
/*
 * Shared by the files of the virtual bus (can/vbus.c, can/vbus_wire.c, can/vbus_trace.c): the
 * frame checks of the wire model and the traces. Not a module of its own: it extends can/vbus.h.
 *
 * Thread-safety: the traces belong to the thread that drives the bus.
 */
#ifndef HL_CAN_VBUS_INTERNAL_H
#define HL_CAN_VBUS_INTERNAL_H

#include <stdbool.h>
#include <stdint.h>

#include "can/vbus.h"

/* The DLC of a payload length (0..8; FD also 12..64 as 9..15), -1 for no DLC. */
int hl_vbus_dlc(uint8_t len, bool fd);
/* A standard ID <= 0x7FF, or an extended one (HL_DBC_EFF_FLAG) <= 0x1FFFFFFF. */
bool hl_vbus_id_valid(uint32_t can_id);
/* The frame's arbitration bits as one number: the lower wins the bus. */
uint64_t hl_vbus_arbitration_key(uint32_t can_id);

struct hl_vbus_trace;

/*
 * Opens a trace by its extension (".log": candump -L, ".blf": Vector BLF); now_ns: the bus's
 * time, for BLF's start time. 0, -EINVAL (another extension), -errno from the file.
 */
int hl_vbus_trace_open(const char *path, const char *iface, int64_t epoch_ns, int64_t now_ns,
		       struct hl_vbus_trace **ret);
/* Whether the trace writes candump -L lines (else BLF). */
bool hl_vbus_trace_is_log(const struct hl_vbus_trace *t);
/* Writes one frame. 0 or -errno. */
int hl_vbus_trace_write(struct hl_vbus_trace *t, const struct hl_vbus_frame *f, int64_t frame_ns,
			unsigned bits);
/* Flushes, completes BLF's header and closes; 0 or the first -errno. NULL is fine. */
int hl_vbus_trace_close(struct hl_vbus_trace *t);

#endif
