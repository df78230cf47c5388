/* SPDX-License-Identifier: MIT */
/*
 * The virtual bus: per-node transmit FIFOs, arbitration at the instant the bus is free, and
 * delivery in end order (docs/sil.md, "The virtual bus"). The wire of each frame comes from
 * hl_vbus_wire() (can/vbus_wire.c), worked out once when the frame is queued.
 *
 * Locking: lock guards the queues, the counts and now; the driving thread takes it to choose
 * and take the next frame and lets go of it before the receive callbacks and the traces run.
 */
#include "can/vbus.h"
#include "can/vbus_internal.h"

#include <errno.h>
#include <net/if.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#define MAX_BITRATE 16000000 /* bit/s */

struct pending {
	struct hl_vbus_frame f;
	int64_t ready_ns;
	int64_t ns; /* SOF to the end of EOF */
	int64_t ns_ifs; /* with intermission */
	unsigned bits, stuff;
	uint64_t key; /* arbitration bits */
};

struct node {
	hl_vbus_rx_fn rx;
	void *ctx;
	struct pending *q; /* HL_VBUS_QUEUE slots, a ring */
	unsigned head, count;
};

struct hl_vbus {
	pthread_mutex_t lock;
	uint32_t bitrate, data_bitrate;
	char name[IFNAMSIZ];
	int64_t now_ns;
	int64_t free_ns; /* when the bus can carry the next SOF */
	struct node node[HL_VBUS_MAX_NODES];
	struct hl_vbus_counts counts;
	struct hl_vbus_trace *log, *blf; /* the driving thread's */
	void (*notify)(void *ctx); /* told of every accepted send (hl_vbus_set_notify) */
	void *notify_ctx;
};

int hl_vbus_new(const struct hl_vbus_config *cfg, struct hl_vbus **ret)
{
	const char *name = cfg && cfg->name ? cfg->name : "vbus0";
	struct hl_vbus *b;
	pthread_mutexattr_t a;
	int rc;

	b = calloc(1, sizeof(*b));
	if (!b)
		return -ENOMEM;
	b->bitrate = cfg && cfg->bitrate ? cfg->bitrate : HL_VBUS_DEFAULT_BITRATE;
	b->data_bitrate = cfg && cfg->data_bitrate ? cfg->data_bitrate :
						     HL_VBUS_DEFAULT_DATA_BITRATE;
	if (b->bitrate > MAX_BITRATE || b->data_bitrate > MAX_BITRATE || !name[0] ||
	    strlen(name) >= sizeof(b->name)) {
		free(b);
		return -EINVAL;
	}
	strcpy(b->name, name);
	/* Priority inheritance, as the project's other locks shared with real-time threads. */
	rc = pthread_mutexattr_init(&a);
	if (rc == 0) {
		rc = pthread_mutexattr_setprotocol(&a, PTHREAD_PRIO_INHERIT);
		if (rc == 0)
			rc = pthread_mutex_init(&b->lock, &a);
		pthread_mutexattr_destroy(&a);
	}
	if (rc) {
		free(b);
		return -rc;
	}
	*ret = b;
	return 0;
}

void hl_vbus_free(struct hl_vbus *b)
{
	if (!b)
		return;
	hl_vbus_trace_close(b->log);
	hl_vbus_trace_close(b->blf);
	for (int i = 0; i < b->counts.n_nodes; i++)
		free(b->node[i].q);
	pthread_mutex_destroy(&b->lock);
	free(b);
}

int hl_vbus_attach(struct hl_vbus *b, const char *name, hl_vbus_rx_fn rx, void *ctx)
{
	struct pending *q;
	int i;

	if (!name || strlen(name) >= sizeof(b->counts.node[0].name))
		return -EINVAL;
	q = calloc(HL_VBUS_QUEUE, sizeof(*q));
	if (!q)
		return -ENOMEM;
	pthread_mutex_lock(&b->lock);
	i = b->counts.n_nodes;
	if (i == HL_VBUS_MAX_NODES) {
		pthread_mutex_unlock(&b->lock);
		free(q);
		return -ENOSPC;
	}
	b->node[i] = (struct node){ .rx = rx, .ctx = ctx, .q = q };
	strcpy(b->counts.node[i].name, name);
	b->counts.n_nodes = i + 1;
	pthread_mutex_unlock(&b->lock);
	return i;
}

