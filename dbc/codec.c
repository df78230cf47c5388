/* SPDX-License-Identifier: MIT */
/*
 * Signal decode and encode.
 *
 * Decoding copies the frame into a buffer with 8 zero bytes of padding and reads each signal
 * with one 64-bit load (plus one byte when a signal of up to 64 bits starts mid-byte and so
 * spans 9 bytes), a shift and a mask, all precomputed by hl_dbc_extract_init():
 *
 *   Intel (@1): bit b of the frame is bit b % 8 of byte b / 8 (LSB first). The start bit is
 *     the signal's LSB; the little-endian word at byte start / 8, shifted right by start % 8,
 *     holds the signal in its low bits.
 *   Motorola (@0): the start bit is the signal's MSB in the same "sawtooth" numbering; in the
 *     big-endian linear numbering (bit 0 = MSB of byte 0) it sits at
 *     pos = 8 * (start / 8) + 7 - start % 8, and the signal is bits pos .. pos + len - 1. The
 *     big-endian word at byte pos / 8, shifted left by pos % 8, has the signal in its top bits.
 *
 * Encoding goes bit by bit instead: it is not on the hot path, and a second, independent way
 * to place bits makes the round-trip tests meaningful.
 */
#include <endian.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dbc/internal.h"

#define DENSE_MUX_LIMIT 65536 /* entries of a dense multiplexor table, else ranges */

static int motorola_pos(int start_bit)
{
	return 8 * (start_bit / 8) + 7 - start_bit % 8;
}

int hl_dbc_signal_end_byte(int start_bit, int length, enum hl_dbc_byte_order order)
{
	if (order == HL_DBC_INTEL)
		return (start_bit + length + 7) / 8;
	return (motorola_pos(start_bit) + length + 7) / 8;
}

void hl_dbc_extract_init(struct hl_dbc_signal *s)
{
	struct hl_dbc_extract *x = &s->x;

	if (s->order == HL_DBC_INTEL) {
		x->byte = (uint16_t)(s->start_bit / 8);
		x->shift = (uint8_t)(s->start_bit % 8);
	} else {
		int pos = motorola_pos(s->start_bit);

		x->byte = (uint16_t)(pos / 8);
		x->shift = (uint8_t)(pos % 8);
	}
	x->len = (uint8_t)s->length;
	x->mask = s->length == 64 ? UINT64_MAX : ((uint64_t)1 << s->length) - 1;
	x->sign = s->is_signed && s->type == HL_DBC_INTEGER ? (uint64_t)1 << (s->length - 1) : 0;
}

/* buf holds at least x->byte + 9 bytes. */
static inline uint64_t extract(const struct hl_dbc_signal *s, const uint8_t *buf)
{
	const struct hl_dbc_extract *x = &s->x;
	uint64_t w;

	memcpy(&w, buf + x->byte, 8);
	if (s->order == HL_DBC_INTEL) {
		w = le64toh(w) >> x->shift;
		if (x->shift)
			w |= (uint64_t)buf[x->byte + 8] << (64 - x->shift);
		w &= x->mask;
	} else {
		w = be64toh(w) << x->shift;
		if (x->shift)
			w |= (uint64_t)buf[x->byte + 8] >> (8 - x->shift);
		w >>= 64 - x->len; /* len == 64: no shift */
	}
	return (w ^ x->sign) - x->sign; /* sign extension; identity when sign == 0 */
}

static inline double phys(const struct hl_dbc_signal *s, uint64_t raw)
{
	double v;

	switch (s->type) {
	case HL_DBC_FLOAT: {
		uint32_t u = (uint32_t)raw;
		float f;

		memcpy(&f, &u, sizeof(f));
		v = f;
		break;
	}
	case HL_DBC_DOUBLE:
		memcpy(&v, &raw, sizeof(v));
		break;
	default:
		v = s->is_signed ? (double)(int64_t)raw : (double)raw;
		break;
	}
	return v * s->factor + s->offset;
}

double hl_dbc_signal_phys(const struct hl_dbc_signal *s, uint64_t raw)
{
	return phys(s, raw);
}

/* --- the decode plan, built once per message after parsing --- */

static int fail(struct hl_dbc_error *err, int line, int col, const char *fmt, const char *a,
		const char *b)
{
	err->line = line;
	err->column = col;
	snprintf(err->msg, sizeof(err->msg), fmt, a, b);
	return -EBADMSG;
}

