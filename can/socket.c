/* SPDX-License-Identifier: MIT */
#include "can/socket.h"
#include "can/vbus_port.h"

#include <errno.h>
#include <net/if.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <linux/errqueue.h>
#include <linux/net_tstamp.h>

#define MAX_IDS 512
#define RETRY_MIN_MS 50
#define RETRY_MAX_MS 250

struct hl_can_socket {
	char ifname[IFNAMSIZ];
	struct can_filter *filters;
	int n_filters;
	int fd;
	int retry_ms;
	uint32_t drops_at_open; /* SO_RXQ_OVFL is per socket: keep the total across reopens */
	uint64_t drops_before;
	struct hl_can_socket_stats st;
	struct hl_vbus_port *port; /* on a virtual bus registered under ifname (can/vbus_port.h) */
};

int hl_can_socket_new(const char *ifname, const uint32_t *ids, int n_ids,
		      struct hl_can_socket **ret)
{
	struct hl_can_socket *s;

	if (!ifname || !ifname[0] || strlen(ifname) >= IFNAMSIZ || n_ids < 0 || n_ids > MAX_IDS)
		return -EINVAL;
	s = calloc(1, sizeof(*s));
	if (!s)
		return -ENOMEM;
	strcpy(s->ifname, ifname);
	s->fd = -1;
	s->retry_ms = RETRY_MIN_MS;
	s->n_filters = n_ids;
	if (n_ids) {
		s->filters = calloc(n_ids, sizeof(*s->filters));
		if (!s->filters) {
			free(s);
			return -ENOMEM;
		}
	}
	for (int i = 0; i < n_ids; i++) {
		s->filters[i].can_id = ids[i];
		s->filters[i].can_mask = CAN_EFF_FLAG | CAN_RTR_FLAG |
					 ((ids[i] & CAN_EFF_FLAG) ? CAN_EFF_MASK : CAN_SFF_MASK);
	}
	*ret = s;
	return 0;
}

static void close_socket(struct hl_can_socket *s)
{
	if (s->fd < 0 || s->port) /* a virtual bus's port never goes down */
		return;
	close(s->fd);
	s->fd = -1;
	s->st.open = false;
	s->st.closes++;
	s->drops_before = s->st.kernel_drops;
	s->drops_at_open = 0;
}

void hl_can_socket_free(struct hl_can_socket *s)
{
	if (!s)
		return;
	if (s->fd >= 0 && !s->port)
		close(s->fd);
	hl_vbus_port_close(s->port);
	free(s->filters);
	free(s);
}

static int64_t timespec_ns(const struct timespec *ts)
{
	return (int64_t)ts->tv_sec * 1000000000 + ts->tv_nsec;
}

/*
 * The interface is a virtual bus of this process: a port on it takes the socket's place (its
 * eventfd the fd to poll); it is opened once and never goes down.
 */
static int open_virtual(struct hl_can_socket *s)
{
	uint32_t ids[MAX_IDS];
	int rc;

	if (s->port)
		return 0;
	for (int i = 0; i < s->n_filters; i++) {
		const uint32_t id = s->filters[i].can_id;

		ids[i] = id & CAN_EFF_FLAG ? (id & CAN_EFF_MASK) | HL_DBC_EFF_FLAG : id;
	}
	rc = hl_vbus_port_open(hl_vbus_lookup(s->ifname), "socket", ids, s->n_filters, &s->port);
	if (rc < 0)
		return rc;
	s->fd = hl_vbus_port_fd(s->port);
	s->st.open = true;
	s->st.fd_enabled = true;
	s->st.bus = HL_CAN_BUS_ACTIVE;
	s->st.opens++;
	return 0;
}

/* A frame of the virtual bus as a socket gives it: CLOCK_REALTIME receive time. */
static int read_virtual(struct hl_can_socket *s, struct hl_can_rx *ret)
{
	struct hl_vbus_frame f;
	struct timespec real, mono;

	if (hl_vbus_port_read(s->port, &f) == 0)
		return 0;
	clock_gettime(CLOCK_REALTIME, &real);
	clock_gettime(CLOCK_MONOTONIC, &mono);
	memset(ret, 0, sizeof(*ret));
	ret->frame.can_id = f.can_id & HL_DBC_EFF_FLAG ?
				    (f.can_id & ~HL_DBC_EFF_FLAG) | CAN_EFF_FLAG :
				    f.can_id;
	ret->frame.len = f.len;
	ret->frame.flags = f.brs ? CANFD_BRS : 0;
	memcpy(ret->frame.data, f.data, f.len);
	ret->fd = f.fd;
	/* the bus's time is CLOCK_MONOTONIC; the reader expects the kernel's CLOCK_REALTIME */
	ret->t_rx_ns = f.t_ns + (timespec_ns(&real) - timespec_ns(&mono));
	s->st.frames++;
	s->st.fd_frames += f.fd;
	s->st.kernel_drops = hl_vbus_port_dropped(s->port);
	return 1;
}