int hl_vbus_send(struct hl_vbus *b, int node, int64_t t_ns, uint32_t can_id, const uint8_t *data,
		 uint8_t len, bool fd, bool brs)
{
	struct pending p = { .f = { .can_id = can_id, .len = len, .fd = fd, .brs = brs } };
	void (*notify)(void *ctx);
	void *notify_ctx;
	struct node *n;
	int64_t ns;

	ns = hl_vbus_wire(can_id, data, len, fd, brs, b->bitrate, b->data_bitrate, &p.bits,
			  &p.stuff, &p.ns_ifs);
	if (ns < 0)
		return -EINVAL;
	p.ns = ns;
	p.key = hl_vbus_arbitration_key(can_id);
	p.f.node = node;
	if (len)
		memcpy(p.f.data, data, len);
	pthread_mutex_lock(&b->lock);
	if (node < 0 || node >= b->counts.n_nodes) {
		pthread_mutex_unlock(&b->lock);
		return -EINVAL;
	}
	n = &b->node[node];
	if (n->count == HL_VBUS_QUEUE) {
		b->counts.node[node].queue_full++;
		pthread_mutex_unlock(&b->lock);
		return -ENOBUFS;
	}
	p.ready_ns = t_ns > b->now_ns ? t_ns : b->now_ns;
	n->q[(n->head + n->count) % HL_VBUS_QUEUE] = p;
	n->count++;
	notify = b->notify;
	notify_ctx = b->notify_ctx;
	pthread_mutex_unlock(&b->lock);
	if (notify)
		notify(notify_ctx);
	return 0;
}

void hl_vbus_set_notify(struct hl_vbus *b, void (*fn)(void *ctx), void *ctx)
{
	pthread_mutex_lock(&b->lock);
	b->notify = fn;
	b->notify_ctx = ctx;
	pthread_mutex_unlock(&b->lock);
}

/*
 * The frame the bus carries next (lock held): the earliest head of a queue fixes when the bus
 * is next contended, max(its ready time, the free bus); every head ready by then competes and
 * the lowest arbitration field wins, equal fields by node index (a real bus would see two
 * transmitters of one ID as an error; here the lower node goes first). -1 when none pending.
 */
static int pick(const struct hl_vbus *b, int64_t *ret_start)
{
	int64_t first = INT64_MAX, start;
	int win = -1;

	for (int i = 0; i < b->counts.n_nodes; i++)
		if (b->node[i].count && b->node[i].q[b->node[i].head].ready_ns < first)
			first = b->node[i].q[b->node[i].head].ready_ns;
	if (first == INT64_MAX)
		return -1;
	start = first > b->free_ns ? first : b->free_ns;
	for (int i = 0; i < b->counts.n_nodes; i++) {
		const struct pending *p = &b->node[i].q[b->node[i].head];

		if (!b->node[i].count || p->ready_ns > start)
			continue;
		if (win < 0 || p->key < b->node[win].q[b->node[win].head].key)
			win = i;
	}
	*ret_start = start;
	return win;
}

int64_t hl_vbus_next(struct hl_vbus *b)
{
	int64_t start, end = INT64_MAX;
	int win;

	pthread_mutex_lock(&b->lock);
	win = pick(b, &start);
	if (win >= 0)
		end = start + b->node[win].q[b->node[win].head].ns;
	pthread_mutex_unlock(&b->lock);
	return end;
}

