/* SPDX-License-Identifier: MIT */
/*
 * A virtual CAN bus (docs/sil.md, "The virtual bus"): the bus of software in the loop, a bus of
 * its own in this process, not SocketCAN and not vcan. Nodes attach to it and send frames, each
 * the byte string that would be on the wire (the caller encodes it through its database, E2E
 * CRC and alive counter included); the bus carries them on a virtual clock (ns, the caller's):
 *
 *   - a classic frame takes its wire time at the configured bit rate (default 500 kbit/s):
 *     SOF, arbitration, control, data, CRC-15 with the bit stuffing counted on the frame's real
 *     bits (a stuff bit after five equal bits, from SOF to the end of the CRC sequence), then
 *     the CRC delimiter, ACK slot and delimiter, 7 EOF bits (never stuffed) and the 3 bits of
 *     intermission before the next frame can start;
 *   - a CAN FD frame runs its arbitration phase at the nominal rate and, with bit-rate switch,
 *     its data phase (from the BRS bit to the CRC delimiter) at the data rate; FD's fixed stuff
 *     bits in the CRC field and the stuff count are counted as ISO 11898-1:2015 places them;
 *   - when the bus is free and several frames are pending, the lowest arbitration field wins
 *     (ID by ID bit by bit as on the wire: a standard frame beats an extended one with the same
 *     11 base bits); the others wait for the next free bus, and the losses are counted;
 *   - a node's own frames keep their order (one transmit queue per node, as one controller's
 *     mailbox FIFO).
 * A frame's time stamp is the end of its EOF: when a receiver has it (as the kernel stamps it).
 * Every frame is delivered to every other attached node, in the order they end, through the
 * node's receive callback, and written to the open traces (candump -L and Vector BLF).
 *
 * Thread-safety: one thread drives a bus (hl_vbus_run_until); hl_vbus_send() may be called from
 * any thread (a mutex guards the queues); receive callbacks run on the driving thread, must
 * not call back into the bus and should only store the frame.
 */
#ifndef HL_CAN_VBUS_H
#define HL_CAN_VBUS_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "dbc/database.h"

#define HL_VBUS_MAX_NODES 8
#define HL_VBUS_QUEUE 256 /* frames a node may have pending; more: -ENOBUFS, counted */
#define HL_VBUS_DEFAULT_BITRATE 500000
#define HL_VBUS_DEFAULT_DATA_BITRATE 2000000

struct hl_vbus_config {
	uint32_t bitrate; /* nominal, bit/s; 0: 500 kbit/s */
	uint32_t data_bitrate; /* CAN FD data phase with BRS, bit/s; 0: 2 Mbit/s */
	const char *name; /* the interface name the traces give ("vbus0" if NULL) */
};

/* A frame on the bus. can_id carries HL_DBC_EFF_FLAG for an extended ID. */
struct hl_vbus_frame {
	int64_t t_ns; /* end of frame: when the receivers have it */
	int64_t t_start_ns; /* start of frame (SOF) */
	uint32_t can_id;
	uint8_t len; /* payload bytes: 0..8 classic, an FD length 0..64 */
	bool fd;
	bool brs; /* FD with bit-rate switch */
	int node; /* the sender */
	uint8_t data[64];
};

typedef void (*hl_vbus_rx_fn)(void *ctx, const struct hl_vbus_frame *f);

struct hl_vbus_node_counts {
	char name[32];
	uint64_t sent; /* frames that completed on the bus */
	uint64_t received; /* frames of the other nodes carried while attached */
	uint64_t arbitration_lost; /* times a pending frame lost to a lower ID */
	uint64_t queue_full; /* sends refused: HL_VBUS_QUEUE frames pending */
	int64_t max_wait_ns; /* longest time from ready to start of frame */
};

struct hl_vbus_counts {
	uint64_t frames;
	uint64_t bits; /* on the wire, stuff bits and intermission included */
	uint64_t stuff_bits;
	int64_t busy_ns; /* time the bus carried frames, intermission included */
	int n_nodes;
	struct hl_vbus_node_counts node[HL_VBUS_MAX_NODES];
	uint64_t trace_errors; /* trace writes that failed (the caller logs from the count) */
};

struct hl_vbus;

/* 0, -EINVAL (a bit rate of 0 after defaults, or over 16 Mbit/s), -ENOMEM. */
int hl_vbus_new(const struct hl_vbus_config *cfg, struct hl_vbus **ret);
/* Closes the traces (flushed, BLF's header completed) and frees. */
void hl_vbus_free(struct hl_vbus *b);

/* Attaches a node (rx may be NULL: it only sends). Its index >= 0, or -ENOSPC, -EINVAL. */
int hl_vbus_attach(struct hl_vbus *b, const char *name, hl_vbus_rx_fn rx, void *ctx);

/*
 * The node receives nothing more (its slot stays taken; what it queued is still sent). A
 * delivery that has begun on the driving thread may still reach it: free its context only when
 * the bus is not driven, or from the driving thread.
 */
void hl_vbus_detach(struct hl_vbus *b, int node);

/*
 * Node node queues a frame ready at t_ns (it may not start before; a t_ns earlier than the
 * bus's current time means "now"). 0, -EINVAL (a bad node, length or an FD length that is no
 * DLC), -ENOBUFS (the node's queue is full, counted).
 */
int hl_vbus_send(struct hl_vbus *b, int node, int64_t t_ns, uint32_t can_id, const uint8_t *data,
		 uint8_t len, bool fd, bool brs);

/* When the next frame ends (its t_ns), INT64_MAX when nothing is pending. */
int64_t hl_vbus_next(struct hl_vbus *b);
/* Carries every frame that ends at or before t_ns, delivering each; the bus's time is t_ns. */
void hl_vbus_run_until(struct hl_vbus *b, int64_t t_ns);
int64_t hl_vbus_now(const struct hl_vbus *b);

/*
 * Writes every frame from now on to path: candump -L lines (".log", time = t_ns as seconds
 * since epoch_ns + t_ns) or Vector BLF (".blf", objects CAN_MESSAGE2 / CAN_FD_MESSAGE_64 in
 * uncompressed log containers, on channel 1). At most one trace of each kind. 0, -EINVAL (an
 * unknown extension), -EEXIST, -errno from opening the file (the caller names it in its log).
 */
int hl_vbus_trace(struct hl_vbus *b, const char *path, int64_t epoch_ns);

void hl_vbus_counts(struct hl_vbus *b, struct hl_vbus_counts *ret);

/*
 * fn(ctx) is called after every accepted hl_vbus_send(), from the sending thread, outside the
 * bus's lock (the real-time driver's wake-up, can/vbus_rt.h); NULL: none.
 */
void hl_vbus_set_notify(struct hl_vbus *b, void (*fn)(void *ctx), void *ctx);

/*
 * The wire of one frame at the given rates: *ret_bits every bit from SOF to the end of
 * intermission (stuff bits included), *ret_stuff the stuff bits, the frame's time in ns from
 * SOF to the end of EOF (intermission excluded) as the return value; ret_ns_ifs (may be NULL):
 * the time including intermission. -1 for a frame no bus can carry.
 */
int64_t hl_vbus_wire(uint32_t can_id, const uint8_t *data, uint8_t len, bool fd, bool brs,
		     uint32_t bitrate, uint32_t data_bitrate, unsigned *ret_bits,
		     unsigned *ret_stuff, int64_t *ret_ns_ifs);

#endif
