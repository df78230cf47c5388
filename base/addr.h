/* SPDX-License-Identifier: MIT */
/*
 * Address parsing shared by the daemon's listeners and senders (HTTP, the frame stream's TCP
 * socket, the pose input, the configuration's checks).
 *
 * Thread-safety: any thread (getaddrinfo is thread-safe).
 */
#ifndef HL_BASE_ADDR_H
#define HL_BASE_ADDR_H

#include <stdbool.h>
#include <sys/socket.h>

/*
 * Parses "HOST:PORT": HOST an IPv4 address, [IPv6] or localhost (the only name looked up),
 * PORT 0..65535. 0 or -EINVAL. ret_loopback (may be NULL): the address is a loopback one
 * (127.0.0.0/8, ::1); the daemon may warn when it is not.
 */
int hl_addr_parse(const char *listen, struct sockaddr_storage *ret_addr, bool *ret_loopback);

#endif
