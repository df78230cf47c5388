/* SPDX-License-Identifier: MIT */
#include "can/assembler.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "can/e2e.h"

struct plan {
	const struct hl_dbc_message *m;
	int lamp;
	struct hl_e2e_config e2e;
	int *source_of; /* per signal: 0-based source index, -1 */
	int mux; /* the multiplexor signal's index, -1 for none */
	int mode; /* the HdlBeamMode signal's index, -1 for none */
	int first_part, n_parts;
	uint64_t *part_mux; /* multiplexor value of each of its parts */
};

struct lamp {
	char *name;
	int n_sources, n_parts;
	enum hl_e2e_profile profile;
	unsigned counter_max;
	float *staging, *out;
	uint64_t parts_seen;
	int cur_counter; /* the cycle being assembled, -1 for none */
	int last_counter; /* of the last complete cycle, -1 for none */
	uint64_t abandoned; /* incomplete cycles since the last complete one */
	uint64_t seq;
	int64_t t_first_ns, t_last_ns, t_complete_ns;
	const struct hl_dbc_signal *mode_signal; /* HdlBeamMode, NULL for none */
	int64_t mode_staging; /* its raw value in the cycle being assembled */
	bool stale;
	struct hl_lamp_counters c;
};

struct hl_assembler {
	const struct hl_dbc *db;
	int64_t timeout_ns;
	int n_lamps, n_plans;
	struct lamp lamps[HL_ASM_MAX_LAMPS];
	struct plan *plans;
	struct hl_dbc_value *values;
	struct hl_asm_counters c;
};

static int fail(struct hl_asm_error *err, const char *fmt, ...)
{
	va_list ap;

	if (err) {
		va_start(ap, fmt);
		vsnprintf(err->msg, sizeof(err->msg), fmt, ap);
		va_end(ap);
	}
	return -EINVAL;
}

void hl_assembler_free(struct hl_assembler *a)
{
	if (!a)
		return;
	for (int p = 0; p < a->n_plans; p++) {
		free(a->plans[p].source_of);
		free(a->plans[p].part_mux);
	}
	for (int l = 0; l < a->n_lamps; l++) {
		free(a->lamps[l].name);
		free(a->lamps[l].staging);
		free(a->lamps[l].out);
	}
	free(a->plans);
	free(a->values);
	free(a);
}

static bool selected(const struct hl_dbc_signal *sg, uint64_t mux);

