/* SPDX-License-Identifier: MIT */
/*
 * The SocketCAN source: a raw CAN socket on one interface, CAN FD when the interface's MTU
 * allows it, kernel filters for the dimming messages, kernel receive timestamps on
 * CLOCK_REALTIME (and the controller's own timestamp beside them when it has one), the
 * kernel's drop counter (SO_RXQ_OVFL) and error frames for the controller state.
 *
 * An interface that goes down or disappears closes the socket (hl_can_socket_read returns
 * -ENETDOWN or -ENODEV); the owner reopens it with hl_can_socket_open after a back-off
 * (hl_can_socket_retry_ms) and receiving resumes. Nothing here exits or logs.
 *
 * Thread-safety: one thread (the CAN thread) owns a socket; hl_can_socket_stats copies
 * counters that only that thread writes, so other threads must get them through it.
 */
#ifndef HL_CAN_SOCKET_H
#define HL_CAN_SOCKET_H

#include <stdbool.h>
#include <stdint.h>

#include <linux/can.h>

enum hl_can_bus_state {
	HL_CAN_BUS_UNKNOWN, /* no error frame seen yet */
	HL_CAN_BUS_ACTIVE,
	HL_CAN_BUS_WARNING,
	HL_CAN_BUS_PASSIVE,
	HL_CAN_BUS_OFF,
};

struct hl_can_rx {
	struct canfd_frame frame; /* for a classic frame, len is its DLC (0..8) */
	bool fd; /* received as a CAN FD frame */
	bool error; /* an error frame (frame.can_id has CAN_ERR_FLAG) */
	/*
	 * When the kernel received it, CLOCK_REALTIME ns: its software receive timestamp
	 * (SO_TIMESTAMPING, or SO_TIMESTAMPNS on kernels without it), or, if the kernel gave none,
	 * the time of the read. Never the controller's clock, whose epoch and rate are its own.
	 */
	int64_t t_rx_ns;
	/* The controller's receive timestamp (SO_TIMESTAMPING raw hardware), ns on the
	 * controller's clock; 0 when the driver has none. */
	int64_t t_hw_ns;
};

struct hl_can_socket_stats {
	bool open;
	bool fd_enabled;
	enum hl_can_bus_state bus;
	uint64_t frames; /* data frames received */
	uint64_t fd_frames;
	uint64_t error_frames;
	uint64_t kernel_drops; /* SO_RXQ_OVFL, summed over reopens */
	uint64_t bus_off; /* times the controller went bus-off */
	uint64_t restarts; /* controller restarts */
	uint64_t opens; /* successful opens, the first included */
	uint64_t closes; /* interface down or gone */
};

struct hl_can_socket;

/*
 * A source for ifname receiving only the given CAN IDs (CAN_EFF_FLAG set for extended ones);
 * n_ids 0 receives every ID. Does not open yet. 0, -EINVAL (bad name or too many IDs), -ENOMEM.
 */
int hl_can_socket_new(const char *ifname, const uint32_t *ids, int n_ids,
		      struct hl_can_socket **ret);
void hl_can_socket_free(struct hl_can_socket *s);

/* Opens (or reopens) the socket. 0, -ENODEV (no such interface), -ENETDOWN (down), -errno. */
int hl_can_socket_open(struct hl_can_socket *s);
/* The socket's fd for poll(), -1 while closed. */
int hl_can_socket_fd(const struct hl_can_socket *s);
/* Milliseconds to wait before the next open attempt: 50 ms doubling to 250 ms (so a replugged
 * adapter is back well within a second); reset on success. */
int hl_can_socket_retry_ms(struct hl_can_socket *s);

/*
 * Reads one frame without blocking: 1 and *ret filled, 0 when there is none, or -errno
 * (-ENETDOWN, -ENODEV, ...) after which the socket is closed and must be reopened.
 * Error frames are returned too (ret->error) after updating the bus state.
 */
int hl_can_socket_read(struct hl_can_socket *s, struct hl_can_rx *ret);

/*
 * Sends one frame without blocking (the restbus): can_id with CAN_EFF_FLAG for an extended ID,
 * len bytes (a classic frame: 0..8; CAN FD: a valid FD length up to 64). 0, -EAGAIN or -ENOBUFS
 * when the interface's queue is full (nothing sent), -EPROTONOSUPPORT for a CAN FD frame on an
 * interface without CAN FD, -EINVAL for a bad length, or -errno (-ENETDOWN, -ENODEV, ...) after
 * which the socket is closed and must be reopened. The owner thread only.
 */
int hl_can_socket_send(struct hl_can_socket *s, uint32_t can_id, const uint8_t *data, uint8_t len,
		       bool fd);
/*
 * The kernel filter (CAN_RAW_FILTER) every open sets: its count, 0 for none (every ID passes),
 * and in *ret the filters, owned by s and fixed until hl_can_socket_free. Any thread.
 */
int hl_can_socket_filters(const struct hl_can_socket *s, const struct can_filter **ret);

void hl_can_socket_stats(const struct hl_can_socket *s, struct hl_can_socket_stats *ret);
const char *hl_can_socket_ifname(const struct hl_can_socket *s);
const char *hl_can_bus_state_name(enum hl_can_bus_state state);

#endif