int hl_can_socket_open(struct hl_can_socket *s)
{
	const can_err_mask_t err_mask = CAN_ERR_TX_TIMEOUT | CAN_ERR_LOSTARB | CAN_ERR_CRTL |
					CAN_ERR_PROT | CAN_ERR_ACK | CAN_ERR_BUSOFF |
					CAN_ERR_RESTARTED;
	const int one = 1;
	const int stamping = SOF_TIMESTAMPING_RX_HARDWARE | SOF_TIMESTAMPING_RAW_HARDWARE |
			     SOF_TIMESTAMPING_RX_SOFTWARE | SOF_TIMESTAMPING_SOFTWARE;
	struct sockaddr_can addr = { .can_family = AF_CAN };
	struct ifreq ifr;
	int fd, rc;

	if (s->port || hl_vbus_lookup(s->ifname))
		return open_virtual(s);
	if (s->fd >= 0)
		close_socket(s);
	fd = socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC | SOCK_NONBLOCK, CAN_RAW);
	if (fd < 0)
		return -errno;
	memset(&ifr, 0, sizeof(ifr));
	strcpy(ifr.ifr_name, s->ifname);
	if (ioctl(fd, SIOCGIFINDEX, &ifr) < 0) {
		rc = errno == ENODEV ? -ENODEV : -errno;
		goto err_close;
	}
	addr.can_ifindex = ifr.ifr_ifindex;
	if (ioctl(fd, SIOCGIFFLAGS, &ifr) < 0) {
		rc = -errno;
		goto err_close;
	}
	if (!(ifr.ifr_flags & IFF_UP)) {
		rc = -ENETDOWN;
		goto err_close;
	}
	/* CAN FD only where the interface carries it (MTU check before enabling, as candump) */
	if (ioctl(fd, SIOCGIFMTU, &ifr) < 0) {
		rc = -errno;
		goto err_close;
	}
	s->st.fd_enabled = ifr.ifr_mtu == CANFD_MTU &&
			   setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &one, sizeof(one)) == 0;
	if ((s->n_filters && setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FILTER, s->filters,
					sizeof(*s->filters) * s->n_filters) < 0) ||
	    setsockopt(fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &err_mask, sizeof(err_mask)) < 0 ||
	    setsockopt(fd, SOL_SOCKET, SO_RXQ_OVFL, &one, sizeof(one)) < 0) {
		rc = -errno;
		goto err_close;
	}
	if (setsockopt(fd, SOL_SOCKET, SO_TIMESTAMPING, &stamping, sizeof(stamping)) < 0 &&
	    setsockopt(fd, SOL_SOCKET, SO_TIMESTAMPNS, &one, sizeof(one)) < 0) {
		rc = -errno;
		goto err_close;
	}
	if (bind(fd, (struct sockaddr *)&addr, sizeof(addr)) < 0) {
		rc = -errno;
		goto err_close;
	}
	s->fd = fd;
	s->st.open = true;
	s->st.opens++;
	s->retry_ms = RETRY_MIN_MS;
	return 0;

err_close:
	close(fd);
	return rc;
}

int hl_can_socket_fd(const struct hl_can_socket *s)
{
	return s->fd;
}

int hl_can_socket_retry_ms(struct hl_can_socket *s)
{
	const int ms = s->retry_ms;

	s->retry_ms = ms * 2 > RETRY_MAX_MS ? RETRY_MAX_MS : ms * 2;
	return ms;
}

static void track_errors(struct hl_can_socket *s, const struct canfd_frame *f)
{
	s->st.error_frames++;
	if (f->can_id & CAN_ERR_BUSOFF) {
		if (s->st.bus != HL_CAN_BUS_OFF)
			s->st.bus_off++;
		s->st.bus = HL_CAN_BUS_OFF;
	}
	if (f->can_id & CAN_ERR_RESTARTED) {
		s->st.restarts++;
		s->st.bus = HL_CAN_BUS_ACTIVE;
	}
	if ((f->can_id & CAN_ERR_CRTL) && f->len > 1) {
		const uint8_t c = f->data[1];

		if (c & (CAN_ERR_CRTL_RX_PASSIVE | CAN_ERR_CRTL_TX_PASSIVE))
			s->st.bus = HL_CAN_BUS_PASSIVE;
		else if (c & (CAN_ERR_CRTL_RX_WARNING | CAN_ERR_CRTL_TX_WARNING))
			s->st.bus = HL_CAN_BUS_WARNING;
		else if (c & CAN_ERR_CRTL_ACTIVE)
			s->st.bus = HL_CAN_BUS_ACTIVE;
	}
}