/* The message's sources and its parts (one per multiplexor value that carries sources). */
static int plan_message(struct hl_assembler *a, struct plan *p, struct hl_asm_error *err)
{
	const struct hl_dbc_message *m = p->m;

	p->mux = -1;
	p->mode = -1;
	p->source_of = malloc(sizeof(int) * (m->n_signals ? m->n_signals : 1));
	p->part_mux = calloc(HL_ASM_MAX_PARTS, sizeof(uint64_t));
	if (!p->source_of || !p->part_mux)
		return -ENOMEM;
	for (int s = 0; s < m->n_signals; s++) {
		const struct hl_dbc_signal *sg = &m->signals[s];
		struct hl_dbc_attr_value v;

		p->source_of[s] = -1;
		if (sg->is_multiplexor && sg->mux_parent < 0)
			p->mux = s;
		/* the beam mode: an explicit BA_ as for HdlSource, named values (VAL_) */
		if (!sg->is_multiplexor && !sg->unusable &&
		    hl_dbc_signal_attr(a->db, m, sg, "HdlBeamMode", &v) == 0 && v.i > 0) {
			if (p->mode >= 0)
				return fail(
					err,
					"message %s (line %d): HdlBeamMode on %s and %s; expected "
					"one signal",
					m->name, m->line, m->signals[p->mode].name, sg->name);
			if (sg->n_values == 0)
				return fail(
					err,
					"signal %s of message %s (line %d): HdlBeamMode needs the "
					"modes' names as VAL_ descriptions",
					sg->name, m->name, sg->line);
			p->mode = s;
			continue;
		}
		/* only an explicit BA_ gives a source: CANdb++ forces a default inside the
		 * definition's range (INT 1 4096 gives 1), which would put every signal on
		 * source 1; a multiplexor selects the page and is never a source */
		if (sg->is_multiplexor || sg->unusable ||
		    hl_dbc_signal_attr(a->db, m, sg, "HdlSource", &v) != 0 || v.i <= 0)
			continue;
		if (v.i > HL_DBC_MAX_SIGNALS)
			return fail(
				err,
				"signal %s of message %s (line %d): HdlSource %lld is beyond %d",
				sg->name, m->name, sg->line, (long long)v.i, HL_DBC_MAX_SIGNALS);
		p->source_of[s] = (int)v.i - 1;
	}
	for (int s = 0; s < m->n_signals; s++) {
		const struct hl_dbc_signal *sg = &m->signals[s];

		if (p->source_of[s] < 0)
			continue;
		if (sg->mux_parent >= 0 && sg->mux_parent != p->mux)
			return fail(
				err,
				"signal %s of message %s (line %d): sources under nested multiplexors are not supported",
				sg->name, m->name, sg->line);
		if (sg->mux_parent < 0) {
			if (p->n_parts == 0)
				p->n_parts = 1; /* the whole message is one part */
			continue;
		}
		for (int r = 0; r < sg->n_mux_ranges; r++) {
			for (uint64_t v = sg->mux_ranges[r].lo; v <= sg->mux_ranges[r].hi; v++) {
				int q = 0;

				while (q < p->n_parts && p->part_mux[q] != v)
					q++;
				if (q == p->n_parts) {
					if (p->n_parts == HL_ASM_MAX_PARTS)
						return fail(
							err,
							"message %s (line %d): more than %d pages",
							m->name, m->line, HL_ASM_MAX_PARTS);
					p->part_mux[p->n_parts++] = v;
				}
				if (v == sg->mux_ranges[r].hi)
					break;
			}
		}
	}
	if (p->n_parts == 0)
		return fail(err,
			    "message %s (line %d) has an HdlLamp but no signal with an HdlSource",
			    m->name, m->line);
	if (p->mode >= 0 && m->signals[p->mode].mux_parent >= 0) {
		const struct hl_dbc_signal *sg = &m->signals[p->mode];
		bool carried = false;

		for (int q = 0; q < p->n_parts && sg->mux_parent == p->mux; q++)
			carried = carried || selected(sg, p->part_mux[q]);
		if (!carried)
			return fail(err,
				    "signal %s of message %s (line %d): HdlBeamMode on a page that "
				    "carries no source",
				    sg->name, m->name, sg->line);
	}
	return 0;
}

/* Every source 1..K of each lamp in exactly one signal. */
static int check_sources(struct hl_assembler *a, struct hl_asm_error *err)
{
	for (int l = 0; l < a->n_lamps; l++) {
		struct lamp *lamp = &a->lamps[l];
		int *count;

		lamp->n_sources = 0;
		for (int p = 0; p < a->n_plans; p++)
			if (a->plans[p].lamp == l)
				for (int s = 0; s < a->plans[p].m->n_signals; s++)
					if (a->plans[p].source_of[s] + 1 > lamp->n_sources)
						lamp->n_sources = a->plans[p].source_of[s] + 1;
		if (lamp->n_sources == 0)
			return fail(
				err,
				"lamp '%s' has no message with HdlLamp \"%s\" and HdlSource signals",
				lamp->name, lamp->name);
		count = calloc(lamp->n_sources, sizeof(int));
		if (!count)
			return -ENOMEM;
		for (int p = 0; p < a->n_plans; p++)
			if (a->plans[p].lamp == l)
				for (int s = 0; s < a->plans[p].m->n_signals; s++)
					if (a->plans[p].source_of[s] >= 0)
						count[a->plans[p].source_of[s]]++;
		for (int k = 0; k < lamp->n_sources; k++) {
			if (count[k] != 1) {
				int n = count[k];

				free(count);
				return fail(
					err,
					"lamp '%s': source %d is carried by %d signals; expected exactly one",
					lamp->name, k + 1, n);
			}
		}
		free(count);
	}
	return 0;
}

