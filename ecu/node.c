/* SPDX-License-Identifier: MIT */
/* The ECU as a node of the virtual bus: see ecu/node.h. */
#include "ecu/node.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ecu/beams.h"
#include "ecu/io.h"
#include "fmu/fmu.h"

/* One cycle's frames, waiting for their send time (the late fault). */
struct out_cycle {
	int64_t due_ns;
	int n[2];
	struct hl_encoded_frame frames[2][HL_ASM_MAX_PARTS];
};

struct hl_ecu_node {
	struct hl_ecu_node_config cfg;
	char name[256];
	struct hl_vbus *bus;
	int node;
	struct hl_inputs_decoder *dec;
	struct hl_ecu_io *io;
	double *in, *out;
	int n_in, n_out;
	/* the reference ECU */
	struct hl_ecu *e;
	struct hl_ecu_io_model model;
	float *beams[2][2]; /* [lamp][low, high] */
	/* or the FMU */
	struct hl_fmu *fmu;
	int *in_idx, *out_idx;
	int *set_idx; /* scratch: the FMU's indices and values of one step's inputs */
	double *set_val;
	float *fmu_out[2];
	int64_t next_step;
	unsigned counter[2];
	struct out_cycle *q;
	int q_size, q_head, q_len;
	struct hl_ecu_node_counts c;
};

int hl_ecu_node_fault(const char *name, struct hl_ecu_node_config *cfg, struct hl_ecu_config *ref)
{
	char *end;
	long ms;

	if (strcmp(name, "ignore-objects") == 0) {
		ref->faults |= HL_ECU_FAULT_IGNORE_OBJECTS;
	} else if (strcmp(name, "no-failsafe") == 0) {
		ref->faults |= HL_ECU_FAULT_NO_FAILSAFE;
	} else if (strcmp(name, "stuck-counter") == 0) {
		cfg->stuck_counter = true;
	} else if (strcmp(name, "bad-crc") == 0) {
		cfg->bad_crc = true;
	} else if (strncmp(name, "late=", 5) == 0) {
		errno = 0;
		ms = strtol(name + 5, &end, 10);
		if (errno || end == name + 5 || *end || ms < 1 || ms > HL_ECU_NODE_MAX_LATE_MS)
			return -EINVAL;
		cfg->late_ms = (int)ms;
	} else {
		return -EINVAL;
	}
	return 0;
}

/* The bus's delivery: the communication stack takes the frame into the named inputs. */
static void receive(void *ctx, const struct hl_vbus_frame *f)
{
	struct hl_ecu_node *n = ctx;
	struct hl_vehicle_state vs;
	struct hl_camera_objects ob;
	int d;

	n->c.rx_frames++;
	d = hl_inputs_decode(n->dec, f->can_id, f->data, f->len, &vs, &ob);
	if (d == HL_INPUTS_VEHICLE) {
		hl_ecu_io_set_vehicle(n->io, &vs, f->t_ns, n->in);
	} else if (d == HL_INPUTS_OBJECTS) {
		hl_ecu_io_set_objects(n->io, &ob, f->t_ns, n->in);
	} else if (d == -EBADMSG) {
		for (int i = 0; i < hl_inputs_map_n_messages(n->cfg.map); i++) {
			const struct hl_inputs_message *m = hl_inputs_map_message(n->cfg.map, i);

			if (m->msg->can_id == f->can_id)
				hl_ecu_io_set_e2e_error(n->io,
							m->kind == HL_INPUTS_VEHICLE ?
								HL_ECU_INPUT_VEHICLE :
								HL_ECU_INPUT_OBJECTS,
							n->in);
		}
	}
}