static int cmp_range(const void *a, const void *b)
{
	const struct hl_dbc_mux_range *x = a, *y = b;

	return x->lo < y->lo ? -1 : x->lo > y->lo;
}

/* Sorted, overlaps merged: a value then matches at most one range of a signal. */
static void normalize_ranges(struct hl_dbc_signal *s)
{
	struct hl_dbc_mux_range *r = (struct hl_dbc_mux_range *)s->mux_ranges;
	int n = 0;

	if (s->n_mux_ranges < 2)
		return;
	qsort(r, s->n_mux_ranges, sizeof(*r), cmp_range);
	for (int i = 1; i < s->n_mux_ranges; i++) {
		if (r[i].lo <= r[n].hi || (r[n].hi != UINT64_MAX && r[i].lo == r[n].hi + 1)) {
			if (r[i].hi > r[n].hi)
				r[n].hi = r[i].hi;
		} else {
			r[++n] = r[i];
		}
	}
	s->n_mux_ranges = n + 1;
}

static bool in_ranges(const struct hl_dbc_signal *s, uint64_t v)
{
	for (int i = 0; i < s->n_mux_ranges; i++)
		if (v >= s->mux_ranges[i].lo && v <= s->mux_ranges[i].hi)
			return true;
	return false;
}

static int build_table(struct hl_dbc_message *m, int mux, struct mux_table *t)
{
	uint64_t top = 0;
	int n_children = 0;

	for (int i = 0; i < m->n_signals; i++) {
		const struct hl_dbc_signal *s = &m->signals[i];

		if (s->mux_parent != mux || s->unusable)
			continue;
		n_children++;
		for (int r = 0; r < s->n_mux_ranges; r++)
			if (s->mux_ranges[r].hi > top)
				top = s->mux_ranges[r].hi;
	}
	if (top < DENSE_MUX_LIMIT && (top + 1) * n_children <= DENSE_MUX_LIMIT) {
		uint32_t k = 0;

		t->n_values = (uint32_t)top + 1;
		t->offsets = malloc(sizeof(uint32_t) * (t->n_values + 1));
		t->children = malloc(sizeof(uint16_t) * ((size_t)t->n_values * n_children + 1));
		if (!t->offsets || !t->children)
			return -ENOMEM;
		for (uint32_t v = 0; v < t->n_values; v++) {
			t->offsets[v] = k;
			for (int i = 0; i < m->n_signals; i++)
				if (m->signals[i].mux_parent == mux && !m->signals[i].unusable &&
				    in_ranges(&m->signals[i], v))
					t->children[k++] = (uint16_t)i;
		}
		t->offsets[t->n_values] = k;
		return 0;
	}
	{
		size_t n_ranges = 0;

		for (int i = 0; i < m->n_signals; i++)
			if (m->signals[i].mux_parent == mux && !m->signals[i].unusable)
				n_ranges += m->signals[i].n_mux_ranges;
		t->ranges = malloc(sizeof(*t->ranges) * (n_ranges + 1));
		if (!t->ranges)
			return -ENOMEM;
	}
	for (int i = 0; i < m->n_signals; i++) {
		const struct hl_dbc_signal *s = &m->signals[i];

		if (s->mux_parent != mux || s->unusable)
			continue;
		for (int r = 0; r < s->n_mux_ranges; r++) {
			t->ranges[t->n_ranges].lo = s->mux_ranges[r].lo;
			t->ranges[t->n_ranges].hi = s->mux_ranges[r].hi;
			t->ranges[t->n_ranges].child = (uint16_t)i;
			t->n_ranges++;
		}
	}
	return 0;
}

