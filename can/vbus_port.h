/* SPDX-License-Identifier: MIT */
/*
 * A port of the virtual bus for code written for SocketCAN (docs/sil.md, "Real time"): a
 * virtual bus registered under an interface name ("vbus0") is what can/socket.h opens when
 * asked for that name, so that hdlampd's CAN input and restbus run on it unchanged. A port is a
 * node of the bus: it receives every frame of the other nodes that passes its filter into a
 * queue (HL_VBUS_PORT_QUEUE frames; more are dropped and counted, as a socket's receive buffer
 * would), readable when its eventfd is; what it sends is ready on the bus at the time of the
 * call on CLOCK_MONOTONIC: ports are for a bus driven in real time (can/vbus_rt.h).
 *
 * Thread-safety: the registry is locked; a port is read and written by one thread, and filled by
 * the thread that drives its bus.
 */
#ifndef HL_CAN_VBUS_PORT_H
#define HL_CAN_VBUS_PORT_H

#include <stdbool.h>
#include <stdint.h>

#include "can/vbus.h"

#define HL_VBUS_PORT_QUEUE 4096

/* Registers b under name (at most 4 at once). 0, -EEXIST, -ENOSPC, -EINVAL. */
int hl_vbus_register(const char *name, struct hl_vbus *b);
void hl_vbus_unregister(const char *name);
/* The bus registered under name, or NULL. */
struct hl_vbus *hl_vbus_lookup(const char *name);

struct hl_vbus_port;

/*
 * A port on b named owner, taking only the IDs ids[n_ids] (HL_DBC_EFF_FLAG for extended; none:
 * every frame). 0, -ENOSPC (the bus has no room for a node), -ENOMEM.
 */
int hl_vbus_port_open(struct hl_vbus *b, const char *owner, const uint32_t *ids, int n_ids,
		      struct hl_vbus_port **ret);
/*
 * Detaches the port (hl_vbus_detach) and frees it: while the bus is not driven, or from its
 * driving thread.
 */
void hl_vbus_port_close(struct hl_vbus_port *p);
/* Readable while frames wait (an eventfd). */
int hl_vbus_port_fd(const struct hl_vbus_port *p);
/* The oldest waiting frame: 1, or 0 when none waits. */
int hl_vbus_port_read(struct hl_vbus_port *p, struct hl_vbus_frame *ret);
/* Sends now (CLOCK_MONOTONIC). 0 or hl_vbus_send()'s -errno. */
int hl_vbus_port_send(struct hl_vbus_port *p, uint32_t can_id, const uint8_t *data, uint8_t len,
		      bool fd);
/* Frames dropped because the queue was full. */
uint64_t hl_vbus_port_dropped(const struct hl_vbus_port *p);

#endif