static int setup_reference(struct hl_ecu_node *n, char *err, size_t err_size)
{
	struct hl_ecu_lamp lamps[2];
	const char *what = NULL;
	int rc;

	for (int l = 0; l < n->cfg.n_lamps; l++) {
		const int ns = hl_lid_n_sources(n->cfg.lids[l]);

		for (int b = 0; b < 2; b++) {
			n->beams[l][b] = calloc((size_t)ns, sizeof(float));
			if (!n->beams[l][b])
				return -ENOMEM;
		}
		rc = hl_ecu_beams_default(n->cfg.lids[l], (enum hl_side)l,
					  n->cfg.ref->window_fraction, n->beams[l][0],
					  n->beams[l][1]);
		if (rc < 0) {
			snprintf(err, err_size, "ecu reference: the %s lamp's default beams: %s",
				 n->cfg.lamp_names[l], strerror(-rc));
			return rc;
		}
		lamps[l] = (struct hl_ecu_lamp){ .lid = n->cfg.lids[l],
						 .low = n->beams[l][0],
						 .high = n->beams[l][1] };
		/* the scenarios' default lamp poses, as hdlamp ecu mounts them (docs/ecu.md) */
		lamps[l].mount = (struct hl_ecu_mount){ .pos_m = { 0.0, l == 0 ? 0.7 : -0.7, 0.65 },
							.pitch_deg = atan(-0.01) * 180.0 / M_PI };
	}
	rc = hl_ecu_new(n->cfg.ref, lamps, n->cfg.n_lamps, &n->e, &what);
	if (rc < 0)
		snprintf(err, err_size, "ecu reference: %s%s%s", strerror(-rc), what ? ": " : "",
			 what ? what : "");
	hl_ecu_io_model_init(&n->model);
	return rc;
}

/*
 * The FMU's variables: every input it declares must be one of ours (a Real input), and every
 * lamp source must be one of its Real outputs; the others are errors that name the variable.
 */
static int setup_fmu(struct hl_ecu_node *n, char *err, size_t err_size)
{
	const struct hl_fmu_options o = { .step_s = (double)n->cfg.period_ns / 1e9,
					  .log = n->cfg.log };
	int n_fmu_in = 0, rc;

	rc = hl_fmu_open(n->cfg.ecu, 0.0, &o, &n->fmu, err, err_size);
	if (rc < 0)
		return rc;
	n->in_idx = calloc((size_t)n->n_in, sizeof(int));
	n->set_idx = calloc((size_t)n->n_in, sizeof(int));
	n->set_val = calloc((size_t)n->n_in, sizeof(double));
	if (!n->set_idx || !n->set_val)
		return -ENOMEM;
	n->out_idx = calloc((size_t)n->n_out, sizeof(int));
	if (!n->in_idx || !n->out_idx)
		return -ENOMEM;
	for (int i = 0; i < n->n_in; i++)
		n->in_idx[i] = -1;
	for (int v = 0; v < hl_fmu_n_vars(n->fmu); v++) {
		const struct hl_fmu_var *var = hl_fmu_var(n->fmu, v);
		int k;

		if (var->causality != HL_FMU_INPUT)
			continue;
		k = hl_ecu_io_input_index(n->io, var->name);
		if (k < 0) {
			snprintf(
				err, err_size,
				"'%s': input '%s' (modelDescription.xml line %d) is none of the ECU's "
				"inputs (docs/ecu.md, \"The ECU as an FMU\")",
				n->cfg.ecu, var->name, var->line);
			return -EINVAL;
		}
		if (var->type != HL_FMU_REAL) {
			snprintf(
				err, err_size,
				"'%s': input '%s' (modelDescription.xml line %d) is %s; expected Real",
				n->cfg.ecu, var->name, var->line, hl_fmu_type_name(var->type));
			return -EINVAL;
		}
		n->in_idx[k] = v;
		n_fmu_in++;
	}
	for (int k = 0; k < n->n_out; k++) {
		const char *name = hl_ecu_io_output_name(n->io, k);
		const int v = hl_fmu_find(n->fmu, name);
		const struct hl_fmu_var *var = v >= 0 ? hl_fmu_var(n->fmu, v) : NULL;

		if (!var || var->causality != HL_FMU_OUTPUT) {
			snprintf(err, err_size, "'%s': no output '%s' (the lamp's source %d)",
				 n->cfg.ecu, name, k);
			return -EINVAL;
		}
		if (var->type != HL_FMU_REAL) {
			snprintf(
				err, err_size,
				"'%s': output '%s' (modelDescription.xml line %d) is %s; expected Real",
				n->cfg.ecu, name, var->line, hl_fmu_type_name(var->type));
			return -EINVAL;
		}
		n->out_idx[k] = v;
	}
	if (n_fmu_in == 0)
		fprintf(n->cfg.log, "ecu: '%s' declares no input: it cannot see the road\n",
			n->cfg.ecu);
	return 0;
}