int hl_assembler_new(const struct hl_dbc *db, const char *const *lamp_names, int n_lamps,
		     int timeout_ms, int64_t now_ns, struct hl_assembler **ret,
		     struct hl_asm_error *err)
{
	struct hl_assembler *a;
	int rc;

	if (n_lamps < 1 || n_lamps > HL_ASM_MAX_LAMPS || timeout_ms < 1)
		return fail(err, "between 1 and %d lamps and a positive timeout are needed",
			    HL_ASM_MAX_LAMPS);
	a = calloc(1, sizeof(*a));
	if (!a)
		return -ENOMEM;
	a->db = db;
	a->timeout_ns = (int64_t)timeout_ms * 1000000;
	a->plans = calloc(hl_dbc_n_messages(db) + 1, sizeof(*a->plans));
	a->values = calloc(hl_dbc_max_signals(db) + 1, sizeof(*a->values));
	rc = a->plans && a->values ? 0 : -ENOMEM;
	for (int l = 0; l < n_lamps && rc == 0; l++) {
		a->lamps[l].name = strdup(lamp_names[l]);
		a->lamps[l].cur_counter = -1;
		a->lamps[l].last_counter = -1;
		a->lamps[l].t_complete_ns = now_ns;
		a->n_lamps++;
		if (!a->lamps[l].name)
			rc = -ENOMEM;
	}
	for (int i = 0; i < hl_dbc_n_messages(db) && rc == 0; i++) {
		const struct hl_dbc_message *m = hl_dbc_message(db, i);
		struct hl_dbc_attr_value lamp, e2e;
		struct plan *p;
		int l = 0;

		if (hl_dbc_message_attr(db, m, "HdlLamp", &lamp) < 0 || !lamp.s || !lamp.s[0])
			continue;
		while (l < n_lamps && strcmp(lamp_names[l], lamp.s) != 0)
			l++;
		if (l == n_lamps) {
			rc = fail(err,
				  "message %s (line %d): HdlLamp \"%s\" is not a configured lamp",
				  m->name, m->line, lamp.s);
			break;
		}
		p = &a->plans[a->n_plans++];
		p->m = m;
		p->lamp = l;
		if (hl_dbc_message_attr(db, m, "HdlE2E", &e2e) < 0 || !e2e.s)
			e2e.s = "none";
		if (hl_e2e_config_parse(e2e.s, &p->e2e) < 0) {
			rc = fail(
				err,
				"message %s (line %d): HdlE2E \"%s\"; expected e.g. \"P1 dataid=0x0123\" or \"none\"",
				m->name, m->line, e2e.s);
			break;
		}
		if (p->e2e.profile != HL_E2E_NONE &&
		    (size_t)m->size < hl_e2e_min_len(p->e2e.profile)) {
			rc = fail(err, "message %s (line %d): %d bytes cannot carry E2E %s",
				  m->name, m->line, m->size, hl_e2e_profile_name(p->e2e.profile));
			break;
		}
		rc = plan_message(a, p, err);
		if (rc < 0)
			break;
		p->first_part = a->lamps[l].n_parts;
		a->lamps[l].n_parts += p->n_parts;
		if (a->lamps[l].n_parts > HL_ASM_MAX_PARTS) {
			rc = fail(err, "lamp '%s': more than %d parts per cycle", lamp.s,
				  HL_ASM_MAX_PARTS);
			break;
		}
		if (p->first_part > 0 && a->lamps[l].profile != p->e2e.profile) {
			rc = fail(err, "message %s (line %d): lamp '%s' mixes E2E profiles",
				  m->name, m->line, lamp.s);
			break;
		}
		a->lamps[l].profile = p->e2e.profile;
		a->lamps[l].counter_max = hl_e2e_counter_max(p->e2e.profile);
		if (p->mode >= 0) {
			if (a->lamps[l].mode_signal) {
				rc = fail(
					err,
					"lamp '%s': HdlBeamMode on %s and %s; expected one signal",
					lamp.s, a->lamps[l].mode_signal->name,
					m->signals[p->mode].name);
				break;
			}
			a->lamps[l].mode_signal = &m->signals[p->mode];
		}
	}
	if (rc == 0)
		rc = check_sources(a, err);
	for (int l = 0; l < a->n_lamps && rc == 0; l++) {
		a->lamps[l].staging = calloc(a->lamps[l].n_sources, sizeof(float));
		a->lamps[l].out = calloc(a->lamps[l].n_sources, sizeof(float));
		if (!a->lamps[l].staging || !a->lamps[l].out)
			rc = -ENOMEM;
	}
	if (rc < 0) {
		if (rc == -ENOMEM)
			fail(err, "out of memory");
		hl_assembler_free(a);
		return rc;
	}
	*ret = a;
	return 0;
}

