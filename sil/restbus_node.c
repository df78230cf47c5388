/* SPDX-License-Identifier: MIT */
/* The restbus as a node of the virtual bus: see sil/restbus_node.h. */
#include "sil/restbus_node.h"

#include <errno.h>
#include <stdlib.h>

#include "world/scenario_clock.h"
#include "world/world.h"

#define MAX_PENDING 8 /* camera cycles whose frames are still on the bus */

struct pending_cycle {
	int64_t deadline_ns;
	double t_s;
	uint32_t visible;
	int frames_left;
};

struct hl_restbus_node {
	struct hl_restbus_node_config cfg;
	struct hl_vbus *bus;
	int node;
	int64_t veh_period, cam_period;
	int64_t veh_next, cam_next;
	unsigned veh_counter, veh_counter_max, cam_counter, cam_counter_max;
	struct pending_cycle pend[MAX_PENDING];
	int n_pend;
	struct hl_restbus_node_counts c;
};

int hl_restbus_node_new(const struct hl_restbus_node_config *cfg, struct hl_vbus *bus,
			struct hl_restbus_node **ret)
{
	struct hl_restbus_node *rb;
	const int n = hl_inputs_map_n_messages(cfg->map);

	if (n < 2 || hl_inputs_map_message(cfg->map, 0)->cycle_ms == 0 ||
	    hl_inputs_map_message(cfg->map, 1)->cycle_ms == 0)
		return -EINVAL;
	rb = calloc(1, sizeof(*rb));
	if (!rb)
		return -ENOMEM;
	rb->cfg = *cfg;
	rb->bus = bus;
	rb->veh_period = (int64_t)hl_inputs_map_message(cfg->map, 0)->cycle_ms * 1000000;
	rb->cam_period = (int64_t)hl_inputs_map_message(cfg->map, 1)->cycle_ms * 1000000;
	rb->veh_counter_max = hl_inputs_map_counter_max(cfg->map, 0);
	rb->cam_counter_max = hl_inputs_map_counter_max(cfg->map, 1);
	rb->node = hl_vbus_attach(bus, "restbus", NULL, NULL);
	if (rb->node < 0) {
		const int rc = rb->node;

		free(rb);
		return rc;
	}
	*ret = rb;
	return 0;
}

void hl_restbus_node_free(struct hl_restbus_node *rb)
{
	free(rb);
}

int64_t hl_restbus_node_next(const struct hl_restbus_node *rb)
{
	return rb->veh_next < rb->cam_next ? rb->veh_next : rb->cam_next;
}

int hl_restbus_node_index(const struct hl_restbus_node *rb)
{
	return rb->node;
}

/* The scenario's state at virtual time t (scenario time t, held at the end). */
static void world_at(const struct hl_restbus_node *rb, int64_t t, struct hl_world_state *w)
{
	hl_world_at(rb->cfg.sc, hl_scenario_clock_at(rb->cfg.sc, 0, t), w);
}

static bool send(struct hl_restbus_node *rb, int64_t t, const struct hl_inputs_frame *fr)
{
	if (hl_vbus_send(rb->bus, rb->node, t, fr->can_id, fr->data, fr->len, fr->fd, fr->fd) < 0) {
		rb->c.tx_full++;
		return false;
	}
	rb->c.frames_sent++;
	return true;
}

static void serve_vehicle(struct hl_restbus_node *rb, int64_t t)
{
	struct hl_world_state w;
	struct hl_vehicle_state vs;
	struct hl_inputs_frame fr;

	world_at(rb, t, &w);
	hl_restbus_vehicle(rb->cfg.sc, &w, rb->cfg.light_switch, rb->cfg.adb_enable, &vs);
	if (hl_inputs_encode_vehicle(rb->cfg.map, &vs, rb->veh_counter, &fr) < 0)
		rb->c.encode_errors++;
	else
		send(rb, t, &fr);
	rb->veh_counter = rb->veh_counter >= rb->veh_counter_max ? 0 : rb->veh_counter + 1;
	rb->c.vehicle_cycles++;
}

/* The judge is told of a camera cycle once its frames are all on the bus. */
static void camera_done(struct hl_restbus_node *rb, int64_t t_input)
{
	const struct pending_cycle *p = &rb->pend[0];

	if (rb->cfg.loop)
		hl_loop_latency_camera(rb->cfg.loop, p->deadline_ns, p->t_s, p->visible, t_input);
	rb->n_pend--;
	for (int i = 0; i < rb->n_pend; i++)
		rb->pend[i] = rb->pend[i + 1];
}

static void serve_camera(struct hl_restbus_node *rb, int64_t t)
{
	struct hl_inputs_frame fr[HL_INPUTS_MAX_CYCLE_FRAMES];
	struct hl_world_state w;
	struct hl_camera_objects o;
	struct hl_restbus_unseen un;
	struct pending_cycle p = { .deadline_ns = t };
	int n;

	world_at(rb, t, &w);
	hl_restbus_objects(rb->cfg.sc, &w, &rb->cfg.cam, hl_inputs_map_slots(rb->cfg.map), &o, &un);
	n = hl_inputs_encode_objects(rb->cfg.map, &o, rb->cam_counter, fr);
	p.t_s = w.t_s;
	for (int k = 0; n >= 0 && k < o.n; k++)
		if (o.obj[k].id >= 1 && o.obj[k].id <= 32)
			p.visible |= 1u << (o.obj[k].id - 1);
	if (n < 0)
		rb->c.encode_errors++;
	for (int k = 0; k < n; k++)
		if (send(rb, t, &fr[k]))
			p.frames_left++;
	rb->cam_counter = rb->cam_counter >= rb->cam_counter_max ? 0 : rb->cam_counter + 1;
	rb->c.camera_cycles++;
	rb->c.objects_sent += n < 0 ? 0 : (uint64_t)o.n;
	if (rb->n_pend == MAX_PENDING) /* the bus is that far behind: tell the judge now */
		camera_done(rb, t);
	rb->pend[rb->n_pend++] = p;
	if (p.frames_left == 0) /* nothing went out: the cycle's input is its deadline */
		camera_done(rb, t);
}

void hl_restbus_node_run(struct hl_restbus_node *rb, int64_t t)
{
	/* the vehicle state first, as hdlampd's restbus serves its deadlines */
	if (t == rb->veh_next) {
		serve_vehicle(rb, t);
		rb->veh_next += rb->veh_period;
	}
	if (t == rb->cam_next) {
		serve_camera(rb, t);
		rb->cam_next += rb->cam_period;
	}
}

void hl_restbus_node_delivered(struct hl_restbus_node *rb, const struct hl_vbus_frame *f)
{
	if (f->node != rb->node || rb->n_pend == 0)
		return;
	for (int i = 1; i < hl_inputs_map_n_messages(rb->cfg.map); i++)
		if (hl_inputs_map_message(rb->cfg.map, i)->msg->can_id == f->can_id) {
			if (--rb->pend[0].frames_left == 0)
				camera_done(rb, f->t_ns);
			return;
		}
}

void hl_restbus_node_counts(const struct hl_restbus_node *rb, struct hl_restbus_node_counts *ret)
{
	*ret = rb->c;
}