int hl_ecu_node_new(const struct hl_ecu_node_config *cfg, struct hl_vbus *bus,
		    struct hl_ecu_node **ret, char *err, size_t err_size)
{
	struct hl_ecu_node *n = calloc(1, sizeof(*n));
	const char *base;
	int rc;

	if (!n)
		return -ENOMEM;
	n->cfg = *cfg;
	n->bus = bus;
	n->next_step = cfg->start_ns;
	base = strrchr(cfg->ecu, '/');
	snprintf(n->name, sizeof(n->name), "%s", base ? base + 1 : cfg->ecu);
	n->q_size = cfg->late_ms / (int)(cfg->period_ns / 1000000) + 2;
	n->q = calloc((size_t)n->q_size, sizeof(*n->q));
	rc = n->q ? hl_inputs_decoder_new(cfg->map, &n->dec) : -ENOMEM;
	if (rc == 0)
		rc = hl_ecu_io_new(cfg->map, (const struct hl_lid *const *)cfg->lids,
				   cfg->lamp_names, cfg->n_lamps, &n->io, err, err_size);
	if (rc == 0) {
		n->n_in = hl_ecu_io_n_inputs(n->io);
		n->n_out = hl_ecu_io_n_outputs(n->io);
		n->in = calloc((size_t)n->n_in, sizeof(double));
		n->out = calloc((size_t)n->n_out, sizeof(double));
		rc = n->in && n->out ? 0 : -ENOMEM;
	}
	if (rc == 0) {
		hl_ecu_io_init_inputs(n->io, n->in);
		rc = strcmp(cfg->ecu, "reference") == 0 ? setup_reference(n, err, err_size) :
							  setup_fmu(n, err, err_size);
	}
	for (int l = 0; rc == 0 && l < cfg->n_lamps; l++) {
		n->fmu_out[l] = calloc((size_t)hl_ecu_io_lamp_sources(n->io, l), sizeof(float));
		if (!n->fmu_out[l])
			rc = -ENOMEM;
	}
	if (rc == 0) {
		rc = hl_vbus_attach(bus, "ecu", receive, n);
		n->node = rc;
		if (rc >= 0)
			rc = 0;
		else
			snprintf(err, err_size, "ecu: cannot attach to the bus: %s", strerror(-rc));
	}
	if (rc < 0) {
		if (rc == -ENOMEM && !err[0])
			snprintf(err, err_size, "ecu: %s", strerror(ENOMEM));
		hl_ecu_node_free(n);
		return rc;
	}
	*ret = n;
	return 0;
}

void hl_ecu_node_free(struct hl_ecu_node *n)
{
	if (!n)
		return;
	hl_fmu_close(n->fmu);
	hl_ecu_free(n->e);
	for (int l = 0; l < 2; l++) {
		free(n->beams[l][0]);
		free(n->beams[l][1]);
		free(n->fmu_out[l]);
	}
	free(n->in_idx);
	free(n->set_idx);
	free(n->set_val);
	free(n->out_idx);
	free(n->in);
	free(n->out);
	hl_ecu_io_free(n->io);
	hl_inputs_decoder_free(n->dec);
	free(n->q);
	free(n);
}

int64_t hl_ecu_node_next_step(const struct hl_ecu_node *n)
{
	return n->next_step;
}

int64_t hl_ecu_node_next_send(const struct hl_ecu_node *n)
{
	return n->q_len ? n->q[n->q_head].due_ns : INT64_MAX;
}