void hl_assembler_restart(struct hl_assembler *a)
{
	for (int l = 0; l < a->n_lamps; l++) {
		struct lamp *lamp = &a->lamps[l];

		if (lamp->parts_seen)
			lamp->c.incomplete++;
		lamp->parts_seen = 0;
		lamp->cur_counter = -1;
		lamp->last_counter = -1;
		lamp->abandoned = 0;
	}
}

uint32_t hl_assembler_expire(struct hl_assembler *a, int64_t now_ns)
{
	uint32_t mask = 0;

	for (int l = 0; l < a->n_lamps; l++) {
		struct lamp *lamp = &a->lamps[l];

		if (lamp->stale || now_ns - lamp->t_complete_ns < a->timeout_ns)
			continue;
		lamp->stale = true;
		lamp->c.stale_events++;
		mask |= 1u << l;
	}
	return mask;
}

int64_t hl_assembler_next_deadline(const struct hl_assembler *a)
{
	int64_t t = INT64_MAX;

	for (int l = 0; l < a->n_lamps; l++)
		if (!a->lamps[l].stale && a->lamps[l].t_complete_ns + a->timeout_ns < t)
			t = a->lamps[l].t_complete_ns + a->timeout_ns;
	return t;
}

static const struct plan *find_plan(const struct hl_assembler *a, const struct hl_dbc_message *m)
{
	for (int p = 0; p < a->n_plans; p++)
		if (a->plans[p].m == m)
			return &a->plans[p];
	return NULL;
}

static void complete(struct lamp *lamp, int l, unsigned counter, int64_t now_ns,
		     struct hl_cycle *ret, struct hl_asm_events *ev)
{
	if (lamp->profile != HL_E2E_NONE && lamp->last_counter >= 0) {
		unsigned lost = 0;

		if (hl_e2e_counter_check(lamp->counter_max, (unsigned)lamp->last_counter, counter,
					 &lost) == HL_E2E_COUNTER_LOST &&
		    lost > lamp->abandoned)
			lamp->c.lost_cycles += lost - lamp->abandoned;
	}
	lamp->abandoned = 0;
	lamp->last_counter = lamp->profile != HL_E2E_NONE ? (int)counter : -1;
	lamp->cur_counter = -1;
	lamp->parts_seen = 0;
	lamp->seq++;
	lamp->c.cycles++;
	lamp->t_complete_ns = now_ns;
	memcpy(lamp->out, lamp->staging, sizeof(float) * lamp->n_sources);
	if (lamp->stale) {
		lamp->stale = false;
		lamp->c.recoveries++;
		ev->recovered |= 1u << l;
	}
	*ret = (struct hl_cycle){
		.lamp = l,
		.seq = lamp->seq,
		.counter = counter,
		.t_rx_first_ns = lamp->t_first_ns,
		.t_rx_last_ns = lamp->t_last_ns,
		.n_sources = lamp->n_sources,
		.i = lamp->out,
		.mode = lamp->mode_signal ? lamp->mode_staging : -1,
	};
}

