/* SPDX-License-Identifier: MIT */
/*
 * One candump -L log line, the log, replay and fixture format (docs/design.md §5), as can-utils
 * writes and reads it:
 *
 *   (1436509052.249713) can0 123#11223344          classic, 11-bit ID (3 hex digits)
 *   (1436509052.249713) can0 18FEF100#0102         classic, 29-bit ID (8 hex digits)
 *   (1436509052.249713) can0 123#R  /  123#R4      remote request (optional DLC)
 *   (1436509052.249713) can0 123#1122334455667788_C  classic 8 bytes sent with DLC 12
 *   (1436509052.249713) can0 123##1<data>          CAN FD: one hex digit of flags, then data
 *   (1436509052.249713) can0 20000004#0000...      error frame (CAN_ERR_FLAG in the ID)
 *   (2.501000) can0 20000080#                      error frame without data, as python-can's
 *                                                  can.Logger writes it: DLC 0
 *
 * Data bytes are pairs of hex digits, optionally separated by '.'; an optional " R" / " T"
 * (candump -x: received / transmitted) may follow.
 *
 * Thread-safety: pure functions, any thread; nothing allocates.
 */
#ifndef HL_CAN_CANDUMP_H
#define HL_CAN_CANDUMP_H

#include <linux/can.h>
#include <net/if.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define HL_CANDUMP_MAX_LINE 256 /* longest line hl_candump_format() writes, with its NUL */

struct hl_candump_frame {
	int64_t t_us; /* timestamp, microseconds since the epoch */
	char iface[IFNAMSIZ];
	bool fd; /* CAN FD frame (frame.flags valid) */
	uint8_t len8_dlc; /* classic 8-byte frame sent with DLC 9..15, else 0 */
	char dir; /* 'R', 'T' or 0 when the line has no direction */
	struct canfd_frame frame; /* can_id with CAN_EFF_FLAG / CAN_RTR_FLAG / CAN_ERR_FLAG */
};

struct hl_candump_error {
	int column; /* 1-based */
	char msg[160];
};

/*
 * Parses a line of len bytes (a trailing "\n" or "\r\n" is allowed). 0, or -EBADMSG with the
 * column and what was expected there.
 */
int hl_candump_parse(const char *line, size_t len, struct hl_candump_frame *ret,
		     struct hl_candump_error *ret_err);
/* Formats a frame as candump -L does, without newline. Returns the length, -ENOSPC when size
 * is too small, -EINVAL for a frame no line can express. */
int hl_candump_format(const struct hl_candump_frame *f, char *buf, size_t size);

#endif