int hl_dbc_plan_build(struct hl_dbc_message *m, const struct sig_where *w, struct hl_dbc_error *err)
{
	struct hl_dbc_signal *sigs = (struct hl_dbc_signal *)m->signals;
	struct hl_dbc_plan *plan;
	int top = -1, n_top = 0;

	for (int i = 0; i < m->n_signals; i++)
		if (sigs[i].is_multiplexor && !w[i].mux_value && !w[i].mul_line) {
			top = i;
			n_top++;
		}
	for (int i = 0; i < m->n_signals; i++) {
		struct hl_dbc_signal *s = &sigs[i];

		hl_dbc_extract_init(s);
		if (w[i].mul_line || !w[i].mux_value)
			continue;
		/* mN without SG_MUL_VAL_: the message's one plain multiplexor selects it */
		if (n_top == 0)
			return fail(
				err, w[i].line, w[i].column,
				"signal '%s' is multiplexed (m<n>) but message '%s' has no multiplexor (M)",
				s->name, m->name);
		if (n_top > 1)
			return fail(
				err, w[i].line, w[i].column,
				"signal '%s' is multiplexed (m<n>) but message '%s' has several multiplexors: expected an SG_MUL_VAL_ naming one",
				s->name, m->name);
		if (top == i)
			return fail(err, w[i].line, w[i].column,
				    "signal '%s' of message '%s' is multiplexed by itself", s->name,
				    m->name);
		s->mux_parent = top;
	}
	for (int i = 0; i < m->n_signals; i++) {
		int steps = 0;

		normalize_ranges(&sigs[i]);
		for (int j = sigs[i].mux_parent; j >= 0; j = sigs[j].mux_parent)
			if (++steps > m->n_signals)
				return fail(
					err, w[i].mul_line ? w[i].mul_line : w[i].line,
					w[i].mul_line ? w[i].mul_column : w[i].column,
					"the multiplexor chain of signal '%s' in message '%s' loops",
					sigs[i].name, m->name);
	}
	plan = calloc(1, sizeof(*plan));
	if (!plan)
		return -ENOMEM;
	m->plan = plan;
	plan->roots = malloc(sizeof(uint16_t) * (m->n_signals + 1));
	if (!plan->roots)
		return -ENOMEM;
	for (int i = 0; i < m->n_signals; i++) {
		/* a signal past the message's end is never read; nor are its dependents */
		if (sigs[i].mux_parent < 0 && !sigs[i].unusable)
			plan->roots[plan->n_roots++] = (uint16_t)i;
		if (sigs[i].is_multiplexor)
			plan->n_tables++;
	}
	plan->tables = calloc(plan->n_tables + 1, sizeof(*plan->tables));
	if (!plan->tables)
		return -ENOMEM;
	for (int i = 0, t = 0; i < m->n_signals; i++) {
		if (!sigs[i].is_multiplexor)
			continue;
		sigs[i].mux_table = t;
		if (build_table(m, i, &plan->tables[t++]) < 0)
			return -ENOMEM;
	}
	return 0;
}

void hl_dbc_plan_free(struct hl_dbc_plan *plan)
{
	if (!plan)
		return;
	for (int i = 0; i < plan->n_tables; i++) {
		free(plan->tables[i].offsets);
		free(plan->tables[i].children);
		free(plan->tables[i].ranges);
	}
	free(plan->tables);
	free(plan->roots);
	free(plan);
}

int hl_dbc_decode(const struct hl_dbc_message *m, const uint8_t *data, size_t len,
		  struct hl_dbc_value *ret_values)
{
	const struct hl_dbc_plan *plan = m->plan;
	const struct hl_dbc_signal *sigs = m->signals;
	uint8_t buf[HL_DBC_MAX_PAYLOAD + 8];
	int n = 0;

	if (m->independent)
		return -ENOENT;
	if (len < (size_t)m->size)
		return -EMSGSIZE;
	memcpy(buf, data, m->size);
	memset(buf + m->size, 0, 8);
	for (int i = 0; i < plan->n_roots; i++) {
		const struct hl_dbc_signal *s = &sigs[plan->roots[i]];
		uint64_t raw = extract(s, buf);

		ret_values[n].signal = plan->roots[i];
		ret_values[n].raw = raw;
		ret_values[n].phys = phys(s, raw);
		n++;
	}
	/* a multiplexor's dependents go behind it; they may be multiplexors themselves */
	for (int k = 0; k < n; k++) {
		const struct hl_dbc_signal *mux = &sigs[ret_values[k].signal];
		const struct mux_table *t;
		uint64_t v = ret_values[k].raw;

		if (mux->mux_table < 0)
			continue;
		t = &plan->tables[mux->mux_table];
		if (t->offsets) {
			if (v >= t->n_values)
				continue;
			for (uint32_t c = t->offsets[v]; c < t->offsets[v + 1]; c++) {
				const struct hl_dbc_signal *s = &sigs[t->children[c]];
				uint64_t raw = extract(s, buf);

				ret_values[n].signal = t->children[c];
				ret_values[n].raw = raw;
				ret_values[n].phys = phys(s, raw);
				n++;
			}
		} else {
			for (int r = 0; r < t->n_ranges; r++) {
				const struct hl_dbc_signal *s;
				uint64_t raw;

				if (v < t->ranges[r].lo || v > t->ranges[r].hi)
					continue;
				s = &sigs[t->ranges[r].child];
				raw = extract(s, buf);
				ret_values[n].signal = t->ranges[r].child;
				ret_values[n].raw = raw;
				ret_values[n].phys = phys(s, raw);
				n++;
			}
		}
	}
	return n;
}