int hl_assembler_feed(struct hl_assembler *a, const struct canfd_frame *f, int64_t t_rx_ns,
		      int64_t now_ns, struct hl_cycle *ret_cycle, struct hl_asm_events *ev)
{
	const struct hl_dbc_message *m = NULL;
	const struct plan *p;
	struct lamp *lamp;
	uint32_t id;
	unsigned counter = 0;
	int n, part = 0;
	uint64_t bit;

	*ev = (struct hl_asm_events){ .stale = hl_assembler_expire(a, now_ns) };
	if (f->can_id & CAN_ERR_FLAG) {
		a->c.error_frames++;
		return 0;
	}
	if (f->can_id & CAN_RTR_FLAG) {
		a->c.other_frames++;
		return 0;
	}
	id = (f->can_id & CAN_EFF_FLAG) ? (f->can_id & (CAN_EFF_MASK | CAN_EFF_FLAG)) :
					  (f->can_id & CAN_SFF_MASK);
	n = hl_dbc_decode_frame(a->db, id, f->data, f->len, &a->c.dbc, &m, a->values);
	if (n < 0)
		return 0; /* unknown ID or short frame: counted by the decoder */
	p = find_plan(a, m);
	if (!p) {
		a->c.other_frames++;
		return 0;
	}
	lamp = &a->lamps[p->lamp];
	lamp->c.frames++;
	if (p->e2e.profile != HL_E2E_NONE) {
		if (hl_e2e_check(&p->e2e, f->data, f->len) < 0) {
			lamp->c.crc_errors++;
			return 0;
		}
		counter = hl_e2e_counter(&p->e2e, f->data);
	}
	if (p->mux >= 0) {
		uint64_t mux = UINT64_MAX;

		for (int v = 0; v < n; v++)
			if ((int)a->values[v].signal == p->mux)
				mux = a->values[v].raw;
		while (part < p->n_parts && p->part_mux[part] != mux)
			part++;
		if (part == p->n_parts) {
			a->c.other_frames++; /* a page that carries no source */
			return 0;
		}
	}
	bit = 1ull << (p->first_part + part);

	if (lamp->profile != HL_E2E_NONE) {
		if (lamp->cur_counter != (int)counter && lamp->last_counter == (int)counter) {
			lamp->c.repeated_frames++;
			return 0;
		}
		if (lamp->cur_counter != (int)counter) {
			if (lamp->cur_counter >= 0) {
				lamp->c.incomplete++;
				lamp->abandoned++;
			}
			lamp->cur_counter = (int)counter;
			lamp->parts_seen = 0;
		}
		if (lamp->parts_seen & bit) {
			lamp->c.repeated_frames++;
			return 0;
		}
	} else if (lamp->parts_seen & bit) {
		lamp->c.incomplete++;
		lamp->parts_seen = 0;
	}
	if (lamp->parts_seen == 0)
		lamp->t_first_ns = t_rx_ns;
	lamp->t_last_ns = t_rx_ns;
	for (int v = 0; v < n; v++) {
		const int k = p->source_of[a->values[v].signal];
		double i = a->values[v].phys;

		if ((int)a->values[v].signal == p->mode)
			lamp->mode_staging = a->values[v].raw > INT64_MAX ?
						     INT64_MAX :
						     (int64_t)a->values[v].raw;
		if (k < 0)
			continue;
		if (!(i >= 0.0 && i <= 1.0)) {
			lamp->c.out_of_range++;
			i = i > 1.0 ? 1.0 : 0.0;
		}
		lamp->staging[k] = (float)i;
	}
	lamp->parts_seen |= bit;
	if (lamp->parts_seen != (lamp->n_parts == 64 ? UINT64_MAX : (1ull << lamp->n_parts) - 1))
		return 0;
	complete(lamp, p->lamp, counter, now_ns, ret_cycle, ev);
	return 1;
}

static bool selected(const struct hl_dbc_signal *sg, uint64_t mux)
{
	if (sg->mux_parent < 0)
		return true;
	for (int r = 0; r < sg->n_mux_ranges; r++)
		if (mux >= sg->mux_ranges[r].lo && mux <= sg->mux_ranges[r].hi)
			return true;
	return false;
}

int hl_assembler_encode(const struct hl_assembler *a, int lamp, const float *i, unsigned counter,
			struct hl_encoded_frame *ret, int max)
{
	return hl_assembler_encode_mode(a, lamp, i, counter, -1, ret, max);
}