/* Takes the winner off its queue and books the bus (lock held). */
static void take(struct hl_vbus *b, int win, int64_t start, struct pending *ret)
{
	struct node *n = &b->node[win];
	struct hl_vbus_node_counts *c = &b->counts.node[win];

	*ret = n->q[n->head];
	n->head = (n->head + 1) % HL_VBUS_QUEUE;
	n->count--;
	for (int i = 0; i < b->counts.n_nodes; i++)
		if (i != win && b->node[i].count && b->node[i].q[b->node[i].head].ready_ns <= start)
			b->counts.node[i].arbitration_lost++;
	ret->f.t_start_ns = start;
	ret->f.t_ns = start + ret->ns;
	c->sent++;
	if (start - ret->ready_ns > c->max_wait_ns)
		c->max_wait_ns = start - ret->ready_ns;
	for (int i = 0; i < b->counts.n_nodes; i++)
		if (i != win)
			b->counts.node[i].received++;
	b->counts.frames++;
	b->counts.bits += ret->bits;
	b->counts.stuff_bits += ret->stuff;
	b->counts.busy_ns += ret->ns_ifs;
	b->free_ns = start + ret->ns_ifs;
}

static void trace(struct hl_vbus *b, struct hl_vbus_trace *t, const struct pending *p)
{
	if (t && hl_vbus_trace_write(t, &p->f, p->ns, p->bits) < 0) {
		pthread_mutex_lock(&b->lock);
		b->counts.trace_errors++;
		pthread_mutex_unlock(&b->lock);
	}
}

void hl_vbus_run_until(struct hl_vbus *b, int64_t t_ns)
{
	for (;;) {
		struct pending p;
		hl_vbus_rx_fn rx[HL_VBUS_MAX_NODES];
		void *ctx[HL_VBUS_MAX_NODES];
		int64_t start;
		int win;

		pthread_mutex_lock(&b->lock);
		win = pick(b, &start);
		if (win < 0 || start + b->node[win].q[b->node[win].head].ns > t_ns) {
			if (t_ns > b->now_ns)
				b->now_ns = t_ns;
			pthread_mutex_unlock(&b->lock);
			return;
		}
		take(b, win, start, &p);
		for (int i = 0; i < HL_VBUS_MAX_NODES; i++) { /* as attached now (hl_vbus_detach) */
			rx[i] = i != win ? b->node[i].rx : NULL;
			ctx[i] = b->node[i].ctx;
		}
		pthread_mutex_unlock(&b->lock);
		for (int i = 0; i < HL_VBUS_MAX_NODES; i++)
			if (rx[i])
				rx[i](ctx[i], &p.f);
		trace(b, b->log, &p);
		trace(b, b->blf, &p);
	}
}

void hl_vbus_detach(struct hl_vbus *b, int node)
{
	pthread_mutex_lock(&b->lock);
	if (node >= 0 && node < b->counts.n_nodes) {
		b->node[node].rx = NULL;
		b->node[node].ctx = NULL;
	}
	pthread_mutex_unlock(&b->lock);
}

int64_t hl_vbus_now(const struct hl_vbus *b)
{
	return b->now_ns; /* written by the driving thread only, the one that may call this */
}

static bool ends_with(const char *s, const char *suffix)
{
	size_t n = strlen(s), k = strlen(suffix);

	return n >= k && strcmp(s + n - k, suffix) == 0;
}

int hl_vbus_trace(struct hl_vbus *b, const char *path, int64_t epoch_ns)
{
	struct hl_vbus_trace **slot;

	if (ends_with(path, ".log"))
		slot = &b->log;
	else if (ends_with(path, ".blf"))
		slot = &b->blf;
	else
		return -EINVAL;
	if (*slot)
		return -EEXIST;
	return hl_vbus_trace_open(path, b->name, epoch_ns, b->now_ns, slot);
}

void hl_vbus_counts(struct hl_vbus *b, struct hl_vbus_counts *ret)
{
	pthread_mutex_lock(&b->lock);
	*ret = b->counts;
	pthread_mutex_unlock(&b->lock);
}
