/* SPDX-License-Identifier: MIT */
/*
 * "HOST:PORT" as every listening and sending address of hdlampd takes it (http.listen,
 * stream.tcp, the pose input's udp:HOST:PORT, config checks).
 */
#include "base/addr.h"

#include <arpa/inet.h>
#include <errno.h>
#include <netdb.h>
#include <netinet/in.h>
#include <stdlib.h>
#include <string.h>

int hl_addr_parse(const char *listen, struct sockaddr_storage *ret_addr, bool *ret_loopback)
{
	struct addrinfo hints = { .ai_socktype = SOCK_STREAM, .ai_flags = AI_NUMERICSERV };
	struct addrinfo *ai = NULL;
	char host[256], *end;
	const char *colon, *port;
	size_t n;
	long p;
	bool loop;

	if (!listen)
		return -EINVAL;
	colon = strrchr(listen, ':');
	if (!colon || colon == listen)
		return -EINVAL;
	port = colon + 1;
	errno = 0;
	p = strtol(port, &end, 10);
	if (!*port || *end || errno || p < 0 || p > 65535 || *port == '-' || *port == '+')
		return -EINVAL;
	n = (size_t)(colon - listen);
	if (listen[0] == '[') {
		if (n < 3 || listen[n - 1] != ']')
			return -EINVAL;
		memcpy(host, listen + 1, n - 2);
		host[n - 2] = '\0';
		hints.ai_family = AF_INET6;
		hints.ai_flags |= AI_NUMERICHOST;
	} else {
		if (n >= sizeof(host) || memchr(listen, ':', n))
			return -EINVAL;
		memcpy(host, listen, n);
		host[n] = '\0';
		/* Only localhost is looked up: any other name must be a literal address. */
		hints.ai_family = strcmp(host, "localhost") == 0 ? AF_INET : AF_UNSPEC;
		if (strcmp(host, "localhost") != 0)
			hints.ai_flags |= AI_NUMERICHOST;
	}
	if (getaddrinfo(host, port, &hints, &ai) != 0 || !ai)
		return -EINVAL;
	if (ai->ai_addrlen > sizeof(*ret_addr)) {
		freeaddrinfo(ai);
		return -EINVAL;
	}
	if (ai->ai_family == AF_INET) {
		const struct sockaddr_in *in = (const struct sockaddr_in *)ai->ai_addr;

		loop = (ntohl(in->sin_addr.s_addr) >> 24) == 127;
	} else {
		const struct sockaddr_in6 *in6 = (const struct sockaddr_in6 *)ai->ai_addr;

		loop = IN6_IS_ADDR_LOOPBACK(&in6->sin6_addr);
	}
	memset(ret_addr, 0, sizeof(*ret_addr));
	memcpy(ret_addr, ai->ai_addr, ai->ai_addrlen);
	freeaddrinfo(ai);
	if (ret_loopback)
		*ret_loopback = loop;
	return 0;
}