int hl_assembler_encode_mode(const struct hl_assembler *a, int lamp, const float *i,
			     unsigned counter, int64_t mode, struct hl_encoded_frame *ret, int max)
{
	int n = 0;

	for (int pi = 0; pi < a->n_plans; pi++) {
		const struct plan *p = &a->plans[pi];
		const struct hl_dbc_message *m = p->m;

		if (p->lamp != lamp)
			continue;
		for (int part = 0; part < p->n_parts; part++) {
			struct hl_encoded_frame *out = &ret[n];

			if (n == max)
				return -ENOSPC;
			memset(out, 0, sizeof(*out));
			out->frame.can_id = m->id | (m->extended ? CAN_EFF_FLAG : 0);
			out->frame.len = (uint8_t)m->size;
			out->fd = m->size > 8;
			if (p->mux >= 0 &&
			    hl_dbc_signal_set_raw(&m->signals[p->mux], p->part_mux[part],
						  out->frame.data, m->size) < 0)
				return -EINVAL;
			for (int s = 0; s < m->n_signals; s++) {
				const int k = p->source_of[s];

				if (k < 0 ||
				    (p->mux >= 0 && !selected(&m->signals[s], p->part_mux[part])))
					continue;
				if (hl_dbc_signal_encode(&m->signals[s], i[k], out->frame.data,
							 m->size) < 0)
					return -EINVAL;
			}
			if (mode >= 0 && p->mode >= 0 &&
			    (p->mux < 0 || selected(&m->signals[p->mode], p->part_mux[part])) &&
			    hl_dbc_signal_set_raw(&m->signals[p->mode], (uint64_t)mode,
						  out->frame.data, m->size) < 0)
				return -EINVAL;
			if (p->e2e.profile != HL_E2E_NONE &&
			    hl_e2e_protect(&p->e2e, out->frame.data, m->size, counter) < 0)
				return -EINVAL;
			n++;
		}
	}
	return n;
}

int hl_assembler_n_lamps(const struct hl_assembler *a)
{
	return a->n_lamps;
}

const char *hl_assembler_lamp_name(const struct hl_assembler *a, int lamp)
{
	return a->lamps[lamp].name;
}

int hl_assembler_n_sources(const struct hl_assembler *a, int lamp)
{
	return a->lamps[lamp].n_sources;
}

const struct hl_dbc_signal *hl_assembler_source_signal(const struct hl_assembler *a, int lamp,
						       int source)
{
	if (lamp < 0 || lamp >= a->n_lamps || source < 0 || source >= a->lamps[lamp].n_sources)
		return NULL;
	for (int p = 0; p < a->n_plans; p++) {
		const struct plan *pl = &a->plans[p];

		if (pl->lamp != lamp)
			continue;
		for (int s = 0; s < pl->m->n_signals; s++)
			if (pl->source_of[s] == source)
				return &pl->m->signals[s];
	}
	return NULL;
}

unsigned hl_assembler_counter_max(const struct hl_assembler *a, int lamp)
{
	return a->lamps[lamp].counter_max;
}

int hl_assembler_ids(const struct hl_assembler *a, uint32_t *ids, int max)
{
	for (int p = 0; p < a->n_plans && p < max; p++)
		ids[p] = a->plans[p].m->id | (a->plans[p].m->extended ? CAN_EFF_FLAG : 0);
	return a->n_plans;
}

bool hl_assembler_stale(const struct hl_assembler *a, int lamp)
{
	return a->lamps[lamp].stale;
}

const struct hl_dbc_signal *hl_assembler_mode_signal(const struct hl_assembler *a, int lamp)
{
	return lamp >= 0 && lamp < a->n_lamps ? a->lamps[lamp].mode_signal : NULL;
}

int hl_assembler_mode_value(const struct hl_assembler *a, int lamp, const char *name, int64_t *ret)
{
	const struct hl_dbc_signal *sg = hl_assembler_mode_signal(a, lamp);

	for (int k = 0; sg && k < sg->n_values; k++) {
		if (strcasecmp(sg->values[k].desc, name) == 0) {
			*ret = sg->values[k].value;
			return 0;
		}
	}
	return -ENOENT;
}

const struct hl_lamp_counters *hl_assembler_lamp_counters(const struct hl_assembler *a, int lamp)
{
	return &a->lamps[lamp].c;
}

const struct hl_asm_counters *hl_assembler_counters(const struct hl_assembler *a)
{
	return &a->c;
}