int hl_dbc_signal_get_raw(const struct hl_dbc_signal *s, const uint8_t *data, size_t len,
			  uint64_t *ret_raw)
{
	uint8_t buf[HL_DBC_MAX_PAYLOAD + 8] = { 0 };
	size_t end = hl_dbc_signal_end_byte(s->start_bit, s->length, s->order);

	if (end > len || end > HL_DBC_MAX_PAYLOAD)
		return -EMSGSIZE;
	memcpy(buf, data, end);
	*ret_raw = extract(s, buf);
	return 0;
}

int hl_dbc_signal_raw_from_phys(const struct hl_dbc_signal *s, double value, uint64_t *ret_raw)
{
	double half = fabs(s->factor) / 2, r;

	if (!isfinite(value))
		return -ERANGE;
	if (s->min < s->max && (value < s->min - half || value > s->max + half))
		return -ERANGE;
	r = (value - s->offset) / s->factor;
	if (s->type == HL_DBC_FLOAT) {
		float f = (float)r;
		uint32_t u;

		if (!isfinite(f))
			return -ERANGE;
		memcpy(&u, &f, sizeof(u));
		*ret_raw = u;
		return 0;
	}
	if (s->type == HL_DBC_DOUBLE) {
		if (!isfinite(r))
			return -ERANGE;
		memcpy(ret_raw, &r, sizeof(r));
		return 0;
	}
	r = nearbyint(r);
	if (s->is_signed) {
		double lo = -ldexp(1, s->length - 1), hi = ldexp(1, s->length - 1);

		if (r < lo || r >= hi)
			return -ERANGE;
		*ret_raw = (uint64_t)(int64_t)r;
	} else {
		if (r < 0 || r >= ldexp(1, s->length))
			return -ERANGE;
		*ret_raw = (uint64_t)r;
	}
	return 0;
}

int hl_dbc_signal_set_raw(const struct hl_dbc_signal *s, uint64_t raw, uint8_t *data, size_t len)
{
	size_t end = hl_dbc_signal_end_byte(s->start_bit, s->length, s->order);

	if (end > len)
		return -EMSGSIZE;
	for (int i = 0; i < s->length; i++) {
		int bit, byte, shift;
		uint8_t v;

		if (s->order == HL_DBC_INTEL) {
			bit = s->start_bit + i; /* value bit i */
			v = (raw >> i) & 1;
			byte = bit / 8;
			shift = bit % 8;
		} else {
			bit = motorola_pos(s->start_bit) + i; /* value bit length - 1 - i */
			v = (raw >> (s->length - 1 - i)) & 1;
			byte = bit / 8;
			shift = 7 - bit % 8;
		}
		data[byte] = (uint8_t)((data[byte] & ~(1u << shift)) | ((unsigned)v << shift));
	}
	return 0;
}

int hl_dbc_signal_encode(const struct hl_dbc_signal *s, double value, uint8_t *data, size_t len)
{
	uint64_t raw;
	int rc = hl_dbc_signal_raw_from_phys(s, value, &raw);

	if (rc < 0)
		return rc;
	return hl_dbc_signal_set_raw(s, raw, data, len);
}

bool hl_dbc_signal_present(const struct hl_dbc_message *m, const struct hl_dbc_signal *s,
			   const uint8_t *data, size_t len)
{
	if (s->unusable)
		return false;
	while (s->mux_parent >= 0) {
		const struct hl_dbc_signal *mux = &m->signals[s->mux_parent];

		if (mux->unusable)
			return false;
		uint64_t v;
		bool in = false;

		if (hl_dbc_signal_get_raw(mux, data, len, &v) < 0)
			return false;
		for (int r = 0; r < s->n_mux_ranges; r++)
			if (v >= s->mux_ranges[r].lo && v <= s->mux_ranges[r].hi)
				in = true;
		if (!in)
			return false;
		s = mux;
	}
	return true;
}