/* The cycle at t: the outputs into n->out. */
static int compute(struct hl_ecu_node *n, int64_t t, char *err, size_t err_size)
{
	if (n->e) {
		struct hl_ecu_status st;

		hl_ecu_io_apply(n->io, &n->model, n->in, n->e);
		hl_ecu_step(n->e, t, &st);
		if (st.failsafe)
			n->c.failsafe_steps++;
		hl_ecu_io_outputs(n->io, n->e, n->out);
		return 0;
	}
	{
		int *idx = n->set_idx, k = 0;
		double *vals = n->set_val;
		const double h = (double)n->cfg.period_ns / 1e9;

		for (int i = 0; i < n->n_in; i++) {
			if (n->in_idx[i] < 0)
				continue;
			idx[k] = n->in_idx[i];
			vals[k++] = n->in[i];
		}
		if (k && hl_fmu_set_real(n->fmu, idx, vals, k) < 0) {
			snprintf(err, err_size, "'%s': cannot set its inputs", n->cfg.ecu);
			return -EINVAL;
		}
		/* fmi2DoStep from the previous step's time to this one: the cycle at t */
		return hl_fmu_step(n->fmu, (double)t / 1e9 - h, h, n->out_idx, n->out, n->n_out,
				   err, err_size);
	}
}

static void send_cycle(struct hl_ecu_node *n, const struct out_cycle *oc, int64_t t)
{
	for (int l = 0; l < n->cfg.n_lamps; l++)
		for (int i = 0; i < oc->n[l]; i++) {
			const struct hl_encoded_frame *e = &oc->frames[l][i];

			if (hl_vbus_send(n->bus, n->node, t, e->frame.can_id, e->frame.data,
					 e->frame.len, e->fd, e->fd) == 0)
				n->c.frames_sent++;
			else
				n->c.tx_errors++;
		}
}

int hl_ecu_node_run(struct hl_ecu_node *n, int64_t t, char *err, size_t err_size)
{
	if (t == n->next_step) {
		struct out_cycle *oc;
		int rc = compute(n, t, err, err_size);

		if (rc < 0)
			return rc;
		n->c.steps++;
		n->next_step += n->cfg.period_ns;
		if (n->q_len == n->q_size) {
			snprintf(err, err_size, "ecu: %d late cycles pending", n->q_len);
			return -ENOSPC;
		}
		oc = &n->q[(n->q_head + n->q_len) % n->q_size];
		oc->due_ns = t + (int64_t)n->cfg.late_ms * 1000000;
		for (int l = 0; l < n->cfg.n_lamps; l++) {
			const int first = hl_ecu_io_lamp_first(n->io, l);
			const int ns = hl_ecu_io_lamp_sources(n->io, l);
			const unsigned max = hl_assembler_counter_max(n->cfg.a, l);

			for (int k = 0; k < ns; k++) {
				const double v = n->out[first + k];

				/* an FMU's value outside [0, 1] is clamped as a lamp would */
				n->fmu_out[l][k] = (float)(v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v);
			}
			oc->n[l] = hl_assembler_encode(n->cfg.a, l, n->fmu_out[l], n->counter[l],
						       oc->frames[l], HL_ASM_MAX_PARTS);
			if (oc->n[l] < 0) {
				snprintf(err, err_size,
					 "ecu: lamp '%s': cannot encode its cycle: %s",
					 n->cfg.lamp_names[l], strerror(-oc->n[l]));
				return oc->n[l];
			}
			if (n->cfg.bad_crc)
				for (int i = 0; i < oc->n[l]; i++)
					oc->frames[l][i].frame.data[0] ^= 0x01;
			if (!n->cfg.stuck_counter)
				n->counter[l] = max ? (n->counter[l] + 1) % (max + 1) : 0;
		}
		n->q_len++;
	}
	while (n->q_len > 0 && n->q[n->q_head].due_ns <= t) {
		send_cycle(n, &n->q[n->q_head], t);
		n->q_head = (n->q_head + 1) % n->q_size;
		n->q_len--;
	}
	return 0;
}

void hl_ecu_node_counts(const struct hl_ecu_node *n, struct hl_ecu_node_counts *ret)
{
	*ret = n->c;
	ret->inputs = *hl_inputs_decoder_counters(n->dec);
}

const char *hl_ecu_node_name(const struct hl_ecu_node *n)
{
	return n->name;
}
