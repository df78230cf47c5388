/* SPDX-License-Identifier: MIT */
/* A port of the virtual bus for SocketCAN code: see can/vbus_port.h. */
#include "can/vbus_port.h"

#include <errno.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/eventfd.h>
#include <time.h>
#include <unistd.h>

#define MAX_BUSES 4

static pthread_mutex_t reg_lock = PTHREAD_MUTEX_INITIALIZER;
static struct {
	char name[32];
	struct hl_vbus *bus;
} reg[MAX_BUSES];

int hl_vbus_register(const char *name, struct hl_vbus *b)
{
	int free_slot = -1, rc = 0;

	if (!name || !name[0] || strlen(name) >= sizeof(reg[0].name) || !b)
		return -EINVAL;
	pthread_mutex_lock(&reg_lock);
	for (int i = 0; i < MAX_BUSES; i++) {
		if (reg[i].bus && strcmp(reg[i].name, name) == 0)
			rc = -EEXIST;
		if (!reg[i].bus && free_slot < 0)
			free_slot = i;
	}
	if (rc == 0 && free_slot < 0)
		rc = -ENOSPC;
	if (rc == 0) {
		strcpy(reg[free_slot].name, name);
		reg[free_slot].bus = b;
	}
	pthread_mutex_unlock(&reg_lock);
	return rc;
}

void hl_vbus_unregister(const char *name)
{
	pthread_mutex_lock(&reg_lock);
	for (int i = 0; i < MAX_BUSES; i++)
		if (reg[i].bus && strcmp(reg[i].name, name) == 0)
			reg[i].bus = NULL;
	pthread_mutex_unlock(&reg_lock);
}

struct hl_vbus *hl_vbus_lookup(const char *name)
{
	struct hl_vbus *b = NULL;

	pthread_mutex_lock(&reg_lock);
	for (int i = 0; i < MAX_BUSES; i++)
		if (reg[i].bus && strcmp(reg[i].name, name) == 0)
			b = reg[i].bus;
	pthread_mutex_unlock(&reg_lock);
	return b;
}

struct hl_vbus_port {
	struct hl_vbus *bus;
	int node;
	int efd;
	uint32_t *ids;
	int n_ids;
	pthread_mutex_t lock;
	struct hl_vbus_frame *q;
	unsigned head, len;
	uint64_t dropped;
};

static bool wanted(const struct hl_vbus_port *p, uint32_t can_id)
{
	if (p->n_ids == 0)
		return true;
	for (int i = 0; i < p->n_ids; i++)
		if (p->ids[i] == can_id)
			return true;
	return false;
}

/* The driving thread's delivery. */
static void receive(void *ctx, const struct hl_vbus_frame *f)
{
	struct hl_vbus_port *p = ctx;
	const uint64_t one = 1;

	if (!wanted(p, f->can_id))
		return;
	pthread_mutex_lock(&p->lock);
	if (p->len == HL_VBUS_PORT_QUEUE) {
		p->dropped++;
	} else {
		p->q[(p->head + p->len) % HL_VBUS_PORT_QUEUE] = *f;
		if (p->len++ == 0 && write(p->efd, &one, sizeof(one)) < 0)
			p->dropped += 0; /* the counter cannot overflow at one per empty queue */
	}
	pthread_mutex_unlock(&p->lock);
}

int hl_vbus_port_open(struct hl_vbus *b, const char *owner, const uint32_t *ids, int n_ids,
		      struct hl_vbus_port **ret)
{
	struct hl_vbus_port *p = calloc(1, sizeof(*p));
	int rc;

	if (!p)
		return -ENOMEM;
	p->bus = b;
	p->q = calloc(HL_VBUS_PORT_QUEUE, sizeof(*p->q));
	p->ids = n_ids ? calloc((size_t)n_ids, sizeof(*p->ids)) : NULL;
	p->efd = eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
	if (!p->q || (n_ids && !p->ids) || p->efd < 0) {
		rc = p->efd < 0 ? -errno : -ENOMEM;
		goto fail;
	}
	if (n_ids)
		memcpy(p->ids, ids, sizeof(*ids) * (size_t)n_ids);
	p->n_ids = n_ids;
	pthread_mutex_init(&p->lock, NULL);
	rc = hl_vbus_attach(b, owner, receive, p);
	if (rc < 0) {
		pthread_mutex_destroy(&p->lock);
		goto fail;
	}
	p->node = rc;
	*ret = p;
	return 0;
fail:
	if (p->efd >= 0)
		close(p->efd);
	free(p->ids);
	free(p->q);
	free(p);
	return rc;
}

void hl_vbus_port_close(struct hl_vbus_port *p)
{
	if (!p)
		return;
	hl_vbus_detach(p->bus, p->node);
	pthread_mutex_destroy(&p->lock);
	close(p->efd);
	free(p->ids);
	free(p->q);
	free(p);
}

int hl_vbus_port_fd(const struct hl_vbus_port *p)
{
	return p->efd;
}

int hl_vbus_port_read(struct hl_vbus_port *p, struct hl_vbus_frame *ret)
{
	uint64_t v;
	int got = 0;

	pthread_mutex_lock(&p->lock);
	if (p->len) {
		*ret = p->q[p->head];
		p->head = (p->head + 1) % HL_VBUS_PORT_QUEUE;
		p->len--;
		got = 1;
	}
	if (p->len == 0 && read(p->efd, &v, sizeof(v)) < 0)
		v = 0; /* nothing to reset: EAGAIN */
	pthread_mutex_unlock(&p->lock);
	return got;
}

int hl_vbus_port_send(struct hl_vbus_port *p, uint32_t can_id, const uint8_t *data, uint8_t len,
		      bool fd)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return hl_vbus_send(p->bus, p->node, (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec, can_id,
			    data, len, fd, fd);
}

uint64_t hl_vbus_port_dropped(const struct hl_vbus_port *p)
{
	return p->dropped;
}