int hl_can_socket_send(struct hl_can_socket *s, uint32_t can_id, const uint8_t *data, uint8_t len,
		       bool fd)
{
	struct canfd_frame f = { .can_id = can_id, .len = len };
	const size_t mtu = fd ? CANFD_MTU : CAN_MTU;
	ssize_t n;
	int rc;

	/*
	 * CAN FD lengths above 8: 12, 16, 20, 24, 32, 48, 64, the bytes of DLC 9..15 (ISO
	 * 11898-1:2015 is not public; the table as a controller manual gives it: Microchip, "DLC
	 * Encoding", https://onlinedocs.microchip.com/oxy/GUID-E48B4A26-F201-4F0A-BCBA-16461582816A-en-US-3/GUID-A706C28E-8EC4-4CB2-AC6F-D2F0B6233CE5.html)
	 */
	if (len > (fd ? CANFD_MAX_DLEN : CAN_MAX_DLEN) ||
	    (len > 8 && len != 12 && len != 16 && len != 20 && len != 24 && len != 32 &&
	     len != 48 && len != 64))
		return -EINVAL;
	if (s->fd < 0)
		return -ENETDOWN;
	if (s->port)
		return hl_vbus_port_send(s->port,
					 can_id & CAN_EFF_FLAG ?
						 (can_id & CAN_EFF_MASK) | HL_DBC_EFF_FLAG :
						 can_id & CAN_SFF_MASK,
					 data, len, fd);
	if (fd && !s->st.fd_enabled)
		return -EPROTONOSUPPORT;
	memcpy(f.data, data, len);
	n = send(s->fd, &f, mtu, MSG_DONTWAIT);
	if (n == (ssize_t)mtu)
		return 0;
	if (n >= 0)
		return -EIO; /* a raw CAN socket sends whole frames or none */
	if (errno == EAGAIN || errno == ENOBUFS || errno == EINTR)
		return errno == ENOBUFS ? -ENOBUFS : -EAGAIN;
	rc = -errno;
	close_socket(s);
	return rc;
}

int hl_can_socket_read(struct hl_can_socket *s, struct hl_can_rx *ret)
{
	char ctrl[CMSG_SPACE(sizeof(struct scm_timestamping)) + CMSG_SPACE(sizeof(uint32_t)) +
		  CMSG_SPACE(sizeof(struct timespec))];
	struct iovec iov = { .iov_base = &ret->frame, .iov_len = sizeof(ret->frame) };
	struct msghdr msg = {
		.msg_iov = &iov,
		.msg_iovlen = 1,
		.msg_control = ctrl,
		.msg_controllen = sizeof(ctrl),
	};
	ssize_t n;
	int rc;

	if (s->fd < 0)
		return -ENETDOWN;
	if (s->port)
		return read_virtual(s, ret);
	n = recvmsg(s->fd, &msg, MSG_DONTWAIT);
	if (n < 0) {
		if (errno == EAGAIN || errno == EINTR)
			return 0;
		rc = -errno;
		close_socket(s);
		return rc;
	}
	/* The frame type is told apart by the byte count, as candump does. */
	if (n == CAN_MTU) {
		ret->fd = false;
	} else if (n == CANFD_MTU) {
		ret->fd = true;
	} else {
		return 0; /* cannot happen on a CAN_RAW socket; nothing usable */
	}
	ret->t_rx_ns = 0;
	ret->t_hw_ns = 0;
	for (struct cmsghdr *c = CMSG_FIRSTHDR(&msg); c; c = CMSG_NXTHDR(&msg, c)) {
		if (c->cmsg_level != SOL_SOCKET)
			continue;
		if (c->cmsg_type == SO_RXQ_OVFL) {
			uint32_t drops;

			memcpy(&drops, CMSG_DATA(c), sizeof(drops));
			s->st.kernel_drops = s->drops_before + drops;
		} else if (c->cmsg_type == SCM_TIMESTAMPING) {
			struct scm_timestamping ts;

			memcpy(&ts, CMSG_DATA(c), sizeof(ts));
			/* ts[0]: software, CLOCK_REALTIME; ts[2]: raw hardware, the controller's */
			ret->t_rx_ns = timespec_ns(&ts.ts[0]);
			ret->t_hw_ns = timespec_ns(&ts.ts[2]);
		} else if (c->cmsg_type == SO_TIMESTAMPNS) {
			struct timespec ts;

			memcpy(&ts, CMSG_DATA(c), sizeof(ts));
			ret->t_rx_ns = timespec_ns(&ts);
		}
	}
	if (ret->t_rx_ns == 0) {
		struct timespec now;

		clock_gettime(CLOCK_REALTIME, &now);
		ret->t_rx_ns = timespec_ns(&now);
	}
	ret->error = (ret->frame.can_id & CAN_ERR_FLAG) != 0;
	if (ret->error) {
		track_errors(s, &ret->frame);
		return 1;
	}
	s->st.frames++;
	s->st.fd_frames += ret->fd;
	return 1;
}

int hl_can_socket_filters(const struct hl_can_socket *s, const struct can_filter **ret)
{
	*ret = s->filters;
	return s->n_filters;
}

void hl_can_socket_stats(const struct hl_can_socket *s, struct hl_can_socket_stats *ret)
{
	*ret = s->st;
}

const char *hl_can_socket_ifname(const struct hl_can_socket *s)
{
	return s->ifname;
}

const char *hl_can_bus_state_name(enum hl_can_bus_state state)
{
	switch (state) {
	case HL_CAN_BUS_ACTIVE:
		return "error-active";
	case HL_CAN_BUS_WARNING:
		return "error-warning";
	case HL_CAN_BUS_PASSIVE:
		return "error-passive";
	case HL_CAN_BUS_OFF:
		return "bus-off";
	default:
		return "unknown";
	}
}
